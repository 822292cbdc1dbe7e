// The cluster hierarchy of a GpuModel part, without a GL context (renderer/lod/cluster_build.hpp).
// Oracle: the definitions written out again here: a cluster holds exactly the part's triangles
// whose centroid falls in its cell, in input order; a cell's bounds are exactly the bounds of
// its triangles' vertices; simplified levels and groups only use vertices of the clusters they
// replace, shrink, and carry a non-negative error that never decreases from level to level.
// No tolerances: every comparison is exact (integers, or the same float -> double values).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <vector>

#include "renderer/lod/cluster_build.hpp"

using namespace geoslice;

namespace {

// A height field of n x n quads over [0, 100]^2 m with hills (z up to 5 m), so that
// simplification has something to remove and a non-zero error.
struct Sheet {
    std::vector<glm::vec3> local;
    std::vector<std::uint32_t> indices;
};

Sheet heightField(int n) {
    Sheet s;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = 100.0 * i / n, y = 100.0 * j / n;
            s.local.emplace_back(x, y, 5.0 * std::sin(x * 0.07) * std::cos(y * 0.05));
        }
    auto v = [&](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            s.indices.insert(s.indices.end(), {v(i, j), v(i + 1, j), v(i + 1, j + 1)});
            s.indices.insert(s.indices.end(), {v(i, j), v(i + 1, j + 1), v(i, j + 1)});
        }
    return s;
}

Aabb boundsOf(const std::vector<glm::vec3>& p) {
    Aabb b;
    for (const auto& q : p) b.extend(glm::dvec3(q));
    return b;
}

struct Built {
    CellGrid grid;
    GpuModel::DrawPart part;
    std::vector<std::uint32_t> sorted, lodIndices;
    std::vector<Aabb> cellBounds;
};

Built build(const Sheet& s, bool lod, std::size_t firstIndex) {
    Built b;
    b.grid = makeGrid(boundsOf(s.local), s.indices.size() / 3, 256, 1024);
    b.cellBounds.assign(b.grid.count(), Aabb{});
    b.part.firstIndex = firstIndex;
    std::vector<std::uint32_t> remap;
    buildClusters(b.grid, s.local, s.indices, lod, 5, b.part, b.sorted, b.lodIndices, b.cellBounds, remap);
    return b;
}

std::uint32_t cellOfTriangle(const CellGrid& g, const Sheet& s, const std::uint32_t* t) {
    return g.cellOf((glm::dvec3(s.local[t[0]]) + glm::dvec3(s.local[t[1]]) + glm::dvec3(s.local[t[2]])) / 3.0);
}

}  // namespace

TEST(ClusterBuild, ClustersAreTheTrianglesOfTheirCellInInputOrder) {
    const Sheet s = heightField(60);  // 7200 triangles
    const std::size_t first = 1000;   // where the part would start in the index buffer
    const Built b = build(s, false, first);
    ASSERT_GT(b.grid.count(), 4u);
    ASSERT_EQ(b.sorted.size(), s.indices.size());
    // The oracle: the input triangles grouped by cell, input order kept within a cell.
    std::vector<std::vector<std::array<std::uint32_t, 3>>> byCell(b.grid.count());
    for (std::size_t t = 0; t < s.indices.size(); t += 3)
        byCell[cellOfTriangle(b.grid, s, &s.indices[t])].push_back({s.indices[t], s.indices[t + 1], s.indices[t + 2]});
    std::size_t expectedClusters = 0;
    for (const auto& c : byCell) expectedClusters += !c.empty();
    ASSERT_EQ(b.part.clusters.size(), expectedClusters);
    std::size_t at = first;
    std::uint32_t lastCell = 0;
    for (std::size_t k = 0; k < b.part.clusters.size(); ++k) {
        const auto& cl = b.part.clusters[k];
        if (k) {
            EXPECT_GT(cl.cell, lastCell);  // cells in increasing order, no cell twice
        }
        lastCell = cl.cell;
        EXPECT_EQ(cl.levels, 1);
        EXPECT_EQ(cl.first[0], at);  // clusters tile the part's range without gaps
        const auto& expect = byCell[cl.cell];
        ASSERT_EQ(std::size_t(cl.count[0]), 3 * expect.size());
        for (std::size_t t = 0; t < expect.size(); ++t)
            for (int e = 0; e < 3; ++e) EXPECT_EQ(b.sorted[cl.first[0] - first + 3 * t + e], expect[t][e]);
        // The cell's bounds are exactly those of its triangles' vertices.
        Aabb bounds;
        for (const auto& t : expect)
            for (std::uint32_t v : t) bounds.extend(glm::dvec3(s.local[v]));
        EXPECT_EQ(b.cellBounds[cl.cell].min, bounds.min);
        EXPECT_EQ(b.cellBounds[cl.cell].max, bounds.max);
        at += std::size_t(cl.count[0]);
    }
    EXPECT_EQ(at, first + s.indices.size());
    EXPECT_TRUE(b.part.groups.empty());
    EXPECT_TRUE(b.lodIndices.empty());
}

