// bake/: the attribute-indexed texture of paper section 2.2. A model's meshes are cut into
// charts (85-degree dihedral region growing, each chart a topological disk), each chart is
// flattened by LSCM (Levy, Petitjean, Ray, Maillot 2002, "Least squares conformal maps for
// automatic texture atlas generation"), the charts are shelf-packed into [0,1]^2 with a
// 2-texel margin at one uniform texel density, and every texel a triangle touches
// (conservative rasterization) gets the triangle's attribute record id in an R32UI texture,
// padded by one texel across chart borders (seams).
//
// Style: free functions over plain arrays, deterministic output for any thread count.
// Threads: every function may be called from any thread; bakeModel() uses its own workers.
//
// Frames: mesh positions are world (double, metres) or local (float, world - Model::origin);
// chart UVs are metres in the chart's own plane; packed UVs are texture coordinates in
// [0,1]^2 of one page, with the page index added to u (u in [page, page + 1)), so a
// one-page bake has plain [0,1]^2 UVs. Texel (x, y) of a page covers
// u in [x/W, (x+1)/W), v in [y/H, (y+1)/H); row y = 0 is the first row in memory (v = 0:
// glTF's first image row, GL's t = 0), so nearest sampling is texelFetch at layer floor(u),
// texel floor((u - layer) * W), floor(v * H).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice::bake {

// ---- 1. Charts (charts.cpp) ------------------------------------------------------------

struct ChartOptions {
    // Two triangles sharing a manifold, consistently oriented edge may join one chart when
    // their normals differ by at most this angle (the paper's 85 degrees).
    double maxDihedralDegrees = 85.0;
    // Shape bound: no triangle of a chart deviates from the chart's seed normal by more than
    // this, so every triangle projects onto the seed plane without flipping (keeps LSCM well
    // conditioned and far from folds).
    double maxConeDegrees = 80.0;
    // Size bound: triangles per chart. Growth is breadth-first from the seed, so charts are
    // compact (about round in hops).
    std::uint32_t maxTriangles = 2048;
};
// bakeModel() also cuts any chart too large for a page at PackOptions::minDensity, and any
// chart whose LSCM flips or collapses a triangle (splitTriangles, then LSCM again).

// Charts as lists of triangle indices: chart c holds triangles[offsets[c] .. offsets[c+1]).
struct Charts {
    std::vector<std::uint32_t> offsets{0};
    std::vector<std::uint32_t> triangles;
    std::size_t count() const { return offsets.size() - 1; }
};

// Welds vertices with exactly equal positions: weld[v] is the smallest vertex index with
// v's position. Deterministic. positions may hold NaN (never welded).
std::vector<std::uint32_t> weldVertices(const glm::dvec3* positions, std::size_t vertexCount);

// Splits a mesh (indices: 3 per triangle, already welded) into charts by region growing.
// Every chart is a topological disk (isTopologicalDisk): charts that are not are cut in two
// until they are. Chart order: by smallest triangle index; triangles in ascending order.
Charts buildCharts(const glm::dvec3* positions, std::size_t vertexCount, const std::uint32_t* indices,
                   std::size_t triangleCount, const ChartOptions& options = {});

// True when the triangles (indices into `indices`, 3 per triangle) form a topological disk:
// edge-connected, every vertex with at most one outgoing border half-edge (no pinches),
// one border loop, and Euler characteristic V - E + F = 1. Edges join two triangles only
// when they run opposite ways (consistent orientation).
bool isTopologicalDisk(const std::uint32_t* indices, const std::uint32_t* triangles, std::size_t count);

// Cuts a set of triangles in two at the median of their centroids along the longest axis
// of the centroids' bounds, then splits each half into edge-connected components. Every
// output part is non-empty; one triangle is returned unchanged. Appends to `out`.
void splitTriangles(const glm::dvec3* positions, const std::uint32_t* indices, const std::uint32_t* triangles,
                    std::size_t count, std::vector<std::vector<std::uint32_t>>& out);

// ---- 2. LSCM (lscm.cpp) ----------------------------------------------------------------

// One chart flattened: chart-local vertices (indices into the mesh's vertex array), their
// UVs in metres (scaled so the chart's UV area equals its 3D area), and 3 chart-local
// vertex indices per triangle, in the order of the chart's triangle list.
struct ChartUv {
    std::vector<std::uint32_t> vertices;
    std::vector<glm::dvec2> uv;
    std::vector<std::uint32_t> corners;
    std::size_t badTriangles = 0;  // flipped or degenerate in UV (relative area < 1e-9)
    double area3d = 0.0;           // m^2
};

