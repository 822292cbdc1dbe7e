// A small generated tetrahedral layered model with pinch-outs, for the volume-mesh, .vtu
// and oracle tests. World coordinates in metres.
//
// Grid: nx * ny * nz cubes of `cell` metres from `origin`, every cube cut into the six
// Kuhn tetrahedra along its (0,0,0)-(1,1,1) diagonal (conforming: neighbouring cubes cut
// their shared face alike), vertices displaced by a smooth field (`jitter` metres) so that
// no face is axis-aligned. Regions (cube (i, j, k), k up):
//   0 "basement"  k < nz/3            1 "sandstone"  nz/3 <= k < 2nz/3
//   2 "shale"     k >= 2nz/3          3 "lens"       cubes (2,2,a), (3,3,a), (4,4,a+1), a = nz/3
// The lens touches itself along the vertical edge x = 3, y = 3 (cubes (2,2,a) and (3,3,a))
// and at the single point (4, 4, a+1) (cubes (3,3,a) and (4,4,a+1)); the sandstone around
// it touches itself along the same edge and has a two-cone vertex at the same point.
//
// With `overlap` > 0, every region gets its own copy of its vertices, moved along a fixed
// oblique direction by overlap * a smooth field in [-1, 1] with a different phase per
// region: neighbours then overlap where the lower one moved up and leave gaps where it
// moved down, by up to 2 * overlap metres (a few centimetres for overlap = 0.02).
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "model/mesh/volume_mesh.hpp"
#include "model/model.hpp"

namespace geoslice::test {

struct TetModelOptions {
    int nx = 8, ny = 8, nz = 6;  // cubes; nx, ny >= 6 and nz >= 3 for the lens to fit
    double cell = 10.0;          // cube edge, metres
    glm::dvec3 origin{0.0};      // world position of grid vertex (0, 0, 0)
    double jitter = 1.5;         // amplitude of the smooth vertex displacement, metres
    double overlap = 0.0;        // per-region displacement amplitude, metres (0: shared vertices)
    bool invertOdd = false;      // write the three odd-permutation tetrahedra of each cube inverted
};

struct TetModel {
    VolumeMesh mesh;
    std::vector<std::string> regionNames{"basement", "sandstone", "shale", "lens"};
    std::size_t regionCount() const { return regionNames.size(); }
};

inline TetModel tetLayeredModel(const TetModelOptions& o = {}) {
    TetModel out;
    VolumeMesh& m = out.mesh;
    const int vx = o.nx + 1, vy = o.ny + 1, vz = o.nz + 1;
    const int a = o.nz / 3;
    auto regionOf = [&](int i, int j, int k) {
        if ((i == 2 && j == 2 && k == a) || (i == 3 && j == 3 && k == a) || (i == 4 && j == 4 && k == a + 1)) return 3;
        if (k < a) return 0;
        if (k < 2 * o.nz / 3) return 1;
        return 2;
    };
    auto gridPoint = [&](int i, int j, int k) {
        const double x = i * o.cell, y = j * o.cell, z = k * o.cell;
        const double s = o.jitter;
        return o.origin + glm::dvec3(x + 0.4 * s * std::sin(0.11 * y + 0.07 * z),
                                     y + 0.4 * s * std::sin(0.09 * x + 0.13 * z + 1.0),
                                     z + s * std::sin(0.05 * x + 0.3) * std::cos(0.06 * y + 0.2));
    };
    const std::size_t gridVertices = static_cast<std::size_t>(vx) * vy * vz;
    const int copies = o.overlap > 0.0 ? static_cast<int>(out.regionCount()) : 1;
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.3, 0.2, 1.0));
    m.positions.reserve(gridVertices * static_cast<std::size_t>(copies));
    for (int r = 0; r < copies; ++r)
        for (int k = 0; k < vz; ++k)
            for (int j = 0; j < vy; ++j)
                for (int i = 0; i < vx; ++i) {
                    glm::dvec3 p = gridPoint(i, j, k);
                    if (o.overlap > 0.0) {
                        const glm::dvec3 q = p - o.origin;
                        p += dir * (o.overlap * std::sin(0.07 * q.x + 1.3 * r) * std::cos(0.05 * q.y - 0.7 * r));
                    }
                    m.positions.push_back(p);
                }
    auto vid = [&](int r, int i, int j, int k) {
        return static_cast<std::uint32_t>(static_cast<std::size_t>(o.overlap > 0.0 ? r : 0) * gridVertices +
                                          static_cast<std::size_t>((k * vy + j) * vx + i));
    };
    // Kuhn tetrahedra: the paths 0 -> e_p0 -> e_p0 + e_p1 -> (1,1,1) over the six axis orders.
    const std::array<std::array<int, 3>, 6> perms{
        {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}}};  // even, then odd
    for (int k = 0; k < o.nz; ++k)
        for (int j = 0; j < o.ny; ++j)
            for (int i = 0; i < o.nx; ++i) {
                const int r = regionOf(i, j, k);
                for (std::size_t p = 0; p < perms.size(); ++p) {
                    std::array<int, 3> c{i, j, k};
                    std::array<std::uint32_t, 4> t{};
                    t[0] = vid(r, c[0], c[1], c[2]);
                    for (int s = 0; s < 3; ++s) {
                        ++c[static_cast<std::size_t>(perms[p][static_cast<std::size_t>(s)])];
                        t[static_cast<std::size_t>(s + 1)] = vid(r, c[0], c[1], c[2]);
                    }
                    // Even orders give a positive tetrahedron (x, y, z), odd ones a negative.
                    const bool odd = p >= 3;
                    if (odd && !o.invertOdd) std::swap(t[2], t[3]);
                    m.addCell(VolumeMesh::CellType::Tetra, {t[0], t[1], t[2], t[3]}, r);
                }
            }
    return out;
}

// Signed volume of tetrahedron (a, b, c, d), plain double arithmetic.
inline double tetVolume(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    return glm::dot(b - a, glm::cross(c - a, d - a)) / 6.0;
}

// Is p inside tetrahedron (a, b, c, d) (either orientation)? Barycentric signs in double;
// a point on a face counts as inside.
inline bool pointInTet(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                       const glm::dvec3& d) {
    const double v = tetVolume(a, b, c, d);
    if (v == 0.0) return false;
    const double s = v > 0 ? 1.0 : -1.0;
    return s * tetVolume(p, b, c, d) >= 0 && s * tetVolume(a, p, c, d) >= 0 && s * tetVolume(a, b, p, d) >= 0 &&
           s * tetVolume(a, b, c, p) >= 0;
}

}  // namespace geoslice::test
