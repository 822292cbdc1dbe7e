// Block models: a regular grid of cells with one value per cell and property (ore grade,
// density, ...), attached to a model and clipped by its bodies (issue 15 item 1).
//
// Grid frame: cell (i, j, k) is the half-open box
//   origin + a axis[0] + b axis[1] + c axis[2],  a in [i size[0], (i+1) size[0]), b, c alike,
// with orthonormal `axis` vectors (world x, y, z for a CSV; a Voxet's step directions), so a
// world point p has grid coordinates g_a = (p - origin) . axis[a]. World metres throughout.
//
// Clipping: a block property counts only inside the bodies named by `clipBodies` (all closed
// bodies when empty): the section draws it there (cell ∩ plane ∩ body), the pixel query
// answers it there, and grade-tonnage tables use the cell ∩ body volumes.
//
// Sources:
//  - CSV (readBlockRows / blockModelFromCsv): a header row naming x, y, z (cell centre,
//    world), dx, dy, dz (cell size) and one or more property columns, any order, ',' or
//    ';' separated (RFC 4180 quoting, model/text_scan.hpp csvRecord). A property header may
//    carry its unit in brackets: "grade [g/t Au]" (name "grade", unit "g/t Au"). Rows must
//    lie on one regular grid: every size equal to the first row's, every centre on the
//    lattice; cells not listed have no value (NaN). An empty field is no value too.
//  - A GOCAD Voxet already in Model::grids (blockModelFromGrid): point samples become cell
//    centres (cells of the step size around them), cell-centred properties keep their cells;
//    steps must be orthogonal.
//  - A GOCAD SGrid already in Model::grids (blockModelFromGrid): a curvilinear grid whose
//    cells are the hexahedra between its points; properties must be on cells
//    (PROP_ALIGNMENT CELLS).
//
// Cell shapes (the one place that says what a cell is; consumers ask the BlockModel):
//  - CellShape::Box (CSV, Voxet): the half-open boxes above. O(1) cellAt; sections, volumes
//    and the GL texture work on the box directly.
//  - CellShape::Hexahedron (SGrid): cell (i, j, k) has the 8 corner points
//    corners[corner(i + di, j + dj, k + dk)], d in {0, 1}. A curvilinear cell's faces are
//    bilinear patches, in general NOT planar, so the cell is DEFINED here as the union of six
//    tetrahedra about its diagonal from corner 000 to corner 111 (the Kuhn / Freudenthal
//    split: for each order (a, b, c) of the three axes the tetrahedron 000, e_a, e_a + e_b,
//    111). Every quad face is split by its diagonal from its lowest to its highest corner in
//    both cells that share it, so neighbours' tetrahedra meet face to face: the cells tile
//    their union with no gap and no overlap. The tetrahedra decide every answer: a section
//    draws the union of their cuts, a point is in the cell whose tetrahedron holds it, volumes
//    are tetrahedron ∩ body. On a grid of boxes the six tetrahedra fill each box exactly, so
//    an SGrid whose points are a regular lattice gives the Box answers (the tests' oracle).
//    Every tetrahedron must have a positive volume in the grid's orientation (cells inverted,
//    flat or with non-finite points are refused, naming the cell).
// Pure functions; a BlockModel is immutable once attached (any thread may read it).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "model/result.hpp"

namespace geoslice {

struct Model;
struct Grid;
struct Aabb;
class CellLocator;

enum class CellShape { Box, Hexahedron };

// The tetrahedra of a cell's split (see above): corner numbers 0..7, bit 0 = +i, bit 1 = +j,
// bit 2 = +k, ordered so that each has a positive volume in a right-handed lattice.
extern const std::array<std::array<int, 4>, 6> kCellTets;
using Tet = std::array<glm::dvec3, 4>;

// At most this many cells in a block model's grid (the lattice spanned by a CSV's rows).
constexpr std::size_t kMaxBlockCells = std::size_t(1) << 27;

struct BlockProperty {
    std::string name;            // e.g. "grade"
    std::string unit;            // e.g. "g/t Au"; may be empty
    std::vector<double> values;  // one per cell, linear index (i fastest); NaN = no value
};

struct BlockModel {
    std::string source;  // the CSV file or "Voxet 'name'", for messages and summaries
    glm::dvec3 origin{0.0};
    std::array<glm::dvec3, 3> axis{glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)};
    std::array<double, 3> size{1.0, 1.0, 1.0};  // cell edge along each axis, metres (> 0)
    std::array<std::size_t, 3> dims{0, 0, 0};   // cells along each axis
    std::vector<BlockProperty> properties;
    std::vector<std::string> clipBodies;       // body names; empty = every closed body
    std::vector<std::uint32_t> clipBodyIndex;  // resolved Model::bodies indices (attachBlockModel)
    CellShape shape = CellShape::Box;
    // Hexahedron: (dims[0] + 1)(dims[1] + 1)(dims[2] + 1) corner points, world, i fastest;
    // `locator` indexes the cells' bounds. Box: both empty (origin, axis and size say it all).
    std::vector<glm::dvec3> corners;
    std::shared_ptr<const CellLocator> locator;

