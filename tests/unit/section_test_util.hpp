// Helpers shared by the section_*_test.cpp files: generated models, random planes
// through a model, and an independent brute-force section area (no BVH, no chaining).
#pragma once

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "section/cut/contours.hpp"
#include "section/index/section_index.hpp"
#include "tests/common/random_plane.hpp"
#include "tests/common/synthetic_model.hpp"

namespace geoslice::test {

inline std::unique_ptr<SectionIndex> indexFor(const Model& m) {
    auto idx = buildSectionIndex(m);
    EXPECT_TRUE(idx.ok()) << (idx.ok() ? "" : idx.error().message);
    return std::move(idx).value();
}

// Signed area (m², counter-clockwise in the section frame positive) of the cut of one
// mesh by the plane, by Green's theorem over the cut segments of every triangle, each
// oriented from the triangle's normal: no BVH, no chaining, no welding.
inline double bruteForceArea(const Mesh& mesh, const Plane& plane, const SectionFrame& frame,
                             const glm::dvec3& origin) {
    double area = 0.0;
    const glm::dvec2 ref = frame.toPlane(glm::dvec3(0.0));  // keeps the products small
    const double dLocal = plane.d + glm::dot(plane.normal, origin);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        glm::dvec3 p[3];
        double s[3];
        for (int k = 0; k < 3; ++k) {
            p[k] = mesh.positions[mesh.indices[3 * t + static_cast<std::size_t>(k)]] - origin;
            s[k] = glm::dot(plane.normal, p[k]) + dLocal;
        }
        glm::dvec3 pts[2];
        int n = 0;
        for (int k = 0; k < 3; ++k) {
            const int k1 = (k + 1) % 3;
            if ((s[k] >= 0.0) == (s[k1] >= 0.0)) continue;
            const double f = s[k] / (s[k] - s[k1]);
            if (n < 2) pts[n++] = p[k] + f * (p[k1] - p[k]);
        }
        if (n != 2) continue;
        // Interior on the left in u/v: the segment runs along N x n.
        const glm::dvec3 normal = glm::cross(p[1] - p[0], p[2] - p[0]);
        const glm::dvec3 dir = glm::cross(normal, plane.normal);
        if (glm::dot(pts[1] - pts[0], dir) < 0.0) std::swap(pts[0], pts[1]);
        const glm::dvec2 a = frame.toPlane(pts[0]) - ref, b = frame.toPlane(pts[1]) - ref;
        area += 0.5 * (a.x * b.y - a.y * b.x);
    }
    return area;
}

// Bit for bit: the same bodies (rings point by point, areas) and traces (tolerance: none).
inline void expectSameSection(const Section& x, const Section& y, const std::string& what) {
    ASSERT_EQ(x.bodies.size(), y.bodies.size()) << what;
    for (std::size_t i = 0; i < x.bodies.size(); ++i) {
        const BodySection &a = x.bodies[i], &b = y.bodies[i];
        EXPECT_EQ(a.part, b.part) << what;
        EXPECT_EQ(a.area, b.area) << what;
        EXPECT_EQ(a.openChains, b.openChains) << what;
        ASSERT_EQ(a.polygons.size(), b.polygons.size()) << what;
        for (std::size_t j = 0; j < a.polygons.size(); ++j) {
            EXPECT_EQ(a.polygons[j].outer, b.polygons[j].outer) << what;
            EXPECT_EQ(a.polygons[j].holes, b.polygons[j].holes) << what;
        }
    }
    ASSERT_EQ(x.traces.size(), y.traces.size()) << what;
    for (std::size_t i = 0; i < x.traces.size(); ++i) EXPECT_EQ(x.traces[i].points, y.traces[i].points) << what;
}

inline double bodyArea(const Section& s, std::uint32_t part) {
    for (const auto& b : s.bodies)
        if (b.part == part) return b.area;
    return 0.0;
}

}  // namespace geoslice::test
