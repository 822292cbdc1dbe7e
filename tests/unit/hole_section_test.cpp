// Drillholes on sections: the segment index (model/drillholes/hole_index.hpp) against a brute
// force scan, and the drawing of holes on profile views (section/holes/hole_section.hpp,
// api/holes.hpp) against an independent projection oracle.
//
// The oracle: a vertical plane y = Yc (normal +y, so offset = y - Yc, negative = in front)
// has plane u = world x and v = world z (SectionFrame: u = normalize(n x z) = +x, v = u x n =
// +z, origin the foot of the perpendicular from the world origin, x = 0); with frame
// u0..u1 = Xc-200..Xc+200, v0..v1 = Zc-150..Zc+150 on a 400 x 300 image a pixel is 1 m, so
// world (x, z) is pixel ((x - u0), (v1 - z)). A straight hole collared at (Xc, Yc-30, Zc+100)
// with azimuth 0 and dip -45 is at (Xc, Yc - 30 + d/sqrt2, Zc + 100 - d/sqrt2) at depth d: it
// pierces the plane at d = 30 sqrt2, and with holes=20 is drawn from d = 10 sqrt2 to 50 sqrt2.
// Tolerances: section coordinates 1e-6 m (a few double operations on ~1e3 m values);
// SVG pixel coordinates 1e-3 px (printed with 3 decimals); the query's depth within 1 m (the
// pixel centre is 0.5 px = 0.5 m from the pierce, sqrt2 x that along the hole).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <regex>

#include "api/catalog.hpp"
#include "api/holes.hpp"
#include "api/pixel_query.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "model/drillholes/hole_index.hpp"
#include "model/synthetic/synthetic.hpp"
#include "section/holes/hole_section.hpp"

