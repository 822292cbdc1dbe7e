// Plane cuts and closed contours: degenerate positions (vertices on the plane, faces in
// the plane, shared edges), analytic areas, nesting, traces, and random planes through
// generated models against an independent brute-force cut.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "section/cut/contours.hpp"
#include "section/cut/plane_cut.hpp"
#include "section_test_util.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
// Square metres, areas from coordinates of tens of metres: exact up to rounding of the
// shoelace sums (~1e-13 m^2 there), with margin.
constexpr double kAreaTolM2 = 1e-9;
// Square metres, areas of shapes with whole or unit-scale coordinates (and zero areas): a few
// double steps.
constexpr double kExactAreaTolM2 = 1e-12;
// Square metres, areas of about 1e4 m^2: relative 1e-12 of rounding.
constexpr double kLargeAreaTolM2 = 1e-8;
// Relative: the inscribed UV sphere's cut disc is short of the true sphere's by about twice
// r (1 - cos(pi/128)) = 3e-4 r, more off-centre.
constexpr double kUvSphereRelTol = 2e-3;
// Relative: our cut against the brute-force cut of the same triangles, both double.
constexpr double kSameCutRelTol = 1e-9;
// Relative: per-body areas against an independent brute-force cut (observed ~1e-12).
constexpr double kBruteForceRelTol = 1e-6;
// Metres, a trace length of 10 m from coordinates under 10 m: rounding only.
constexpr double kTraceTolM = 1e-9;

Section cut(const SectionIndex& idx, const Plane& p) {
    auto s = computeSection(idx, p);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return s.ok() ? std::move(s).value() : Section{};
}

double totalArea(const Section& s) {
    double a = 0.0;
    for (const auto& b : s.bodies) a += b.area;
    return a;
}

}  // namespace

TEST(SectionContours, BoxHorizontalAndTilted) {
    Model m = modelOf({makePart("box", PartKind::Body, 7, boxMesh({0, 0, 0}, {10, 20, 5}))});
    auto idx = indexFor(m);
    Section s = cut(*idx, Plane{{0, 0, 1}, -2.5});
    ASSERT_EQ(s.bodies.size(), 1u);
    EXPECT_EQ(s.bodies[0].record, 7u);
    EXPECT_EQ(s.bodies[0].openChains, 0u);
    ASSERT_EQ(s.bodies[0].polygons.size(), 1u);
    EXPECT_TRUE(s.bodies[0].polygons[0].holes.empty());
    EXPECT_NEAR(s.bodies[0].area, 200.0, kAreaTolM2);         // exact up to rounding
    EXPECT_GT(ringArea(s.bodies[0].polygons[0].outer), 0.0);  // outer rings counter-clockwise

    // Tilted across all four vertical edges: area = base / |n_z|.
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.05, -0.08, 1.0));
    Section t = cut(*idx, Plane{n, -glm::dot(n, glm::dvec3(5, 10, 2.5))});
    ASSERT_EQ(t.bodies.size(), 1u);
    EXPECT_NEAR(t.bodies[0].area, 200.0 / n.z, kAreaTolM2);
}

