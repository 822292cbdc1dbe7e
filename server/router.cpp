#include "server/router.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "model/text_scan.hpp"
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
            const std::string what = text::escapeText(e.what());
            spdlog::error("event=handler_exception route={} what=\"{}\"", route.name, what);
            res = HttpResponse();
            problem(res, 500, "internal error: " + what, req.path, "internal");
        } catch (...) {
            spdlog::error("event=handler_exception route={} what=(not a std::exception)", route.name);
            res = HttpResponse();
            problem(res, 500, "internal error", req.path, "internal");
        }
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    metrics_.request(route.name, route.method, res.status, s);
    spdlog::debug("event=request method={} route={} path=\"{}\" status={} ms={:.3f}", route.method, route.name,
                  text::escapeText(req.path), res.status, s * 1e3);
    --inFlight_;
}

Status checkRequestText(const HttpRequest& req) {
    if (!text::isUtf8(req.path))
        return makeError(ErrorCode::InvalidArgument,
                         "the request path is not valid UTF-8: '" + text::escapeText(req.path) + "'");
    for (const auto& [name, value] : req.params) {
        if (!text::isUtf8(name))
            return makeError(ErrorCode::InvalidArgument,
                             "a query parameter name is not valid UTF-8: '" + text::escapeText(name) + "'");
        if (!text::isUtf8(value))
            return makeError(ErrorCode::InvalidArgument, "parameter '" + text::escapeText(name) +
                                                             "' is not valid UTF-8: '" + text::escapeText(value) + "'");
    }
    // Field values may carry obs-text (RFC 9110 5.5); the ones the routes read must be UTF-8.
    for (const char* name : {"Content-Type", "If-None-Match", "Authorization", "X-Api-Key", "Origin"}) {
        const std::string value = req.get_header_value(name);
        if (!text::isUtf8(value))
            return makeError(ErrorCode::InvalidArgument, std::string("header '") + name + "' is not valid UTF-8: '" +
                                                             text::escapeText(value) + "'");
    }
    return {};
}

std::string Router::allowedMethods(const std::string& path) const {
    std::string allow;
    for (const auto& r : routes_) {
        if (!std::regex_match(path, r.pattern)) continue;
        for (const std::string& m :
             r.method == "GET" ? std::vector<std::string>{"GET", "HEAD"} : std::vector<std::string>{r.method})
            if (allow.find(m) == std::string::npos) allow += (allow.empty() ? "" : ", ") + m;
    }
    if (!allow.empty()) allow += ", OPTIONS";
    return allow;
}

void Router::dispatch(HttpRequest& req, HttpResponse& res) const {
    if (auto s = checkRequestText(req); !s) {
        problem(res, 400, s.error().message, req.path, "invalid_utf8");
    } else if (req.method == "OPTIONS") {
        const std::string allow = allowedMethods(req.path);
        if (allow.empty()) {
            problem(res, 404, "no route for " + req.path, req.path, "not_found");
        } else {
            res.set_header("Allow", allow);
            if (!cors_.empty()) {
                res.set_header("Access-Control-Allow-Methods", allow);
                res.set_header("Access-Control-Allow-Headers", "Content-Type, If-None-Match");
                res.set_header("Access-Control-Max-Age", "86400");
            }
            res.status = 204;
        }
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
        } else if (const std::string allow = allowedMethods(req.path); !allow.empty()) {
            res.set_header("Allow", allow);
            problem(res, 405, "method " + req.method + " is not allowed on " + req.path + "; allowed: " + allow,
                    req.path, "method_not_allowed");
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
