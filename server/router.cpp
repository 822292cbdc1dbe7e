#include "server/router.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "model/text_scan.hpp"
#include "server/respond.hpp"

namespace geoslice::server {

namespace {

bool startsWithNoCase(std::string_view s, std::string_view prefix) {
    if (s.size() < prefix.size()) return false;
    for (std::size_t i = 0; i < prefix.size(); ++i) {
        char a = s[i], b = prefix[i];
        if (a >= 'A' && a <= 'Z') a = char(a - 'A' + 'a');
        if (b >= 'A' && b <= 'Z') b = char(b - 'A' + 'a');
        if (a != b) return false;
    }
    return true;
}

std::string trimmed(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return std::string(s);
}

// While keys are on, an answer that depends on the key must not be stored by a shared cache
// (nginx's proxy_cache would hand it to the next client, key or not): "public" becomes
// "private"; a 401 is never stored.
void keepPrivate(HttpResponse& res) {
    std::string cc = res.get_header_value("Cache-Control");
    res.erase_header("Cache-Control");
    if (res.status == 401)
        cc = "no-store";
    else if (cc.rfind("public", 0) == 0)
        cc = "private" + cc.substr(6);
    else if (cc.find("private") == std::string::npos && cc.find("no-store") == std::string::npos)
        cc = cc.empty() ? "private" : "private, " + cc;
    res.set_header("Cache-Control", cc);
}

}  // namespace

std::string presentedKey(const HttpRequest& req) {
    const std::string authorization = req.get_header_value("Authorization");
    if (startsWithNoCase(authorization, "Bearer ")) return trimmed(std::string_view(authorization).substr(7));
    return trimmed(req.get_header_value("X-Api-Key"));
}

Router::Router(Metrics& metrics, CorsPolicy cors, const api::AccessKeys& keys, const std::atomic<bool>& draining,
               std::atomic<int>& inFlight)
    : metrics_(metrics), cors_(std::move(cors)), keys_(keys), draining_(draining), inFlight_(inFlight) {}

void Router::add(const char* method, const std::string& name, const std::string& pattern, Handler fn,
                 RouteAccess access) {
    routes_.push_back({method, name, std::regex(pattern), std::move(fn), access});
}

bool Router::authenticate(HttpRequest& req, HttpResponse& res) const {
    const std::string presented = presentedKey(req);
    if (const api::ApiKey* key = keys_.authenticate(presented)) {
        req.key = key;
        return true;
    }
    // RFC 6750 3: no credentials is a bare challenge; wrong ones are invalid_token. The key
    // is never repeated back, logged or counted.
    const std::string authorization = req.get_header_value("Authorization");
    const bool otherScheme = presented.empty() && !authorization.empty();
    std::string detail;
    if (otherScheme)
        detail =
            "header 'Authorization': only the Bearer scheme is accepted; send 'Authorization: Bearer KEY' or "
            "'X-Api-Key: KEY'";
    else if (presented.empty())
        detail = "this route needs an API key: send 'Authorization: Bearer KEY' or 'X-Api-Key: KEY'";
    else
        detail = "the API key is not valid";
    res.set_header("WWW-Authenticate", presented.empty() && !otherScheme ? "Bearer realm=\"geoslice\""
                                       : otherScheme ? "Bearer realm=\"geoslice\", error=\"invalid_request\""
                                                     : "Bearer realm=\"geoslice\", error=\"invalid_token\"");
    problem(res, 401, detail, req.path, "unauthorized");
    // Counted by kind (a rise of "invalid" is someone guessing); never by key or client.
    metrics_.count("geoslice_auth_failures_total", presented.empty()
                                                       ? (otherScheme ? "reason=\"scheme\"" : "reason=\"missing\"")
                                                       : "reason=\"invalid\"");
    return false;
}

void Router::run(const Route& route, HttpRequest& req, HttpResponse& res) const {
    const auto t0 = std::chrono::steady_clock::now();
    ++inFlight_;
    if (draining_) {
        res.set_header("Connection", "close");
        res.set_header("Retry-After", "1");
        problem(res, 503, "the server is shutting down", req.path);
    } else if (keys_.enabled() && route.access == RouteAccess::Key && !authenticate(req, res)) {
        // answered: 401
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
    addValidators(req, res);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    metrics_.request(route.name, route.method, res.status, s);
    // The key's name, never the key.
    spdlog::debug("event=request method={} route={} path=\"{}\" status={} ms={:.3f} key={}", route.method, route.name,
                  text::escapeText(req.path), res.status, s * 1e3, req.key ? req.key->name : "-");
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
    for (const char* name : {"Content-Type", "If-None-Match", "Origin"}) {
        const std::string value = req.get_header_value(name);
        if (!text::isUtf8(value))
            return makeError(ErrorCode::InvalidArgument, std::string("header '") + name + "' is not valid UTF-8: '" +
                                                             text::escapeText(value) + "'");
    }
    // Credentials are never repeated back, not even escaped.
    for (const char* name : {"Authorization", "X-Api-Key"})
        if (!text::isUtf8(req.get_header_value(name)))
            return makeError(ErrorCode::InvalidArgument, std::string("header '") + name + "' is not valid UTF-8");
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
    const auto t0 = std::chrono::steady_clock::now();
    const std::string origin = cors_.allowOrigin(req.get_header_value("Origin"));
    const Route* found = nullptr;
    if (auto s = checkRequestText(req); !s) {
        problem(res, 400, s.error().message, req.path, "invalid_utf8");
    } else if (req.method == "OPTIONS") {
        // A preflight carries no credentials (Fetch): never authenticated.
        const std::string allow = allowedMethods(req.path);
        if (allow.empty()) {
            problem(res, 404, "no route for " + req.path, req.path, "not_found");
        } else {
            res.set_header("Allow", allow);
            if (!origin.empty()) {
                res.set_header("Access-Control-Allow-Methods", allow);
                res.set_header("Access-Control-Allow-Headers", "Authorization, Content-Type, If-None-Match, X-Api-Key");
                res.set_header("Access-Control-Max-Age", "86400");
            }
            res.status = 204;
        }
    } else {
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
    // What no route answered (bad text, OPTIONS, 404, 405) is counted too, under one label.
    if (!found)
        metrics_.request("(unmatched)", req.method, res.status,
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    res.set_header("X-Content-Type-Options", "nosniff");
    std::string vary;
    if (keys_.enabled() && found && found->access == RouteAccess::Key) {
        keepPrivate(res);
        vary = "Authorization, X-Api-Key";
    }
    // Operational routes are for the operator's probes and scrapers, not for browsers on
    // other origins: no CORS there.
    const bool operational = req.path == "/metrics" || req.path == "/readyz";
    if (!operational) {
        // With an allow-list the answer depends on the Origin, listed or not.
        if (cors_.mode == CorsPolicy::Mode::List) vary += vary.empty() ? "Origin" : ", Origin";
        if (!origin.empty()) {
            res.set_header("Access-Control-Allow-Origin", origin);
            res.set_header("Access-Control-Expose-Headers", "ETag, Retry-After, WWW-Authenticate");
        }
    }
    if (!vary.empty()) res.set_header("Vary", vary);
}

}  // namespace geoslice::server
