// Reserves: analytic volumes of a box and a sphere with a cap cut off (within 0.1%, the
// issue's bound; the meshes are exact for the box and within the polyhedral error for the
// sphere), nested net volumes, tonnage and metal units, bad planes, and the kept and
// removed sides of random planes through a generated mine adding up to the whole.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "section/cut/contours.hpp"
#include "section/volumes/reserves.hpp"
#include "section_test_util.hpp"
#include "test_meshes.hpp"
#include "tests/common/random_plane.hpp"
#include "tests/common/synthetic_model.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
// Cubic metres, box volumes up to 5e5 m^3 (also at GK eastings, through the reference point):
// exact in double up to rounding of the divergence sums, ~1e-10 m^3, with margin.
constexpr double kBoxVolumeTolM3 = 1e-6;
// Tonnes, tonnage of 1.2e6 t: the volume's rounding times a density of 2.5 t/m^3 and more.
constexpr double kBoxTonnageTolT = 1e-3;
// Tonnes or grams, tonnage and metal of the small nested boxes (1e4 t, 8e3 g): rounding only.
constexpr double kNestedTolT = 1e-6;
// Relative: a 512 x 256 UV sphere is short of the true sphere (and its caps) by ~1e-4.
constexpr double kUvSphereRelTol = 1e-3;
// Relative: the same body's volume from two computations in double (kept + removed sides,
// validation's signed volume, a closed-form cut).
constexpr double kSameVolumeRelTol = 1e-9;

}  // namespace

TEST(Reserves, BoxWholeAndClipped) {
    // Far from the origin (Gauss-Kruger easting) to exercise the reference point.
    const glm::dvec3 lo(35500000.0, 3380000.0, -200.0), hi = lo + glm::dvec3(100, 60, 40);
    const Mesh box = boxMesh(lo, hi);
    EXPECT_NEAR(meshVolume(box), 240000.0, kBoxVolumeTolM3);
    const Plane above{{0, 0, 1}, -(lo.z + 10.0)};  // keeps z >= lo.z + 10
    EXPECT_NEAR(meshVolume(box, &above), 100.0 * 60.0 * 30.0, kBoxVolumeTolM3);
    // A tilted plane through the box centre keeps exactly half (central symmetry).
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8)), c = 0.5 * (lo + hi);
    const Plane tilted{n, -glm::dot(n, c)};
    EXPECT_NEAR(meshVolume(box, &tilted), 120000.0, kBoxVolumeTolM3);
    // A plane keeping x >= lo.x + 25 and one missing the box.
    const Plane x25{{1, 0, 0}, -(lo.x + 25.0)};
    EXPECT_NEAR(meshVolume(box, &x25), 75.0 * 60.0 * 40.0, kBoxVolumeTolM3);
    const Plane none{{0, 0, 1}, -(hi.z + 1.0)};
    EXPECT_EQ(meshVolume(box, &none), 0.0);
}

TEST(Reserves, SphereAndCapWithinATenthOfAPercent) {
    const double r = 10.0;
    const glm::dvec3 c(500.0, 300.0, -50.0);
    const Mesh sphere = sphereMesh(c, r, 512, 256);
    const double analytic = 4.0 / 3.0 * kPi * r * r * r;
    EXPECT_NEAR(meshVolume(sphere), analytic, kUvSphereRelTol * analytic);
    for (double h : {2.0, 7.5, 10.0, 16.0}) {        // cap heights
        const Plane cap{{0, 0, 1}, -(c.z + r - h)};  // keeps z >= top - h
        const double v = kPi * h * h * (3.0 * r - h) / 3.0;
        EXPECT_NEAR(meshVolume(sphere, &cap), v, kUvSphereRelTol * v) << "h = " << h;
        // The same cap on a slanted axis.
        const glm::dvec3 n = glm::normalize(glm::dvec3(1, 2, -0.5));
        const Plane slanted{n, -glm::dot(n, c + (r - h) * n)};
        EXPECT_NEAR(meshVolume(sphere, &slanted), v, kUvSphereRelTol * v) << "slanted h = " << h;
    }
}

