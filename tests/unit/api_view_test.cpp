// api/ without a socket (issue 14 "done when"): plans and their canonical forms, section
// ids, the tile grid's maths and pixel mappings, on the demo model (EPSG:4523, eastings near
// 3.55e7 m). Oracles: the parameters as written, exact powers-of-two arithmetic for tiles,
// and the plane equation / polyline geometry for pixel -> world.
// Tolerances: tile edges are exact (power-of-two sizes, adjacent tiles share the same double
// expression); pixel -> world within 1e-6 m of the plane (a double step at 3.55e7 m is
// 7.5e-9 m; a pixel centre is a handful of operations from it); frame aspect ratios 1e-12
// relative (one division each).
#include <gtest/gtest.h>

#include <cmath>

#include "api/catalog.hpp"
#include "api/plan.hpp"
#include "api/tile_grid.hpp"
#include "api/view.hpp"
#include "tests/common/tolerances.hpp"

namespace geoslice::api {
namespace {

using test::kGkWorldTolM;  // metres, world points of the demo at GK eastings (tests/common/tolerances.hpp)
// Relative: a ratio of pixel sizes: a few double steps.
constexpr double kRatioRelTol = 1e-12;
// Metres: an elevation (hundreds of metres) carried from the section's v: steps of 1e-13 m.
constexpr double kElevationTolM = 1e-9;

const CatalogModel& demo() {
    static const std::shared_ptr<const CatalogModel> m = makeDemoModel(5000).value();
    return *m;
}

ViewPlan plan(const Params& p) {
    auto r = parseViewPlan(p, "demo", demo().model.crs);
    EXPECT_TRUE(r) << r.error().message;
    return r ? r.value() : ViewPlan{};
}

// "a,b,c,d" of the plane with normal direction n through the demo model's centre.
std::string planeThroughCentre(glm::dvec3 n) {
    n = glm::normalize(n);
    const glm::dvec3 c = demo().index->bounds.centre();
    char buf[160];
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g", n.x, n.y, n.z, -glm::dot(n, c));
    return buf;
}

}  // namespace

TEST(ApiPlan, CanonicalTextIsAFixedPointAndNormalisesPlanes) {
    const ViewPlan p = plan({{"plane", "0,2,0,-6777692"}, {"size", "300x200"}, {"vx", "2.5"}, {"bg", "#ff000080"}});
    EXPECT_DOUBLE_EQ(p.section.plane.normal.y, 1.0);
    EXPECT_DOUBLE_EQ(p.section.plane.d, -3388846.0);
    EXPECT_EQ(p.width, 300);
    EXPECT_EQ(p.height, 200);
    EXPECT_EQ(p.canonical(), "model=demo&plane=0,1,0,-3388846&vx=2.5&bg=ff000080&view=profile&size=300x200");
    for (const Params& q :
         {Params{{"plane", "0,1,0,-3388846"}, {"frame", "1,2,3,4.5"}}, Params{{"elevation", "250"}, {"vx", "3"}},
          Params{{"line", "35502500,3388000,35504500,3389000"}, {"size", "64x32"}}}) {
        const std::string once = plan(q).canonical();
        // Parse the canonical text again (its parameters after "model=demo&").
        Params again;
        std::string rest = once.substr(once.find('&') + 1);
        while (!rest.empty()) {
            const std::size_t amp = rest.find('&');
            const std::string item = rest.substr(0, amp);
            again[item.substr(0, item.find('='))] = item.substr(item.find('=') + 1);
            rest = amp == std::string::npos ? "" : rest.substr(amp + 1);
        }
        EXPECT_EQ(plan(again).canonical(), once);
    }
}

TEST(ApiPlan, SectionIdsRoundTrip) {
    const ViewPlan p = plan({{"plane", planeThroughCentre({0.3, 0.8, 0.5})}, {"vx", "3"}});
    const std::string sid = encodeSectionId(p.section);
    auto back = decodeSectionId(sid, [](const std::string& id) { return id == "demo" ? &demo().model.crs : nullptr; });
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back.value().canonical(), p.section.canonical());
    EXPECT_FALSE(decodeSectionId("!!", [](const std::string&) { return &demo().model.crs; }));
}