// Least squares conformal map of one chart (a topological disk) with two pinned vertices
// (the extremes along the chart's principal axis), solved by sparse Cholesky of the normal
// equations (Eigen SimplicialLDLT). Triangles whose 3D area is zero still get corners but
// no energy term. A chart of one triangle is its exact planar layout.
ChartUv lscmChart(const glm::dvec3* positions, const std::uint32_t* indices, const std::uint32_t* triangles,
                  std::size_t count);

// Distortion of a parameterization, per triangle from the singular values s1 >= s2 of the
// 3D -> UV Jacobian (UV scaled to the model-wide area ratio): angle distortion s1/s2 (1 is
// conformal), area distortion max(s1 s2, 1/(s1 s2)) (1 keeps area). Means are weighted by
// 3D area.
struct Distortion {
    double meanAngle = 1.0, maxAngle = 1.0;
    double meanArea = 1.0, maxArea = 1.0;
};

// Sums over triangles for Distortion; add() merges charts, result() gives the means.
struct DistortionSums {
    double weight = 0.0, angle = 0.0, area = 0.0, maxAngle = 1.0, maxArea = 1.0;
    void add(const DistortionSums& o);
    Distortion result() const;
};

// Distortion of one flattened chart (uv in metres, area-normalised as lscmChart returns it).
// Triangles of zero 3D area are skipped; a collapsed UV triangle counts as distortion 1e9.
DistortionSums measureDistortion(const glm::dvec3* positions, const std::uint32_t* indices,
                                 const std::uint32_t* triangles, std::size_t count, const ChartUv& chart);

// ---- 3. Packing (pack.cpp) -------------------------------------------------------------

struct PackOptions {
    std::uint32_t width = 4096, height = 4096;  // texels per page
    std::uint32_t margin = 2;                   // empty texels between charts (and at page borders: margin / 2)
    double minDensity = 0.02;                   // texels per metre below which more pages are used
    std::uint32_t maxPages = 16;                // texture budget: more pages than this is an error
};

// A chart's cell rectangle on a page, in texels. The chart's UV bounds map to
// [x + 0.5, x + 0.5 + extent * density] (same in y), so each rectangle has half a texel of
// slack on every side for float rounding.
struct Placement {
    std::uint32_t page = 0, x = 0, y = 0, w = 0, h = 0;
};

struct Packing {
    double density = 0.0;  // texels per metre, the same for every chart
    std::uint32_t pages = 0;
    std::vector<Placement> placements;  // one per chart, input order
};

// Cells a chart of `extent` metres occupies at `density`: ceil(extent * density + 1).
std::uint32_t chartCells(double extent, double density);

// Shelf packing (charts sorted by height, tallest first, ties by index; left to right,
// shelves bottom to top, pages in order) at the largest uniform density that fits one page;
// when that density is below minDensity, at minDensity on as many pages as needed. Errors:
// OutOfRange when a chart cannot fit a page at minDensity or more than maxPages are needed.
Result<Packing> packCharts(const glm::dvec2* extents, std::size_t count, const PackOptions& options);

// The incremental re-bake's packer (rebakePart): places `count` charts of `extents` metres at
// `density` into the free space of an existing packing of `placedCount` rectangles on `pages`
// pages made by packCharts with the same options, or by packCharts and earlier calls of this.
// Free space: the rectangles of the charts with replaced[c] != 0, the room above charts
// shorter than their shelf, the ends of shelves and the top of each page; first fit, tallest
// chart first (ties by index), guillotine splits, a place taken only where it keeps
// options.margin from every chart that stays and every chart placed before it; when that is
// full, new pages (within options.maxPages). Charts not replaced keep their rectangles.
// Result: the new charts' placements (input order), `pages` = the page count after, `density`.
// Errors: OutOfRange when more than options.maxPages pages would be needed or a chart is larger
// than a page ("its new charts do not fit ..."; the caller names the part).
Result<Packing> packIntoFreeSpace(const Placement* placed, const std::uint8_t* replaced, std::size_t placedCount,
                                  std::uint32_t pages, const glm::dvec2* extents, std::size_t count, double density,
                                  const PackOptions& options);