TEST(SectionContours, VerticesExactlyOnThePlane) {
    // Box [-1,1]^3 (origin 0), plane x = y through two vertical edges: a 2*sqrt(2) x 2 rectangle.
    Model m = modelOf({makePart("box", PartKind::Body, 1, boxMesh({-1, -1, -1}, {1, 1, 1}))});
    auto idx = indexFor(m);
    for (double sign : {1.0, -1.0}) {
        const glm::dvec3 n = sign * glm::normalize(glm::dvec3(1, -1, 0));
        Section s = cut(*idx, Plane{n, 0.0});
        ASSERT_EQ(s.bodies.size(), 1u);
        EXPECT_EQ(s.bodies[0].openChains, 0u);
        EXPECT_NEAR(s.bodies[0].area, 4.0 * std::sqrt(2.0), kExactAreaTolM2);
    }
    // A plane that only touches a corner: nothing (or a degenerate point), area 0.
    for (double sign : {1.0, -1.0}) {
        const glm::dvec3 n = sign * glm::normalize(glm::dvec3(1, 1, 1));
        auto s = computeSection(*idx, Plane{n, -sign * std::sqrt(3.0)});
        if (s.ok()) {
            EXPECT_NEAR(totalArea(s.value()), 0.0, kExactAreaTolM2);
        }
    }
    // Horizontal plane through the middle ring of an octahedron-like double pyramid:
    // vertices exactly on the plane, 4 of them.
    Mesh oct;
    oct.positions = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (std::uint32_t i = 0; i < 4; ++i) {
        const std::uint32_t j = (i + 1) % 4;
        oct.indices.insert(oct.indices.end(), {i, j, 4u, j, i, 5u});
    }
    Model mo = modelOf({makePart("oct", PartKind::Body, 1, oct)});
    auto io = indexFor(mo);
    for (double nz : {1.0, -1.0}) {
        Section s = cut(*io, Plane{{0, 0, nz}, 0.0});
        ASSERT_EQ(s.bodies.size(), 1u);
        EXPECT_EQ(s.bodies[0].openChains, 0u);
        EXPECT_NEAR(s.bodies[0].area, 2.0, kExactAreaTolM2);  // the square |x| + |y| <= 1
    }
}

TEST(SectionContours, CoplanarFacesFollowTheSymbolicRule) {
    // Two stacked boxes share the face z = 10. The cut by z = 10 belongs to the body on the
    // removed side (the plane moves infinitesimally that way), exactly once.
    Model m = modelOf({makePart("low", PartKind::Body, 1, boxMesh({0, 0, 0}, {10, 10, 10})),
                       makePart("high", PartKind::Body, 2, boxMesh({0, 0, 10}, {10, 10, 20}))});
    auto idx = indexFor(m);
    Section up = cut(*idx, Plane{{0, 0, 1}, -10.0});  // keeps z >= 10: removed side is below
    EXPECT_NEAR(bodyArea(up, 0), 100.0, kExactAreaTolM2);
    EXPECT_NEAR(bodyArea(up, 1), 0.0, kExactAreaTolM2);
    Section down = cut(*idx, Plane{{0, 0, -1}, 10.0});  // keeps z <= 10
    EXPECT_NEAR(bodyArea(down, 0), 0.0, kExactAreaTolM2);
    EXPECT_NEAR(bodyArea(down, 1), 100.0, kExactAreaTolM2);
    for (const auto& b : up.bodies) EXPECT_EQ(b.openChains, 0u);
    for (const auto& b : down.bodies) EXPECT_EQ(b.openChains, 0u);
    // A vertical plane along the shared side faces of two boxes side by side.
    Model side = modelOf({makePart("w", PartKind::Body, 1, boxMesh({0, 0, 0}, {10, 10, 10})),
                          makePart("e", PartKind::Body, 2, boxMesh({10, 0, 0}, {20, 10, 10}))});
    auto is = indexFor(side);
    Section east = cut(*is, Plane{{1, 0, 0}, -10.0});
    EXPECT_NEAR(bodyArea(east, 0), 100.0, kExactAreaTolM2);
    EXPECT_NEAR(bodyArea(east, 1), 0.0, kExactAreaTolM2);
}

