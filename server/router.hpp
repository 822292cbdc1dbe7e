// The router: routes are added once at start-up (method, a name for metrics and logs, a
// regular expression that must match the whole path); dispatch() then runs on handler
// threads. Before any route: a path, query parameter or read header that is not UTF-8 is a
// 400 naming it (checkRequestText; nothing from a request reaches JSON, a log line or a
// metric label unchecked). Around every handler: 503 while draining, any exception becomes
// a 500 with a JSON body, the request is counted and timed per route. OPTIONS answers a
// routed path with its Allow (and the CORS preflight headers); a path routed for other
// methods is a 405 with Allow; no match is a 404.
//
// Threads: add() before the transport starts (the route table is then read-only);
// dispatch() from any number of handler threads at once.
#pragma once

#include <atomic>
#include <functional>
#include <regex>
#include <string>
#include <vector>

#include "model/result.hpp"
#include "server/http_message.hpp"
#include "server/metrics.hpp"

namespace geoslice::server {

// OK when the request's path, query parameter names and values, and the header values the
// routes read are UTF-8; otherwise an InvalidArgument naming the part, its bytes escaped.
Status checkRequestText(const HttpRequest& req);

class Router {
public:
    using Handler = std::function<void(const HttpRequest&, HttpResponse&)>;

    // `cors`: the Access-Control-Allow-Origin value ("" = no CORS). `draining` is set by
    // shutdown; `inFlight` counts requests inside handlers (shutdown waits for it).
    Router(Metrics& metrics, std::string cors, const std::atomic<bool>& draining, std::atomic<int>& inFlight);

    void add(const char* method, const std::string& name, const std::string& pattern, Handler fn);
    // Runs on a transport handler thread: req.matches gets [0] = path, then the groups.
    void dispatch(HttpRequest& req, HttpResponse& res) const;

private:
    struct Route {
        std::string method;
        std::string name;
        std::regex pattern;
        Handler fn;
    };
    void run(const Route& route, const HttpRequest& req, HttpResponse& res) const;
    // "GET, HEAD, OPTIONS" for the methods routed on `path`; "" when no route matches it.
    std::string allowedMethods(const std::string& path) const;
    Metrics& metrics_;
    const std::string cors_;
    const std::atomic<bool>& draining_;
    std::atomic<int>& inFlight_;
    std::vector<Route> routes_;  // written by add() before serving, read-only after
};

}  // namespace geoslice::server