// ---- 4. Index texture (raster.cpp) -----------------------------------------------------

// Conservative rasterization: sets mask[y * w + x] = 1 for every texel cell [x,x+1]x[y,y+1]
// of a w x h grid that the closed triangle (texel coordinates) touches, including zero-area
// triangles (a segment or a point). Separating-axis test per cell of the bounding box.
void rasterizeConservative(const glm::dvec2 tri[3], std::uint8_t* mask, std::uint32_t w, std::uint32_t h);

// Seam padding: every unset cell with a set 8-neighbour is set (one texel of dilation).
void dilateMask(std::uint8_t* mask, std::uint32_t w, std::uint32_t h);

// ---- 5. Spatially varying attributes (field.cpp) ----------------------------------------

// A block model: axis-aligned blocks (world centre and size, metres) with one value each, e.g.
// ore grade. Blocks may differ in size (sub-blocks); where blocks overlap, the smallest wins.
struct BlockModel {
    std::string name;  // the value column's header, e.g. "SiO2_pct"
    std::vector<glm::dvec3> centres, sizes;
    std::vector<double> values;
};

// CSV with a header row naming x,y,z (block centre, world: easting, northing, elevation),
// dx,dy,dz (block size) and exactly one more column, the value; any column order, ',' or ';'.
// Read by the project's one block CSV reader (model/blocks/block_model.hpp readBlockRows); sizes may
// differ here (sub-blocks). Errors name the source and line: a missing column, a
// non-number, a non-finite or empty value or a size <= 0.
Result<BlockModel> parseBlockCsv(std::string_view text, const std::string& source);

// Grade classes of a field: class k holds values in [breaks[k-1], breaks[k]) (class 0 below
// breaks[0], the last class from breaks.back() up). breaks must be finite and increasing.
// Two sources, at most one per bake:
// - blocks: a texel's value is that of the block holding its point (see BakedModel);
// - vertexProperty: a per-vertex property (Mesh::propertyNames, e.g. a TSurf PVRTX column
//   "grade"): a texel's value is interpolated barycentrically from its triangle's three vertex
//   values (the source mesh's vertices, before welding) at the texel centre's point on its
//   nearest triangle. Parts without the property, and NaN (no-data) values, keep the part's
//   record. A name no part has is an InvalidArgument error that lists the known names.
struct FieldOptions {
    const BlockModel* blocks = nullptr;  // none (and no vertexProperty): one record per part
    std::string vertexProperty;          // empty: none
    std::vector<double> breaks;
    std::string unit;  // e.g. "% SiO2", copied into the class records' gradeUnit
    bool enabled() const { return blocks != nullptr || !vertexProperty.empty(); }
};

// ---- Whole-model bake (bake.cpp) -------------------------------------------------------

struct BakeOptions {
    ChartOptions charts;
    PackOptions pack;
    FieldOptions field;
    unsigned threads = 0;  // 0: hardware concurrency
};

// One part of the baked mesh: vertices split along chart borders.
struct BakedPart {
    std::size_t source = 0;  // index into the model's bodies, then surfaces (bodies.size() + i)
    std::string name;
    PartKind kind = PartKind::Body;
    RecordId record = kNoRecord;
    std::vector<glm::vec3> positions;  // local frame (world - origin), metres
    // What float32 lost: local = double(positions[i]) + double(positionsLo[i]) to ~1e-7 of
    // the float step, so vertices a fraction of a millimetre apart stay apart 100 km from
    // the origin (writePackage stores them where float32 alone would merge vertices).
    std::vector<glm::vec3> positionsLo;
    std::vector<glm::vec2> uvs;  // page + u, v (see the header comment)
    std::vector<std::uint32_t> indices;
};

struct BakeStats {
    std::size_t triangles = 0, charts = 0, splitCharts = 0, vertices = 0;
    double texelUtilisation = 0.0;  // texels holding an id / all texels of all pages
    Distortion distortion;
    double secondsCharts = 0, secondsLscm = 0, secondsPack = 0, secondsRaster = 0;
};

// Where one chart went: its part (index into BakedModel::parts), its cell rectangle, its
// distortion sums (kept for incremental re-bakes).
struct ChartSlot {
    std::uint32_t part = 0;
    Placement rect;
    DistortionSums distortion;
};

