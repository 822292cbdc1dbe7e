// Analytic test shapes shared by unit tests: boxes and UV spheres as closed, outward
// triangle meshes in world coordinates.
#pragma once

#include <cmath>
#include <utility>
#include <vector>

#include "model/mesh/validate.hpp"
#include "model/model.hpp"

namespace geoslice::test {

// Axis-aligned box [lo, hi], 12 triangles, outward.
inline Mesh boxMesh(const glm::dvec3& lo, const glm::dvec3& hi) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    const std::uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& t : f) m.indices.insert(m.indices.end(), {t[0], t[1], t[2]});
    return m;
}

// UV sphere (poles on z), nTheta x nPhi, outward. Inscribed polyhedron: its volume is
// below 4/3 pi r^3 by O(1/n^2).
inline Mesh sphereMesh(const glm::dvec3& c, double r, int nTheta = 48, int nPhi = 24) {
    constexpr double kPi = 3.14159265358979323846;
    Mesh m;
    m.positions.push_back(c + glm::dvec3(0, 0, r));
    for (int j = 1; j < nPhi; ++j)
        for (int i = 0; i < nTheta; ++i) {
            double th = 2 * kPi * i / nTheta, ph = kPi * j / nPhi;
            m.positions.push_back(
                c + r * glm::dvec3(std::sin(ph) * std::cos(th), std::sin(ph) * std::sin(th), std::cos(ph)));
        }
    m.positions.push_back(c - glm::dvec3(0, 0, r));
    const auto south = static_cast<std::uint32_t>(m.positions.size() - 1);
    auto R = [&](int j, int i) { return 1u + static_cast<std::uint32_t>((j - 1) * nTheta + (i % nTheta)); };
    for (int i = 0; i < nTheta; ++i) m.indices.insert(m.indices.end(), {0u, R(1, i), R(1, i + 1)});
    for (int j = 1; j + 1 < nPhi; ++j)
        for (int i = 0; i < nTheta; ++i)
            m.indices.insert(m.indices.end(),
                             {R(j + 1, i), R(j + 1, i + 1), R(j, i + 1), R(j + 1, i), R(j, i + 1), R(j, i)});
    for (int i = 0; i < nTheta; ++i) m.indices.insert(m.indices.end(), {south, R(nPhi - 1, i + 1), R(nPhi - 1, i)});
    return m;
}

inline void reverse(Mesh& m) {
    for (std::size_t t = 0; t < m.triangleCount(); ++t) std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
}

inline void append(Mesh& dst, const Mesh& src) {
    const auto base = static_cast<std::uint32_t>(dst.positions.size());
    dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
    for (auto i : src.indices) dst.indices.push_back(base + i);
}

inline Part makePart(std::string name, PartKind kind, RecordId record, Mesh mesh) {
    Part p;
    p.name = std::move(name);
    p.kind = kind;
    p.record = record;
    p.mesh = std::move(mesh);
    return p;
}

// A model of these parts, recentred and validated (closed flags, orientation, nesting).
inline Model modelOf(std::vector<Part> bodies, std::vector<Part> surfaces = {}) {
    Model m;
    m.bodies = std::move(bodies);
    m.surfaces = std::move(surfaces);
    m.recentre();
    validate(m);
    return m;
}

}  // namespace geoslice::test
