// The model catalog: GET /v1/models (summaries without legends; while API keys are on, of
// the models the request's key may read), /v1/models/{id} (one
// summary), /v1/models/{id}/legend.png (the legend image, optionally with the rows of a
// block-property colouring: colour=PROP[&breaks=..&ramp=..]), /v1/models/{id}/context.geojson
// (the plan's context layer, api/context_layer.hpp).
#include <chrono>

#include "api/legend.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {
namespace {

void legend(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), {"colour", "breaks", "ramp"}); !s)
        return problem(res, s.error(), req.path);
    auto colour = api::parseBlockColouring(params.value());
    if (!colour) return problem(res, colour.error(), req.path);
    api::SectionDef def;
    def.colour = colour.value();
    auto classes = api::blockClasses(*m, def);
    if (!classes) return problem(res, classes.error(), req.path);
    const std::string key = cache_key::legend(*m, def, classes.value() ? &*classes.value() : nullptr);
    if (auto hit = st.cache->find(key)) return sendEncoded(req, res, *hit);
    // Drawn and encoded on a render worker (the threading rule: HTTP threads only wait),
    // coalesced and cached like every other image.
    auto result = st.cache->render(
        key,
        [&st, m, classes = classes.value(), etag = RenderCache::etagOf(key)](
            workers::WorkerState&, const std::atomic<bool>& cancel) -> Rendered {
            const auto t0 = std::chrono::steady_clock::now();
            api::LegendImage legend = api::renderLegend(*m, 2, classes ? &*classes : nullptr);
            api::ViewImage v;
            v.width = legend.width;
            v.height = legend.height;
            v.rgba = std::move(legend.rgba);
            st.metrics.render("legend", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            return encodeEntry(v, ImageFormat::Png, 0, etag, &cancel);
        },
        kVectorBytes, false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

// The context layer in the model's CRS: 404 without one, 409 when its sidecar did not load.
void context(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), {}); !s) return problem(res, s.error(), req.path);
    if (!m->context) {
        if (!m->contextWarning.empty())
            return problem(res, 409, "model '" + m->id + "': " + m->contextWarning, req.path, "context_not_loaded");
        return problem(res, 404,
                       "model '" + m->id + "' has no context layer: put " + m->id +
                           ".context.geojson beside the model file (docs/http.md)",
                       req.path, "not_found");
    }
    const std::string key = cache_key::reserves(*m, "context-layer");
    if (auto hit = st.cache->find(key, "context")) return sendEncoded(req, res, *hit);
    auto result = st.cache->render(
        key,
        [m, etag = RenderCache::etagOf(key)](workers::WorkerState&, const std::atomic<bool>&) -> Rendered {
            return documentEntry(*m->context, "application/geo+json", etag);
        },
        kVectorBytes, false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

}  // namespace

void addModelRoutes(Router& router, ServerState& st) {
    router.add("GET", "/v1/models", "/v1/models", [&st](const HttpRequest& req, HttpResponse& res) {
        Json list = Json::array();
        for (const auto& m : st.catalog.list()) {
            if (!mayRead(st, req, m->id)) continue;  // a key lists the models it may read, no others
            Json s = m->summary();
            s.erase("legend");
            list.push_back(std::move(s));
        }
        sendJson(res, Json{{"models", std::move(list)}, {"loading", !st.loaded}});
    });
    router.add("GET", "/v1/models/{id}", "/v1/models/([^/]+)", [&st](const HttpRequest& req, HttpResponse& res) {
        auto m = findModel(st, req, req.matches[1], res);
        if (m) sendJson(res, m->summary());
    });
    router.add("GET", "/v1/models/{id}/legend.png", "/v1/models/([^/]+)/legend\\.png",
               [&st](const HttpRequest& req, HttpResponse& res) { legend(st, req, res); });
    router.add("GET", "/v1/models/{id}/context.geojson", "/v1/models/([^/]+)/context\\.geojson",
               [&st](const HttpRequest& req, HttpResponse& res) { context(st, req, res); });
}

}  // namespace geoslice::server