struct BakedModel {
    std::vector<BakedPart> parts;  // bodies then surfaces, as in the model; empty parts skipped
    std::uint32_t width = 0, height = 0, pages = 0;
    std::vector<std::uint32_t> texels;  // pages * height * width, row-major, 0 = no geology
    double density = 0.0;               // texels per metre
    std::vector<ChartSlot> charts;
    PackOptions pack;  // the options it was packed with
    // With a field: one record per (part record, class), ids from the model table's nextId()
    // up (record r's classes in order; with a vertex property, only the records of parts that
    // have it). A texel's point is its centre mapped back onto its nearest triangle. Blocks: a
    // texel whose point lies in a block holds the record of its part's record and that block's
    // class. Vertex property: a texel whose interpolated value is a number holds the record of
    // its part's record and that value's class. Other texels hold their part's record.
    // writePackage() adds these records to the attribute table.
    std::vector<AttributeRecord> fieldRecords;
    BakeStats stats;
};

// Stage name ("charts", "lscm", "pack", "raster") and fraction done in [0, 1]; called from
// the calling thread only.
using ProgressFn = std::function<void(std::string_view stage, double fraction)>;

// Errors: InvalidArgument (bad options, non-finite positions, indices out of range),
// OutOfRange (the model does not fit the texture budget; the message says what to change).
Result<BakedModel> bakeModel(const Model& model, const BakeOptions& options = {}, const ProgressFn& progress = {});

// Incremental re-bake (the paper's future work): re-bakes only baked.parts[part] from the
// model's current geometry and record for it (model.bodies, then model.surfaces, index
// BakedPart::source). Its old texels are cleared, its charts are built and flattened again
// and placed at the bake's density into free space: the rectangles its old charts held, the
// free room above shorter charts in each shelf, the ends of shelves and the top of each page
// (first fit, tallest first, guillotine splits), and when that is full, on new pages (within
// PackOptions::maxPages; a full bake compacts again). Other parts' UVs and texels do not
// change. Errors: InvalidArgument (bad part index, bad geometry), OutOfRange when the new
// charts need more than maxPages pages, Unsupported for bakes with a field (either source). On error `baked`
// is unchanged.
// `options` gives the chart options and threads; page size, margin and budget are baked.pack.
Status rebakePart(const Model& model, std::size_t part, BakedModel& baked, const BakeOptions& options = {});

// ---- 6. Attribute mapping accuracy (accuracy.cpp) ----------------------------------------

// One part's UV mesh as the sampler reads it: 2 floats per vertex (page + u, v), 3 vertex
// indices per triangle, and the record its texels should hold.
struct UvPart {
    const float* uvs = nullptr;
    const std::uint32_t* indices = nullptr;
    std::size_t indexCount = 0;
    RecordId record = kNoRecord;
};

struct IdAccuracy {
    std::size_t points = 0, correct = 0;
    double fraction() const { return points ? double(correct) / double(points) : 0.0; }
};

// The paper's "attribute mapping accuracy" of a per-body bake: about `points` random surface
// points, spread over the parts in proportion to their triangles (ceil(points x t / total),
// at least one per part with triangles); per point a uniform triangle of its part, then
// uniform barycentrics (r1 + r2 > 1 folded back), the UV interpolated in float as a GPU does;
// a point is correct when the nearest texel (fetchId) holds its part's record. Deterministic
// for a seed. The benchmark's figure and the tests' 100 % come from this one function.
IdAccuracy sampleIdAccuracy(const UvPart* parts, std::size_t count, const std::uint32_t* texels, std::uint32_t width,
                            std::uint32_t height, std::uint32_t pages, std::size_t points, std::uint64_t seed);
// Over every part of a fresh bake, or of a loaded package (bake/package.hpp).
IdAccuracy sampleIdAccuracy(const BakedModel& baked, std::size_t points, std::uint64_t seed);
struct Package;
IdAccuracy sampleIdAccuracy(const Package& package, std::size_t points, std::uint64_t seed);

// The same for baked part `p` alone (`samples` points): the accuracy a re-bake keeps.
double partIdAccuracy(const BakedModel& baked, std::size_t p, std::size_t samples, std::uint64_t seed);

// The record id stored at a texture coordinate (page + u, v), nearest texel; 0 outside.
RecordId fetchId(const std::uint32_t* texels, std::uint32_t width, std::uint32_t height, std::uint32_t pages,
                 glm::dvec2 uv);

}  // namespace geoslice::bake
