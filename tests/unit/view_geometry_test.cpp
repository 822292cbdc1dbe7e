// The geometry vocabulary of model/ (issue 14): the plane frame, vertical exaggeration with
// its one pivot rule, the one framing rule and default frame, and the renderer's display
// profile of a true frame. Oracles: the display map applied to world points directly
// (z' = pivot + k (z - pivot)), and plain vector geometry. Tolerances: 1e-12 for unit-scale
// quantities (a few double steps); 1e-6 m for world points near Gauss-Kruger eastings of
// 3.5e7 m (a double step there is 7.5e-9 m; the maps chain a few dozen operations); 1e-9
// for lengths measured over a 100 m baseline there (7.5e-9 m / 100 m, with margin).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "model/exaggeration.hpp"
#include "model/plane.hpp"
#include "model/view_frame.hpp"
#include "renderer/views.hpp"

using namespace geoslice;

namespace {

// A Gauss-Kruger-sized model box (zone-prefixed easting) and a plane through its centre.
Aabb gkBounds() {
    Aabb b;
    b.extend({35'500'000.0, 3'385'000.0, -1200.0});
    b.extend({35'509'000.0, 3'392'000.0, 900.0});
    return b;
}

Plane planeThrough(const glm::dvec3& n, const glm::dvec3& p) {
    const glm::dvec3 u = glm::normalize(n);
    return makePlane(u.x, u.y, u.z, -glm::dot(u, p)).value();
}

}  // namespace

TEST(VerticalExaggerationRule, PivotIsTheBoundsCentreElevation) {
    const Aabb b = gkBounds();
    const VerticalExaggeration ve = VerticalExaggeration::aboutCentreOf(2.5, b);
    EXPECT_EQ(ve.factor, 2.5);
    EXPECT_EQ(ve.pivotZ, -150.0);  // (-1200 + 900) / 2, exact in double
    const glm::dvec3 p{35'504'000.0, 3'388'000.0, 400.0};
    EXPECT_DOUBLE_EQ(ve.toDisplay(p).z, -150.0 + 2.5 * 550.0);
    EXPECT_NEAR(glm::length(ve.toWorld(ve.toDisplay(p)) - p), 0.0, 1e-9);
    EXPECT_TRUE(checkExaggeration(ve).ok());
    EXPECT_FALSE(checkExaggeration({kMinExaggeration * 0.5, 0.0}).ok());
    EXPECT_FALSE(checkExaggeration({kMaxExaggeration * 1.5, 0.0}).ok());
}

// vStretch = how much display space lengthens plane v (u is untouched), against mapping
// points of the plane to display space directly.
TEST(VerticalExaggerationRule, StretchOfPlaneAxesMatchesTheDisplayMap) {
    std::mt19937_64 rng(14);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const Aabb b = gkBounds();
    for (double k : {0.1, 0.5, 1.0, 2.0, 7.5, 100.0})
        for (int i = 0; i < 50; ++i) {
            glm::dvec3 n{unit(rng), unit(rng), unit(rng)};
            if (i == 0) n = {0.0, 1.0, 0.0};   // vertical: stretch k
            if (i == 1) n = {0.0, 0.0, -1.0};  // horizontal: no stretch
            if (glm::length(n) < 0.1) continue;
            const Plane p = planeThrough(n, b.centre());
            const SectionFrame f = makeSectionFrame(p, glm::dvec3(0.0));
            const VerticalExaggeration ve = VerticalExaggeration::aboutCentreOf(k, b);
            const glm::dvec3 a = f.toWorld({f.toPlane(b.centre()).x, f.toPlane(b.centre()).y});
            const double alongU = glm::length(ve.toDisplay(a + 100.0 * f.u) - ve.toDisplay(a)) / 100.0;
            const double alongV = glm::length(ve.toDisplay(a + 100.0 * f.v) - ve.toDisplay(a)) / 100.0;
            EXPECT_NEAR(alongU, 1.0, 1e-9) << "k " << k;
            EXPECT_NEAR(alongV, ve.vStretch(p.normal), 1e-9) << "k " << k;
            if (i == 0) {
                EXPECT_DOUBLE_EQ(ve.vStretch(p.normal), k);
            }
            if (i == 1) {
                EXPECT_DOUBLE_EQ(ve.vStretch(p.normal), 1.0);
            }
        }
}

