// Virtual boreholes: analytic depths through boxes, a nested sphere and a terrain sheet,
// neighbours sharing faces, rays starting inside a body, bad input, and random rays
// through a generated mine checked point by point against the Embree oracle.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "section/rays/borehole.hpp"
#include "section/rays/classify.hpp"
#include "test_meshes.hpp"
#include "tests/common/synthetic_model.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

std::unique_ptr<BoreholeTracer> tracerFor(const Model& m) {
    auto t = BoreholeTracer::build(m);
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.error().message);
    return std::move(t).value();
}

// A flat terrain sheet z = h over [x0, x1] x [y0, y1], two triangles.
Mesh sheet(double x0, double y0, double x1, double y1, double h) {
    Mesh m;
    m.positions = {{x0, y0, h}, {x1, y0, h}, {x1, y1, h}, {x0, y1, h}};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

// Float32 local frame of a 100 m model: the tolerance of section/rays/borehole.hpp is 0.1 mm
// plus 1e-6 x (50 m + distance); hits themselves are within a few float ulps (< 0.05 mm).
constexpr double kTol = 2e-4;
// Metres: samples this close to an interval's end are not compared (kTol, with margin).
constexpr double kNearEndM = 5e-3;
// Metres: the borehole's origin (the collar plus 1 m, computed in double from the model's
// bounds): a few double steps.
constexpr double kOriginTolM = 1e-12;
// Metres: x, y of a vertical borehole's hit points, carried from the (double) origin.
constexpr double kHitXyTolM = 1e-9;
// Metres: a ray from 1e7 m away, entering the model's box near its hit: the tracer's float
// tolerance there (section/rays/borehole.hpp: 1e-6 x (half-extent + distance from the box entry)
// + 0.1 mm) is about 0.15 mm; 1 mm bounds it.
constexpr double kFarRayTolM = 1e-3;

}  // namespace

TEST(Borehole, NestedSphereInABoxUnderTerrain) {
    // Host box z in [0, 50]; lens sphere r = 10 at (50, 50, 25); terrain at z = 60; a
    // second stratum box z in [-30, 0] sharing the host's bottom face.
    Model m = modelOf({makePart("host", PartKind::Body, 10, boxMesh({0, 0, 0}, {100, 100, 50})),
                       makePart("lens", PartKind::Body, 20, sphereMesh({50, 50, 25}, 10, 96, 48)),
                       makePart("base", PartKind::Body, 30, boxMesh({0, 0, -30}, {100, 100, 0}))},
                      {makePart("terrain", PartKind::Surface, 40, sheet(0, 0, 100, 100, 60))});
    ASSERT_EQ(m.bodies[1].report.parent, 0);
    auto tr = tracerFor(m);
    // Through the sphere's axis, off the mesh's vertices (x, y not on a grid line).
    auto bh = tr->traceVertical(50.0, 50.0);
    ASSERT_TRUE(bh.ok()) << bh.error().message;
    // Origin 1 m above the top (terrain, 60): collar at the terrain, depth 1 m from the origin.
    EXPECT_NEAR(bh->origin.z, 61.0, kOriginTolM);
    EXPECT_NEAR(bh->collarDepth, 1.0, kTol);
    ASSERT_EQ(bh->crossings.size(), 1u);
    EXPECT_EQ(bh->crossings[0].record, 40u);
    EXPECT_NEAR(bh->crossings[0].elevation, 60.0, kTol);
    EXPECT_NEAR(bh->crossings[0].depthCollar, 0.0, kTol);
    ASSERT_EQ(bh->intervals.size(), 4u);
    const RecordId records[4] = {10, 20, 10, 30};
    // The poles of the UV sphere are vertices at z = 35 and 15.
    const double tops[4] = {50, 35, 15, 0}, bottoms[4] = {35, 15, 0, -30};
    for (int k = 0; k < 4; ++k) {
        const BoreholeInterval& iv = bh->intervals[static_cast<std::size_t>(k)];
        EXPECT_EQ(iv.record, records[k]) << k;
        EXPECT_NEAR(iv.fromElevation, tops[k], kTol) << k;
        EXPECT_NEAR(iv.toElevation, bottoms[k], kTol) << k;
        EXPECT_NEAR(iv.fromCollar, 60.0 - tops[k], kTol) << k;
        EXPECT_NEAR(iv.toCollar, 60.0 - bottoms[k], kTol) << k;
        EXPECT_NEAR(iv.from, 61.0 - tops[k], kTol) << k;
        EXPECT_NEAR(iv.fromWorld.x, 50.0, kHitXyTolM);
    }
    // Beside the lens: host then base, joined at z = 0 with no gap.
    auto side = tr->traceVertical(10.5, 20.25);
    ASSERT_TRUE(side.ok());
    ASSERT_EQ(side->intervals.size(), 2u);
    EXPECT_EQ(side->intervals[0].record, 10u);
    EXPECT_EQ(side->intervals[1].record, 30u);
    EXPECT_DOUBLE_EQ(side->intervals[0].to, side->intervals[1].from);
    EXPECT_NEAR(side->intervals[0].toElevation, 0.0, kTol);
    // On the diagonal edge that two triangles of each box's top and bottom share: the same.
    auto corner = tr->traceVertical(30.0, 70.0);
    ASSERT_TRUE(corner.ok());
    ASSERT_EQ(corner->intervals.size(), 2u);
    EXPECT_NEAR(corner->intervals[1].toElevation, -30.0, kTol);
}