namespace geoslice {
namespace {

constexpr double kSqrt2 = 1.4142135623730951;
constexpr double kCoordTolM = 1e-6;
constexpr double kSvgTolPx = 1e-3;

DrillholeDatabase databaseOf(const std::string& collar, const std::string& survey) {
    DrillholeSources s;
    s.source = "test";
    s.collar = {"collar", "collar.csv", collar, {}, {}, DipConvention::NegativeDown};
    s.survey = DrillholeTableSource{"survey", "survey.csv", survey, {}, {}, DipConvention::NegativeDown};
    s.intervals.push_back({"lith",
                           "lith.csv",
                           "hole,from,to,rock\nA,0,40,sandstone\nA,40,120,shale\nC,0,200,granite\n",
                           {},
                           {},
                           DipConvention::NegativeDown});
    auto db = buildDrillholes(std::move(s));
    EXPECT_TRUE(db) << db.error().message;
    return std::move(db.value());
}

std::string num(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

struct Fixture {
    std::shared_ptr<const api::CatalogModel> model;
    glm::dvec3 c{0.0};
};

const Fixture& fixture() {
    static const Fixture f = [] {
        SyntheticOptions o;
        o.triangles = 2000;
        Model m = generateSynthetic(o).value();
        const glm::dvec3 c = m.bounds().centre();
        const std::string collar = "hole,x,y,z,depth\nA," + num(c.x) + "," + num(c.y - 30.0) + "," + num(c.z + 100.0) +
                                   ",120\nB," + num(c.x + 100.0) + "," + num(c.y + 60.0) + "," + num(c.z + 100.0) +
                                   ",200\nC," + num(c.x - 100.0) + "," + num(c.y - 5.0) + "," + num(c.z + 120.0) +
                                   ",200\n";
        const std::string survey = "hole,depth,azimuth,dip\nA,0,0,-45\nC,0,90,-60\nC,50,80,-70\nC,100,60,-80\n";
        Fixture fx;
        fx.c = c;
        fx.model =
            api::catalogModelOf("holes", std::move(m), "v1", api::RayBuild::Now, databaseOf(collar, survey)).value();
        return fx;
    }();
    return f;
}

api::ViewPlan planOf(api::Params p) {
    const Fixture& f = fixture();
    p["size"] = "400x300";
    p["frame"] = num(f.c.x - 200.0) + "," + num(f.c.x + 200.0) + "," + num(f.c.z - 150.0) + "," + num(f.c.z + 150.0);
    if (!p.count("line")) p["plane"] = "0,1,0," + num(-f.c.y);
    auto plan = api::parseViewPlan(p, "holes", f.model->model.crs);
    EXPECT_TRUE(plan) << plan.error().message;
    return plan.value();
}

const DrillholeDatabase& db() { return *fixture().model->drillholes; }

}  // namespace

TEST(HoleIndex, SegmentsNearAPlaneMatchABruteForceScan) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::string collar = "hole,x,y,z,depth\n", survey = "hole,depth,azimuth,dip\n";
    for (int h = 0; h < 300; ++h) {
        const std::string id = "H" + std::to_string(h);
        collar += id + "," + num(1000.0 * u(rng)) + "," + num(1000.0 * u(rng)) + "," + num(100.0 * u(rng)) + ",300\n";
        double az = 360.0 * u(rng), dip = -30.0 - 60.0 * u(rng);
        for (int s = 0; s < 10; ++s) {
            survey += id + "," + std::to_string(30 * s) + "," + num(az) + "," + num(dip) + "\n";
            az = std::fmod(az + 15.0 * u(rng), 360.0);
            dip = std::clamp(dip - 5.0 * u(rng), -89.0, -1.0);
        }
    }
    DrillholeSources s;
    s.collar = {"collar", "collar.csv", collar, {}, {}, DipConvention::NegativeDown};
    s.survey = DrillholeTableSource{"survey", "survey.csv", survey, {}, {}, DipConvention::NegativeDown};
    const DrillholeDatabase d = buildDrillholes(std::move(s)).value();
    const HoleIndex index(d);
    ASSERT_GT(index.segments().size(), 3000u);
    // Every chord's ends lie on the desurveyed path (exactly: they are HolePath::at of their depths).
    for (const HoleSegment& seg : index.segments()) {
        EXPECT_LT(glm::length(seg.a - d.holes[seg.hole].path.at(seg.from)), 1e-9);
        EXPECT_LT(glm::length(seg.b - d.holes[seg.hole].path.at(seg.to)), 1e-9);
    }
    for (int k = 0; k < 100; ++k) {
        const double th = 6.28318 * u(rng), ph = 3.14159 * u(rng);
        const glm::dvec3 n(std::sin(ph) * std::cos(th), std::sin(ph) * std::sin(th), std::cos(ph));
        const double dd = -glm::dot(n, glm::dvec3(1000.0 * u(rng), 1000.0 * u(rng), -150.0 * u(rng)));
        const double w = k % 10 == 0 ? 0.0 : 60.0 * u(rng);
        std::vector<std::uint32_t> got, want;
        index.segmentsNearPlane(n, dd, w, got);
        for (std::uint32_t i = 0; i < index.segments().size(); ++i) {
            const HoleSegment& seg = index.segments()[i];
            const double sa = glm::dot(n, seg.a) + dd, sb = glm::dot(n, seg.b) + dd;
            if (std::min(sa, sb) <= w && std::max(sa, sb) >= -w) want.push_back(i);
        }
        EXPECT_EQ(got, want) << "plane " << k;
    }
}

TEST(HoleSection, PlaneProjectionMatchesTheOracle) {
    const Fixture& f = fixture();
    const api::ViewPlan plan = planOf({{"holes", "20"}});
    auto mapping = api::profileMapping(*f.model, plan);
    ASSERT_TRUE(mapping);
    auto holes = api::viewHoles(*f.model, plan.section, mapping.value());
    ASSERT_TRUE(holes);
    const HoleSection& hs = holes.value().section;
    double lo = 1e9, hi = -1e9;
    for (const HoleTracePiece& p : hs.pieces) {
        const std::string& id = db().holes[p.hole].id;
        ASSERT_NE(id, "B") << "hole B is 60 m from the plane, outside the 20 m window";
        for (const auto& [d, uv, off] : {std::tuple{p.from, p.a, p.offsetA}, std::tuple{p.to, p.b, p.offsetB}}) {
            const glm::dvec3 w = db().holes[p.hole].path.at(d);
            // Straight holes exactly; a curved hole's points between chord ends (where the window
            // clips it or the plane splits it) lie on the chord, within kMaxChordError of the arc.
            const double tol = id == "C" ? kMaxChordError : kCoordTolM;
            // The perpendicular projection on y = Yc: (x, z); the offset y - Yc.
            EXPECT_NEAR(uv.x, w.x, tol) << id << " at " << d;
            EXPECT_NEAR(uv.y, w.z, tol) << id << " at " << d;
            EXPECT_NEAR(off, w.y - f.c.y, tol) << id << " at " << d;
            EXPECT_LE(std::abs(off), 20.0 + kCoordTolM);
        }
        // The front/behind split: in front exactly while y < Yc.
        const double mid = 0.5 * (p.from + p.to);
        EXPECT_EQ(p.front, db().holes[p.hole].path.at(mid).y < f.c.y) << id << " at " << mid;
        if (id == "A") lo = std::min(lo, p.from), hi = std::max(hi, p.to);
    }
    // Hole A (straight): drawn from 10 sqrt2 to 50 sqrt2 m, split at the pierce 30 sqrt2 m.
    EXPECT_NEAR(lo, 10.0 * kSqrt2, kCoordTolM);
    EXPECT_NEAR(hi, 50.0 * kSqrt2, kCoordTolM);
    int pierceA = 0;
    for (const HolePierce& p : hs.pierces) {
        if (db().holes[p.hole].id != "A") continue;
        ++pierceA;
        EXPECT_NEAR(p.depth, 30.0 * kSqrt2, kCoordTolM);
        EXPECT_NEAR(p.at.x, f.c.x, kCoordTolM);
        EXPECT_NEAR(p.at.y, f.c.z + 70.0, kCoordTolM);
    }
    EXPECT_EQ(pierceA, 1);
    // A wider window brings hole B in.
    const api::ViewPlan wide = planOf({{"holes", "100"}});
    auto wh = api::viewHoles(*f.model, wide.section, mapping.value());
    bool hasB = false;
    for (const HoleTracePiece& p : wh.value().section.pieces) hasB |= db().holes[p.hole].id == "B";
    EXPECT_TRUE(hasB);
}

TEST(HoleSection, CurvedHoleStationsProjectOntoThePlane) {
    // Hole C's survey stations (nodes of its path, hence chord ends) within the window appear in
    // the GeoJSON at their perpendicular projection (x, z).
    const Fixture& f = fixture();
    auto text = api::renderVector(*f.model, planOf({{"holes", "50"}}), api::VectorFormat::GeoJson, VectorFrame::Plane);
    ASSERT_TRUE(text);
    const auto doc = nlohmann::json::parse(text.value());
    const HolePath& path = db().find("C")->path;
    int matched = 0;
    for (std::size_t k = 0; k < path.depth.size(); ++k) {
        const glm::dvec3 w = path.position[k];
        if (std::abs(w.y - f.c.y) > 50.0) continue;
        for (const auto& feat : doc["features"]) {
            const auto& p = feat["properties"];
            if (p.value("kind", "") != "drillhole" || p["hole"] != "C") continue;
            for (const auto& [key, idx] : {std::pair{"from", 0}, std::pair{"to", 1}}) {
                if (std::abs(p[key].get<double>() - path.depth[k]) > 1e-9) continue;
                const auto& xy = feat["geometry"]["coordinates"][idx];
                EXPECT_NEAR(xy[0].get<double>(), w.x, kCoordTolM);
                EXPECT_NEAR(xy[1].get<double>(), w.z, kCoordTolM);
                ++matched;
            }
        }
    }
    EXPECT_GE(matched, 3);
    // Interval columns ride along: hole A's first 40 m are sandstone.
    bool sandstone = false;
    for (const auto& feat : doc["features"]) {
        const auto& p = feat["properties"];
        if (p.value("kind", "") == "drillhole" && p["hole"] == "A" && p["to"].get<double>() <= 40.0)
            sandstone |= p.value("rock", "") == "sandstone";
    }
    EXPECT_TRUE(sandstone);
}

TEST(HoleSection, SvgAndImageDrawTheOracleTrace) {
    const Fixture& f = fixture();
    const api::ViewPlan plan = planOf({{"holes", "20"}});
    auto svg = api::renderVector(*f.model, plan, api::VectorFormat::Svg, VectorFrame::Plane);
    ASSERT_TRUE(svg);
    const std::regex line(
        "<line x1=\"([-0-9.]+)\" y1=\"([-0-9.]+)\" x2=\"([-0-9.]+)\" "
        "y2=\"([-0-9.]+)\"[^>]*data-hole=\"A\"[^>]*data-side=\"(front|behind)\"");
    double ylo = 1e9, yhi = -1e9;
    int n = 0;
    for (auto it = std::sregex_iterator(svg.value().begin(), svg.value().end(), line); it != std::sregex_iterator();
         ++it) {
        const double x1 = std::stod((*it)[1]), y1 = std::stod((*it)[2]), x2 = std::stod((*it)[3]),
                     y2 = std::stod((*it)[4]);
        EXPECT_NEAR(x1, 200.0, kSvgTolPx);
        EXPECT_NEAR(x2, 200.0, kSvgTolPx);
        // Pixel row 80 is the pierce (z = Zc + 70): above it in front, below it behind.
        const bool front = (*it)[5] == "front";
        EXPECT_EQ(front, std::max(y1, y2) <= 80.0 + kSvgTolPx) << y1 << " " << y2;
        ylo = std::min({ylo, y1, y2});
        yhi = std::max({yhi, y1, y2});
        ++n;
    }
    EXPECT_GE(n, 2);
    EXPECT_NEAR(ylo, 60.0, kSvgTolPx);
    EXPECT_NEAR(yhi, 100.0, kSvgTolPx);
    EXPECT_NE(svg.value().find("<circle class=\"pierce\" cx=\"200.000\" cy=\"80.000\""), std::string::npos);

    auto with = api::renderProfile(*f.model, plan);
    auto without = api::renderProfile(*f.model, planOf({{"holes", "0"}}));
    ASSERT_TRUE(with && without);
    auto px = [](const api::ViewImage& v, int x, int y) { return &v.rgba[(std::size_t(y) * v.width + x) * 4]; };
    // The pierce disc is white around pixel point (200, 80).
    for (int c = 0; c < 3; ++c) EXPECT_GT(px(with.value(), 200, 80)[c], 230) << c;
    // The front part (rows 60-80) is the solid near-black trace.
    for (int c = 0; c < 3; ++c) EXPECT_LT(px(with.value(), 200, 70)[c], 60) << c;
    // Behind (rows 80-100): dashed, so some rows differ from the image without holes.
    int changed = 0;
    for (int y = 86; y < 100; ++y)
        changed += std::memcmp(px(with.value(), 200, y), px(without.value(), 200, y), 4) != 0;
    EXPECT_GT(changed, 3);
    // Hole B (x = Xc + 100: column 300) is outside the window: its column is untouched; so is
    // everything more than 10 px from hole A's trace and clear of the labels above it.
    for (int y = 0; y < 300; ++y) EXPECT_EQ(std::memcmp(px(with.value(), 300, y), px(without.value(), 300, y), 4), 0);
    for (int y = 0; y < 300; ++y)
        for (int x : {188, 212}) {
            if (y < 60 && x > 200) continue;  // hole A's label and C's are above and right of their tops
            EXPECT_EQ(std::memcmp(px(with.value(), x, y), px(without.value(), x, y), 4), 0) << x << "," << y;
        }
    // The ID buffer is the model's alone.
    EXPECT_EQ(with.value().ids, without.value().ids);
}

TEST(HoleSection, PixelQueryAnswersTheHoleNextToTheModel) {
    const Fixture& f = fixture();
    const api::ViewPlan plan = planOf({{"holes", "20"}});
    auto a = api::answerPixel(*f.model, plan, 200, 80, nullptr);
    ASSERT_TRUE(a);
    ASSERT_TRUE(a.value().hole);
    EXPECT_EQ(db().holes[a.value().hole->hole].id, "A");
    EXPECT_NEAR(a.value().hole->depth, 30.0 * kSqrt2, 1.0);
    std::string out;
    api::writeQueryAnswer(*f.model, a.value(), out);
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j["drillhole"]["id"], "A");
    EXPECT_EQ(j["drillhole"]["intervals"][0]["columns"]["rock"], "shale");  // 40-120 m
    EXPECT_TRUE(j.contains("record"));
    // Far from every drawn hole: no drillhole in the answer.
    auto b = api::answerPixel(*f.model, plan, 300, 100, nullptr);
    ASSERT_TRUE(b);
    EXPECT_FALSE(b.value().hole);
}

