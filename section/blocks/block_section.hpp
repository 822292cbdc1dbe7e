// Block models on sections (issue 15 items 1-2): the colour classes of a block property,
// each cell's exact intersection with a section plane (a convex polygon in plane u/v), and
// that polygon clipped to a body's section region (the cell's part inside the body).
//
// Cell ∩ plane, for each cell shape of model/blocks/block_model.hpp:
//  - Box: a box in the block model's grid frame; the plane crosses at most 6 of its 12
//    edges, and the crossing points, ordered around their mean, are the convex polygon
//    (counter-clockwise in u/v). Cells are visited column by column along the grid axis most
//    parallel to the normal, so the work is the cells cut.
//  - Hexahedron (SGrid): the cell is the union of its six tetrahedra (block_model.hpp), so its
//    cut is the union of their cuts: one convex polygon (triangle or quadrilateral) per
//    tetrahedron the plane crosses, the cell's polygons consecutive in the list. The cut of a
//    curvilinear cell is in general not convex; its tetrahedra's polygons tile it exactly
//    (shared edges give bit-identical points). The locator (model/blocks/cell_locator.hpp) finds
//    the cells whose bounds the plane crosses.
//
// Clipping to a body: the body's region (its section polygons, holes and nested bodies
// included: section/cut/contours.hpp) is clipped ring by ring against the convex cell polygon
// (Sutherland-Hodgman, one half-plane per cell edge). Each clipped ring keeps its
// orientation, so the even-odd / winding union of the clipped rings is exactly region ∩
// cell (rings may carry zero-width spurs along the cell's edges, which add no area and no
// pixel centres).
//
// Pixels: the raster path (api/view.cpp) colours a pixel by the cell holding its centre
// (BlockModel::cellAt: the cell whose tetrahedron holds it, for hexahedra) when its ID-buffer
// record is a clipping body's: the point sampling of these same polygons, with the ID
// buffer's rule for the body. Along a row of a plane's pixels the cells (boxes, or the
// tetrahedra of hexahedra) are walked as spans (section/blocks/block_raster.cpp), with cellAt's
// answer at every pixel. Thread-safety: pure functions.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/attributes.hpp"
#include "model/blocks/block_model.hpp"
#include "model/model.hpp"
#include "model/result.hpp"
#include "section/cut/contours.hpp"
#include "section/cut/polyline.hpp"
#include "section/fill/raster.hpp"
#include "section/fill/vector_export.hpp"
#include "section/index/section_index.hpp"

namespace geoslice {

// Named colour ramps: "viridis" (default), "magma", "greys", "spectral" (low red, high blue
// reversed: low blue .. high red). Colours at t in [0, 1], interpolated in sRGB between the
// ramp's published key colours (matplotlib's viridis / magma, ColorBrewer Greys / Spectral).
const std::vector<std::string_view>& rampNames();
bool isRampName(std::string_view name);
Rgba8 rampColour(std::string_view ramp, double t);

// The classes of a property: class k holds values in [breaks[k-1], breaks[k]) (class 0 below
// breaks[0], the last from breaks.back() up); class k of n = breaks.size() + 1 has the ramp's
// colour at t = k / (n - 1) (t = 0.5 when n = 1).
struct PropertyClasses {
    int property = -1;  // index into BlockModel::properties
    std::string ramp = "viridis";
    std::vector<double> breaks;  // finite, strictly increasing
    std::vector<Rgba8> colours;  // breaks.size() + 1

