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

#include "renderer/views.hpp"
#include "tests/common/tolerances.hpp"
#include "view/camera.hpp"
#include "view/exaggeration.hpp"
#include "view/plane.hpp"
#include "view/view_frame.hpp"

using namespace geoslice;

namespace {

// Tolerances (the header comment says why in full).
// Ratios, cosines and angles (rad) of unit-scale quantities: a few double steps.
constexpr double kUnitTol = 1e-12;
// |a normalised vector| - 1: normalize leaves a few 1e-16.
constexpr double kUnitLengthTol = 1e-15;
// A ratio of lengths over a 100 m baseline at GK eastings: 7.5e-9 m steps / 100 m, with margin.
constexpr double kBaselineTol = 1e-9;
// Metres, coordinates under 1e4 m (frame centres, a z-only round trip): double steps of 2e-12 m.
constexpr double kSmallCoordTolM = 1e-9;
using test::kGkWorldTolM;  // metres, world points at GK eastings (tests/common/tolerances.hpp)
// Pixels: double matrices and rays; 7.5e-9 m steps against pixels of 5-50 m.
constexpr double kPixelTol = 1e-6;

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
    EXPECT_NEAR(glm::length(ve.toWorld(ve.toDisplay(p)) - p), 0.0, kSmallCoordTolM);
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
            EXPECT_NEAR(alongU, 1.0, kBaselineTol) << "k " << k;
            EXPECT_NEAR(alongV, ve.vStretch(p.normal), kBaselineTol) << "k " << k;
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
            EXPECT_NEAR(pu / pv, stretch, kUnitTol * stretch);
            EXPECT_NEAR(0.5 * (r.u0 + r.u1), 2500.0, kSmallCoordTolM);
            EXPECT_NEAR(0.5 * (r.v0 + r.v1), 250.0, kSmallCoordTolM);
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
            const ProfileCamera shown = profileCamera(p, exact.rect, ve);
            for (int j = 0; j < h; j += 7)
                for (int i = 0; i < w; i += 9) {
                    const glm::dvec3 a = exact.pixelCentreWorld(i, j);
                    const glm::dvec3 g = ve.toWorld(pixelRay(shown, w, h, i + 0.5, j + 0.5).origin);
                    EXPECT_NEAR(glm::length(a - g), 0.0, kGkWorldTolM) << "k " << k << " pixel " << i << "," << j;
                }
        }
}

// The perspective camera's pixel rays (view/camera.hpp): the image centre looks at the
// target, the top edge's centre is fov/2 above it, the right edge's centre at the
// horizontal half-angle atan(aspect tan(fov/2)); the default camera's distance rule. Angles
// to 1e-12 rad (a few double steps of unit vectors).
TEST(PerspectiveCameraRays, CentreEdgesAndDefault) {
    PerspectiveCamera cam;
    cam.eye = {35'504'000.0, 3'380'000.0, 2000.0};
    cam.target = {35'504'500.0, 3'388'000.0, -100.0};
    cam.fovYDegrees = 50.0;
    const int w = 300, h = 200;
    const glm::dvec3 f = glm::normalize(cam.target - cam.eye);
    auto angle = [](const glm::dvec3& a, const glm::dvec3& b) {
        return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
    };
    const PixelRay centre = pixelRay(cam, w, h, 150.0, 100.0);
    EXPECT_EQ(centre.origin, cam.eye);
    EXPECT_NEAR(angle(centre.direction, f), 0.0, kUnitTol);
    EXPECT_NEAR(glm::length(centre.direction), 1.0, kUnitLengthTol);
    const double half = glm::radians(25.0);
    EXPECT_NEAR(angle(pixelRay(cam, w, h, 150.0, 0.0).direction, f), half, kUnitTol);
    EXPECT_NEAR(angle(pixelRay(cam, w, h, 300.0, 100.0).direction, f), std::atan(1.5 * std::tan(half)), kUnitTol);
    // Up is up: the top edge's ray climbs more steeply than the centre's.
    EXPECT_GT(pixelRay(cam, w, h, 150.0, 0.0).direction.z, centre.direction.z);

    const Aabb b = gkBounds();
    const PerspectiveCamera d = defaultCamera(b);
    const double radius = 0.5 * glm::length(b.size());
    EXPECT_EQ(d.target, b.centre());
    // At the target's distance the image's half-height is 1.05 bounding radii (relative 1e-12:
    // a few double steps). The sphere's silhouette from the eye is a little wider (asin, not
    // atan): its near half may reach past the frame's edge.
    const double halfHeight = glm::length(d.eye - d.target) * std::tan(glm::radians(0.5 * d.fovYDegrees));
    EXPECT_NEAR(halfHeight / radius, 1.05, kUnitTol);
    EXPECT_GT(d.eye.z, d.target.z);
}

