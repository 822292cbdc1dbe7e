// Charts: welding, the topological-disk test on meshes whose topology is known, region growing
// under the dihedral threshold (a box gives exactly its 6 faces), the size bound, and the
// partition property (every triangle in exactly one chart, every chart a disk).
#include <gtest/gtest.h>

#include <numeric>

#include "bake/bake.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

// An n x n grid of unit squares in the plane z = 0, two triangles each, counter-clockwise from +z.
Mesh gridMesh(int n) {
    Mesh m;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) m.positions.push_back({double(x), double(y), 0.0});
    auto id = [n](int x, int y) { return static_cast<std::uint32_t>(y * (n + 1) + x); };
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            m.indices.insert(m.indices.end(), {id(x, y), id(x + 1, y), id(x + 1, y + 1)});
            m.indices.insert(m.indices.end(), {id(x, y), id(x + 1, y + 1), id(x, y + 1)});
        }
    return m;
}

std::vector<std::uint32_t> allTriangles(const Mesh& m) {
    std::vector<std::uint32_t> t(m.triangleCount());
    std::iota(t.begin(), t.end(), 0u);
    return t;
}

bool disk(const Mesh& m, std::vector<std::uint32_t> tris) {
    return bake::isTopologicalDisk(m.indices.data(), tris.data(), tris.size());
}

}  // namespace

TEST(BakeCharts, WeldJoinsExactlyEqualPositionsOnly) {
    const std::vector<glm::dvec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {1, 0, 1e-12}, {std::nan(""), 0, 0}, {1, 0, 0}};
    auto w = bake::weldVertices(p.data(), p.size());
    EXPECT_EQ(w, (std::vector<std::uint32_t>{0, 1, 0, 3, 4, 1}));
}

TEST(BakeCharts, DiskTestOnKnownTopologies) {
    const Mesh grid = gridMesh(4);
    EXPECT_TRUE(disk(grid, allTriangles(grid)));  // a square: disk
    EXPECT_TRUE(disk(grid, {0}));                 // one triangle
    // An annulus: the grid without its 2 x 2 central cells (a hole) has two border loops.
    std::vector<std::uint32_t> annulus;
    for (std::uint32_t t = 0; t < grid.triangleCount(); ++t) {
        const int cell = int(t / 2), x = cell % 4, y = cell / 4;
        if ((x == 1 || x == 2) && (y == 1 || y == 2)) continue;  // the 2 x 2 central cells
        annulus.push_back(t);
    }
    EXPECT_FALSE(disk(grid, annulus));
    // Two cells touching at one corner only (a pinched vertex): cells (0,0) and (1,1).
    EXPECT_FALSE(disk(grid, {0, 1, 10, 11}));
    // Two separate cells.
    EXPECT_FALSE(disk(grid, {0, 1, 6, 7}));
    // A closed box (sphere topology, Euler characteristic 2) and a box minus one face (disk).
    const Mesh box = boxMesh({0, 0, 0}, {1, 2, 3});
    EXPECT_FALSE(disk(box, allTriangles(box)));
    auto open = allTriangles(box);
    open.erase(open.begin(), open.begin() + 2);
    EXPECT_TRUE(disk(box, open));
}

TEST(BakeCharts, BoxFacesAreSeparateChartsUnder85Degrees) {
    const Mesh box = boxMesh({0, 0, 0}, {10, 20, 30});
    auto w = bake::weldVertices(box.positions.data(), box.positions.size());
    std::vector<std::uint32_t> idx(box.indices.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = w[box.indices[i]];
    auto charts = bake::buildCharts(box.positions.data(), box.positions.size(), idx.data(), box.triangleCount());
    ASSERT_EQ(charts.count(), 6u);  // 90-degree edges exceed the 85-degree threshold
    for (std::size_t c = 0; c < 6; ++c) EXPECT_EQ(charts.offsets[c + 1] - charts.offsets[c], 2u);
    // At 95 degrees with a wide cone, faces join, yet every chart stays a disk (a closed box
    // cannot be one chart).
    bake::ChartOptions wide;
    wide.maxDihedralDegrees = 95.0;
    wide.maxConeDegrees = 180.0;
    auto joined = bake::buildCharts(box.positions.data(), box.positions.size(), idx.data(), box.triangleCount(), wide);
    EXPECT_LT(joined.count(), 6u);
    EXPECT_GE(joined.count(), 2u);
    for (std::size_t c = 0; c < joined.count(); ++c)
        EXPECT_TRUE(bake::isTopologicalDisk(idx.data(), joined.triangles.data() + joined.offsets[c],
                                            joined.offsets[c + 1] - joined.offsets[c]));
}

TEST(BakeCharts, SphereChartsPartitionTrianglesIntoBoundedDisks) {
    const Mesh s = sphereMesh({0, 0, 0}, 100.0, 64, 32);
    auto w = bake::weldVertices(s.positions.data(), s.positions.size());
    std::vector<std::uint32_t> idx(s.indices.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = w[s.indices[i]];
    bake::ChartOptions o;
    o.maxTriangles = 300;
    auto charts = bake::buildCharts(s.positions.data(), s.positions.size(), idx.data(), s.triangleCount(), o);
    std::vector<int> seen(s.triangleCount(), 0);
    for (std::size_t c = 0; c < charts.count(); ++c) {
        const std::uint32_t n = charts.offsets[c + 1] - charts.offsets[c];
        EXPECT_LE(n, 300u);
        EXPECT_TRUE(bake::isTopologicalDisk(idx.data(), charts.triangles.data() + charts.offsets[c], n));
        for (std::uint32_t k = charts.offsets[c]; k < charts.offsets[c + 1]; ++k) ++seen[charts.triangles[k]];
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int v) { return v == 1; }));
    EXPECT_GE(charts.count(), s.triangleCount() / 300);
}

TEST(BakeCharts, SplitHalvesIntoConnectedPieces) {
    const Mesh grid = gridMesh(8);
    auto tris = allTriangles(grid);
    std::vector<std::vector<std::uint32_t>> out;
    bake::splitTriangles(grid.positions.data(), grid.indices.data(), tris.data(), tris.size(), out);
    ASSERT_EQ(out.size(), 2u);  // two halves of a square, each connected
    EXPECT_EQ(out[0].size() + out[1].size(), tris.size());
    EXPECT_EQ(out[0].size(), tris.size() / 2);
}