TEST(ClusterBuild, LevelsAndGroupsUseOnlyTheirClustersVerticesAndCoarsen) {
    const Sheet s = heightField(120);  // 28800 triangles: clusters large enough to simplify
    const std::size_t first = 0;
    const Built lodBuilt = build(s, true, first);
    const Built plain = build(s, false, first);
    // Level 0 does not depend on the level of detail.
    EXPECT_EQ(lodBuilt.sorted, plain.sorted);
    ASSERT_EQ(lodBuilt.part.clusters.size(), plain.part.clusters.size());
    auto verticesOf = [&](const GpuModel::DrawPart::Cluster& c) {
        return std::set<std::uint32_t>(lodBuilt.sorted.begin() + std::ptrdiff_t(c.first[0] - first),
                                       lodBuilt.sorted.begin() + std::ptrdiff_t(c.first[0] - first + c.count[0]));
    };
    std::size_t simplified = 0;
    for (const auto& c : lodBuilt.part.clusters) {
        const std::set<std::uint32_t> own = verticesOf(c);
        EXPECT_EQ(c.error[0], 0.0f);
        for (int l = 1; l < c.levels; ++l) {
            ++simplified;
            ASSERT_LE(c.first[l] + std::size_t(c.count[l]), lodBuilt.lodIndices.size());
            EXPECT_EQ(c.count[l] % 3, 0);
            EXPECT_LT(c.count[l], c.count[l - 1]);    // each level is coarser
            EXPECT_GE(c.error[l], c.error[l - 1]);    // errors accumulate
            for (GLsizei i = 0; i < c.count[l]; ++i)  // a simplified copy uses its cluster's vertices only
                EXPECT_TRUE(own.count(lodBuilt.lodIndices[c.first[l] + std::size_t(i)]));
        }
    }
    EXPECT_GT(simplified, 0u);
    ASSERT_FALSE(lodBuilt.part.groups.empty());
    for (const auto& g : lodBuilt.part.groups) {
        ASSERT_GE(g.members.size(), 2u);
        ASSERT_LE(g.first + std::size_t(g.count), lodBuilt.lodIndices.size());
        EXPECT_GT(g.count, 0);
        EXPECT_EQ(g.count % 3, 0);
        EXPECT_GE(g.error, 0.0f);
        std::set<std::uint32_t> members;
        std::size_t memberTriangles = 0;
        for (std::uint32_t m : g.members) {
            ASSERT_LT(m, lodBuilt.part.clusters.size());
            const auto own = verticesOf(lodBuilt.part.clusters[m]);
            members.insert(own.begin(), own.end());
            memberTriangles += std::size_t(lodBuilt.part.clusters[m].count[0]);
        }
        EXPECT_LT(std::size_t(g.count), memberTriangles);  // coarser than its members at full detail
        for (GLsizei i = 0; i < g.count; ++i) EXPECT_TRUE(members.count(lodBuilt.lodIndices[g.first + std::size_t(i)]));
    }
}
