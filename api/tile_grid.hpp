// The tile grid of a section's u/v plane and its tiles, from the exact section engine.
// Pixel frames as in api/view.hpp. Pure functions of (model, section), any thread.
#pragma once

#include <atomic>

#include <nlohmann/json.hpp>

#include "api/view.hpp"

namespace geoslice::api {

// The tile grid of a section (documented in the OpenAPI text): zoom 0 is one tile of
// `tileSize` pixels covering a square of `size0` metres along u (size0 / exaggeration
// along v) whose top-left corner is (u0, v1) of the section's extent (the model's bounds
// projected on the plane). Zoom z has 2^z x 2^z tiles; tile (z, x, y) covers
//   u in [u0 + x s, u0 + (x + 1) s],  v in [v1 - (y + 1) s / k, v1 - y s / k],  s = size0 / 2^z.
// Leaflet (L.CRS.Simple, tileSize 256): lng = (u - u0) * 256 / size0, lat = (v - v1) * k * 256 / size0.
struct TileGrid {
    FrameRect extent;           // section contents' u/v rectangle
    double size0 = 1.0;         // metres along u of the zoom-0 tile (a power of two)
    double exaggeration = 1.0;  // k below: the picture's stretch of plane v, VerticalExaggeration::vStretch
    int tileSize = 256;
    int maxZoom = 0;  // tiles are no finer than about 1 cm per pixel

    Result<FrameRect> tileRect(int z, long long x, long long y) const;
    nlohmann::ordered_json describe() const;
};
Result<TileGrid> tileGrid(const CatalogModel& model, const SectionDef& def);

// The same grid in the standard descriptions, so that a GIS adds a section by URL. `base` is
// the absolute URL of the section ("http://host/v1/sections/<sid>"); `title` names it.
//  - TileJSON 3.0.0 (github.com/mapbox/tilejson-spec): tiles, minzoom/maxzoom, scheme xyz,
//    and a "geoslice" member with the grid; no "bounds" (the tiles are in the section's
//    plane, not on the globe: clients use a simple, non-geographic CRS, as with Leaflet's
//    L.CRS.Simple).
//  - OGC API - Tiles (OGC 20-057) tileset metadata with a link to
//  - an OGC Two Dimensional Tile Matrix Set (OGC 17-083r4) in a local engineering CRS: the
//    section picture's frame (u east, v * exaggeration up, metres), origin top-left at
//    (u0, v1 * k), matrix z of 2^z x 2^z tiles with square cells of size0 / 2^z / tileSize.
// `query`: appended to every URL they give (the model-version pin, "?version=...").
nlohmann::ordered_json tileJson(const TileGrid& grid, const std::string& base, const std::string& title,
                                const std::string& query = "");
nlohmann::ordered_json ogcTileset(const TileGrid& grid, const std::string& base, const std::string& title,
                                  const std::string& query = "");
nlohmann::ordered_json ogcTileMatrixSet(const TileGrid& grid, const std::string& base);
Result<ViewImage> renderSectionTile(const CatalogModel& model, const SectionDef& def, const TileGrid& grid, int z,
                                    long long x, long long y, const std::atomic<bool>* cancel = nullptr);

}  // namespace geoslice::api
