// LSCM on charts with known answers: a planar chart and a developable one (a triangulated
// cylinder strip, flat once unrolled) are isometries (every UV edge length equals its 3D length,
// distortion 1), a curved cap is conformal to within a stated bound, and flips are reported.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "bake/bake.hpp"

using namespace geoslice;

namespace {

constexpr double kPi = 3.14159265358979323846;
// Square metres: a 6000 m^2 chart 35 km from the origin: double round-off of its triangles.
constexpr double kChartAreaTolM2 = 1e-6;
// Relative: an isometric parametrisation's edge lengths and distortion (1 at best) over a
// 100 m chart at Gauss-Kruger eastings: double round-off, ~1e-9, with margin.
constexpr double kIsometryRelTol = 1e-8;
// Relative: LSCM of a developable cylinder is an isometry up to the solver's round-off.
constexpr double kSolverIsometryRelTol = 1e-7;

struct Chart {
    std::vector<glm::dvec3> positions;
    std::vector<std::uint32_t> indices;
    std::vector<std::uint32_t> tris() const {
        std::vector<std::uint32_t> t(indices.size() / 3);
        std::iota(t.begin(), t.end(), 0u);
        return t;
    }
};

// (n+1) x (n+1) vertices through f(i/n, j/n), two triangles per cell, counter-clockwise in (s, t).
template <class F>
Chart gridChart(int n, F f) {
    Chart c;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) c.positions.push_back(f(double(i) / n, double(j) / n));
    auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            c.indices.insert(c.indices.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            c.indices.insert(c.indices.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return c;
}

// Largest relative difference between UV and 3D edge lengths.
double maxEdgeError(const Chart& c, const bake::ChartUv& uv) {
    double worst = 0.0;
    for (std::size_t t = 0; t < c.indices.size() / 3; ++t)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = uv.corners[3 * t + e], b = uv.corners[3 * t + (e + 1) % 3];
            const double l3 = glm::length(c.positions[uv.vertices[a]] - c.positions[uv.vertices[b]]);
            const double l2 = glm::length(uv.uv[a] - uv.uv[b]);
            worst = std::max(worst, std::abs(l2 - l3) / l3);
        }
    return worst;
}

}  // namespace

TEST(BakeLscm, TiltedPlaneIsAnIsometry) {
    // A 100 m x 60 m sheet in a plane tilted 30 degrees about x, 35 km from the origin (a
    // Gauss-Kruger-like easting); distortion 1 to 1e-9 (double round-off over 100 m).
    const Chart c = gridChart(12, [](double s, double t) {
        return glm::dvec3(35.5e6 + 100.0 * s, 3.4e6 + 60.0 * t * std::cos(kPi / 6),
                          500.0 + 60.0 * t * std::sin(kPi / 6));
    });
    const auto tris = c.tris();
    auto uv = bake::lscmChart(c.positions.data(), c.indices.data(), tris.data(), tris.size());
    EXPECT_EQ(uv.badTriangles, 0u);
    EXPECT_NEAR(uv.area3d, 6000.0, kChartAreaTolM2);
    EXPECT_LT(maxEdgeError(c, uv), kIsometryRelTol);
    auto d = bake::measureDistortion(c.positions.data(), c.indices.data(), tris.data(), tris.size(), uv).result();
    EXPECT_NEAR(d.meanAngle, 1.0, kIsometryRelTol);
    EXPECT_NEAR(d.maxArea, 1.0, kIsometryRelTol);
}

TEST(BakeLscm, CylinderStripUnrollsExactly) {
    // A quarter cylinder of radius 50 m, 40 m long: each cell's two triangles share a planar
    // quad, interior vertex angles sum to 2 pi, so the polyhedral strip is developable and its
    // LSCM is an isometry (to solver round-off, 1e-7).
    const Chart c = gridChart(16, [](double s, double t) {
        const double a = s * kPi / 2;
        return glm::dvec3(50.0 * std::cos(a), 40.0 * t, 50.0 * std::sin(a));
    });
    const auto tris = c.tris();
    auto uv = bake::lscmChart(c.positions.data(), c.indices.data(), tris.data(), tris.size());
    EXPECT_EQ(uv.badTriangles, 0u);
    EXPECT_LT(maxEdgeError(c, uv), kSolverIsometryRelTol);
}

TEST(BakeLscm, CurvedCapIsNearlyConformal) {
    // A spherical cap (radius 100 m, 60 degrees across): not developable, so area distortion
    // grows towards the rim, but LSCM keeps angles: mean s1/s2 below 1.02 at this resolution.
    const Chart c = gridChart(20, [](double s, double t) {
        const double x = (s - 0.5) * 100.0, y = (t - 0.5) * 100.0;
        return glm::dvec3(x, y, std::sqrt(100.0 * 100.0 - x * x - y * y));
    });
    const auto tris = c.tris();
    auto uv = bake::lscmChart(c.positions.data(), c.indices.data(), tris.data(), tris.size());
    EXPECT_EQ(uv.badTriangles, 0u);
    auto d = bake::measureDistortion(c.positions.data(), c.indices.data(), tris.data(), tris.size(), uv).result();
    EXPECT_LT(d.meanAngle, 1.02);
    EXPECT_GT(d.maxArea, 1.01);  // the cap does stretch
}

TEST(BakeLscm, SingleAndDegenerateTriangles) {
    const std::vector<glm::dvec3> p = {{0, 0, 0}, {3, 0, 0}, {0, 4, 0}, {1, 1, 1}, {1, 1, 1}, {2, 2, 2}};
    const std::vector<std::uint32_t> idx = {0, 1, 2, 3, 4, 5};
    const std::uint32_t first = 0, second = 1;
    auto uv = bake::lscmChart(p.data(), idx.data(), &first, 1);
    ASSERT_EQ(uv.uv.size(), 3u);
    EXPECT_DOUBLE_EQ(glm::length(uv.uv[1] - uv.uv[0]), 3.0);
    EXPECT_DOUBLE_EQ(glm::length(uv.uv[2] - uv.uv[0]), 4.0);
    EXPECT_DOUBLE_EQ(uv.area3d, 6.0);
    auto degenerate = bake::lscmChart(p.data(), idx.data(), &second, 1);  // zero area: a segment in UV, not "bad"
    EXPECT_EQ(degenerate.badTriangles, 0u);
    EXPECT_EQ(degenerate.area3d, 0.0);
}

TEST(BakeLscm, FlippedTriangleIsReported) {
    // A planar grid with one interior triangle wound the other way: its neighbours hold its
    // vertices where the plane puts them, so in its own corner order it is flipped (or
    // collapsed) in UV, and lscmChart must say so (bakeModel then splits the chart).
    Chart c = gridChart(6, [](double s, double t) { return glm::dvec3(60.0 * s, 60.0 * t, 0.0); });
    const std::size_t t = 2 * (3 * 6 + 3);  // a triangle of cell (3, 3)
    std::swap(c.indices[3 * t + 1], c.indices[3 * t + 2]);
    const auto tris = c.tris();
    auto uv = bake::lscmChart(c.positions.data(), c.indices.data(), tris.data(), tris.size());
    EXPECT_GE(uv.badTriangles, 1u);
    // The split pieces flatten cleanly once the odd triangle is alone.
    const std::uint32_t odd = static_cast<std::uint32_t>(t);
    auto single = bake::lscmChart(c.positions.data(), c.indices.data(), &odd, 1);
    EXPECT_EQ(single.badTriangles, 0u);
}
