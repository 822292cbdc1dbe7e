// GET / and /web/{asset}: the embedded web client (server/web_assets.hpp). index.html is
// revalidated on every load (no-cache + ETag); the other assets are fetched with
// ?v=<build id> by the page and cached for a day. Open to anyone while API keys are on: the
// client holds no model data; it sends the key it is given (web/api.js).
#include "server/respond.hpp"
#include "server/routes/routes.hpp"
#include "server/web_assets.hpp"

namespace geoslice::server {
namespace {

void sendAsset(const HttpRequest& req, HttpResponse& res, const WebAsset* a, bool revalidate) {
    if (!a) return problem(res, 404, "no web asset '" + req.path.substr(0, 120) + "'", req.path, "not_found");
    res.set_header("ETag", std::string(a->etag));
    res.set_header("Cache-Control", revalidate ? "no-cache" : "public, max-age=86400");
    res.set_header("X-Content-Type-Options", "nosniff");
    if (etagMatches(req.get_header_value("If-None-Match"), std::string(a->etag))) {
        res.status = 304;
        return;
    }
    res.set_content(std::string(a->body), std::string(a->contentType));
}

}  // namespace

void addWebRoutes(Router& router, ServerState&) {
    router.add(
        "GET", "/", "/",
        [](const HttpRequest& req, HttpResponse& res) { sendAsset(req, res, findWebAsset("index.html"), true); },
        RouteAccess::Open);
    router.add(
        "GET", "/web/{asset}", "/web/([A-Za-z0-9._/-]+)",
        [](const HttpRequest& req, HttpResponse& res) { sendAsset(req, res, findWebAsset(req.matches[1]), false); },
        RouteAccess::Open);
}

}  // namespace geoslice::server
