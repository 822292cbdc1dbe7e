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
Result<ViewImage> renderSectionTile(const CatalogModel& model, const SectionDef& def, const TileGrid& grid, int z,
                                    long long x, long long y, const std::atomic<bool>* cancel = nullptr);

}  // namespace geoslice::api
