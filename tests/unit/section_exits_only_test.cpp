// Closed bodies cut with exit points only (PlaneCut::exitsOnly, the default of
// computeSection): each crossing point computed once, at the triangle the ring leaves by.
// The sections must be those of the cut with both points of every segment, bit for bit.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "section/cut/contours.hpp"
#include "section/cut/plane_cut.hpp"
#include "section_test_util.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

Section sectionOf(const SectionIndex& idx, const Plane& p, bool exitsOnly, unsigned threads = 1) {
    SectionOptions o;
    o.exitsOnly = exitsOnly;
    o.threads = threads;
    auto s = computeSection(idx, p, o);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return s.ok() ? std::move(s).value() : Section{};
}

}  // namespace

TEST(SectionExitsOnly, SameSectionsAsBothPointsBitForBit) {
    // A ring's entry points are its exit points shifted by one, computed by the symmetric
    // edgeCrossing from the same values, so rings, areas and traces must be identical
    // (tolerance: none), on 1 and 2 threads (240k triangles: above the cut's two-thread
    // threshold, so the partner's exit segments are merged too).
    Model m = syntheticModel(240000, OreVariant::Nested, 5);
    auto idx = indexFor(m);
    std::mt19937_64 rng(23);
    for (int k = 0; k < 16; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        const Section both = sectionOf(*idx, p, false);
        EXPECT_FALSE(both.bodies.empty());
        expectSameSection(sectionOf(*idx, p, true), both, "plane " + std::to_string(k));
        expectSameSection(sectionOf(*idx, p, true, 2), both, "2 threads, plane " + std::to_string(k));
    }
    // Vertices, edges and whole faces in the plane (distance 0 counts as kept, so a ring may
    // pass a vertex twice and drop the repeat): nested boxes cut through the lens's faces (the
    // lens lies on the kept side: only the host is cut) and through both boxes' corners.
    const Model boxes = modelOf({makePart("host", PartKind::Body, 1, boxMesh({0, 0, 0}, {10, 10, 10})),
                                 makePart("lens", PartKind::Body, 2, boxMesh({2, 2, 2}, {6, 6, 6}))});
    auto bi = indexFor(boxes);
    const glm::dvec3 diag = glm::normalize(glm::dvec3(1, 1, 0)), anti = glm::normalize(glm::dvec3(1, -1, 0));
    for (const Plane& p : {Plane{{0, 0, 1}, -2.0}, Plane{{0, 0, -1}, 6.0}, Plane{{1, 0, 0}, -2.0},
                           Plane{diag, -glm::dot(diag, glm::dvec3(2, 2, 0))}, Plane{anti, 0.0}, Plane{-anti, 0.0}}) {
        const Section both = sectionOf(*bi, p, false);
        EXPECT_EQ(both.bodies.size(), p.d == 0.0 ? 2u : 1u);
        expectSameSection(sectionOf(*bi, p, true), both, "boxes");
    }
}

TEST(SectionExitsOnly, ExitSegmentsCarryTheirTrianglesEntryAndExit) {
    // The cut's exit segments against the full segments of the same cut: same count per
    // part, same keys and exit point, and the triangle id names a triangle of that part.
    Model m = syntheticModel(30000, OreVariant::Nested, 3);
    auto idx = indexFor(m);
    std::mt19937_64 rng(31);
    for (int k = 0; k < 6; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        PlaneCut both, exits;
        beginCut(*idx, p, both);
        beginCut(*idx, p, exits, true);
        cutWithBvh(*idx, nullptr, both);
        cutWithBvh(*idx, nullptr, exits);
        EXPECT_EQ(both.segments, exits.segments);
        for (std::size_t part = 0; part < idx->parts.size(); ++part) {
            if (part >= idx->bodyCount) {
                EXPECT_TRUE(exits.exits[part].empty());
                EXPECT_EQ(exits.parts[part].size(), both.parts[part].size());
                continue;
            }
            EXPECT_TRUE(exits.parts[part].empty()) << "closed body " << part;
            ASSERT_EQ(exits.exits[part].size(), both.parts[part].size()) << "part " << part;
            for (std::size_t i = 0; i < both.parts[part].size(); ++i) {
                const CutSegment& s = both.parts[part][i];
                const ExitSegment& e = exits.exits[part][i];
                EXPECT_TRUE(s.keyA == e.keyA && s.keyB == e.keyB && s.b == e.b) << "part " << part << " " << i;
                EXPECT_GE(e.triangle, idx->bvh.meshFirst[part]);
                EXPECT_LT(e.triangle, idx->bvh.meshFirst[part + 1]);
            }
        }
    }
}