// The framing rule: contents plus margin inside, centred, pixel aspect = the stretch.
TEST(DefaultFrame, FitsContentsWithMarginAndStretchedPixels) {
    for (double stretch : {1.0, 3.0, 0.25})
        for (auto [w, h] : {std::pair{1024, 512}, std::pair{300, 900}, std::pair{64, 64}}) {
            const glm::dvec2 lo{1000.0, -200.0}, hi{4000.0, 700.0};
            const FrameRect r = fitRect(lo, hi, w, h, stretch);
            const double pu = (r.u1 - r.u0) / w, pv = (r.v1 - r.v0) / h;
            EXPECT_NEAR(pu / pv, stretch, 1e-12 * stretch);
            EXPECT_NEAR(0.5 * (r.u0 + r.u1), 2500.0, 1e-9);
            EXPECT_NEAR(0.5 * (r.v0 + r.v1), 250.0, 1e-9);
            const double mu = kDefaultFrameMargin * 3000.0, mv = kDefaultFrameMargin * 900.0;
            EXPECT_LE(r.u0, lo.x - mu + 1e-9);
            EXPECT_GE(r.u1, hi.x + mu - 1e-9);
            EXPECT_LE(r.v0, lo.y - mv + 1e-9);
            EXPECT_GE(r.v1, hi.y + mv - 1e-9);
            // Tight along one axis: the frame is no larger than it must be.
            const bool tightU = std::abs((r.u1 - r.u0) - (3000.0 + 2 * mu)) < 1e-9;
            const bool tightV = std::abs((r.v1 - r.v0) - (900.0 + 2 * mv)) < 1e-9;
            EXPECT_TRUE(tightU || tightV);
        }
}

// The model's bounds projected on the plane are inside the default frame, for any plane.
TEST(DefaultFrame, ContainsTheModelOnThePlane) {
    const Aabb b = gkBounds();
    const glm::dvec3 origin = b.centre();
    for (const glm::dvec3 n : {glm::dvec3(0, 1, 0), glm::dvec3(0.3, 0.8, 0.5), glm::dvec3(0, 0, -1)}) {
        const Plane p = planeThrough(n, b.centre());
        const FrameRect r = defaultFrame(p, b, origin, 512, 256, VerticalExaggeration::aboutCentreOf(3.0, b));
        const SectionFrame f = makeSectionFrame(p, origin);
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 corner{(c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y,
                                    (c & 4) ? b.max.z : b.min.z};
            const glm::dvec2 uv = f.toPlane(corner - origin);
            EXPECT_GE(uv.x, r.u0);
            EXPECT_LE(uv.x, r.u1);
            EXPECT_GE(uv.y, r.v0);
            EXPECT_LE(uv.y, r.v1);
        }
    }
}

// The GL renderer's display profile of a true frame shows, at every pixel centre, the world
// point the exact engine's PixelFrame puts there (after mapping display -> world): the two
// engines draw the same picture for the same frame and exaggeration.
TEST(DefaultFrame, DisplayProfileShowsTheSameWorldPointsAsThePixelFrame) {
    const Aabb b = gkBounds();
    const int w = 64, h = 32;
    for (double k : {1.0, 2.0, 5.0})
        for (const glm::dvec3 n : {glm::dvec3(0, 1, 0), glm::dvec3(0.3, 0.8, 0.5), glm::dvec3(-0.6, 0.2, -0.7)}) {
            const Plane p = planeThrough(n, b.centre());
            const VerticalExaggeration ve = VerticalExaggeration::aboutCentreOf(k, b);
            PixelFrame exact;
            exact.section = makeSectionFrame(p, glm::dvec3(0.0));
            exact.rect = defaultFrame(p, b, glm::dvec3(0.0), w, h, ve);
            exact.width = w;
            exact.height = h;
            const ProfileView shown = profileView(p, exact.rect, ve);
            for (int j = 0; j < h; j += 7)
                for (int i = 0; i < w; i += 9) {
                    const glm::dvec3 a = exact.pixelCentreWorld(i, j);
                    const glm::dvec3 g = ve.toWorld(profilePixelWorld(shown, w, h, i, j));
                    EXPECT_NEAR(glm::length(a - g), 0.0, 1e-6) << "k " << k << " pixel " << i << "," << j;
                }
        }
}
