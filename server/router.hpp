// The router: routes are added once at start-up (method, a name for metrics and logs, a
// regular expression that must match the whole path); dispatch() then runs on handler
// threads. Around every handler: 503 while draining, a stray exception becomes a 500
// with a JSON body, the request is counted and timed per route. OPTIONS answers any path
// (CORS preflight); no match is a 404.
//
// Threads: add() before the transport starts (the route table is then read-only);
// dispatch() from any number of handler threads at once.
#pragma once

#include <atomic>
#include <functional>
#include <regex>
#include <string>
#include <vector>

#include "server/http_message.hpp"
#include "server/metrics.hpp"

namespace geoslice::server {

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
    Metrics& metrics_;
    const std::string cors_;
    const std::atomic<bool>& draining_;
    std::atomic<int>& inFlight_;
    std::vector<Route> routes_;  // written by add() before serving, read-only after
};

}  // namespace geoslice::server
