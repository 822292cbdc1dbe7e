// The router: routes are added once at start-up (method, a name for metrics and logs, a
// regular expression that must match the whole path, and whether the route needs an API
// key); dispatch() then runs on handler threads. Before any route: a path, query parameter
// or read header that is not UTF-8 is a 400 naming it (checkRequestText; nothing from a
// request reaches JSON, a log line or a metric label unchecked). Around every handler: 503
// while draining, then, while API keys are on (api/access_keys.hpp) and the route needs one,
// authentication: no key or an unknown one is a 401 with WWW-Authenticate: Bearer, a known
// one is put on the request (HttpRequest::key) for the model routes to check its scope
// (routes/common.hpp findModel: 403). Any exception becomes a 500 with a JSON body; the
// request is counted and timed per route. OPTIONS answers a routed path with its Allow (and
// the CORS preflight headers); a path routed for other methods is a 405 with Allow; no match
// is a 404. CORS (CorsPolicy): Access-Control-Allow-Origin on every answer but /metrics and
// /readyz, "*" or the request's Origin when the allow-list names it (with Vary: Origin).
// While keys are on, answers of keyed routes are Cache-Control: private (never stored by a
// shared cache such as nginx's) and Vary: Authorization, X-Api-Key; a 401 is no-store.
//
// Threads: add() before the transport starts (the route table is then read-only);
// dispatch() from any number of handler threads at once.
#pragma once

#include <atomic>
#include <functional>
#include <regex>
#include <string>
#include <vector>

#include "api/access_keys.hpp"
#include "model/result.hpp"
#include "server/config.hpp"
#include "server/http_message.hpp"
#include "server/metrics.hpp"

namespace geoslice::server {

// OK when the request's path, query parameter names and values, and the header values the
// routes read are UTF-8; otherwise an InvalidArgument naming the part, its bytes escaped
// (but for Authorization and X-Api-Key, whose values are never repeated back).
Status checkRequestText(const HttpRequest& req);

// Key: the route answers only requests with a valid API key while keys are on (the model
// routes). Open: anyone (the web client, /healthz, /readyz, /metrics, /openapi.json).
enum class RouteAccess { Key, Open };

// The API key a request presents: the token of "Authorization: Bearer KEY" (scheme
// case-insensitive), else the value of X-Api-Key; "" when neither is there.
std::string presentedKey(const HttpRequest& req);

class Router {
public:
    using Handler = std::function<void(const HttpRequest&, HttpResponse&)>;

    // `cors`: who may read answers cross-origin. `keys`: the API keys (none: every route is
    // open); must outlive the router. `draining` is set by shutdown; `inFlight` counts
    // requests inside handlers (shutdown waits for it).
    Router(Metrics& metrics, CorsPolicy cors, const api::AccessKeys& keys, const std::atomic<bool>& draining,
           std::atomic<int>& inFlight);

    // A route needs an API key unless it says Open: a new route is closed by default.
    void add(const char* method, const std::string& name, const std::string& pattern, Handler fn,
             RouteAccess access = RouteAccess::Key);
    // Runs on a transport handler thread: req.matches gets [0] = path, then the groups.
    void dispatch(HttpRequest& req, HttpResponse& res) const;

private:
    struct Route {
        std::string method;
        std::string name;
        std::regex pattern;
        Handler fn;
        RouteAccess access;
    };
    void run(const Route& route, HttpRequest& req, HttpResponse& res) const;
    // Sets req.key from the presented key (true), or answers 401 (false).
    bool authenticate(HttpRequest& req, HttpResponse& res) const;
    // "GET, HEAD, OPTIONS" for the methods routed on `path`; "" when no route matches it.
    std::string allowedMethods(const std::string& path) const;
    Metrics& metrics_;
    const CorsPolicy cors_;
    const api::AccessKeys& keys_;
    const std::atomic<bool>& draining_;
    std::atomic<int>& inFlight_;
    std::vector<Route> routes_;  // written by add() before serving, read-only after
};

}  // namespace geoslice::server
