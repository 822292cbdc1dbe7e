// Executing plans on the CPU: profile views and tiles from the exact section engine, the
// documented tile grid over a section's u/v plane, and pixel queries.
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
#include "section/block_section.hpp"
#include "section/polyline.hpp"
#include "section/raster.hpp"

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

// A profile view (plane, elevation or polyline section) with the exact engine. A plane that
// misses the model gives an empty (background) image, not an error. `cancel` (may be
// null) is read at least once per image row: when set, DeadlineExceeded within milliseconds.
Result<ViewImage> renderProfile(const CatalogModel& model, const ViewPlan& plan,
                                const std::atomic<bool>* cancel = nullptr);

// A profile view's vector form: GeoJSON (coordinates in the section's 2D frame, or world
// x, y, z when `world`) or SVG (the pixel frame of the same view, so it overlays the
// image). Returns the document text.
Result<std::string> renderVector(const CatalogModel& model, const ViewPlan& plan, bool svg, bool world,
                                 const std::atomic<bool>* cancel = nullptr);

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

// A pixel query: the record at the centre of pixel (px, py) of the plan's view, the world
// point, and its place in the section. From the cached ID buffer of the identical view
// when `cached` is given, otherwise from the exact oracle at the pixel centre; the two
// agree (tests/server). Errors: OutOfRange for a pixel outside the image.
struct QueryAnswer {
    long long px = 0, py = 0;
    RecordId record = kNoRecord;
    glm::dvec3 world{0.0};
    glm::dvec2 section{0.0};     // (u, v) plane metres, or (chainage, elevation) for a line
    double distanceAlong = 0.0;  // metres: from the image's left edge (plane), or chainage (line)
    bool line = false;
    bool perspective = false;  // world = the first visible point on the ray (NaN: none); distanceAlong = from the eye
    bool fromIdBuffer = false;
    std::size_t cell = BlockModel::kNoCell;  // the block cell (blockCellAt), from the cells buffer when cached
};
// InvalidArgument naming the parameter ('plane', 'planes' or 'elevation') when the cut of a
// perspective view keeps no part of the model's bounds (api/cut.hpp).
Status checkPerspectiveCut(const CatalogModel& model, const ViewPlan& plan);
// The ray through a pixel of a perspective view: pixelRay of model/camera.hpp.
// A query that needs the model's rays (perspective, or no cached ID buffer) waits for them
// (CatalogModel::rays) as `wait` allows: DeadlineExceeded when they are not built in time.
Result<QueryAnswer> answerPixel(const CatalogModel& model, const ViewPlan& plan, long long px, long long py,
                                const ViewImage* cached, const RayWait& wait = {});
// The answer as JSON (appended to `out`): record and attributes, body, world point,
// distance along the section, CGCS2000 projected (easting, northing, zone) and geodetic
// (lon, lat, height) coordinates with their axis order named.
void writeQueryAnswer(const CatalogModel& model, const QueryAnswer& answer, std::string& out);
// answerPixel + writeQueryAnswer.
Result<std::string> queryPixel(const CatalogModel& model, const ViewPlan& plan, long long px, long long py,
                               const ViewImage* cached, const RayWait& wait = {});

// A virtual borehole: `x`, `y` (world metres; or `lon`, `lat` degrees) -> the intervals
// with from/to depth below the collar and elevation, record and attributes, and the open
// surfaces crossed. Errors name the parameter; a point outside the model is OutOfRange;
// DeadlineExceeded when the model's rays are not built within `wait`.
Result<nlohmann::ordered_json> boreholeAt(const CatalogModel& model, const Params& params, const RayWait& wait = {});

// The JSON of a world point: {x, y, z, crs, axes, projected: {...}, geodetic: {...},
// wgs84: {...} or wgs84Note} (README "Query answer coordinates").
nlohmann::ordered_json worldPointJson(const CatalogModel& model, const glm::dvec3& world);

}  // namespace geoslice::api