TEST(HoleSection, PolylineLegsProjectAndClipByChainage) {
    const Fixture& f = fixture();
    // Leg 0 runs east along y = Yc (kept side north, as the plane), leg 1 north from Xc + 50.
    const std::string line = num(f.c.x - 200.0) + "," + num(f.c.y) + "," + num(f.c.x + 50.0) + "," + num(f.c.y) + "," +
                             num(f.c.x + 50.0) + "," + num(f.c.y + 200.0);
    const api::ViewPlan plan = planOf({{"line", line}, {"holes", "20"}});
    auto mapping = api::profileMapping(*f.model, plan);
    ASSERT_TRUE(mapping) << mapping.error().message;
    const HoleSection hs = holesOnLine(*f.model->holeIndex, mapping.value().line, 20.0);
    int pierceA = 0;
    for (const HolePierce& p : hs.pierces)
        if (db().holes[p.hole].id == "A") {
            ++pierceA;
            EXPECT_EQ(p.leg, 0u);
            EXPECT_NEAR(p.at.x, 200.0, kCoordTolM);  // chainage of x = Xc
            EXPECT_NEAR(p.at.y, f.c.z + 70.0, kCoordTolM);
        }
    EXPECT_EQ(pierceA, 1);
    for (const HoleTracePiece& p : hs.pieces) {
        EXPECT_GE(p.a.x, p.leg == 0 ? -kCoordTolM : 250.0 - kCoordTolM);
        EXPECT_LE(p.a.x, p.leg == 0 ? 250.0 + kCoordTolM : 450.0 + kCoordTolM);
        EXPECT_NE(db().holes[p.hole].id, "B");  // 60 m from leg 0, 50 m from leg 1
    }
}

TEST(HoleSection, ParametersAreValidatedAndCanonical) {
    const Fixture& f = fixture();
    auto bad = api::parseViewPlan({{"plane", "0,1,0,0"}, {"holes", "-1"}}, "holes", f.model->model.crs);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("'holes'"), std::string::npos);
    const api::ViewPlan p = planOf({{"holes", "30"}, {"holecolour", "rock"}});
    EXPECT_NE(p.canonical().find("&holes=30&holecolour=rock&holeramp=viridis"), std::string::npos);
    EXPECT_EQ(planOf({}).canonical().find("&hole"), std::string::npos);
    auto missing = api::holeStyle(*f.model, api::HoleDrawing{50.0, "nope", "viridis", std::nullopt});
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("lith.rock"), std::string::npos);
    auto style = api::holeStyle(*f.model, api::HoleDrawing{50.0, "rock", "viridis", std::nullopt});
    ASSERT_TRUE(style);
    EXPECT_EQ(style.value().categories, (std::vector<std::string>{"granite", "sandstone", "shale"}));
    EXPECT_EQ(api::holeLegendJson(style.value())["entries"].size(), 4u);  // three and "no interval"
}

}  // namespace geoslice
