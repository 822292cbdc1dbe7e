#include "server/router.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "server/respond.hpp"

namespace geoslice::server {

Router::Router(Metrics& metrics, std::string cors, const std::atomic<bool>& draining, std::atomic<int>& inFlight)
    : metrics_(metrics), cors_(std::move(cors)), draining_(draining), inFlight_(inFlight) {}

void Router::add(const char* method, const std::string& name, const std::string& pattern, Handler fn) {
    routes_.push_back({method, name, std::regex(pattern), std::move(fn)});
}

void Router::run(const Route& route, const HttpRequest& req, HttpResponse& res) const {
    const auto t0 = std::chrono::steady_clock::now();
    ++inFlight_;
    if (draining_) {
        res.set_header("Connection", "close");
        res.set_header("Retry-After", "1");
        problem(res, 503, "the server is shutting down", req.path);
    } else {
        try {
            route.fn(req, res);
        } catch (const std::exception& e) {
            spdlog::error("event=handler_exception route={} what={}", route.name, e.what());
            problem(res, 500, std::string("internal error: ") + e.what(), req.path, "internal");
        }
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    metrics_.request(route.name, route.method, res.status, s);
    spdlog::debug("event=request method={} route={} path={} status={} ms={:.3f}", route.method, route.name, req.path,
                  res.status, s * 1e3);
    --inFlight_;
}

void Router::dispatch(HttpRequest& req, HttpResponse& res) const {
    if (req.method == "OPTIONS") {
        if (!cors_.empty()) {
            res.set_header("Access-Control-Allow-Methods", "GET, POST, OPTIONS");
            res.set_header("Access-Control-Allow-Headers", "Content-Type, If-None-Match");
            res.set_header("Access-Control-Max-Age", "86400");
        }
        res.status = 204;
    } else {
        const Route* found = nullptr;
        std::smatch m;
        for (const auto& r : routes_)
            if (r.method == req.method && std::regex_match(req.path, m, r.pattern)) {
                found = &r;
                break;
            }
        if (found) {
            req.matches.clear();
            for (const auto& group : m) req.matches.push_back(group.str());
            run(*found, req, res);
        } else {
            problem(res, 404, "no route for " + req.method + " " + req.path, req.path, "not_found");
        }
    }
    res.set_header("X-Content-Type-Options", "nosniff");
    // Operational routes are for the operator's probes and scrapers, not for browsers on
    // other origins: no CORS there.
    const bool operational = req.path == "/metrics" || req.path == "/readyz";
    if (!cors_.empty() && !operational) {
        res.set_header("Access-Control-Allow-Origin", cors_);
        res.set_header("Access-Control-Expose-Headers", "ETag, Retry-After");
    }
}

}  // namespace geoslice::server
