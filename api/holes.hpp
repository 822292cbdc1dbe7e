// Drillholes drawn on profile views (plane, polyline and elevation sections; images, tiles,
// SVG, GeoJSON, print sheets) and found by pixel queries. The model's drillhole database
// (CatalogModel::drillholes) is projected onto the section by section/holes/hole_section.hpp
// within the window SectionDef::holes.window (holes=W metres, default 50; 0: none).
//
// How a hole is drawn (one rule for PNG, SVG and print):
//  - the part IN FRONT of the section (offset < 0: between the viewer and the cut face) solid
//    and wide, the part BEHIND it dashed, thinner and lighter;
//  - where the hole pierces the section, a white disc ringed in black;
//  - its id at its shallowest drawn point, with a collar mark (a triangle) when that is the
//    collar;
//  - without holecolour= the trace is near-black on a white casing; with holecolour=COL each
//    interval of COL's table takes its class colour on a dark casing (text columns: one
//    colour per category, the model body's colour where the category is a unit's name,
//    record name or lithology, else a fixed qualitative palette; number columns: the classes
//    of holebreaks= on holeramp=, default five equal classes over the column's range, as
//    block properties are coloured), and depths without an interval are grey.
// Pixel frames as api/view.hpp. Pure functions of (model, plan), any thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "api/json_writer.hpp"
#include "api/plan.hpp"
#include "print/map_frame.hpp"
#include "print/sheet.hpp"
#include "section/blocks/block_section.hpp"
#include "section/holes/hole_section.hpp"

namespace geoslice::api {

struct PixelMapping;
struct ViewImage;

constexpr double kHoleQueryPixels = 4.0;  // a pixel query answers a hole drawn this close (pixels)

// How intervals are coloured (holecolour=), resolved against the model's database.
struct HoleStyle {
    const IntervalTable* table = nullptr;  // null: one colour, no column
    int column = -1;                       // index into table->columns
    bool numeric = false;
    std::vector<std::string> categories;  // text columns: sorted
    std::vector<Rgba8> categoryColours;
    std::optional<PropertyClasses> classes;  // number columns
    // The colour of interval i of `table`; nullopt for a blank cell.
    std::optional<Rgba8> colourOf(std::size_t interval) const;
};

// Errors (InvalidArgument naming 'holecolour' / 'holebreaks' / 'holeramp'): a column asked of
// a model without drillholes, no such column (the known ones listed), bad breaks.
Result<HoleStyle> holeStyle(const CatalogModel& model, const HoleDrawing& drawing);
// {"table", "column", "unit", "kind": "categories"|"classes", "entries": [{"label", "colour"}]}
// or null when not coloured by a column.
nlohmann::ordered_json holeLegendJson(const HoleStyle& style);

// A section's holes: the projection and how to colour it. Empty when the model has no
// drillholes or holes=0.
struct ViewHoles {
    HoleSection section;
    HoleStyle style;
    bool empty() const { return section.pieces.empty() && section.labels.empty(); }
};
Result<ViewHoles> viewHoles(const CatalogModel& model, const SectionDef& def, const PixelMapping& mapping);

// Draws the holes over a rendered profile image (ViewImage::rgba, straight alpha), with cairo.
void drawHoles(const CatalogModel& model, const ViewHoles& holes, const PixelMapping& mapping, ViewImage& image);
// The holes as an SVG group in the view's pixel frame (inserted before </svg>).
std::string holesSvg(const CatalogModel& model, const ViewHoles& holes, const PixelMapping& mapping);
// The holes as GeoJSON features: LineStrings (one per piece and interval, properties hole,
// from, to, side front|behind, offset range, and the interval's table and columns), Points
// for pierces (hole, depth) and labels (hole, depth, collar). Coordinates: section 2D
// (u, v or s, z) or, with `toWorld`, world x, y, z of the projected points (on the plane).
std::vector<nlohmann::ordered_json> holesGeoJson(const CatalogModel& model, const ViewHoles& holes,
                                                 const std::function<glm::dvec3(const glm::dvec2&)>* toWorld);

// The holes on a print sheet (print/section_sheet.hpp SheetOptions::overlay): the same marks
// in page millimetres (lines 0.5 / 0.3 mm, dashes 1.5 mm, pierce discs 1 mm across, ids 6 pt),
// clipped to the map box.
void addHolesToSheet(const CatalogModel& model, const ViewHoles& holes, const print::MapFrame& frame,
                     print::Sheet& sheet);

// A pixel query's drillhole: the drawn hole nearest to pixel point (x, y) (pixel frame,
// fractional) within `radiusPx`.
struct HoleHit {
    std::uint32_t hole = 0;
    double depth = 0.0;       // m along the hole at the nearest drawn point
    double distancePx = 0.0;  // from the queried point to the drawn trace
    double offset = 0.0;      // m from the section, positive behind (kept side)
    glm::dvec3 world{0.0};    // the hole's own world point at `depth`
};
std::optional<HoleHit> holeNearPixel(const CatalogModel& model, const ViewHoles& holes, const PixelMapping& mapping,
                                     double x, double y, double radiusPx = kHoleQueryPixels);
// "drillhole": {id, depth, distancePx, offset, side, world, intervals: [{table, from, to,
// columns: {...}}]} (every interval table's interval at that depth).
void writeHoleHit(JsonWriter& w, const CatalogModel& model, const HoleHit& hit);

}  // namespace geoslice::api
