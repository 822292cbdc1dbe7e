// The legend of a model as an image: one row per body and surface with its colour swatch
// and its name (and lithology when known), drawn with stb_easy_font's ASCII bitmap font
// at `scale` x its 7-pixel glyphs. RGBA8, straight alpha, row 0 at the top. Any thread.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "section/blocks/block_section.hpp"

namespace geoslice::api {

struct LegendImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;
};

// With `classes` (a block-property colouring, api/view.hpp blockClasses), the rows end with
// the property's name and unit, the ramp, and one swatch per class labelled with its range.
LegendImage renderLegend(const CatalogModel& model, int scale = 2, const PropertyClasses* classes = nullptr);

// The legend of a block-property colouring, for clients and print layouts:
// {"property", "unit", "ramp", "breaks": [...], "classes": [{"class", "from" (null for the
// first), "to" (null for the last), "colour": "#rrggbb", "label"}]}; class k holds values in
// [from, to).
nlohmann::ordered_json blockLegendJson(const BlockModel& blocks, const PropertyClasses& classes);

}  // namespace geoslice::api
