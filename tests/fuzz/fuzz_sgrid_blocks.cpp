// libFuzzer target for curvilinear (SGrid) block models (model/blocks/block_model.hpp, Hexahedron
// cells): bytes -> a small SGrid (1..4 cells per axis, a lattice of 4 m cells whose points
// are moved by signed bytes, or set to NaN / infinity / a far value by marker bytes, so
// inverted, flat, folded and non-finite cells come up) -> blockModelFromGrid. An SGrid must
// be a block model or an error naming a cell, never a crash or a hang. A block model it
// gives is then used as every consumer does: cellAt (with and without a hint, the same
// answer), the cell ∩ plane polygons of a plane from the bytes (every polygon of positive
// area, counter-clockwise), and cell ∩ box volumes (each within [-1e-9, 1 + 1e-9] of its
// cell's volume, and equal to the whole-body clip's, clippedCellBodyVolumes: both are exact
// up to rounding).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "model/blocks/block_model.hpp"
#include "model/model.hpp"
#include "section/blocks/block_reserves.hpp"
#include "section/blocks/block_section.hpp"
#include "section/cut/contours.hpp"

using namespace geoslice;

namespace {

struct Bytes {
    const std::uint8_t* data;
    std::size_t size, at = 0;
    std::uint8_t next() { return at < size ? data[at++] : 0; }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Bytes in{data, size};
    Grid g;
    g.type = "SGrid";
    g.name = "fuzz";
    g.cellCentred = in.next() % 8 != 0;            // sometimes properties on points (refused)
    for (auto& d : g.dims) d = 1 + in.next() % 5;  // 1..5 points: 0..4 cells
    for (std::size_t k = 0; k < g.dims[2]; ++k)
        for (std::size_t j = 0; j < g.dims[1]; ++j)
            for (std::size_t i = 0; i < g.dims[0]; ++i) {
                glm::dvec3 p(4.0 * double(i), 4.0 * double(j), 4.0 * double(k));
                const std::uint8_t m = in.next();
                if (m == 255)
                    p.x = std::numeric_limits<double>::quiet_NaN();
                else if (m == 254)
                    p.y = std::numeric_limits<double>::infinity();
                else if (m == 253)
                    p.z = 1e9;
                else if (m >= 128)
                    p += glm::dvec3(std::int8_t(in.next()), std::int8_t(in.next()), std::int8_t(in.next())) / 32.0;
                g.points.push_back(p);
            }
    std::size_t cells = 1;
    for (const auto d : g.dims) cells *= d > 1 ? d - 1 : 1;
    GridProperty prop{"grade", "g/t", std::nullopt, {}};
    for (std::size_t c = 0; c < (g.cellCentred ? cells : g.sampleCount()); ++c)
        prop.values.push_back(float(in.next()) / 16.0f);
    g.properties.push_back(prop);
    auto b = blockModelFromGrid(g);
    if (!b.ok()) return 0;
    const BlockModel& bm = b.value();
    if (bm.shape != CellShape::Hexahedron || bm.cellCount() != cells) __builtin_trap();
    std::size_t hint = BlockModel::kNoCell;
    for (int n = 0; n < 16; ++n) {
        const glm::dvec3 p(double(in.next()) / 16.0 - 1.0, double(in.next()) / 16.0 - 1.0,
                           double(in.next()) / 16.0 - 1.0);
        const std::size_t c = bm.cellAt(p);
        if (c != BlockModel::kNoCell && c >= cells) __builtin_trap();
        if (bm.cellAt(p, hint) != c) __builtin_trap();
    }
    glm::dvec3 n(double(std::int8_t(in.next())), double(std::int8_t(in.next())), double(std::int8_t(in.next())) + 0.5);
    n = glm::normalize(n);
    const Plane plane{n, -glm::dot(n, glm::dvec3(double(in.next()) / 16.0))};
    auto polys = cellPolygons(bm, makeSectionFrame(plane, {0, 0, 0}));
    if (!polys.ok()) __builtin_trap();
    for (const CellPolygon& cp : polys.value())
        if (cp.cell >= cells || cp.ring.size() < 3 || !(ringArea(cp.ring) > 0.0)) __builtin_trap();
    Mesh box;
    const glm::dvec3 lo(double(in.next()) / 16.0, double(in.next()) / 16.0, double(in.next()) / 16.0);
    const glm::dvec3 hi = lo + glm::dvec3(1.0 + double(in.next()) / 16.0);
    for (int c = 0; c < 8; ++c)
        box.positions.push_back({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
    // Outward triangles (corner bits: 1 x, 2 y, 4 z).
    box.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                   2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    const std::vector<CellVolume> local = cellBodyVolumes(bm, box), oracle = clippedCellBodyVolumes(bm, box);
    for (const CellVolume& cv : local) {
        const double v = bm.cellVolume(cv.cell);
        if (cv.cell >= cells || cv.volume < -1e-9 * v || cv.volume > (1.0 + 1e-9) * v) __builtin_trap();
    }
    // The local sum against the whole-body clip, cell by cell (absent = 0): both exact up to
    // rounding of 20 m coordinates (1e-13 of a cell); 1e-6 of the cell leaves room for cells
    // near the flatness limit, where rounding is amplified.
    std::size_t a = 0, o = 0;
    while (a < local.size() || o < oracle.size()) {
        const std::size_t cell =
            std::min(a < local.size() ? local[a].cell : cells, o < oracle.size() ? oracle[o].cell : cells);
        const double x = a < local.size() && local[a].cell == cell ? local[a++].volume : 0.0;
        const double y = o < oracle.size() && oracle[o].cell == cell ? oracle[o++].volume : 0.0;
        if (std::abs(x - y) > 1e-6 * bm.cellVolume(cell) + 1e-9) __builtin_trap();
    }
    return 0;
}
