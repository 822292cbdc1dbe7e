// section/index/leaf_tables.hpp: the cut through the leaf tables gives, bit for bit and in the
// same order, the segments of cutting each leaf's triangles one by one from the mesh
// (cutTriangles, the per-triangle path the brute-force cut also takes).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "section/cut/plane_cut.hpp"
#include "section/index/leaf_tables.hpp"
#include "section_test_util.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

std::unique_ptr<SectionIndex> indexWithLeaves(const Model& m, unsigned leafSize) {
    BvhOptions o;
    o.maxLeafSize = leafSize;
    auto idx = buildSectionIndex(m, o);
    EXPECT_TRUE(idx.ok()) << (idx.ok() ? "" : idx.error().message);
    return std::move(idx).value();
}

// The triangles of the leaves cutWithBvh visits, in its order (units, then leaves under each).
std::vector<std::uint32_t> leafTriangles(const SectionIndex& idx, const LocalPlane& plane) {
    std::vector<std::uint32_t> units, leaves, tris;
    queryPlaneUnits(idx.bvh, plane, nullptr, 32, units);
    for (std::uint32_t u : units) queryPlaneLeavesUnder(idx.bvh, u, plane, nullptr, leaves);
    for (std::uint32_t l : leaves) {
        const BvhNode& nd = idx.bvh.nodes[l];
        tris.insert(tris.end(), idx.bvh.triangles.begin() + nd.first, idx.bvh.triangles.begin() + nd.first + nd.count);
    }
    return tris;
}

// Tolerance: none. Same keys, same point bits, same order, part by part.
void expectSameCut(const PlaneCut& a, const PlaneCut& b, const std::string& what) {
    ASSERT_EQ(a.segments, b.segments) << what;
    for (std::size_t p = 0; p < a.parts.size(); ++p) {
        ASSERT_EQ(a.parts[p].size(), b.parts[p].size()) << what << " part " << p;
        for (std::size_t i = 0; i < a.parts[p].size(); ++i) {
            const CutSegment &x = a.parts[p][i], &y = b.parts[p][i];
            ASSERT_TRUE(x.keyA == y.keyA && x.keyB == y.keyB && x.a == y.a && x.b == y.b)
                << what << " part " << p << " segment " << i;
        }
        ASSERT_EQ(a.exits[p].size(), b.exits[p].size()) << what << " part " << p;
        for (std::size_t i = 0; i < a.exits[p].size(); ++i) {
            const ExitSegment &x = a.exits[p][i], &y = b.exits[p][i];
            ASSERT_TRUE(x.keyA == y.keyA && x.keyB == y.keyB && x.b == y.b && x.triangle == y.triangle)
                << what << " part " << p << " exit " << i;
        }
    }
}

void expectTablesCutLikeTriangles(const SectionIndex& idx, const std::vector<Plane>& planes, const std::string& what) {
    for (std::size_t k = 0; k < planes.size(); ++k)
        for (bool exits : {false, true}) {
            PlaneCut viaTables, viaTriangles;
            beginCut(idx, planes[k], viaTables, exits);
            beginCut(idx, planes[k], viaTriangles, exits);
            cutWithBvh(idx, nullptr, viaTables, 1);
            const std::vector<std::uint32_t> tris = leafTriangles(idx, viaTriangles.plane);
            cutTriangles(idx, tris.data(), tris.size(), viaTriangles);
            expectSameCut(viaTables, viaTriangles,
                          what + " plane " + std::to_string(k) + (exits ? " exits only" : " both points"));
            // And on two threads (the partner's chunks appended in order).
            PlaneCut two;
            beginCut(idx, planes[k], two, exits);
            cutWithBvh(idx, nullptr, two, 2);
            expectSameCut(two, viaTriangles, what + " two threads plane " + std::to_string(k));
        }
}

// Random planes, plus horizontal and vertical planes exactly through vertices (distance 0:
// the sign rule's tie) of the model.
std::vector<Plane> planesThrough(const Model& m, int count, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Plane> planes;
    for (int k = 0; k < count; ++k) planes.push_back(randomPlane(m.bounds(), rng, k));
    const Mesh& mesh = m.bodies.empty() ? m.surfaces[0].mesh : m.bodies[0].mesh;
    for (std::size_t i = 0; i < 4 && i < mesh.positions.size(); ++i) {
        const glm::dvec3 w = mesh.positions[i * mesh.positions.size() / 4] + m.origin;
        planes.push_back(makePlane(0, 0, 1, -w.z).value());
        planes.push_back(makePlane(1, 0, 0, -w.x).value());
    }
    return planes;
}

}  // namespace

TEST(SectionLeafTables, CutEqualsEachLeafsTrianglesCutOneByOne) {
    // Strata sharing faces (leaves mixing parts), a nested lens, at leaf sizes 1, 8 and 64
    // (up to 192 distinct vertices a leaf).
    const Model m = syntheticModel(30000, OreVariant::Nested, 3);
    for (unsigned leaf : {1u, 8u, 64u}) {
        auto idx = indexWithLeaves(m, leaf);
        expectTablesCutLikeTriangles(*idx, planesThrough(m, 12, leaf), "leaf " + std::to_string(leaf));
    }
}

