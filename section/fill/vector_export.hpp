// Vector export of a section: GeoJSON and SVG of the bodies' polygons (with holes and
// islands) and the surfaces' traces, with record ids, attributes and areas (m²).
//
// Sources: a plane section (section/cut/contours.hpp: plane u/v metres) or a polyline section
// (section/cut/polyline.hpp: s = chainage, z = elevation, metres). Both are 2D; each knows
// its 2D -> world mapping.
//
// GeoJSON (RFC 7946 structure: a FeatureCollection; one Feature per body with a
// MultiPolygon, exterior rings counter-clockwise and holes clockwise, first position
// repeated last; one Feature per trace with a LineString). Coordinates are either
//   - VectorFrame::Plane: [u, v] in the section's own 2D frame (metres), or
//   - VectorFrame::World: [x, y, z] in the model's CRS (easting, northing, elevation,
//     metres), NOT WGS84 longitude/latitude as RFC 7946 assumes; the collection carries
//     "crs" (the 2008 GeoJSON member, naming the EPSG code when the model has one) and a
//     "geoslice" object that states the frame. A world ring of a non-horizontal section is
//     planar but not horizontal: use the plane frame for 2D GIS tools.
// Feature properties: kind ("body"/"trace"), part (index into the model's bodies or
// surfaces), name, record, area_m2 (bodies: the polygons' area, holes and nested bodies
// subtracted), and "attributes" (the record's full attribute object, or null).
//
// SVG: one <path> per body (fill-rule evenodd, the record's colour, data-record and
// data-part attributes, a <title> with name, record and area) and one <polyline> per
// trace, in the pixel frame of a FrameRect (x right, y down), so an SVG of the same
// rectangle and size overlays the raster image pixel for pixel.
// Thread-safety: pure functions.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "section/cut/contours.hpp"
#include "section/cut/polyline.hpp"
#include "section/fill/raster.hpp"
#include "section/index/section_index.hpp"

namespace geoslice {

enum class VectorFrame { Plane, World };

// What to export: polygons and traces in a 2D frame plus its mapping to world.
struct VectorSource {
    const std::vector<BodySection>* bodies = nullptr;
    const std::vector<SectionTrace>* traces = nullptr;
    std::function<glm::dvec3(const glm::dvec2&)> toWorld;  // 2D (metres) -> world
    std::string axes;                                      // what the 2D axes are, for the output
    // SVG elements drawn over the bodies and under the traces (block cells: section/blocks/block_section.hpp).
    std::string svgOverBodies;
};

// The source views keep pointers into `section`: it must outlive them.
VectorSource vectorSource(const Section& section);
VectorSource vectorSource(const PolylineSection& section);

// GeoJSON FeatureCollection (see above). `index` supplies part names, records and the model.
nlohmann::ordered_json toGeoJson(const SectionIndex& index, const VectorSource& source, VectorFrame frame);

// What the SVG draws over the bodies' fills (section/fill/patterns.hpp, section/fill/labels.hpp):
// lithology patterns as <pattern> elements filling a second <path> per body whose record's
// lithology is known (class "lith"), and unit codes as <text> elements (class "unit-label",
// data-record, on a box of the unit's colour that hides the pattern under the text).
struct SvgOverlays {
    bool patterns = true;
    bool labels = false;    // off: the plain SVG stays an overlay of the image
    double labelPx = 12.0;  // font size of the labels, pixels
    // Advance width of a label at a size (pixels); empty: estimateTextWidth (errs wide).
    std::function<double(const std::string& text, double size)> textWidth;
};

// SVG document of width x height pixels showing `rect` (2D frame of the source).
// Errors: those of checkFrame.
Result<std::string> toSvg(const SectionIndex& index, const VectorSource& source, const FrameRect& rect, int width,
                          int height, const RasterOptions& options = {}, const SvgOverlays& overlays = {});

}  // namespace geoslice