    std::size_t cellCount() const { return dims[0] * dims[1] * dims[2]; }
    std::size_t linear(std::size_t i, std::size_t j, std::size_t k) const { return i + dims[0] * (j + dims[1] * k); }
    std::array<std::size_t, 3> ijk(std::size_t cell) const {
        return {cell % dims[0], (cell / dims[0]) % dims[1], cell / (dims[0] * dims[1])};
    }
    // Grid-frame coordinates of a world point (metres along each axis from origin).
    glm::dvec3 toGrid(const glm::dvec3& world) const {
        const glm::dvec3 d = world - origin;
        return {glm::dot(d, axis[0]), glm::dot(d, axis[1]), glm::dot(d, axis[2])};
    }
    glm::dvec3 toWorld(const glm::dvec3& g) const { return origin + g.x * axis[0] + g.y * axis[1] + g.z * axis[2]; }
    // The cell holding a world point, or kNoCell outside the grid. Box: half-open boxes.
    // Hexahedron: among the tetrahedra whose barycentric coordinates are all >= -1e-12 at the
    // point, the cell of the one whose smallest coordinate is largest (first in the locator's
    // order on a tie): on a face shared by two cells the answer is one of them, the same on
    // every call. The locator visits the cells whose bounds hold the point.
    static constexpr std::size_t kNoCell = std::numeric_limits<std::size_t>::max();
    std::size_t cellAt(const glm::dvec3& world) const;
    // The same answer, sooner for coherent points (a raster): `hint` (a cell, or kNoCell) is
    // tried first and kept when one of its tetrahedra holds the point with every barycentric
    // coordinate > kInsideHint (no other cell of a grid that does not overlap itself can then
    // hold it as well); `hint` is updated to the answer. section/blocks/block_raster.cpp fills
    // pixels without asking on the same threshold.
    static constexpr double kInsideHint = 1e-9;
    std::size_t cellAt(const glm::dvec3& world, std::size_t& hint) const;

    // Corner (i, j, k) of the lattice, 0 <= i <= dims[0] (world).
    glm::dvec3 corner(std::size_t i, std::size_t j, std::size_t k) const;
    // The 8 corners of a cell (index = corner number, see kCellTets).
    std::array<glm::dvec3, 8> cellCorners(std::size_t cell) const;
    // Global lattice index of corner number c (0..7) of a cell: equal for the corners two
    // cells share (so shared edges are computed from the same points in the same order).
    std::size_t cornerIndex(std::size_t cell, int c) const;
    Aabb cellBounds(std::size_t cell) const;
    // A cell's volume, m³ (Hexahedron: the sum of its tetrahedra's).
    double cellVolume(std::size_t cell) const;
    // The block model's bounds (world).
    Aabb bounds() const;
    // Index of the property named `name` (exact), or -1.
    int propertyIndex(std::string_view name) const;
    // Names of the properties, comma-separated (for error messages).
    std::string propertyList() const;
    // Whether the body Model::bodies[body] clips this block model.
    bool clips(std::uint32_t body) const;
};

// The rows of a block CSV: centres, sizes and the property columns as written.
struct BlockRows {
    std::vector<std::string> names, units;    // property columns (header order)
    std::vector<glm::dvec3> centres, sizes;   // world metres
    std::vector<std::vector<double>> values;  // values[column][row]; NaN = empty field
    std::vector<std::size_t> lines;           // 1-based line of each row
};

// Parses a block CSV (see above). Errors name the source and line: a missing x/y/z/dx/dy/dz
// column, no property column, a duplicate column, a field count unlike the header's, a
// non-number, a non-finite coordinate, a size <= 0, an unterminated quote. No rows is not
// an error here (callers say so).
Result<BlockRows> readBlockRows(std::string_view text, const std::string& source);

// The regular grid of a block CSV. Errors: readBlockRows's, a row whose size differs from
// the first row's or whose centre is off the lattice, no rows, two rows in one cell, a lattice of
// more than kMaxBlockCells cells.
Result<BlockModel> blockModelFromCsv(std::string_view text, const std::string& source);

// A Voxet or SGrid of a loaded model as a block model (see above). Errors: Unsupported for
// non-orthogonal or zero steps (Voxet), properties on points (SGrid), or no properties;
// InvalidArgument naming the cell for an SGrid cell that is inverted, flat (a tetrahedron of
// volume <= 1e-12 of its bounds' cube) or has a non-finite corner, or fewer than 2 points
// along an axis.
Result<BlockModel> blockModelFromGrid(const Grid& grid);

// Where a model's block model comes from (model/io/loaders.hpp LoadOptions, CLI --blocks).
struct BlockOptions {
    // A CSV path, or "grid:NAME" for a Voxet of the model itself; empty: the sidecar
    // <stem>.blocks.json or <stem>.blocks.csv beside the model file, if any.
    std::string source;
    std::vector<std::string> clip;  // body names (CLI --blocks-clip); empty: the sidecar's, else all
    std::vector<std::pair<std::string, std::string>> units;  // property -> unit overrides
};

// Reads the block model for `modelPath` per `options` and attaches it to `model`
// (Model::blocks): the JSON sidecar <stem>.blocks.json is
//   {"source": "blocks.csv" | "grid:NAME", "clip": ["Orebody", ...], "units": {"grade": "g/t Au"}}
// (source relative to the sidecar's folder); <stem>.blocks.csv alone is a block model
// clipped by every body. Clip names must be closed bodies of the model (the error lists
// them). No options and no sidecar: nothing to attach, the model is unchanged.
Status attachBlockModel(Model& model, const std::string& modelPath, const BlockOptions& options);

// Resolves clip names against the model's bodies into blocks.clipBodyIndex.
Status resolveBlockClip(const Model& model, BlockModel& blocks);

// The files a model's block model is read from (sidecars and the CSV they name), so that
// callers can hash them into the model's version. Empty when there is none.
std::vector<std::string> blockModelFiles(const std::string& modelPath, const BlockOptions& options);

}  // namespace geoslice
