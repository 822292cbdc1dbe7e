// Stateless sections and their tiles: POST /v1/models/{id}/sections (a section definition
// -> its id, grid and tile URL template), GET /v1/sections/{sid} (the definition back) and
// GET /v1/sections/{sid}/tiles/{z}/{x}/{y}.{png,jpg,webp} (api/view.hpp's tile grid; CPU,
// on a render worker), and the same grid as TileJSON 3.0 (/tilejson.json) and OGC API - Tiles
// (/tiles, /tilematrixset) for GIS clients. The section id carries the whole definition
// (api/plan.hpp).
#include <optional>

#include "api/request.hpp"
#include "api/tile_grid.hpp"
#include "api/view.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {
namespace {

void defineSection(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    if (!requireJsonBody(req, res)) return;
    auto params = api::parseSectionBody(req.body);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), api::sectionParamNames()); !s)
        return problem(res, s.error(), req.path);
    auto def = api::parseSectionDef(params.value(), m->id, m->model.crs);
    if (!def) return problem(res, def.error(), req.path);
    // A colouring this model cannot draw (no block model, no such property, bad breaks) is
    // refused now, not by every tile of the section later.
    if (auto classes = api::blockClasses(*m, def.value()); !classes) return problem(res, classes.error(), req.path);
    auto grid = api::tileGrid(*m, def.value());
    if (!grid) return problem(res, grid.error(), req.path);
    const std::string sid = api::encodeSectionId(def.value());
    Json j;
    j["sid"] = sid;
    j["model"] = m->id;
    j["definition"] = def.value().canonical();
    // URLs pinned to the model's version: a re-bake makes new ones (versionPinHolds).
    const std::string v = versionQuery(*m);
    j["version"] = m->version;
    j["tiles"] = "/v1/sections/" + sid + "/tiles/{z}/{x}/{y}.png" + v;
    j["tilejson"] = "/v1/sections/" + sid + "/tilejson.json" + v;
    j["ogcTiles"] = "/v1/sections/" + sid + "/tiles" + v;
    j["grid"] = grid.value().describe();
    res.set_header("Location", "/v1/sections/" + sid);
    sendJson(res, j, 201);
}

// The model and definition a section id names, or null after answering. The scope of the
// request's key is checked as soon as the id yields its model's name, before that model is
// looked up (as findModel does): 403 whether or not it exists.
std::optional<std::pair<std::shared_ptr<const api::CatalogModel>, api::SectionDef>> section(ServerState& st,
                                                                                            const HttpRequest& req,
                                                                                            HttpResponse& res) {
    std::string forbidden;
    auto def = api::decodeSectionId(req.matches[1], [&](const std::string& id) -> const Crs* {
        if (!mayRead(st, req, id)) {
            forbidden = id;
            return nullptr;
        }
        auto m = st.catalog.find(id);
        return m ? &m->model.crs : nullptr;
    });
    if (!forbidden.empty()) {
        forbidModel(res, forbidden, req.path);
        return std::nullopt;
    }
    if (!def) {
        problem(res, def.error(), req.path);
        return std::nullopt;
    }
    auto m = st.catalog.find(def.value().model);
    if (!m) {
        problem(res, makeError(ErrorCode::NotFound, "section names model '" + def.value().model + "', not loaded"),
                req.path);
        return std::nullopt;
    }
    if (!versionPinHolds(req, *m, res)) return std::nullopt;
    return std::make_pair(m, def.value());
}

void describeSection(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    if (auto p = queryParams(req); !p || !api::checkKnownParams(p.value(), {}).ok())
        return problem(res, 400, "this route takes no query parameters", req.path, "invalid_argument");
    auto s = section(st, req, res);
    if (!s) return;
    auto grid = api::tileGrid(*s->first, s->second);
    if (!grid) return problem(res, grid.error(), req.path);
    sendJson(res, Json{{"sid", std::string(req.matches[1])},
                       {"model", s->first->id},
                       {"definition", s->second.canonical()},
                       {"grid", grid.value().describe()}});
}

// The absolute URL of a section for the standard descriptions: scheme from
// X-Forwarded-Proto (https behind a TLS proxy), host from the Host header when it is a
// plain host[:port] (the transport requires one on HTTP/1.1), else the loopback address.
std::string sectionBase(const HttpRequest& req, const std::string& sid) {
    std::string host = req.get_header_value("X-Forwarded-Host");
    if (host.empty()) host = req.get_header_value("Host");
    bool plain = !host.empty() && host.size() <= 255;
    for (char c : host)
        plain = plain && ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                          c == '-' || c == ':' || c == '[' || c == ']');
    const std::string scheme = req.get_header_value("X-Forwarded-Proto") == "https" ? "https" : "http";
    return scheme + "://" + (plain ? host : std::string("127.0.0.1")) + "/v1/sections/" + sid;
}

