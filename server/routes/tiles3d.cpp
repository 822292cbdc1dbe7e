// The model as OGC 3D Tiles 1.1 (renderer/tiles3d/tileset3d.hpp) for CesiumJS:
// GET /v1/models/{id}/3dtiles/tileset.json and /v1/models/{id}/3dtiles/tiles/{n}.glb (the URIs
// tileset.json names, relative to it). The hierarchy is built once per model version on a
// render worker, at the first request (ServerState::tiles3d); tileset.json and every tile are
// encoded on a render worker and cached like images. Query parameters other than the version
// pin (`version=`, server/routes/common.hpp) are ignored (cache busters). A model without a
// WGS 84 placement (local, or a datum PROJ cannot place) gets 422.
#include <chrono>
#include <functional>
#include <utility>

#include "model/json_text.hpp"
#include "model/version.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {
namespace {

using Built = Result<std::shared_ptr<const Tileset3d>>;

// The model's tileset, built on the first call for its version; later calls (any thread)
// wait for that build. Runs on a render worker.
Built tilesetOf(ServerState& st, const api::CatalogModel& m) {
    std::shared_future<Built> built;
    std::promise<Built> mine;
    bool builder = false;
    {
        std::lock_guard lock(st.tiles3dMutex);
        auto it = st.tiles3d.find(m.id);
        if (it != st.tiles3d.end() && it->second.version == m.version) {
            built = it->second.built;
        } else {
            built = mine.get_future().share();
            st.tiles3d[m.id] = {m.version, built};
            builder = true;
        }
    }
    if (builder) {
        const auto t0 = std::chrono::steady_clock::now();
        std::shared_ptr<const CrsTransform> toWgs84 = m.lonLat;
        Tiles3dOptions options;
        options.trianglesPerTile = st.config.tiles3dTriangles;
        Built result = Tileset3d::build(
            m.model, [&toWgs84](const glm::dvec3& w) { return toWgs84->apply(w); }, options);
        st.metrics.render("3dtiles", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        mine.set_value(std::move(result));
    }
    return built.get();
}

// Answers the problem and returns null when the model cannot be placed on the globe.
std::shared_ptr<const api::CatalogModel> placedModel(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return nullptr;
    if (!m->lonLat) {
        problem(res,
                makeError(ErrorCode::Unsupported,
                          "3D Tiles need the model on the globe: " +
                              (m->model.crs.isLocal()
                                   ? std::string("the model has no CRS (declare one: a <stem>.crs file beside it, "
                                                 "or serve --crs)")
                                   : "no WGS 84 transformation for " + m->model.crs.id() +
                                         (m->lonLatNote.empty() ? std::string() : ": " + m->lonLatNote))),
                req.path);
        return nullptr;
    }
    return m;
}

// One document of the model's tileset (`what`: "tileset.json" or "<n>.glb"), made by
// `produce` from the built tileset on a render worker and cached like an image.
using Document = std::pair<std::string, const char*>;  // body, content type
using Produce = std::function<Result<Document>(const api::CatalogModel&, const Tileset3d&)>;
void answer(ServerState& st, const HttpRequest& req, HttpResponse& res, const std::string& what, Produce produce) {
    auto m = placedModel(st, req, res);
    if (!m) return;
    const std::string key = cache_key::tiles3d(*m, what);
    if (auto hit = st.cache->find(key, "3dtiles")) return sendEncoded(req, res, *hit);
    auto result = st.cache->render(
        key,
        [&st, m, produce = std::move(produce), etag = RenderCache::etagOf(key)](workers::WorkerState&,
                                                                                const std::atomic<bool>&) -> Rendered {
            auto ts = tilesetOf(st, *m);
            if (!ts) return ts.error();
            auto doc = produce(*m, *ts.value());
            if (!doc) return doc.error();
            return documentEntry(std::move(doc->first), doc->second, etag);
        },
        std::max(kVectorBytes, m->model.triangleCount() * 96), false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

void tileset(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    answer(st, req, res, "tileset.json", [](const api::CatalogModel& m, const Tileset3d& ts) -> Result<Document> {
        // Tile URIs pinned to the model's version: a re-bake makes new ones.
        return Document{jsonText(ts.tilesetJson("tiles/", kGeneratorName, versionQuery(m))), "application/json"};
    });
}

void tile(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    const std::string n = req.matches[2];
    answer(st, req, res, n + ".glb", [n](const api::CatalogModel& m, const Tileset3d& ts) -> Result<Document> {
        const std::size_t index = std::stoul(n);  // the route allows 1-9 digits
        if (index >= ts.tileCount())
            return makeError(ErrorCode::NotFound, "3D Tiles: the tileset of '" + m.id + "' has " +
                                                      std::to_string(ts.tileCount()) + " tiles, no " + n);
        auto glb = ts.tileGlb(index);
        if (!glb) return glb.error();
        return Document{std::string(glb->begin(), glb->end()), "model/gltf-binary"};
    });
}

}  // namespace

void addTiles3dRoutes(Router& router, ServerState& st) {
    router.add("GET", "/v1/models/{id}/3dtiles/tileset.json", "/v1/models/([^/]+)/3dtiles/tileset\\.json",
               [&st](const HttpRequest& req, HttpResponse& res) { tileset(st, req, res); });
    router.add("GET", "/v1/models/{id}/3dtiles/tiles/{n}.glb", "/v1/models/([^/]+)/3dtiles/tiles/([0-9]{1,9})\\.glb",
               [&st](const HttpRequest& req, HttpResponse& res) { tile(st, req, res); });
}

}  // namespace geoslice::server
