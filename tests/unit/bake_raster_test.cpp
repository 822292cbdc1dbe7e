// Conservative rasterization against exact oracles: a right triangle whose touched cells are
// known in closed form, random triangles against dense point sampling (every cell holding a
// point of the triangle is set, and no set cell is farther than the triangle's bounds),
// degenerate triangles, and one texel of seam padding.
#include <gtest/gtest.h>

#include <random>

#include "bake/bake.hpp"

using namespace geoslice;

TEST(BakeRaster, RightTriangleTouchesExactlyTheseCells) {
    // x >= 0.5, y >= 0.5, x + y <= 4: cell (i, j) is touched iff i + j <= 4 with i, j in 0..3
    // (corner contacts count: cell (2, 2) touches the hypotenuse at (2, 2)).
    const glm::dvec2 tri[3] = {{0.5, 0.5}, {3.5, 0.5}, {0.5, 3.5}};
    std::vector<std::uint8_t> mask(6 * 6, 0);
    bake::rasterizeConservative(tri, mask.data(), 6, 6);
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 6; ++i)
            EXPECT_EQ(mask[j * 6 + i], (i <= 3 && j <= 3 && i + j <= 4) ? 1 : 0) << i << "," << j;
}

TEST(BakeRaster, EveryCellHoldingAPointOfTheTriangleIsSet) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> d(0.0, 16.0), unit(0.0, 1.0);
    constexpr std::uint32_t kSide = 16;
    for (int trial = 0; trial < 200; ++trial) {
        glm::dvec2 tri[3] = {{d(rng), d(rng)}, {d(rng), d(rng)}, {d(rng), d(rng)}};
        if (trial % 10 == 0) tri[2] = tri[0] + 0.37 * (tri[1] - tri[0]);  // zero area: a segment
        std::vector<std::uint8_t> mask(kSide * kSide, 0);
        bake::rasterizeConservative(tri, mask.data(), kSide, kSide);
        for (int s = 0; s < 4000; ++s) {
            double a = unit(rng), b = unit(rng);
            if (a + b > 1) a = 1 - a, b = 1 - b;
            const glm::dvec2 p = tri[0] + a * (tri[1] - tri[0]) + b * (tri[2] - tri[0]);
            const auto x = static_cast<std::uint32_t>(p.x), y = static_cast<std::uint32_t>(p.y);
            ASSERT_EQ(mask[y * kSide + x], 1) << "trial " << trial << " point " << p.x << "," << p.y;
        }
        // Nothing outside the closed bounds' cells.
        const glm::dvec2 lo = glm::min(tri[0], glm::min(tri[1], tri[2])),
                         hi = glm::max(tri[0], glm::max(tri[1], tri[2]));
        for (std::uint32_t y = 0; y < kSide; ++y)
            for (std::uint32_t x = 0; x < kSide; ++x)
                if (mask[y * kSide + x]) {
                    EXPECT_LE(double(x), hi.x);
                    EXPECT_GE(double(x + 1), lo.x);
                    EXPECT_LE(double(y), hi.y);
                    EXPECT_GE(double(y + 1), lo.y);
                }
    }
}

TEST(BakeRaster, PointTriangleAndClipping) {
    const glm::dvec2 point[3] = {{2.5, 3.5}, {2.5, 3.5}, {2.5, 3.5}};
    std::vector<std::uint8_t> mask(8 * 8, 0);
    bake::rasterizeConservative(point, mask.data(), 8, 8);
    EXPECT_EQ(std::count(mask.begin(), mask.end(), 1), 1);
    EXPECT_EQ(mask[3 * 8 + 2], 1);
    const glm::dvec2 outside[3] = {{-50, -50}, {100, -40}, {-40, 100}};  // covers the grid and beyond
    std::fill(mask.begin(), mask.end(), 0);
    bake::rasterizeConservative(outside, mask.data(), 8, 8);
    EXPECT_EQ(std::count(mask.begin(), mask.end(), 1), 64);
    const glm::dvec2 nan[3] = {{std::nan(""), 0}, {1, 1}, {2, 0}};
    std::fill(mask.begin(), mask.end(), 0);
    bake::rasterizeConservative(nan, mask.data(), 8, 8);
    EXPECT_EQ(std::count(mask.begin(), mask.end(), 0), 64);
}

TEST(BakeRaster, PaddingIsOneTexelWide) {
    std::vector<std::uint8_t> mask(7 * 7, 0);
    mask[3 * 7 + 3] = 1;
    bake::dilateMask(mask.data(), 7, 7);
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 7; ++x) EXPECT_EQ(mask[y * 7 + x] != 0, std::abs(x - 3) <= 1 && std::abs(y - 3) <= 1);
}

TEST(BakeRaster, FetchIsNearestWithPagesInU) {
    // 2 pages of 4 x 2 texels; texel value = page * 100 + y * 10 + x.
    std::vector<std::uint32_t> t(2 * 2 * 4);
    for (std::uint32_t p = 0; p < 2; ++p)
        for (std::uint32_t y = 0; y < 2; ++y)
            for (std::uint32_t x = 0; x < 4; ++x) t[(p * 2 + y) * 4 + x] = p * 100 + y * 10 + x;
    EXPECT_EQ(bake::fetchId(t.data(), 4, 2, 2, {0.0, 0.0}), 0u);
    EXPECT_EQ(bake::fetchId(t.data(), 4, 2, 2, {0.26, 0.51}), 11u);
    EXPECT_EQ(bake::fetchId(t.data(), 4, 2, 2, {1.99, 0.99}), 113u);
    EXPECT_EQ(bake::fetchId(t.data(), 4, 2, 2, {2.0, 0.5}), 0u);  // past the last page
    EXPECT_EQ(bake::fetchId(t.data(), 4, 2, 2, {-0.1, 0.5}), 0u);
    EXPECT_EQ(bake::fetchId(t.data(), 4, 2, 2, {0.5, std::nan("")}), 0u);
}
