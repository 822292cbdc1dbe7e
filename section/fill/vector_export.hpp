// Vector export of a section: GeoJSON and SVG of the bodies' polygons (with holes and
// islands) and the surfaces' traces, with record ids, attributes and areas (m²).
//
// Sources: a plane section (section/cut/contours.hpp: plane u/v metres) or a polyline section
// (section/cut/polyline.hpp: s = chainage, z = elevation, metres). Both are 2D; each knows
// its 2D -> world mapping.
//
// GeoJSON (RFC 7946: a FeatureCollection; one Feature per body with a MultiPolygon, exterior
// rings counter-clockwise and holes clockwise in the written coordinates, first position
// repeated last; one Feature per trace with a LineString). Where the coordinates are
// (GeoJsonSpace, made by geoJsonSpace()):
//   - VectorFrame::LonLat: [lon, lat, elevation] on WGS 84, RFC 7946's only CRS, through the
//     model's CRS -> EPSG:4326 operation; no "crs" member. What GIS tools expect by default.
//   - VectorFrame::Projected: [easting, northing, elevation] in the model's CRS, with the
//     2008 "crs" member GDAL reads (urn:ogc:def:crs:EPSG::<code>, or the CRS's WKT; for a
//     model without CRS, a local engineering CRS: its own x, y, z metres).
//   - VectorFrame::Plane: [u, v] metres in the section's own 2D frame. Its "crs" member is an
//     engineering (local Cartesian) CRS in WKT, so that GDAL and QGIS read the numbers as
//     metres on a plane, never as WGS 84 degrees (a GeoJSON without "crs" is read as WGS 84).
// Every collection has a "geoslice" member stating the frame, its axes, the model's CRS
// and, for LonLat, the operation used and its accuracy.
// A world ring of a non-horizontal section is planar but not horizontal: in 2D GIS tools
// it is the section's trace, widened by its dip.
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

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/crs/crs.hpp"
#include "section/cut/contours.hpp"
#include "section/cut/polyline.hpp"
#include "section/fill/raster.hpp"
#include "section/index/section_index.hpp"

namespace geoslice {

enum class VectorFrame { Plane, Projected, LonLat };

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

// Where a GeoJSON's positions are written (see above). `position` maps a point of the
// source's 2D frame to [u, v] (Plane; z unused) or [x, y, z]; a point PROJ cannot convert
// becomes NaN and is counted in `failures` (toGeoJson and the callers' checkPositions()
// turn that into an error).
struct GeoJsonSpace {
    VectorFrame frame = VectorFrame::Plane;
    std::function<glm::dvec3(const glm::dvec2&)> position;
    nlohmann::ordered_json crsMember;  // the collection's "crs" member; null: none
    nlohmann::ordered_json meta;       // the "geoslice" member
    std::shared_ptr<std::atomic<std::size_t>> failures = std::make_shared<std::atomic<std::size_t>>(0);
    bool threeD() const { return frame != VectorFrame::Plane; }
    // Ok, or an error saying how many points could not be converted.
    Status checkPositions() const;
};

// The space for `frame`: `crs` is the model's CRS, `toLonLat` its operation to EPSG:4326 for
// LonLat and `lonLatNote` what to say about it (an accuracy caveat, or why there is none).
// Errors: LonLat on a model without CRS or without an operation.
Result<GeoJsonSpace> geoJsonSpace(const VectorSource& source, VectorFrame frame, const Crs& crs,
                                  const CrsTransform* toLonLat, const std::string& lonLatNote);

// GeoJSON FeatureCollection (see above). `index` supplies part names, records and the model.
// Error when some positions could not be converted (GeoJsonSpace::failures).
Result<nlohmann::ordered_json> toGeoJson(const SectionIndex& index, const VectorSource& source,
                                         const GeoJsonSpace& space);

// One polygon ring as GeoJSON positions, closed and wound by RFC 7946's right-hand rule in
// the written coordinates (exterior counter-clockwise, holes clockwise).
nlohmann::ordered_json geoJsonRing(const std::vector<glm::dvec2>& ring, bool exterior, const GeoJsonSpace& space);

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
