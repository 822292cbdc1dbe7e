// Vertical sections along a map polyline: analytic areas of a bent line through boxes,
// ring clipping, the pixel -> world mapping, bad lines, a straight line against the plane
// section, and bent lines through generated mines against the Embree oracle.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "section/cut/polyline.hpp"
#include "section/rays/classify.hpp"
#include "section_test_util.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

// Metres: chainages, elevations and world points of sections through boxes with coordinates
// under 200 m (double steps of 3e-14 m; the cut adds a few operations).
constexpr double kCoordTolM = 1e-9;
// Square metres: areas of a few hundred m^2 from those coordinates (shoelace rounding ~1e-12 m^2).
constexpr double kSmallAreaTolM2 = 1e-9;
// Square metres: areas of thousands of m^2 (relative 1e-12 of rounding, with margin).
constexpr double kLargeAreaTolM2 = 1e-8;
// Ratios and areas of rings clipped at whole metres: exact up to a few double steps.
constexpr double kExactTol = 1e-12;
// Relative: the same section's areas summed per leg and per body in another order.
constexpr double kSumOrderRelTol = 1e-9;

double areaOf(const PolylineSection& s, std::uint32_t part) {
    for (const auto& b : s.bodies)
        if (b.part == part) return b.area;
    return 0.0;
}

}  // namespace

TEST(PolylineSection, BentLineThroughBoxesHasAnalyticAreas) {
    // Box a: [0,100] x [0,100] x [0,50]; box b on top: z in [50, 80]. A nested box lens
    // [40,60]^2 x [20,30] inside a. Line (-10, 50) -> (50, 50) -> (50, 150): inside the
    // boxes for 100 m (x 0..50 along y = 50, then y 50..100 along x = 50).
    Model m = modelOf({makePart("a", PartKind::Body, 1, boxMesh({0, 0, 0}, {100, 100, 50})),
                       makePart("b", PartKind::Body, 2, boxMesh({0, 0, 50}, {100, 100, 80})),
                       makePart("lens", PartKind::Body, 3, boxMesh({40, 40, 20}, {60, 60, 30}))});
    auto idx = indexFor(m);
    auto s = computePolylineSection(*idx, {{-10, 50}, {50, 50}, {50, 150}});
    ASSERT_TRUE(s.ok()) << s.error().message;
    ASSERT_EQ(s->legs.size(), 2u);
    EXPECT_DOUBLE_EQ(s->line.length(), 160.0);
    // Lens: 10 m along leg 1 (x 40..50) and 10 m along leg 2 (y 50..60), 10 m high.
    EXPECT_NEAR(areaOf(s.value(), 2), 2 * 10.0 * 10.0, kSmallAreaTolM2);
    EXPECT_NEAR(areaOf(s.value(), 0), 100.0 * 50.0 - 200.0, kLargeAreaTolM2);
    EXPECT_NEAR(areaOf(s.value(), 1), 100.0 * 30.0, kLargeAreaTolM2);
    // Contents span s in [10, 110] (x = 0 at s = 10; y = 100 at s = 60 + 50), z in [0, 80].
    EXPECT_NEAR(s->lo.x, 10.0, kCoordTolM);
    EXPECT_NEAR(s->hi.x, 110.0, kCoordTolM);
    EXPECT_NEAR(s->lo.y, 0.0, kCoordTolM);
    EXPECT_NEAR(s->hi.y, 80.0, kCoordTolM);
    // Image: 1 pixel = 1 m over s 0..160, z -10..90; ids at pixel centres are exact.
    auto img = rasterizePolylineSection(*idx, s.value(), FrameRect{0, -10, 160, 90}, 160, 100);
    ASSERT_TRUE(img.ok()) << img.error().message;
    auto idAt = [&](double sc, double z) {
        const glm::dvec2 px = img->lineToPixel({sc, z});
        return img->ids[static_cast<std::size_t>(px.y) * 160 + static_cast<std::size_t>(px.x)];
    };
    EXPECT_EQ(idAt(5.5, 10.5), 0u);
    EXPECT_EQ(idAt(10.5, 10.5), 1u);
    EXPECT_EQ(idAt(55.5, 25.5), 3u);  // lens, leg 1 (x = 45.5)
    EXPECT_EQ(idAt(65.5, 25.5), 3u);  // lens, leg 2 (y = 55.5)
    EXPECT_EQ(idAt(75.5, 25.5), 1u);  // host beyond the lens
    EXPECT_EQ(idAt(100.5, 60.5), 2u);
    EXPECT_EQ(idAt(110.5, 60.5), 0u);  // y = 100.5: outside
    std::size_t lensPixels = 0, aPixels = 0;
    for (auto id : img->ids) lensPixels += id == 3, aPixels += id == 1;
    EXPECT_EQ(lensPixels, 200u);
    EXPECT_EQ(aPixels, 5000u - 200u);
    // Colour coverage: each fully covered pixel is opaque, the background transparent.
    EXPECT_EQ(img->rgba[4 * (50 * 160 + 30) + 3], 255);
    EXPECT_EQ(img->rgba[4 * (50 * 160 + 5) + 3], 0);
    // Pixel -> world: s = 65.5 is on leg 2 at y = 55.5; z from the row.
    const glm::dvec3 w = img->pixelCentreWorld(65, 64);
    EXPECT_NEAR(w.x, 50.0, kCoordTolM);
    EXPECT_NEAR(w.y, 55.5, kCoordTolM);
    EXPECT_NEAR(w.z, 25.5, kCoordTolM);
    EXPECT_DOUBLE_EQ(img->pixelCentreChainage(65), 65.5);
    // fitPolylineFrame keeps the contents and the aspect ratio.
    const FrameRect f = fitPolylineFrame(s.value(), 200, 100);
    EXPECT_LE(f.u0, 10.0);
    EXPECT_GE(f.u1, 110.0);
    EXPECT_NEAR((f.u1 - f.u0) / (f.v1 - f.v0), 2.0, kExactTol);
}