// The CPU pixel ray (what pixel queries trace) and the GL view matrix (what the renderer
// draws, renderer/views.hpp) are one camera: every point of a pixel's ray projects to that
// pixel's centre, for perspective and profile cameras (the latter exaggerated), in the local
// frame of a Gauss-Kruger model. Tolerance 1e-6 px: the matrices and rays are double; a
// double step at 3.5e7 m is 7.5e-9 m against pixels of 5-50 m.
TEST(CameraPixelRays, ProjectToTheirPixelThroughTheRenderersMatrices) {
    const Aabb b = gkBounds();
    const glm::dvec3 origin = b.centre();
    const int w = 320, h = 200;
    auto toPixel = [&](const glm::dmat4& viewProj, const glm::dvec3& world) {
        const glm::dvec4 c = viewProj * glm::dvec4(world - origin, 1.0);
        return glm::dvec2((c.x / c.w + 1.0) * 0.5 * w, (1.0 - c.y / c.w) * 0.5 * h);
    };
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> px(0.0, w), py(0.0, h), t(10.0, 5000.0);

    const PerspectiveCamera cam{b.centre() + glm::dvec3(-7000.0, -9000.0, 6000.0), b.centre(), {0, 0, 1}, 40.0};
    auto persp = perspectiveTransform(cam, origin, b, w, h);
    ASSERT_TRUE(persp.ok()) << persp.error().message;
    for (int i = 0; i < 200; ++i) {
        const double x = px(rng), y = py(rng);
        const PixelRay r = pixelRay(cam, w, h, x, y);
        const glm::dvec2 p = toPixel(persp->viewProj, r.origin + t(rng) * r.direction);
        EXPECT_NEAR(p.x, x, kPixelTol);
        EXPECT_NEAR(p.y, y, kPixelTol);
    }

    const VerticalExaggeration ve = VerticalExaggeration::aboutCentreOf(3.0, b);
    const Plane plane = planeThrough(glm::normalize(glm::dvec3(0.3, 1.0, 0.2)), b.centre());
    const FrameRect frame = defaultFrame(plane, b, origin, w, h, ve);
    const ProfileCamera shown = profileCamera(plane, frame, ve);  // display space
    const glm::dvec3 displayOrigin = ve.toDisplay(origin);
    auto ortho = profileTransform(shown, displayOrigin, ve.boundsToDisplay(b));
    ASSERT_TRUE(ortho.ok()) << ortho.error().message;
    const PixelFrame pf = pixelFrame(shown, w, h);
    for (int i = 0; i < 200; ++i) {
        const double x = px(rng), y = py(rng);
        const PixelRay r = pixelRay(shown, w, h, x, y);
        EXPECT_NEAR(glm::dot(r.direction, glm::dvec3(shown.plane)), 1.0, kUnitTol);  // along +n
        const glm::dvec4 c = ortho->viewProj * glm::dvec4(r.origin + t(rng) * r.direction - displayOrigin, 1.0);
        EXPECT_NEAR((c.x / c.w + 1.0) * 0.5 * w, x, kPixelTol);
        EXPECT_NEAR((1.0 - c.y / c.w) * 0.5 * h, y, kPixelTol);
        // The same point through the pixel frame (the exact engine's mapping).
        const glm::dvec3 q = pf.section.toWorld(pf.pixelToPlane(x, y));
        EXPECT_NEAR(glm::length(q - r.origin), 0.0, kGkWorldTolM);
    }
}
