// The edge walk over the triangle adjacency (section/adjacency.hpp): the table against an
// independent map of directed edges, its bytes, and sections walked against sections
// chained from segments (bit for bit), with a table that does not fit its mesh too.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <string>
#include <utility>

#include "section/adjacency.hpp"
#include "section/contours.hpp"
#include "section_test_util.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

Section sectionOf(const SectionIndex& idx, const Plane& p, bool walk, unsigned threads = 1) {
    SectionOptions o;
    o.edgeWalk = walk;
    o.threads = threads;
    auto s = computeSection(idx, p, o);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return s.ok() ? std::move(s).value() : Section{};
}

}  // namespace

TEST(SectionEdgeWalk, AdjacencyIsEveryEdgesTwin) {
    // Oracle: a map from each directed edge (a, b) to its triangle and corner; the twin of
    // edge k of t is the entry of (b, a). Every entry of every walkable body must name it.
    Model m = syntheticModel(20000, OreVariant::Nested, 3);
    auto idx = indexFor(m);
    const TriangleAdjacency& adj = idx->adjacency;
    ASSERT_EQ(adj.walkable.size(), m.bodies.size());
    for (std::size_t p = 0; p < m.bodies.size(); ++p) {
        ASSERT_TRUE(adj.walkablePart(p)) << "body " << p << " of a validated closed model";
        const Mesh& mesh = m.bodies[p].mesh;
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edges;
        for (std::uint32_t c = 0; c < mesh.indices.size(); ++c)
            edges[{mesh.indices[c], mesh.indices[c % 3 == 2 ? c - 2 : c + 1]}] = c;
        const std::uint32_t* e = adj.across.data() + 3 * std::size_t(idx->bvh.meshFirst[p]);
        for (std::uint32_t c = 0; c < mesh.indices.size(); ++c) {
            const auto twin = edges.find({mesh.indices[c % 3 == 2 ? c - 2 : c + 1], mesh.indices[c]});
            ASSERT_NE(twin, edges.end());
            ASSERT_EQ(e[c], 4 * (twin->second / 3) + twin->second % 3) << "body " << p << " corner " << c;
        }
    }
    // A box with its top removed has edges with one triangle: not walkable.
    Mesh box = boxMesh({0, 0, 0}, {10, 10, 10});
    box.indices.erase(box.indices.begin() + 6, box.indices.begin() + 12);
    auto open = indexFor(modelOf({makePart("box", PartKind::Body, 1, box)}));
    EXPECT_FALSE(open->adjacency.walkablePart(0));
}

TEST(SectionEdgeWalk, SameSectionsAsChainedSegmentsBitForBit) {
    // The walk computes each crossing once and follows the joins the segment chaining makes,
    // so rings, areas and traces must be identical (tolerance: none), on 1 and 2 threads
    // (240k triangles: above the cut's two-thread threshold).
    Model m = syntheticModel(240000, OreVariant::Nested, 5);
    auto idx = indexFor(m);
    std::mt19937_64 rng(23);
    for (int k = 0; k < 16; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        const Section chained = sectionOf(*idx, p, false);
        expectSameSection(sectionOf(*idx, p, true), chained, "plane " + std::to_string(k));
        expectSameSection(sectionOf(*idx, p, true, 2), chained, "2 threads, plane " + std::to_string(k));
    }
    // Vertices and whole faces in the plane (distance 0 counts as kept): nested boxes cut
    // through their corners, their faces and across.
    Mesh outer = boxMesh({0, 0, 0}, {10, 10, 10});
    Mesh inner = boxMesh({2, 2, 2}, {6, 6, 6});
    const Model boxes =
        modelOf({makePart("host", PartKind::Body, 1, outer), makePart("lens", PartKind::Body, 2, inner)});
    auto bi = indexFor(boxes);
    ASSERT_TRUE(bi->adjacency.walkablePart(0) && bi->adjacency.walkablePart(1));
    const glm::dvec3 diag = glm::normalize(glm::dvec3(1, 1, 0));
    for (const Plane& p : {Plane{{0, 0, 1}, -2.0}, Plane{{0, 0, -1}, 6.0}, Plane{{1, 0, 0}, -2.0},
                           Plane{diag, -glm::dot(diag, glm::dvec3(2, 2, 0))}}) {
        const Section chained = sectionOf(*bi, p, false);
        EXPECT_FALSE(chained.bodies.empty());
        expectSameSection(sectionOf(*bi, p, true), chained, "boxes");
    }
}

TEST(SectionEdgeWalk, ATableThatDoesNotFitItsMeshFallsBackToSegments) {
    // Entries pointing at the wrong triangle (rotated within a body, out of range, or a
    // neighbour's neighbour) are caught by the walk's per-step check: the part is chained from
    // segments instead, so the section is the same bit for bit.
    Model m = syntheticModel(30000, OreVariant::Nested, 7);
    auto idx = indexFor(m);
    std::mt19937_64 rng(29);
    std::vector<Plane> planes;
    std::vector<Section> expected;
    for (int k = 0; k < 6; ++k) {
        planes.push_back(randomPlane(m.bounds(), rng, k));
        expected.push_back(sectionOf(*idx, planes.back(), false));
    }
    std::vector<std::uint32_t>& e = idx->adjacency.across;
    const std::size_t n = 3 * std::size_t(idx->bvh.meshFirst[1]);  // body 0's entries
    for (std::size_t i = 0; i < n; i += 7) e[i] = e[(i + 3) % n];
    e[1] = 0xFFFFFFF0u;
    for (std::size_t k = 0; k < planes.size(); ++k)
        expectSameSection(sectionOf(*idx, planes[k], true), expected[k], "plane " + std::to_string(k));
}

TEST(SectionEdgeWalk, SavedTableLoadsTheSameAndBadBytesAreErrors) {
    Model m = syntheticModel(8000, OreVariant::Nested, 2);
    auto idx = indexFor(m);
    const std::vector<std::uint8_t> bytes = saveTriangleAdjacency(idx->adjacency);
    EXPECT_EQ(bytes.size(), 32 + (m.bodies.size() + 3) / 4 * 4 + 4 * idx->adjacency.across.size());
    auto back = loadTriangleAdjacency(bytes, *idx, "t.adj");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->across, idx->adjacency.across);
    EXPECT_EQ(back->walkable, idx->adjacency.walkable);
    auto expectError = [&](std::vector<std::uint8_t> b, const std::string& what) {
        auto r = loadTriangleAdjacency(b, *idx, "t.adj");
        ASSERT_FALSE(r.ok()) << what;
        EXPECT_EQ(r.error().code, ErrorCode::ParseError) << what;
        EXPECT_NE(r.error().message.find("t.adj"), std::string::npos) << r.error().message;
    };
    expectError({}, "empty");
    expectError(std::vector<std::uint8_t>(bytes.begin(), bytes.end() - 4), "truncated");
    auto badMagic = bytes;
    badMagic[0] = 'X';
    expectError(badMagic, "magic");
    auto badCount = bytes;
    badCount[8] += 1;
    expectError(badCount, "body count");
    auto badFlag = bytes;
    badFlag[32] = 2;
    expectError(badFlag, "flag");
    // A body that is not closed cannot be marked walkable.
    idx->parts[0].closed = false;
    expectError(bytes, "open body marked walkable");
}