TEST(SectionContours, SphereAgainstAnalyticAndBruteForce) {
    const double r = 50.0;
    Model m = modelOf({makePart("ball", PartKind::Body, 3, sphereMesh({100, 200, 300}, r, 256, 128))});
    auto idx = indexFor(m);
    std::mt19937_64 rng(5);
    for (int k = 0; k < 10; ++k) {
        const glm::dvec3 n = glm::normalize(glm::dvec3(
            std::normal_distribution<>()(rng), std::normal_distribution<>()(rng), std::normal_distribution<>()(rng)));
        const double h = 0.6 * r * (k / 10.0);  // distance of the plane from the centre
        const Plane p{n, -glm::dot(n, glm::dvec3(100, 200, 300)) - h};
        Section s = cut(*idx, p);
        ASSERT_EQ(s.bodies.size(), 1u);
        EXPECT_EQ(s.bodies[0].openChains, 0u);
        ASSERT_EQ(s.bodies[0].polygons.size(), 1u);
        // The inscribed UV sphere lies inside the true one by up to r (1 - cos(pi/128)),
        // 3e-4 r: the cut disc's area is short by about twice that fraction, more off-centre.
        const double analytic = kPi * (r * r - h * h);
        EXPECT_NEAR(s.bodies[0].area, analytic, kUvSphereRelTol * analytic);
        const double brute = bruteForceArea(m.bodies[0].mesh, s.plane, s.frame, m.origin);
        EXPECT_NEAR(s.bodies[0].area, brute, kSameCutRelTol * brute);
    }
}

TEST(SectionContours, NestedLensIsAHoleInItsHost) {
    Model m = modelOf({makePart("host", PartKind::Body, 10, boxMesh({0, 0, 0}, {100, 100, 50})),
                       makePart("lens", PartKind::Body, 20, sphereMesh({50, 50, 25}, 10, 64, 32))});
    ASSERT_EQ(m.bodies[1].report.parent, 0);
    auto idx = indexFor(m);
    Section s = cut(*idx, Plane{{0, 0, 1}, -25.3});
    ASSERT_EQ(s.bodies.size(), 2u);
    const double lens = bodyArea(s, 1);
    EXPECT_GT(lens, 300.0);
    EXPECT_NEAR(bodyArea(s, 0), 100.0 * 100.0 - lens, kLargeAreaTolM2);
    ASSERT_EQ(s.bodies[0].polygons.size(), 1u);
    ASSERT_EQ(s.bodies[0].polygons[0].holes.size(), 1u);
    EXPECT_LT(ringArea(s.bodies[0].polygons[0].holes[0]), 0.0);  // holes clockwise

    // Partition: the host carries the cavity itself; same areas.
    Mesh host = boxMesh({0, 0, 0}, {100, 100, 50});
    Mesh cavity = sphereMesh({50, 50, 25}, 10, 64, 32);
    reverse(cavity);
    append(host, cavity);
    Model mp = modelOf({makePart("host", PartKind::Body, 10, host),
                        makePart("lens", PartKind::Body, 20, sphereMesh({50, 50, 25}, 10, 64, 32))});
    EXPECT_EQ(mp.bodies[1].report.parent, -1);
    auto ip = indexFor(mp);
    Section sp = cut(*ip, Plane{{0, 0, 1}, -25.3});
    EXPECT_NEAR(bodyArea(sp, 1), lens, kAreaTolM2);
    EXPECT_NEAR(bodyArea(sp, 0), 100.0 * 100.0 - lens, kLargeAreaTolM2);
}

TEST(SectionContours, OpenSurfaceGivesATrace) {
    Mesh sheet;  // a vertical fault sheet x = 5, y in [0, 10], z in [0, 10], 2x2 quads
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 2; ++i) sheet.positions.push_back({5.0, 5.0 * i, 5.0 * j});
    for (std::uint32_t j = 0; j < 2; ++j)
        for (std::uint32_t i = 0; i < 2; ++i) {
            const std::uint32_t a = j * 3 + i;
            sheet.indices.insert(sheet.indices.end(), {a, a + 1, a + 4, a, a + 4, a + 3});
        }
    Model m = modelOf({makePart("box", PartKind::Body, 1, boxMesh({0, 0, 0}, {10, 10, 10}))},
                      {makePart("fault", PartKind::Surface, 9, sheet)});
    auto idx = indexFor(m);
    Section s = cut(*idx, Plane{{0, 0, 1}, -3.7});
    ASSERT_EQ(s.traces.size(), 1u);
    EXPECT_EQ(s.traces[0].record, 9u);
    EXPECT_FALSE(s.traces[0].closed);
    ASSERT_GE(s.traces[0].points.size(), 2u);
    const glm::dvec2 a = s.traces[0].points.front(), b = s.traces[0].points.back();
    EXPECT_NEAR(glm::length(a - b), 10.0, kTraceTolM);
}

