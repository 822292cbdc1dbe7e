// Executing plans on the CPU: profile views from the exact section engine (images and their
// vector form), their pixel -> world mapping, and colouring by a block model. The tile grid
// is in api/tile_grid.hpp, pixel queries in api/pixel_query.hpp, boreholes in api/borehole.hpp.
//
// Pixel frames: column x to the right, row y downwards, row 0 at the top; pixel (x, y)
// stands for its centre (x + 0.5, y + 0.5), which is where ID buffers are sampled.
// Pure functions of (model, plan), any thread (the model is immutable).
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "api/plan.hpp"
#include "model/result.hpp"
#include "section/blocks/block_section.hpp"
#include "section/cut/polyline.hpp"
#include "section/fill/raster.hpp"

namespace geoslice::api {

// Pixel -> section coordinates -> world of a profile view or tile, computed from the plan
// alone (no cut), so that a cached image and a fresh query agree exactly.
struct PixelMapping {
    Geometry geometry = Geometry::Plane;
    PixelFrame planar;  // Plane and Elevation: plane u/v metres
    SectionLine line;   // Line: chainage s and elevation z play u and v
    FrameRect rect;     // the frame in section coordinates (u/v or s/z), metres
    int width = 0, height = 0;

    // Section coordinates (u, v) or (s, z) of the centre of pixel (i, j).
    glm::dvec2 sectionAt(int i, int j) const;
    glm::dvec3 worldAt(int i, int j) const;
};
Result<PixelMapping> profileMapping(const CatalogModel& model, const ViewPlan& plan);

// A rendered view: colour, record ids and the pixel -> world map.
struct ViewImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;  // straight alpha, row 0 at the top
    std::vector<std::uint32_t> ids;  // record ids, 0 = no geology
    // Views coloured by a block property (SectionDef::colour): the block cell at each pixel
    // centre + 1 where the pixel's record is a clipping body's, else 0; empty otherwise.
    std::vector<std::uint32_t> cells;
    std::optional<PixelMapping> mapping;  // profile views and tiles: exact pixel -> world
    double renderMs = 0.0;
    std::size_t bytes() const { return rgba.size() + ids.size() * 4 + cells.size() * 4 + sizeof(ViewImage); }
};

// The colour classes a section's `colour=` asks for, against the model's block model;
// nullopt when the section is not coloured. Errors (InvalidArgument, naming the parameter):
// the model has no block model, no such property (the known ones are listed), bad breaks.
Result<std::optional<PropertyClasses>> blockClasses(const CatalogModel& model, const SectionDef& def);
// The block cell (BlockModel linear index) at world point `world` whose record is `record`:
// BlockModel::kNoCell when the model has no block model, the record is not a clipping
// body's, or the point is outside the grid. The one rule that both the image and the query use.
std::size_t blockCellAt(const CatalogModel& model, RecordId record, const glm::dvec3& world);
// Colours every pixel whose record is a clipping body's by the class of the cell at its
// centre (cells with no value keep the body's colour) and fills `image.cells`.
void colourByBlocks(const CatalogModel& model, const PropertyClasses& classes, const PixelMapping& mapping,
                    ViewImage& image);

// The exact cell pieces of a perspective view's cut faces, for the GL renderer
// (renderer/passes/block_caps.hpp; what it draws for block models with curvilinear cells, whose
// cells a 3D texture cannot address): for each plane of `planes` (world, in the view's
// order), the cut of every tetrahedron of every cell it crosses (section/blocks/block_section.hpp
// cellPolygons: the profile engine's own polygons) near the clipping bodies (their bounds'
// shadow on the plane), fanned into triangles in the model's local frame (world -
// Model::origin, float32), each vertex with (cell + 1, class: 0 = no value, k + 1 = class k).
// Per plane the triangles of cells with a value come first. Errors: OutOfRange when a plane
// crosses more than `maxPieces` tetrahedra (named).
struct BlockCapTriangles {
    std::vector<glm::vec3> positions;   // 3 per triangle
    std::vector<glm::uvec2> cellClass;  // per vertex
    struct Range {
        std::uint32_t first = 0, valued = 0, unvalued = 0;  // vertices
    };
    std::vector<Range> planes;
    double cutMs = 0.0;  // wall clock of the cuts
};
Result<BlockCapTriangles> blockCapTriangles(const Model& model, const PropertyClasses& classes,
                                            const std::vector<Plane>& planes, std::size_t maxPieces = 4000000);

// A profile view (plane, elevation or polyline section) with the exact engine. A plane that
// misses the model gives an empty (background) image, not an error. `cancel` (may be
// null) is read at least once per image row: when set, DeadlineExceeded within milliseconds.
Result<ViewImage> renderProfile(const CatalogModel& model, const ViewPlan& plan,
                                const std::atomic<bool>* cancel = nullptr);

// A profile view's vector form: GeoJSON (in `frame`: section/fill/vector_export.hpp), SVG
// (the pixel frame of the same view, so it overlays the image) or DXF (Plane or Projected:
// section/fill/dxf_export.hpp; no block cells, no drillholes). Returns the document text.
enum class VectorFormat { GeoJson, Svg, Dxf };
Result<std::string> renderVector(const CatalogModel& model, const ViewPlan& plan, VectorFormat format,
                                 VectorFrame frame, const std::atomic<bool>* cancel = nullptr);

}  // namespace geoslice::api
