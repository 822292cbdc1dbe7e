// Lithology fill patterns: the conventional symbols of geological sections and maps drawn
// over a unit's colour -- dots for sandstone, bricks for limestone, slanted bricks for
// dolomite, dashes for mudstone and shale, dashes and dots for siltstone, circles for
// conglomerate, triangles for breccia, "+" for granite, "x" for diorite, "v" for basalt and
// volcanics, solid black for coal, wavy lines for schist -- after the conventions of
// GB/T 958-2015 (区域地质图图例) and the FGDC Digital Cartographic Standard for Geologic
// Map Symbolization (FGDC-STD-013-2006, section 37, lithologic patterns). The tiles are
// our own simple vector drawings of those conventional symbols, not copies of either
// standard's artwork.
//
// A pattern is a tile of primitives (polylines, stroked circles, filled dots, a solid
// fill) in millimetres, repeated on a grid aligned with the output's origin. One
// definition is drawn by every output: SVG <pattern> elements (section SVG, print SVG),
// cairo (print/pattern_cairo.hpp: PDF tiling patterns, sheet rasters, section images).
//
// Choosing a pattern: a unit's lithology text (AttributeRecord::lithology, else an extra
// column named lith, rock, rock_type or 岩性) is matched case-insensitively against
// English and Chinese names and common codes (SST, LST, ...). In a compound description the
// name that ends last wins, which is the head noun in both languages: "sandy mudstone" and
// "砂质泥岩" are mudstone, "siltstone and feldspathic sandstone" is sandstone, "粉砂岩"
// (siltstone) beats the "砂岩" (sandstone) it ends with by being longer.
// Pure functions, any thread.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "model/attributes.hpp"

namespace geoslice {

enum class Lithology {
    None,
    Sandstone,
    Siltstone,
    Mudstone,
    Shale,
    Clay,
    Limestone,
    Dolomite,
    Conglomerate,
    Breccia,
    Coal,
    Granite,
    Diorite,
    Basalt,
    Tuff,
    Schist,
};

// "sandstone", "limestone", ...; "" for None. Also the suffix of SVG pattern ids ("lith-sandstone").
std::string_view lithologyName(Lithology l);
// Every lithology with a pattern (not None), in enum order.
const std::vector<Lithology>& allLithologies();

// The pattern for a lithology description (see above); None when nothing matches.
Lithology matchLithology(std::string_view text);
// The lithology text of a record: `lithology`, else the first extra string field named
// lith, rock, rock_type or 岩性 (case-insensitive); "" when none.
std::string lithologyText(const AttributeRecord& record);
// matchLithology(lithologyText(record)).
Lithology recordLithology(const AttributeRecord* record);

struct PatternTile {
    double width = 0.0, height = 0.0;  // mm
    double strokeMm = 0.18;
    bool solid = false;                              // the whole tile filled with `ink` (coal)
    std::vector<std::vector<glm::dvec2>> polylines;  // stroked, mm inside the tile (x right, y down)
    std::vector<glm::dvec3> circles;                 // stroked: centre x, y and radius, mm
    std::vector<glm::dvec3> dots;                    // filled: centre x, y and radius, mm
    Rgba8 ink{25, 25, 25, 255};
};

// The tile of a lithology (None: an empty tile of size 0).
const PatternTile& patternTile(Lithology l);

// SVG <pattern id="lith-NAME"> element for `l`, in user units of `unitsPerMm` (a section
// SVG in pixels at 96 dpi: 96 / 25.4; a print SVG in millimetres: 1), userSpaceOnUse.
std::string svgPattern(Lithology l, double unitsPerMm);

// The colour labels should take over a fill: black on light fills, white on dark ones (and on coal).
Rgba8 labelInk(Rgba8 fill, Lithology l);

}  // namespace geoslice
