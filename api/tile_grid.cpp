#include "api/tile_grid.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "model/clock.hpp"

namespace geoslice::api {
namespace {

Status requirePlanar(const SectionDef& def) {
    if (def.geometry == Geometry::Line)
        return makeError(ErrorCode::Unsupported,
                         "tiles of polyline sections are not served yet; use 'plane' or 'elevation'");
    if (!def.cutPlanes.empty())
        return makeError(ErrorCode::InvalidArgument,
                         "parameter 'planes': a section for tiles takes one plane; cut-outs of " +
                             std::to_string(def.cutPlanes.size()) + " planes are for perspective views");
    return {};
}

ViewImage fromSectionImage(SectionImage&& s) {
    ViewImage v;
    v.width = s.frame.width;
    v.height = s.frame.height;
    v.rgba = std::move(s.rgba);
    v.ids = std::move(s.ids);
    PixelMapping m;
    m.planar = s.frame;
    m.rect = s.frame.rect;
    m.width = v.width;
    m.height = v.height;
    v.mapping = m;
    return v;
}

}  // namespace

Result<FrameRect> TileGrid::tileRect(int z, long long x, long long y) const {
    if (z < 0 || z > maxZoom)
        return makeError(ErrorCode::NotFound,
                         "tile zoom " + std::to_string(z) + " is outside 0.." + std::to_string(maxZoom));
    const long long n = 1LL << z;
    if (x < 0 || y < 0 || x >= n || y >= n)
        return makeError(ErrorCode::NotFound, "tile " + std::to_string(z) + "/" + std::to_string(x) + "/" +
                                                  std::to_string(y) + " is outside the grid (0.." +
                                                  std::to_string(n - 1) + " at zoom " + std::to_string(z) + ")");
    const double s = size0 / double(n);
    const double sv = s / exaggeration;
    FrameRect r;
    r.u0 = extent.u0 + double(x) * s;
    r.u1 = r.u0 + s;
    r.v1 = extent.v1 - double(y) * sv;
    r.v0 = r.v1 - sv;
    return r;
}

nlohmann::ordered_json TileGrid::describe() const {
    nlohmann::ordered_json j;
    j["tileSize"] = tileSize;
    j["minZoom"] = 0;
    j["maxZoom"] = maxZoom;
    j["origin"] = {{"u", extent.u0}, {"v", extent.v1}};
    j["size0"] = size0;
    j["exaggeration"] = exaggeration;
    j["extent"] = {{"u0", extent.u0}, {"u1", extent.u1}, {"v0", extent.v0}, {"v1", extent.v1}};
    j["tileRect"] =
        "u in [u0 + x*s, u0 + (x+1)*s], v in [v1 - (y+1)*s/k, v1 - y*s/k], s = size0 / 2^z, k = exaggeration";
    const double scale = 256.0 / size0;
    j["leaflet"] = {
        {"crs", "L.CRS.Simple"},
        {"lngOfU", "lng = (u - origin.u) * 256 / size0"},
        {"latOfV", "lat = (v - origin.v) * exaggeration * 256 / size0"},
        {"bounds", {{(extent.v0 - extent.v1) * exaggeration * scale, 0.0}, {0.0, (extent.u1 - extent.u0) * scale}}}};
    return j;
}

namespace {

// The picture frame of a section's tiles as a local engineering CRS (OGC TMS "crs").
nlohmann::ordered_json pictureCrs(const TileGrid& g) {
    char k[32];
    std::snprintf(k, sizeof k, "%.9g", g.exaggeration);
    return {
        {"wkt", std::string("ENGCRS[\"geoslice section picture (v x ") + k +
                    ")\",EDATUM[\"section plane\"],CS[Cartesian,2],AXIS[\"u\",east,ORDER[1],LENGTHUNIT[\"metre\",1]],"
                    "AXIS[\"v\",north,ORDER[2],LENGTHUNIT[\"metre\",1]]]"}};
}

}  // namespace

nlohmann::ordered_json tileJson(const TileGrid& g, const std::string& base, const std::string& title,
                                const std::string& query) {
    nlohmann::ordered_json j;
    j["tilejson"] = "3.0.0";
    j["name"] = title;
    j["scheme"] = "xyz";
    j["tiles"] = {base + "/tiles/{z}/{x}/{y}.png" + query};
    j["minzoom"] = 0;
    j["maxzoom"] = g.maxZoom;
    j["attribution"] = "geoslice section";
    j["geoslice"] = g.describe();
    return j;
}

nlohmann::ordered_json ogcTileset(const TileGrid& g, const std::string& base, const std::string& title,
                                  const std::string& query) {
    nlohmann::ordered_json links = nlohmann::ordered_json::array();
    links.push_back({{"rel", "self"}, {"type", "application/json"}, {"href", base + "/tiles" + query}});
    links.push_back({{"rel", "http://www.opengis.net/def/rel/ogc/1.0/tiling-scheme"},
                     {"type", "application/json"},
                     {"href", base + "/tilematrixset" + query}});
    for (const char* f : {"png", "jpg", "webp"}) {
        const std::string type = std::string("image/") + (std::string(f) == "jpg" ? "jpeg" : f);
        links.push_back({{"rel", "item"},
                         {"type", type},
                         {"templated", true},
                         {"href", base + "/tiles/{tileMatrix}/{tileCol}/{tileRow}." + f + query}});
    }
    nlohmann::ordered_json limits = nlohmann::ordered_json::array();
    for (int z = 0; z <= g.maxZoom; ++z) {
        const long long n = 1LL << z;
        limits.push_back({{"tileMatrix", std::to_string(z)},
                          {"minTileRow", 0},
                          {"maxTileRow", n - 1},
                          {"minTileCol", 0},
                          {"maxTileCol", n - 1}});
    }
    return {{"title", title},
            {"dataType", "map"},
            {"crs", pictureCrs(g)},
            {"tileMatrixSetURI", base + "/tilematrixset"},
            {"tileMatrixSetLimits", std::move(limits)},
            {"links", std::move(links)}};
}

nlohmann::ordered_json ogcTileMatrixSet(const TileGrid& g, const std::string& base) {
    nlohmann::ordered_json matrices = nlohmann::ordered_json::array();
    for (int z = 0; z <= g.maxZoom; ++z) {
        const double cell = g.size0 / std::exp2(z) / g.tileSize;  // metres per pixel
        const long long n = 1LL << z;
        matrices.push_back({{"id", std::to_string(z)},
                            // OGC's standardised rendering pixel of 0.28 mm
                            {"scaleDenominator", cell / 0.28e-3},
                            {"cellSize", cell},
                            {"cornerOfOrigin", "topLeft"},
                            {"pointOfOrigin", {g.extent.u0, g.extent.v1 * g.exaggeration}},
                            {"tileWidth", g.tileSize},
                            {"tileHeight", g.tileSize},
                            {"matrixWidth", n},
                            {"matrixHeight", n}});
    }
    return {{"id", "geoslice-section"},       {"title", "geoslice section picture grid"},
            {"uri", base + "/tilematrixset"}, {"crs", pictureCrs(g)},
            {"orderedAxes", {"u", "v"}},      {"tileMatrices", std::move(matrices)}};
}

Result<TileGrid> tileGrid(const CatalogModel& model, const SectionDef& def) {
    if (auto s = requirePlanar(def); !s) return s.error();
    auto plane = checkPlaneMeetsBounds(sectionPlane(def), model.index->bounds, model.index->origin);
    if (!plane) return plane.error();
    TileGrid g;
    // The picture's stretch of plane v (view/exaggeration.hpp): def.exaggeration on a
    // vertical plane, 1 on a horizontal one.
    g.exaggeration = exaggerationOf(def, model.index->bounds).vStretch(plane.value().normal);
    // The model's bounds on the plane, no margin; the grid is anchored at its top-left corner.
    g.extent = projectedBounds(plane.value(), model.index->bounds, model.model.origin);
    const double extentU = g.extent.u1 - g.extent.u0;
    const double extentV = (g.extent.v1 - g.extent.v0) * g.exaggeration;
    g.size0 = std::exp2(std::ceil(std::log2(std::max({extentU, extentV, 1e-3}))));
    const double finest = 0.01 * g.tileSize;  // about 1 cm per pixel
    g.maxZoom = std::clamp(int(std::ceil(std::log2(g.size0 / finest))), 0, 24);
    return g;
}

Result<ViewImage> renderSectionTile(const CatalogModel& model, const SectionDef& def, const TileGrid& grid, int z,
                                    long long x, long long y, const std::atomic<bool>* cancel) {
    auto rect = grid.tileRect(z, x, y);
    if (!rect) return rect.error();
    auto classes = blockClasses(model, def);
    if (!classes) return classes.error();
    const auto t0 = std::chrono::steady_clock::now();
    RasterOptions ro;
    ro.background = def.background;
    ro.cancel = cancel;
    auto image = renderTile(*model.index, sectionPlane(def), rect.value(), grid.tileSize, grid.tileSize, ro);
    if (!image) return image.error();
    ViewImage v = fromSectionImage(std::move(image.value()));
    if (classes.value()) colourByBlocks(model, *classes.value(), *v.mapping, v);
    v.renderMs = msSince(t0);
    return v;
}

}  // namespace geoslice::api