// GET /v1/sections/{sid}/tilejson.json, /tiles (OGC API - Tiles tileset) and
// /tilematrixset (OGC TMS): api/tile_grid.hpp. Unknown query parameters are ignored.
void describeTiles(ServerState& st, const HttpRequest& req, HttpResponse& res, const std::string& form) {
    auto s = section(st, req, res);
    if (!s) return;
    auto grid = api::tileGrid(*s->first, s->second);
    if (!grid) return problem(res, grid.error(), req.path);
    const std::string sid = req.matches[1];
    const std::string base = sectionBase(req, sid);
    const std::string title = "geoslice section of " + s->first->id + ": " + s->second.canonical();
    const std::string v = versionQuery(*s->first);
    if (form == "tilejson") return sendJson(res, api::tileJson(grid.value(), base, title, v));
    if (form == "tileset") return sendJson(res, api::ogcTileset(grid.value(), base, title, v));
    sendJson(res, api::ogcTileMatrixSet(grid.value(), base));
}

void tile(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto format = imageFormatFromName(std::string(req.matches[5]));
    if (!format)
        return problem(res, 404, "unknown tile format '" + std::string(req.matches[5]) + "'", req.path, "not_found");
    auto address = api::parseTileAddress(req.matches[2], req.matches[3], req.matches[4]);
    if (!address) return problem(res, address.error(), req.path);
    // Query parameters are ignored (cache busters such as ?v=1 that map clients add); the
    // tile is named by its path alone, and so is its cache entry.
    auto s = section(st, req, res);
    if (!s) return;
    const auto& [m, def] = *s;
    const auto [z, x, y] = address.value();
    // Validated before any cache or ETag is consulted.
    auto grid = api::tileGrid(*m, def);
    if (!grid) return problem(res, grid.error(), req.path);
    if (auto rect = grid.value().tileRect(z, x, y); !rect) return problem(res, rect.error(), req.path);
    const std::string key = cache_key::tile(*m, def, z, x, y, extension(format.value()));
    const std::string etag = RenderCache::etagOf(key);
    if (answerNotModified(req, res, etag)) return;
    if (auto hit = st.cache->find(key, "tile")) return sendEncoded(req, res, *hit);
    auto result = st.cache->render(
        key,
        [&st, m = m, def = def, g = grid.value(), z = z, x = x, y = y, format = format.value(), etag](
            workers::WorkerState&, const std::atomic<bool>& cancel) -> Rendered {
            auto view = api::renderSectionTile(*m, def, g, z, x, y, &cancel);
            if (!view) return view.error();
            st.metrics.render("tile", view.value().renderMs / 1e3);
            return encodeEntry(view.value(), format, 0, etag, &cancel);
        },
        renderBytes(grid.value().tileSize, grid.value().tileSize, false), false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

}  // namespace

void addTileRoutes(Router& router, ServerState& st) {
    router.add("POST", "/v1/models/{id}/sections", "/v1/models/([^/]+)/sections",
               [&st](const HttpRequest& req, HttpResponse& res) { defineSection(st, req, res); });
    router.add("GET", "/v1/sections/{sid}", "/v1/sections/([A-Za-z0-9_-]+)",
               [&st](const HttpRequest& req, HttpResponse& res) { describeSection(st, req, res); });
    router.add("GET", "/v1/sections/{sid}/tilejson.json", "/v1/sections/([A-Za-z0-9_-]+)/tilejson\\.json",
               [&st](const HttpRequest& req, HttpResponse& res) { describeTiles(st, req, res, "tilejson"); });
    router.add("GET", "/v1/sections/{sid}/tiles", "/v1/sections/([A-Za-z0-9_-]+)/tiles",
               [&st](const HttpRequest& req, HttpResponse& res) { describeTiles(st, req, res, "tileset"); });
    router.add("GET", "/v1/sections/{sid}/tilematrixset", "/v1/sections/([A-Za-z0-9_-]+)/tilematrixset",
               [&st](const HttpRequest& req, HttpResponse& res) { describeTiles(st, req, res, "tms"); });
    router.add("GET", "/v1/sections/{sid}/tiles/{z}/{x}/{y}.{format}",
               "/v1/sections/([A-Za-z0-9_-]+)/tiles/(-?[0-9]+)/(-?[0-9]+)/(-?[0-9]+)\\.([A-Za-z0-9]+)",
               [&st](const HttpRequest& req, HttpResponse& res) { tile(st, req, res); });
}

}  // namespace geoslice::server