TEST(Borehole, AnyRayAndRaysStartingInside) {
    Model m = modelOf({makePart("a", PartKind::Body, 1, boxMesh({0, 0, 0}, {10, 10, 10})),
                       makePart("b", PartKind::Body, 2, boxMesh({10, 0, 0}, {30, 10, 10}))});
    auto tr = tracerFor(m);
    // Horizontal ray along +x from inside body a (x = 4): a from 0 to 6 m, then b to 26 m.
    auto bh = tr->traceRay({4.0, 3.3, 7.7}, {2.0, 0.0, 0.0});
    ASSERT_TRUE(bh.ok()) << bh.error().message;
    ASSERT_EQ(bh->intervals.size(), 2u);
    EXPECT_EQ(bh->intervals[0].record, 1u);
    EXPECT_NEAR(bh->intervals[0].from, 0.0, kTol);
    EXPECT_NEAR(bh->intervals[0].to, 6.0, kTol);
    EXPECT_EQ(bh->intervals[1].record, 2u);
    EXPECT_NEAR(bh->intervals[1].to, 26.0, kTol);
    EXPECT_NEAR(bh->collarDepth, 6.0, kTol);  // the first face met: a's far side (shared with b)
    EXPECT_NEAR(bh->intervals[0].fromCollar, -6.0, kTol);
    // A diagonal ray, limited to 5 m: only the part inside the limit.
    const glm::dvec3 d = glm::normalize(glm::dvec3(1, 1, 1));
    auto lim = tr->traceRay(glm::dvec3(-1, 0.5, 0.25), d, 5.0);
    ASSERT_TRUE(lim.ok());
    ASSERT_EQ(lim->intervals.size(), 1u);
    EXPECT_NEAR(lim->intervals[0].from, std::sqrt(3.0), kTol);  // enters at x = 0
    EXPECT_NEAR(lim->intervals[0].to, 5.0, kTol);
    EXPECT_DOUBLE_EQ(lim->length, 5.0);
    // A ray inside the bounds that meets nothing: no intervals, no collar.
    Model gap = modelOf({makePart("a", PartKind::Body, 1, boxMesh({0, 0, 0}, {10, 10, 10})),
                         makePart("b", PartKind::Body, 2, boxMesh({20, 0, 0}, {30, 10, 10}))});
    auto tg = tracerFor(gap);
    auto none = tg->traceVertical(15.0, 5.0);
    ASSERT_TRUE(none.ok());
    EXPECT_TRUE(none->intervals.empty());
    EXPECT_TRUE(std::isnan(none->collarDepth));
}