TEST(Reserves, NestedNetTonnageAndMetal) {
    Model m = modelOf({makePart("host", PartKind::Body, 1, boxMesh({0, 0, 0}, {100, 100, 50})),
                       makePart("lens", PartKind::Body, 2, boxMesh({40, 40, 20}, {60, 60, 30})),
                       makePart("core", PartKind::Body, 3, boxMesh({45, 45, 22}, {55, 55, 28}))});
    ASSERT_EQ(m.bodies[2].report.parent, 1);
    AttributeRecord host;
    host.id = 1;
    host.name = "host";
    host.density = 2.5;
    m.attributes.put(host);
    AttributeRecord lens;
    lens.id = 2;
    lens.name = "lens";
    lens.density = 3.0;
    lens.grade = 2.0;
    lens.gradeUnit = "% Cu";
    m.attributes.put(lens);
    AttributeRecord core;
    core.id = 3;
    core.name = "core";
    core.density = 3.2;
    core.grade = 4.0;
    core.gradeUnit = "g/t Au";
    m.attributes.put(core);
    auto r = computeReserves(m);
    ASSERT_TRUE(r.ok());
    ASSERT_EQ(r->bodies.size(), 3u);
    const BodyReserves &h = r->bodies[0], &l = r->bodies[1], &k = r->bodies[2];
    EXPECT_NEAR(h.grossVolume, 500000.0, kBoxVolumeTolM3);
    EXPECT_NEAR(h.netVolume, 500000.0 - 4000.0, kBoxVolumeTolM3);
    EXPECT_NEAR(l.netVolume, 4000.0 - 600.0, kBoxVolumeTolM3);
    EXPECT_NEAR(k.netVolume, 600.0, kBoxVolumeTolM3);
    EXPECT_NEAR(*h.tonnage, 496000.0 * 2.5, kBoxTonnageTolT);
    EXPECT_FALSE(h.metal.has_value());
    EXPECT_NEAR(*l.tonnage, 3400.0 * 3.0, kNestedTolT);
    EXPECT_NEAR(*l.metal, 3400.0 * 3.0 * 0.02, kNestedTolT);
    EXPECT_EQ(l.metalUnit, "t");
    EXPECT_NEAR(*k.metal, 600.0 * 3.2 * 4.0, kNestedTolT);
    EXPECT_EQ(k.metalUnit, "g");
    EXPECT_EQ(metalContent(10.0, 3.0, "lb/t").second, "t x lb/t");
    // Kept side z >= 25: host 100x100x25 minus the lens's upper half (20x20x5) ...
    auto half = computeReserves(m, Plane{{0, 0, 1}, -25.0});
    ASSERT_TRUE(half.ok());
    EXPECT_NEAR(half->bodies[0].netVolume, 250000.0 - 2000.0, kBoxVolumeTolM3);
    EXPECT_NEAR(half->bodies[1].netVolume, 2000.0 - 300.0, kBoxVolumeTolM3);
    EXPECT_FALSE(computeReserves(m, Plane{{0, 0, 0}, 1.0}).ok());
    EXPECT_FALSE(computeReserves(m, Plane{{NAN, 0, 1}, 1.0}).ok());
}

TEST(Reserves, KeptAndRemovedSidesAddUp) {
    Model m = syntheticModel(30000, OreVariant::Partition, 6);
    auto whole = computeReserves(m);
    ASSERT_TRUE(whole.ok());
    std::mt19937_64 rng(5);
    for (int k = 0; k < 12; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        const Plane q{-p.normal, -p.d};
        auto a = computeReserves(m, p), b = computeReserves(m, q);
        ASSERT_TRUE(a.ok() && b.ok());
        for (std::size_t i = 0; i < whole->bodies.size(); ++i) {
            const double v = whole->bodies[i].grossVolume;
            EXPECT_GT(v, 0.0);
            EXPECT_NEAR(a->bodies[i].grossVolume + b->bodies[i].grossVolume, v, kSameVolumeRelTol * v) << "plane " << k;
            EXPECT_GE(a->bodies[i].grossVolume, -kSameVolumeRelTol * v);
        }
    }
    // The mesh volume agrees with validation's signed volume.
    for (std::size_t i = 0; i < whole->bodies.size(); ++i)
        EXPECT_NEAR(whole->bodies[i].grossVolume, m.bodies[i].report.signedVolume,
                    kSameVolumeRelTol * m.bodies[i].report.signedVolume);
}

TEST(Reserves, KeptVolumeEqualsClosingWithTheSectionPolygons) {
    // The other way to close the clipped shell: sum the clipped triangles about a point o
    // OFF the plane and add the cap, the section polygons of section/cut/contours.hpp, as the
    // cone from o: (1/3) x area x distance(o, plane). Must equal meshVolume (o on the plane,
    // cap contributes zero) to rounding, 1e-9 relative.
    Model m = syntheticModel(30000, OreVariant::Partition, 6);
    auto idx = indexFor(m);
    std::mt19937_64 rng(17);
    for (int k = 0; k < 8; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        auto s = computeSection(*idx, p);
        ASSERT_TRUE(s.ok());
        for (const BodySection& b : s->bodies) {
            const Mesh& mesh = m.bodies[b.part].mesh;
            const glm::dvec3 o = mesh.bounds().centre() + glm::dvec3(37.0, -21.0, 13.0);
            double sum = 0.0;
            for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
                glm::dvec3 q[3];
                double d[3];
                for (int c = 0; c < 3; ++c) {
                    q[c] = mesh.positions[mesh.indices[3 * t + static_cast<std::size_t>(c)]];
                    d[c] = glm::dot(p.normal, q[c]) + p.d;
                }
                glm::dvec3 poly[4];
                int n = 0;
                for (int c = 0; c < 3; ++c) {
                    const int c1 = (c + 1) % 3;
                    if (d[c] >= 0.0) poly[n++] = q[c] - o;
                    if ((d[c] >= 0.0) != (d[c1] >= 0.0))
                        poly[n++] = q[c] + (q[c1] - q[c]) * (d[c] / (d[c] - d[c1])) - o;
                }
                for (int c = 1; c + 1 < n; ++c) sum += glm::dot(poly[0], glm::cross(poly[c], poly[c + 1]));
            }
            const double closed = sum / 6.0 + b.area * (glm::dot(p.normal, o) + p.d) / 3.0;
            const double ours = meshVolume(mesh, &p);
            EXPECT_NEAR(ours, closed, kSameVolumeRelTol * std::abs(m.bodies[b.part].report.signedVolume))
                << "plane " << k << " body " << b.part;
        }
    }
}
