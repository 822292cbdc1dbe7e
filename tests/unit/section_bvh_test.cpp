// The section BVH: plane and plane+rectangle queries against brute force, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "section/index/bvh.hpp"
#include "section_test_util.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

// Global ids of the triangles crossing the plane, by brute force (same sign rule).
std::vector<std::uint32_t> bruteCrossing(const SectionIndex& idx, const LocalPlane& lp) {
    std::vector<std::uint32_t> out;
    for (std::size_t m = 0; m < idx.meshes.size(); ++m) {
        const BvhMesh& mesh = idx.meshes[m];
        for (std::size_t t = 0; t < mesh.triangleCount; ++t) {
            int pos = 0;
            for (int k = 0; k < 3; ++k)
                pos += lp.distanceWorld(mesh.positions[mesh.indices[3 * t + static_cast<std::size_t>(k)]],
                                        idx.origin) >= 0.0;
            if (pos == 1 || pos == 2) out.push_back(idx.bvh.meshFirst[m] + static_cast<std::uint32_t>(t));
        }
    }
    return out;
}

}  // namespace

TEST(SectionBvh, PlaneQueryEqualsBruteForce) {
    Model m = syntheticModel(20000);
    // Leaves of 8 (the default is 64): 4,096 nodes, enough for the pruning check below.
    BvhOptions small;
    small.maxLeafSize = 8;
    auto built = buildSectionIndex(m, small);
    ASSERT_TRUE(built.ok());
    auto idx = std::move(built).value();
    EXPECT_EQ(idx->bvh.triangles.size(), m.triangleCount());
    std::mt19937_64 rng(1);
    for (int k = 0; k < 40; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        const LocalPlane lp = toLocal(p, m.origin);
        std::vector<std::uint32_t> got;
        BvhQueryStats st;
        queryPlane(idx->bvh, idx->meshes.data(), lp, got, &st);
        std::sort(got.begin(), got.end());
        const auto want = bruteCrossing(*idx, lp);
        EXPECT_EQ(got, want) << "plane " << k;
        EXPECT_LT(st.nodesVisited, idx->bvh.nodes.size() / 2) << "the query should skip most nodes";
    }
}

TEST(SectionBvh, RectQueryKeepsEveryTriangleInTheRectangle) {
    Model m = syntheticModel(20000);
    auto idx = indexFor(m);
    std::mt19937_64 rng(2);
    for (int k = 0; k < 20; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        const SectionFrame f = makeSectionFrame(p, m.origin);
        const LocalPlane lp = toLocal(p, m.origin);
        PlaneRect r;
        r.originLocal = f.originLocal;
        r.u = f.u;
        r.v = f.v;
        r.u0 = -500.0;
        r.u1 = 300.0;
        r.v0 = -200.0;
        r.v1 = 100.0;
        std::vector<std::uint32_t> got;
        queryPlaneRect(idx->bvh, idx->meshes.data(), lp, r, got);
        std::sort(got.begin(), got.end());
        std::size_t expected = 0, missing = 0;
        for (std::uint32_t id : bruteCrossing(*idx, lp)) {
            const std::uint32_t mi = idx->bvh.meshOf(id);
            const BvhMesh& mesh = idx->meshes[mi];
            const std::size_t t = id - idx->bvh.meshFirst[mi];
            glm::dvec2 lo(1e300), hi(-1e300);
            for (int c = 0; c < 3; ++c) {
                const glm::dvec2 uv =
                    f.toPlane(mesh.positions[mesh.indices[3 * t + static_cast<std::size_t>(c)]] - m.origin);
                lo = glm::min(lo, uv);
                hi = glm::max(hi, uv);
            }
            if (hi.x < r.u0 || lo.x > r.u1 || hi.y < r.v0 || lo.y > r.v1) continue;
            ++expected;
            missing += !std::binary_search(got.begin(), got.end(), id);
        }
        EXPECT_EQ(missing, 0u) << "plane " << k;
        EXPECT_EQ(got.size(), expected) << "plane " << k;
    }
}

TEST(SectionBvh, DeterministicAcrossThreadCounts) {
    Model m = syntheticModel(200000);
    std::vector<BvhMesh> meshes;
    for (const auto* list : {&m.bodies, &m.surfaces})
        for (const Part& p : *list)
            meshes.push_back(
                {p.mesh.positions.data(), p.mesh.positions.size(), p.mesh.indices.data(), p.mesh.triangleCount()});
    BvhOptions one, two;
    one.threads = 1;
    two.threads = 2;
    auto a = buildBvh(meshes.data(), meshes.size(), m.origin, one);
    auto b = buildBvh(meshes.data(), meshes.size(), m.origin, two);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->triangles, b->triangles);
    ASSERT_EQ(a->nodes.size(), b->nodes.size());
    EXPECT_EQ(std::memcmp(a->nodes.data(), b->nodes.data(), a->nodes.size() * sizeof(BvhNode)), 0);
    // Every node's box holds its children's and its triangles (in the local frame).
    for (std::size_t ni = 0; ni < a->nodes.size(); ++ni) {
        if (ni == 1) continue;  // padding
        const BvhNode& n = a->nodes[ni];
        if (n.count == 0) {
            for (std::uint32_t c : {n.first, n.first + 1})
                for (int k = 0; k < 3; ++k) {
                    EXPECT_LE(n.lo[k], a->nodes[c].lo[k]);
                    EXPECT_GE(n.hi[k], a->nodes[c].hi[k]);
                }
            continue;
        }
        for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
            const std::uint32_t id = a->triangles[i];
            const std::uint32_t mi = a->meshOf(id);
            const std::size_t t = id - a->meshFirst[mi];
            for (int c = 0; c < 3; ++c) {
                const glm::dvec3 p =
                    meshes[mi].positions[meshes[mi].indices[3 * t + static_cast<std::size_t>(c)]] - m.origin;
                for (int k = 0; k < 3; ++k) {
                    ASSERT_LE(double(n.lo[k]), p[k]);
                    ASSERT_GE(double(n.hi[k]), p[k]);
                }
            }
        }
    }
    // Each leaf lists its triangle ids in ascending order (a leaf-ordered mesh is read forwards).
    for (std::size_t ni = 2; ni < a->nodes.size(); ++ni) {
        const BvhNode& n = a->nodes[ni];
        if (n.count == 0) continue;
        EXPECT_TRUE(std::is_sorted(a->triangles.begin() + n.first, a->triangles.begin() + n.first + n.count))
            << "leaf " << ni;
    }
    BvhOptions bad;
    bad.maxLeafSize = 0;
    EXPECT_FALSE(buildBvh(meshes.data(), meshes.size(), m.origin, bad).ok());
}