    int classOf(double value) const;  // -1 for NaN (no value)
    // Class k's range as text, the one form of every legend: "< b0", "b0 - b1", ..., ">= bn"
    // (%g numbers), "all values" with no breaks.
    std::string label(std::size_t k) const;
    Rgba8 colourOf(double value) const { return colours[std::size_t(classOf(value))]; }
};
// Checks the breaks (finite, increasing, at most 64) and fills the colours.
Result<PropertyClasses> makePropertyClasses(int property, std::string ramp, std::vector<double> breaks);
// Five classes of equal width over the property's finite values (the default breaks).
std::vector<double> defaultBreaks(const BlockProperty& property);
// The classes of property `name` of `blocks` (breaks: nullopt = defaultBreaks). Errors
// (InvalidArgument): no such property (the known ones listed), bad ramp or breaks.
Result<PropertyClasses> propertyClasses(const BlockModel& blocks, const std::string& name, const std::string& ramp,
                                        const std::optional<std::vector<double>>& breaks);

// Every cell's class as one byte for GPU textures (renderer/passes/block_texture.hpp): 0 = no value,
// k + 1 = class k (classOf). At most 64 breaks, so it fits.
std::vector<std::uint8_t> cellClassIndex(const BlockModel& blocks, const PropertyClasses& classes);

// Sorted records of the bodies that clip `blocks` (BlockModel::clipBodyIndex) in `model`.
std::vector<RecordId> blockClipRecords(const Model& model, const BlockModel& blocks);

// A stretch of every row's pixels, columns [begin, end), along which worldAt(i, j) is affine
// in i, up to rounding, with `step` world metres per pixel: a plane's whole row
// (PixelFrame::worldPerPixelX), or a polyline section's columns on one leg.
struct RowLine {
    int begin = 0, end = 0;
    glm::dvec3 step{0.0};
};
// The RowLines of a polyline section's image: columns grouped by the leg SectionLine::legAt
// gives their chainage s(i) = chainageAt(i) (the same s as its worldAt's), the leg's map
// direction times `pixelChainage` (metres of s per pixel) as the step.
std::vector<RowLine> polylineRowLines(const SectionLine& line, const std::function<double(int)>& chainageAt, int width,
                                      double pixelChainage);

// The raster rule (see above): for each pixel whose ids[] record is in `clipRecords`, the
// cell holding worldAt(i, j) (the pixel centre, world) goes to cells[] as cell + 1 (0: none)
// and, where the cell has a value, its class colour to rgba[] (opaque). rgba and cells may
// be null. Pixel (i, j) is index j * width + i. `rowLines` (may be empty): where worldAt is
// affine along rows; there the cells are walked on those lines and worldAt is called only
// near cell faces (section/blocks/block_raster.cpp), with the same answer at every pixel; elsewhere
// cellAt is asked at every pixel. worldAt is called from the calling thread and its partner
// thread (section/cut/partner_thread.hpp): it must be safe to call concurrently.
void colourPixelsByBlocks(const BlockModel& blocks, const PropertyClasses& classes,
                          const std::vector<RecordId>& clipRecords, const std::function<glm::dvec3(int, int)>& worldAt,
                          int width, int height, const std::uint32_t* ids, std::uint8_t* rgba, std::uint32_t* cells,
                          const std::vector<RowLine>& rowLines = {});

// One cell's intersection with a plane (Box), or one tetrahedron's of it (Hexahedron): a
// convex polygon in plane u/v, counter-clockwise.
struct CellPolygon {
    std::size_t cell = 0;  // BlockModel linear index
    Ring ring;
};

// Every cell the plane of `frame` crosses in more than a point or an edge, with a polygon of
// positive area; only cells whose polygon's bounding box meets `limit` (u/v metres) when
// given. At most `maxCells` polygons (then OutOfRange naming the count).
Result<std::vector<CellPolygon>> cellPolygons(const BlockModel& blocks, const SectionFrame& frame,
                                              const FrameRect* limit = nullptr, std::size_t maxCells = 4000000);

// `subject` clipped to the convex counter-clockwise polygon `clip` (Sutherland-Hodgman); the
// result keeps the subject's orientation and may be empty.
Ring clipRingToConvex(const Ring& subject, const Ring& clip);

// A cell's part of a clipping body's section region (one per cell and body: a hexahedral
// cell's tetrahedra's pieces are merged into it, their rings abutting along the
// tetrahedra's shared faces' traces; drawn as one path, they show no seam).
struct BlockPiece {
    std::size_t cell = 0;
    std::uint32_t body = 0;  // Model::bodies index
    RecordId record = kNoRecord;
    std::vector<Ring> rings;  // clipped outer rings (ccw) and holes (cw): region ∩ cell
    double area = 0.0;        // m², the signed sum of the rings' areas
};

// The pieces of every cut cell inside every clipping body of `section` (blocks.clipBodyIndex),
// cells with no value in any property included (their properties are NaN). Pieces of zero
// area are dropped.
Result<std::vector<BlockPiece>> blockPieces(const BlockModel& blocks, const Section& section,
                                            const FrameRect* limit = nullptr);

// The same for a polyline section, in line coordinates (s, z): each cut leg's cells (cell ∩
// the leg's plane, u shifted by the leg's uOffset) clipped to the leg's chainage strip
// [s0, s1] (a strip of a convex polygon is convex), then the bodies' rings clipped to them
// as above. A cell crossed by two legs gives a piece per leg. `modelOrigin` is the
// section index's origin (the legs' SectionFrames).
Result<std::vector<BlockPiece>> blockPieces(const BlockModel& blocks, const PolylineSection& section,
                                            const glm::dvec3& modelOrigin, const FrameRect* limit = nullptr);

// SVG paths of the pieces (one per piece, even-odd fill in its class colour; pieces whose
// cell has no value are left out so the body's own fill shows), in the pixel frame of `rect`
// like toSvg (section/fill/vector_export.hpp), with data-cell="i,j,k", data-record and a <title>
// naming the value.
std::string blockPiecesSvg(const BlockModel& blocks, const PropertyClasses& classes,
                           const std::vector<BlockPiece>& pieces, const FrameRect& rect, int width, int height);
// GeoJSON features of the pieces (kind "block": cell [i, j, k], body part, record, area_m2,
// every property's value, the class and its colour), rings in `space` (vector_export.hpp).
nlohmann::ordered_json blockPiecesGeoJson(const BlockModel& blocks, const PropertyClasses& classes,
                                          const std::vector<BlockPiece>& pieces, const GeoJsonSpace& space);

}  // namespace geoslice