TEST(PolylineSection, ClipRingToStrip) {
    const Ring square = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
    EXPECT_NEAR(ringArea(clipRingToStrip(square, 2, 5)), 30.0, kExactTol);
    EXPECT_TRUE(clipRingToStrip(square, 11, 12).empty());
    EXPECT_NEAR(ringArea(clipRingToStrip(square, -5, 50)), 100.0, kExactTol);
    // A U shape (concave): clipping keeps the area of the part inside.
    const Ring u = {{0, 0}, {9, 0}, {9, 9}, {6, 9}, {6, 3}, {3, 3}, {3, 9}, {0, 9}};
    EXPECT_NEAR(ringArea(clipRingToStrip(u, 1, 8)), ringArea(u) - 2 * 9.0, kExactTol);
}

TEST(PolylineSection, BadLinesAreErrors) {
    Model m = modelOf({makePart("a", PartKind::Body, 1, boxMesh({0, 0, 0}, {100, 100, 50}))});
    auto idx = indexFor(m);
    EXPECT_EQ(computePolylineSection(*idx, {{1, 2}}).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(computePolylineSection(*idx, {{1, 2}, {NAN, 3}}).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(computePolylineSection(*idx, {{1, 2}, {1, 2}}).error().code, ErrorCode::InvalidArgument);
    EXPECT_FALSE(computePolylineSection(*idx, {{0, 0}, {1e300, -1e300}}).ok());  // infinite length
    EXPECT_FALSE(computePolylineSection(*idx, std::vector<glm::dvec2>(5000, glm::dvec2(0.0))).ok());
    auto miss = computePolylineSection(*idx, {{500, 0}, {500, 100}});
    ASSERT_FALSE(miss.ok());
    EXPECT_EQ(miss.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(miss.error().message.find("misses the model"), std::string::npos);
    // A line whose legs all run beside the model (their planes cross its box): an error too.
    auto beside = computePolylineSection(*idx, {{200, 50}, {300, 50}, {300, 150}});
    ASSERT_FALSE(beside.ok());
    EXPECT_EQ(beside.error().code, ErrorCode::OutOfRange);
    // One leg beside, one through: the first is not cut, the section is the second's.
    auto part = computePolylineSection(*idx, {{50, 200}, {50, 150}, {50, -50}});
    ASSERT_TRUE(part.ok());
    ASSERT_EQ(part->legs.size(), 2u);
    EXPECT_FALSE(part->legs[0].cut);
    EXPECT_TRUE(part->legs[1].cut);
    ASSERT_EQ(part->bodies.size(), 1u);
    EXPECT_NEAR(part->bodies[0].area, 100.0 * 50.0, kLargeAreaTolM2);
    std::vector<glm::dvec2> many;
    for (int i = 0; i < 300; ++i) many.push_back({double(i), 0.5 * i});
    EXPECT_EQ(computePolylineSection(*idx, many).error().code, ErrorCode::InvalidArgument);
    auto s = computePolylineSection(*idx, {{0, 50}, {100, 50}});
    ASSERT_TRUE(s.ok());
    EXPECT_FALSE(rasterizePolylineSection(*idx, s.value(), FrameRect{0, 0, 0, 1}, 10, 10).ok());
    EXPECT_FALSE(rasterizePolylineSection(*idx, s.value(), FrameRect{0, 0, 1, 1}, 0, 10).ok());
}

TEST(PolylineSection, StraightLineEqualsThePlaneSection) {
    Model m = syntheticModel(30000, OreVariant::Nested, 3);
    auto idx = indexFor(m);
    const Aabb b = m.bounds();
    const glm::dvec2 a(b.min.x + 0.2 * (b.max.x - b.min.x), b.min.y + 0.3 * (b.max.y - b.min.y));
    const glm::dvec2 c(b.min.x + 0.9 * (b.max.x - b.min.x), b.min.y + 0.6 * (b.max.y - b.min.y));
    auto ps = computePolylineSection(*idx, {a, c});
    ASSERT_TRUE(ps.ok());
    const PolylineLeg& leg = ps->legs[0];
    auto plane = computeSection(*idx, leg.plane);
    ASSERT_TRUE(plane.ok());
    // The same rectangle in both: plane u = s - uOffset, restricted to the leg.
    const int W = 200, H = 120;
    const FrameRect r = fitPolylineFrame(ps.value(), W, H, 0.0);
    const FrameRect pr{r.u0 - leg.uOffset, r.v0, r.u1 - leg.uOffset, r.v1};
    auto li = rasterizePolylineSection(*idx, ps.value(), r, W, H);
    auto pi = rasterizeSection(*idx, plane.value(), pr, W, H);
    ASSERT_TRUE(li.ok() && pi.ok());
    std::size_t differ = 0, compared = 0;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const double sc = li->pixelCentreChainage(i);
            if (sc < 1e-6 || sc > ps->line.length() - 1e-6) continue;
            const std::size_t k = static_cast<std::size_t>(j) * W + static_cast<std::size_t>(i);
            differ += li->ids[k] != pi->ids[k];
            ++compared;
        }
    EXPECT_GT(compared, std::size_t(W * H / 2));
    EXPECT_EQ(differ, 0u);
    // Areas equal the plane section's clipped to the leg, and the brute-force cut when the
    // leg spans the model: here it does not, so compare with clipped polygons.
    double planeAreas = 0.0, lineAreas = 0.0;
    for (const auto& bs : plane->bodies)
        for (const auto& poly : bs.polygons) {
            Ring o = poly.outer;
            for (auto& p : o) p.x += leg.uOffset;
            planeAreas += ringArea(clipRingToStrip(o, 0.0, ps->line.length()));
            for (const auto& h : poly.holes) {
                Ring hh = h;
                for (auto& p : hh) p.x += leg.uOffset;
                planeAreas += ringArea(clipRingToStrip(hh, 0.0, ps->line.length()));
            }
        }
    for (const auto& bs : ps->bodies) lineAreas += bs.area;
    EXPECT_NEAR(lineAreas, planeAreas, kSumOrderRelTol * planeAreas);
}

TEST(PolylineSection, IdBufferEqualsTheOracle) {
    // >= 99.99% of pixel centres over 20 random 3-5 point lines (60+ legs), 160 x 96 each,
    // ~50K-triangle mines (nested lens and partition).
    for (OreVariant ore : {OreVariant::Nested, OreVariant::Partition}) {
        Model m = syntheticModel(50000, ore, 8);
        auto idx = indexFor(m);
        auto oracle = Classifier::build(m);
        ASSERT_TRUE(oracle.ok());
        const Aabb b = m.bounds();
        std::mt19937_64 rng(31);
        std::uniform_real_distribution<double> fx(0.05, 0.95);
        const int W = 160, H = 96;
        std::size_t total = 0, agree = 0, inside = 0;
        std::vector<glm::dvec3> pts(static_cast<std::size_t>(W) * H);
        std::vector<RecordId> truth(pts.size());
        RasterOptions opt;
        opt.colour = false;
        for (int k = 0; k < 20; ++k) {
            std::vector<glm::dvec2> line;
            for (int i = 0; i < 3 + k % 3; ++i)
                line.push_back({b.min.x + fx(rng) * (b.max.x - b.min.x), b.min.y + fx(rng) * (b.max.y - b.min.y)});
            auto s = computePolylineSection(*idx, line);
            ASSERT_TRUE(s.ok()) << s.error().message;
            for (const auto& bs : s->bodies) EXPECT_EQ(bs.openChains, 0u);
            auto img = rasterizePolylineSection(*idx, s.value(), fitPolylineFrame(s.value(), W, H), W, H, opt);
            ASSERT_TRUE(img.ok());
            std::vector<std::size_t> keep;
            for (int j = 0; j < H; ++j)
                for (int i = 0; i < W; ++i)
                    pts[static_cast<std::size_t>(j) * W + static_cast<std::size_t>(i)] = img->pixelCentreWorld(i, j);
            (*oracle)->classifyBatch(pts.data(), pts.size(), truth.data(), 2);
            for (std::size_t i = 0; i < pts.size(); ++i) {
                // Beyond the line's ends the image is background by definition.
                const double sc = img->pixelCentreChainage(static_cast<int>(i % W));
                if (sc < 0.0 || sc >= s->line.length()) continue;
                ++total;
                agree += img->ids[i] == truth[i];
                inside += truth[i] != 0;
            }
        }
        EXPECT_GE(double(agree) / double(total), 0.9999) << agree << " / " << total;
        EXPECT_GT(inside, total / 4);
        std::printf("[ oracle   ] polyline %s: %zu of %zu pixel centres differ\n",
                    ore == OreVariant::Nested ? "nested" : "partition", total - agree, total);
    }
}
