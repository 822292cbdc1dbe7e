// The legend of a model as an image: one row per body and surface with its colour swatch
// and its name (and lithology when known), drawn with stb_easy_font's ASCII bitmap font
// at `scale` x its 7-pixel glyphs. RGBA8, straight alpha, row 0 at the top. Any thread.
#pragma once

#include <cstdint>
#include <vector>

#include "api/catalog.hpp"

namespace geoslice::api {

struct LegendImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;
};

LegendImage renderLegend(const CatalogModel& model, int scale = 2);

}  // namespace geoslice::api