TEST(Borehole, BadInputIsAnError) {
    Model m = modelOf({makePart("a", PartKind::Body, 1, boxMesh({0, 0, 0}, {10, 10, 10}))});
    auto tr = tracerFor(m);
    EXPECT_EQ(tr->traceVertical(NAN, 1.0).error().code, ErrorCode::InvalidArgument);
    auto out = tr->traceVertical(50.0, 5.0);
    ASSERT_FALSE(out.ok());
    EXPECT_EQ(out.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(out.error().message.find("(50.000, 5.000)"), std::string::npos) << out.error().message;
    EXPECT_EQ(tr->traceRay({0, 0, 0}, {0, 0, 0}).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(tr->traceRay({0, 0, INFINITY}, {0, 0, 1}).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(tr->traceRay({5, 5, 5}, {0, 0, 1}, 0.0).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(tr->traceRay({5, 5, 5}, {0, 0, 1}, NAN).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(tr->traceRay({50, 50, 50}, {0, 0, 1}).error().code, ErrorCode::OutOfRange);  // points away
    // Far-away and huge values: an answer or an error, never a crash.
    auto far = tr->traceRay({5, 5, 1e7}, {0, 0, -1});
    ASSERT_TRUE(far.ok());
    ASSERT_EQ(far->intervals.size(), 1u);
    EXPECT_NEAR(far->intervals[0].fromElevation, 10.0, kFarRayTolM);
    auto huge = tr->traceRay({1e300, 5, 5}, {-1, 0, 0});
    EXPECT_TRUE(!huge.ok() || huge->intervals.size() <= 1);
    EXPECT_FALSE(tr->traceRay({5, 5, 5}, {1e308, 1e308, 0}).ok());
}

TEST(Borehole, RandomHolesAgreeWithTheOracle) {
    // 40 vertical holes and 40 random rays through a 50K-triangle mine (nested lens and
    // partition): at 64 points along each ray, the interval the point falls in (or none)
    // names the record the oracle classifies the point as. Points within 5 mm of an
    // interval end are skipped (the float32 tolerance of both methods).
    for (OreVariant ore : {OreVariant::Nested, OreVariant::Partition}) {
        Model m = syntheticModel(50000, ore, 5);
        auto tr = tracerFor(m);
        auto oracle = Classifier::build(m);
        ASSERT_TRUE(oracle.ok());
        const Aabb b = m.bounds();
        std::mt19937_64 rng(99);
        std::uniform_real_distribution<double> ux(b.min.x, b.max.x), uy(b.min.y, b.max.y), uz(b.min.z, b.max.z),
            sym(-1.0, 1.0), f01(0.0, 1.0);
        std::size_t checked = 0, agree = 0, inBodies = 0;
        for (int k = 0; k < 80; ++k) {
            Result<Borehole> bh =
                k < 40 ? tr->traceVertical(ux(rng), uy(rng))
                       : tr->traceRay({ux(rng), uy(rng), uz(rng)}, {sym(rng), sym(rng), sym(rng) + 1e-9});
            ASSERT_TRUE(bh.ok()) << bh.error().message;
            for (std::size_t i = 1; i + 1 < bh->intervals.size(); ++i)
                EXPECT_LE(bh->intervals[i - 1].to, bh->intervals[i].from);
            for (int s = 0; s < 64; ++s) {
                const double t = bh->length * (s + f01(rng)) / 64.0;
                RecordId expect = kNoRecord;
                bool nearEnd = false;
                for (const auto& iv : bh->intervals) {
                    nearEnd = nearEnd || std::abs(t - iv.from) < kNearEndM || std::abs(t - iv.to) < kNearEndM;
                    if (t >= iv.from && t < iv.to) expect = iv.record;
                }
                if (nearEnd) continue;
                const RecordId truth = (*oracle)->classify(bh->origin + t * bh->direction);
                ++checked;
                agree += truth == expect;
                inBodies += truth != kNoRecord;
                EXPECT_EQ(expect, truth) << "ray " << k << " t " << t;
            }
        }
        EXPECT_GT(checked, 4500u);
        EXPECT_GT(inBodies, checked / 3);  // the rays mostly run through geology
        std::printf("[ borehole ] %zu of %zu points agree with the oracle\n", agree, checked);
    }
}