TEST(SectionLeafTables, WeldedAndDegenerateTrianglesOfASurface) {
    // A surface whose triangles each have their own three vertices (the weld joins them), with
    // degenerate triangles (two corners at one position: left out of the tables, and cutOne
    // skips them), beside a closed box.
    Mesh sheet;
    const int n = 24;
    auto at = [&](int i, int j) { return glm::dvec3(i * 1.0, j * 1.0, 0.3 * std::sin(0.7 * i) + 0.2 * j); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const glm::dvec3 quad[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
            constexpr int kHalves[2][3] = {{0, 1, 2}, {0, 2, 3}};
            for (const auto& t : kHalves) {
                const auto base = static_cast<std::uint32_t>(sheet.positions.size());
                for (int k = 0; k < 3; ++k) sheet.positions.push_back(quad[t[k]]);
                sheet.indices.insert(sheet.indices.end(), {base, base + 1, base + 2});
            }
            if ((i + j) % 5 == 0) {  // degenerate: corners 0 and 2 at one position
                const auto base = static_cast<std::uint32_t>(sheet.positions.size());
                sheet.positions.insert(sheet.positions.end(), {quad[0], quad[1], quad[0]});
                sheet.indices.insert(sheet.indices.end(), {base, base + 1, base + 2});
            }
        }
    Model m = modelOf({makePart("box", PartKind::Body, 1, boxMesh({2.5, 2.5, -3.0}, {9.5, 9.5, 7.0}))},
                      {makePart("sheet", PartKind::Surface, 2, sheet)});
    for (unsigned leaf : {1u, 8u, 64u}) {
        auto idx = indexWithLeaves(m, leaf);
        ASSERT_FALSE(idx->parts[1].canon.empty());  // the weld joined the sheet's vertices
        expectTablesCutLikeTriangles(*idx, planesThrough(m, 16, 100 + leaf), "sheet leaf " + std::to_string(leaf));
    }
}

TEST(SectionLeafTables, EveryLeafListsItsNonDegenerateTrianglesOnce) {
    // The tables against the tree: runs of consecutive triangles of one part covering the
    // leaf's triangles less the degenerate ones, distinct welded vertices per run, corner
    // bytes naming a vertex of the triangle's own run whose position is the corner's.
    const Model m = syntheticModel(20000, OreVariant::Partition, 2);
    auto idx = indexWithLeaves(m, 8);
    const LeafTables& t = idx->leafTables;
    std::size_t leaves = 0, listed = 0;
    for (std::size_t n = 0; n < idx->bvh.nodes.size(); ++n) {
        const BvhNode& nd = idx->bvh.nodes[n];
        if (nd.count == 0) continue;
        ++leaves;
        const std::uint32_t* w = t.table(n);
        const std::uint32_t runs = w[0] & 0xFFu, vertices = (w[0] >> 8) & 0xFFu, triangles = (w[0] >> 16) & 0xFFu;
        ASSERT_LE(vertices, LeafTables::kMaxVertices);
        std::vector<std::uint32_t> ids;
        const std::uint32_t* vertex = w + 1 + 3 * runs;
        std::uint32_t v0 = 0, c = 0, tri = 0;
        for (std::uint32_t r = 0; r < runs; ++r) {
            const std::uint32_t part = w[1 + 3 * r], first = w[2 + 3 * r], nt = w[3 + 3 * r] & 0xFFu,
                                nv = w[3 + 3 * r] >> 8;
            const SectionPart& sp = idx->parts[part];
            std::vector<std::uint32_t> runVertices(vertex + v0, vertex + v0 + nv);
            std::sort(runVertices.begin(), runVertices.end());
            EXPECT_TRUE(std::adjacent_find(runVertices.begin(), runVertices.end()) == runVertices.end());
            for (std::uint32_t i = 0; i < nt; ++i, ++tri) {
                ids.push_back(idx->bvh.meshFirst[part] + first + i);
                const std::uint32_t* corners = sp.part->mesh.indices.data() + 3 * std::size_t(first + i);
                for (int k = 0; k < 3; ++k, ++c) {
                    const std::uint32_t b = (w[1 + 3 * runs + vertices + c / 4] >> (8 * (c % 4))) & 0xFFu;
                    ASSERT_TRUE(b >= v0 && b < v0 + nv) << "leaf " << n;
                    EXPECT_EQ(vertex[b], sp.weld(corners[k]));
                    EXPECT_EQ(sp.part->mesh.positions[vertex[b]], sp.part->mesh.positions[corners[k]]);
                }
            }
            v0 += nv;
        }
        EXPECT_EQ(v0, vertices);
        EXPECT_EQ(tri, triangles);
        std::vector<std::uint32_t> expected;
        for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
            const std::uint32_t id = idx->bvh.triangles[i];
            const std::uint32_t p = idx->bvh.meshOf(id);
            const SectionPart& sp = idx->parts[p];
            const std::uint32_t* tr = sp.part->mesh.indices.data() + 3 * std::size_t(id - idx->bvh.meshFirst[p]);
            const std::uint32_t a = sp.weld(tr[0]), b = sp.weld(tr[1]), cc = sp.weld(tr[2]);
            if (a != b && b != cc && a != cc) expected.push_back(id);
        }
        EXPECT_EQ(ids, expected) << "leaf " << n;
        listed += ids.size();
    }
    EXPECT_GT(leaves, 1000u);
    EXPECT_EQ(listed, m.triangleCount());  // the generator makes no degenerate triangles
}