// Zoom z halves the tile size; the four children of a tile cover it exactly; a vertical
// plane's grid stretches v by vx, a plan map's not at all (view/exaggeration.hpp).
TEST(ApiTiles, GridMathsAndStretch) {
    const ViewPlan vertical = plan({{"plane", planeThroughCentre({0.0, 1.0, 0.0})}, {"vx", "2"}});
    auto g = tileGrid(demo(), vertical.section);
    ASSERT_TRUE(g) << g.error().message;
    EXPECT_EQ(g->exaggeration, 2.0);
    EXPECT_EQ(std::exp2(std::round(std::log2(g->size0))), g->size0);  // a power of two
    EXPECT_GE(g->size0, g->extent.u1 - g->extent.u0);
    EXPECT_GE(g->size0, (g->extent.v1 - g->extent.v0) * g->exaggeration);
    const FrameRect root = g->tileRect(0, 0, 0).value();
    EXPECT_EQ(root.u0, g->extent.u0);
    EXPECT_EQ(root.v1, g->extent.v1);
    EXPECT_EQ(root.u1 - root.u0, g->size0);
    EXPECT_EQ(root.v1 - root.v0, g->size0 / 2.0);
    for (int x = 0; x < 2; ++x)
        for (int y = 0; y < 2; ++y) {
            const FrameRect c = g->tileRect(1, x, y).value();
            EXPECT_EQ(c.u1 - c.u0, g->size0 / 2.0);
            EXPECT_EQ(c.u0, x == 0 ? root.u0 : g->tileRect(1, 0, y).value().u1);
            EXPECT_EQ(c.v1, y == 0 ? root.v1 : g->tileRect(1, x, 0).value().v0);
        }
    EXPECT_EQ(g->tileRect(1, 1, 1).value().v0, root.v0);
    EXPECT_EQ(g->tileRect(-1, 0, 0).error().code, ErrorCode::NotFound);
    EXPECT_EQ(g->tileRect(2, 4, 0).error().code, ErrorCode::NotFound);
    EXPECT_EQ(g->tileRect(g->maxZoom + 1, 0, 0).error().code, ErrorCode::NotFound);

    auto map = tileGrid(demo(), plan({{"elevation", "200"}, {"vx", "2"}}).section);
    ASSERT_TRUE(map) << map.error().message;
    EXPECT_EQ(map->exaggeration, 1.0);
}

// Pixel -> world of profile views: on the plane (or the polyline's vertical plane), pixel
// centres one pixel apart, and the default frame's pixels stretched as the plane's v.
TEST(ApiPixels, ProfileMappingsLieOnTheSectionAndKeepThePixelAspect) {
    for (const glm::dvec3 n : {glm::dvec3(0, 1, 0), glm::dvec3(0.3, 0.8, 0.5), glm::dvec3(0, 0, -1)}) {
        const ViewPlan p = plan({{"plane", planeThroughCentre(n)}, {"vx", "3"}, {"size", "200x100"}});
        auto m = profileMapping(demo(), p);
        ASSERT_TRUE(m) << m.error().message;
        const Plane& plane = p.section.plane;
        for (int j = 0; j < 100; j += 33)
            for (int i = 0; i < 200; i += 41) {
                const glm::dvec3 w = m->worldAt(i, j);
                EXPECT_NEAR(glm::dot(plane.normal, w) + plane.d, 0.0, kGkWorldTolM);
                EXPECT_NEAR(glm::length(m->worldAt(i + 1, j) - w), (m->rect.u1 - m->rect.u0) / 200.0, kGkWorldTolM);
            }
        const double pu = (m->rect.u1 - m->rect.u0) / 200.0, pv = (m->rect.v1 - m->rect.v0) / 100.0;
        const double stretch = exaggerationOf(p.section, demo().index->bounds).vStretch(plane.normal);
        EXPECT_NEAR(pu / pv, stretch, kRatioRelTol * stretch);
    }
    const ViewPlan line = plan({{"line", "35502500,3388000,35504500,3389000"}, {"size", "100x50"}, {"vx", "2"}});
    auto m = profileMapping(demo(), line);
    ASSERT_TRUE(m) << m.error().message;
    const glm::dvec2 a{35502500, 3388000}, b{35504500, 3389000};
    for (int i = 0; i < 100; i += 9) {
        const glm::dvec2 s = m->sectionAt(i, 10);
        const glm::dvec3 w = m->worldAt(i, 10);
        EXPECT_NEAR(w.z, s.y, kElevationTolM);
        // On the map line through a and b, at chainage s from a.
        const glm::dvec2 along = glm::normalize(b - a);
        EXPECT_NEAR(glm::length(glm::dvec2(w) - (a + s.x * along)), 0.0, kGkWorldTolM);
    }
}

}  // namespace geoslice::api
