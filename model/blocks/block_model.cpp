// Block model cells: the Kuhn split of a cell into tetrahedra, corners, bounds, volumes and
// point location (cellAt). Reading CSV and grids: block_sources.cpp; attaching to a model:
// block_attach.cpp.
#include "model/blocks/block_model.hpp"
#include "model/blocks/block_model_internal.hpp"

#include <algorithm>
#include <cmath>

#include "model/blocks/cell_locator.hpp"
#include "model/model.hpp"

namespace geoslice {

// Kuhn split (see the header): orders (x y z), (y z x), (z x y) as they come, the odd orders
// (x z y), (y x z), (z y x) with their middle corners swapped so every volume is positive.
const std::array<std::array<int, 4>, 6> kCellTets{{
    {0, 1, 3, 7},
    {0, 2, 6, 7},
    {0, 4, 5, 7},
    {0, 5, 1, 7},
    {0, 3, 2, 7},
    {0, 6, 4, 7},
}};

double tetVolume6(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    return glm::dot(b - a, glm::cross(c - a, d - a));
}

namespace {

// The smallest barycentric coordinate of p in the tetrahedron (either orientation).
double minBarycentric(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d,
                      const glm::dvec3& p) {
    const glm::dvec3 e1 = b - a, e2 = c - a, e3 = d - a, q = p - a;
    const double v = glm::dot(e1, glm::cross(e2, e3));
    if (v == 0.0) return -std::numeric_limits<double>::infinity();
    const double l1 = glm::dot(q, glm::cross(e2, e3)) / v;
    const double l2 = glm::dot(e1, glm::cross(q, e3)) / v;
    const double l3 = glm::dot(e1, glm::cross(e2, q)) / v;
    return std::min({1.0 - l1 - l2 - l3, l1, l2, l3});
}

// How deep p lies in a cell: the largest smallest barycentric coordinate over its tetrahedra.
double cellDepth(const BlockModel& b, std::size_t cell, const glm::dvec3& p) {
    const auto k = b.cellCorners(cell);
    double best = -std::numeric_limits<double>::infinity();
    for (const auto& t : kCellTets) best = std::max(best, minBarycentric(k[t[0]], k[t[1]], k[t[2]], k[t[3]], p));
    return best;
}

constexpr double kOnCell = -1e-12;  // barycentric slack: rounding of p - corner (see cellAt)

}  // namespace

std::size_t BlockModel::cellAt(const glm::dvec3& world) const {
    if (shape == CellShape::Hexahedron) {
        std::size_t best = kNoCell;
        double depth = kOnCell;
        locator->cellsAt(world, [&](std::size_t c) {
            const double d = cellDepth(*this, c, world);
            if (d >= depth && (best == kNoCell || d > depth)) {
                best = c;
                depth = d;
            }
        });
        return best;
    }
    const glm::dvec3 g = toGrid(world);
    std::size_t idx[3];
    for (int a = 0; a < 3; ++a) {
        const double t = std::floor(g[a] / size[a]);
        if (!(t >= 0.0) || t >= double(dims[a])) return kNoCell;  // also NaN
        idx[a] = std::size_t(t);
    }
    return linear(idx[0], idx[1], idx[2]);
}

std::size_t BlockModel::cellAt(const glm::dvec3& world, std::size_t& hint) const {
    if (shape == CellShape::Hexahedron && hint != kNoCell && cellDepth(*this, hint, world) > kInsideHint) return hint;
    hint = cellAt(world);
    return hint;
}

glm::dvec3 BlockModel::corner(std::size_t i, std::size_t j, std::size_t k) const {
    if (shape == CellShape::Hexahedron) return corners[i + (dims[0] + 1) * (j + (dims[1] + 1) * k)];
    return origin + double(i) * size[0] * axis[0] + double(j) * size[1] * axis[1] + double(k) * size[2] * axis[2];
}

std::size_t BlockModel::cornerIndex(std::size_t cell, int c) const {
    const auto [i, j, k] = ijk(cell);
    return (i + std::size_t(c & 1)) +
           (dims[0] + 1) * ((j + std::size_t((c >> 1) & 1)) + (dims[1] + 1) * (k + std::size_t(c >> 2)));
}

std::array<glm::dvec3, 8> BlockModel::cellCorners(std::size_t cell) const {
    const auto [i, j, k] = ijk(cell);
    std::array<glm::dvec3, 8> out;
    for (int c = 0; c < 8; ++c)
        out[std::size_t(c)] = corner(i + std::size_t(c & 1), j + std::size_t((c >> 1) & 1), k + std::size_t(c >> 2));
    return out;
}

Aabb BlockModel::cellBounds(std::size_t cell) const {
    Aabb box;
    for (const glm::dvec3& p : cellCorners(cell)) box.extend(p);
    return box;
}

double BlockModel::cellVolume(std::size_t cell) const {
    if (shape == CellShape::Box) return size[0] * size[1] * size[2];
    const auto k = cellCorners(cell);
    double v = 0.0;
    for (const auto& t : kCellTets) v += tetVolume6(k[t[0]], k[t[1]], k[t[2]], k[t[3]]);
    return std::abs(v) / 6.0;
}

Aabb BlockModel::bounds() const {
    if (shape == CellShape::Hexahedron) return locator->bounds();
    Aabb box;
    for (int c = 0; c < 8; ++c)
        box.extend(corner(c & 1 ? dims[0] : 0, (c >> 1) & 1 ? dims[1] : 0, c >> 2 ? dims[2] : 0));
    return box;
}

int BlockModel::propertyIndex(std::string_view name) const {
    for (std::size_t p = 0; p < properties.size(); ++p)
        if (properties[p].name == name) return int(p);
    return -1;
}

std::string BlockModel::propertyList() const {
    std::string s;
    for (const auto& p : properties) s += (s.empty() ? "" : ", ") + p.name;
    return s;
}

bool BlockModel::clips(std::uint32_t body) const {
    return std::find(clipBodyIndex.begin(), clipBodyIndex.end(), body) != clipBodyIndex.end();
}

}  // namespace geoslice