TEST(SectionContours, BadPlanesAreErrors) {
    Model m = modelOf({makePart("box", PartKind::Body, 1, boxMesh({0, 0, 0}, {10, 10, 10}))});
    auto idx = indexFor(m);
    EXPECT_FALSE(makePlane(std::nan(""), 0, 1, 0).ok());
    EXPECT_FALSE(makePlane(0, 0, 0, 1).ok());
    EXPECT_FALSE(makePlane(0, 0, 1, INFINITY).ok());
    auto miss = computeSection(*idx, Plane{{0, 0, 1}, -100.0});
    ASSERT_FALSE(miss.ok());
    EXPECT_EQ(miss.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(miss.error().message.find("misses the model"), std::string::npos);
    EXPECT_FALSE(computeSection(*idx, Plane{{0, 0, 0}, 1.0}).ok());
    auto p = makePlane(0, 0, 2, -10);  // normalised: z >= 5 kept
    ASSERT_TRUE(p.ok());
    EXPECT_DOUBLE_EQ(p->normal.z, 1.0);
    EXPECT_DOUBLE_EQ(p->d, -5.0);
}

TEST(SectionContours, RandomPlanesThroughGeneratedModels) {
    // Every body gives closed loops, and each body's area (host minus nested lens) equals an
    // independent brute-force cut to 1e-6 relative (both double; observed ~1e-12).
    for (OreVariant ore : {OreVariant::Nested, OreVariant::Partition}) {
        Model m = syntheticModel(30000, ore, ore == OreVariant::Nested ? 3 : 4);
        auto idx = indexFor(m);
        std::mt19937_64 rng(11);
        for (int k = 0; k < 30; ++k) {
            const Plane p = randomPlane(m.bounds(), rng, k);
            Section s = cut(*idx, p);
            for (const auto& b : s.bodies) EXPECT_EQ(b.openChains, 0u) << "plane " << k << " body " << b.part;
            for (std::size_t b = 0; b < m.bodies.size(); ++b) {
                double brute = bruteForceArea(m.bodies[b].mesh, s.plane, s.frame, m.origin);
                for (std::size_t c = 0; c < m.bodies.size(); ++c)
                    if (m.bodies[c].report.parent == static_cast<int>(b))
                        brute -= bruteForceArea(m.bodies[c].mesh, s.plane, s.frame, m.origin);
                const double ours = bodyArea(s, static_cast<std::uint32_t>(b));
                EXPECT_NEAR(ours, brute, kBruteForceRelTol * std::max(std::abs(brute), 1.0))
                    << "plane " << k << " body " << b;
            }
            // The BVH path and the brute-force cut give the same segments.
            PlaneCut viaBvh, all;
            beginCut(*idx, s.plane, viaBvh);
            beginCut(*idx, s.plane, all);
            std::vector<std::uint32_t> tris;
            queryPlane(idx->bvh, idx->meshes.data(), viaBvh.plane, tris);
            cutTriangles(*idx, tris.data(), tris.size(), viaBvh);
            cutAllTriangles(*idx, all);
            EXPECT_EQ(viaBvh.segments, all.segments);
        }
    }
}

TEST(SectionContours, TwoThreadsGiveTheSameSectionBitForBit) {
    // The cut's traversal and triangles are shared by two threads above 100k triangles
    // (section/cut/plane_cut.cpp); leaves are taken in unit order whatever the thread count, so
    // segments, rings and areas must be identical, not merely close (tolerance: none).
    Model m = syntheticModel(240000);
    auto idx = indexFor(m);
    std::mt19937_64 rng(5);
    SectionOptions one, two;
    one.threads = 1;
    two.threads = 2;
    for (int k = 0; k < 12; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        PlaneCut a, b;
        beginCut(*idx, p, a);
        beginCut(*idx, p, b);
        cutWithBvh(*idx, nullptr, a, 1);
        cutWithBvh(*idx, nullptr, b, 2);
        ASSERT_EQ(a.segments, b.segments) << "plane " << k;
        for (std::size_t part = 0; part < a.parts.size(); ++part) {
            ASSERT_EQ(a.parts[part].size(), b.parts[part].size()) << "plane " << k << " part " << part;
            for (std::size_t i = 0; i < a.parts[part].size(); ++i) {
                const CutSegment &x = a.parts[part][i], &y = b.parts[part][i];
                ASSERT_TRUE(x.keyA == y.keyA && x.keyB == y.keyB && x.a == y.a && x.b == y.b)
                    << "plane " << k << " part " << part << " segment " << i;
            }
        }
        auto s1 = computeSection(*idx, p, one);
        auto s2 = computeSection(*idx, p, two);
        ASSERT_TRUE(s1.ok() && s2.ok());
        ASSERT_EQ(s1->bodies.size(), s2->bodies.size());
        for (std::size_t i = 0; i < s1->bodies.size(); ++i) {
            EXPECT_EQ(s1->bodies[i].area, s2->bodies[i].area) << "plane " << k;
            ASSERT_EQ(s1->bodies[i].polygons.size(), s2->bodies[i].polygons.size());
            for (std::size_t j = 0; j < s1->bodies[i].polygons.size(); ++j)
                EXPECT_EQ(s1->bodies[i].polygons[j].outer, s2->bodies[i].polygons[j].outer) << "plane " << k;
        }
        EXPECT_EQ(s1->traces.size(), s2->traces.size());
    }
}

TEST(SectionContours, ClosedBodiesChainByEntryKeysLikeTheGeneralJoin) {
    // A closed body's segments are chained through a table of entry keys only (each exit
    // meets exactly one entry); any other part through the table of both ends. Marking the
    // bodies not closed forces the general join: the rings must be identical (tolerance:
    // none, both take the same points in the same order).
    Model m = syntheticModel(30000, OreVariant::Nested, 3);
    auto idx = indexFor(m);
    std::mt19937_64 rng(17);
    for (int k = 0; k < 12; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        for (auto& part : idx->parts) part.closed = part.kind == PartKind::Body;
        Section fast = cut(*idx, p);
        for (auto& part : idx->parts) part.closed = false;
        Section general = cut(*idx, p);
        expectSameSection(fast, general, "plane " + std::to_string(k));
    }
    // A body marked closed whose cut is not a matching (an open box: exits without an
    // entry) falls back to the general join: the same open chain.
    Mesh box = boxMesh({0, 0, 0}, {10, 10, 10});
    Model open = modelOf({makePart("box", PartKind::Body, 1, box)});
    auto oi = indexFor(open);
    const Plane vertical{{1, 0, 0}, -4.0};
    Section whole = cut(*oi, vertical);
    ASSERT_EQ(whole.bodies.size(), 1u);
    EXPECT_EQ(whole.bodies[0].openChains, 0u);
    box.indices.erase(box.indices.begin() + 6, box.indices.begin() + 12);  // drop the top face z = 10
    Model holed = modelOf({makePart("box", PartKind::Body, 1, box)});
    auto hi = indexFor(holed);
    hi->parts[0].closed = false;
    Section general = cut(*hi, vertical);
    hi->parts[0].closed = true;
    Section forced = cut(*hi, vertical);
    expectSameSection(forced, general, "open box");
    ASSERT_EQ(forced.bodies.size(), 1u);
    EXPECT_GE(forced.bodies[0].openChains, 1u);
}
