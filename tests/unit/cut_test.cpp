// Cut-outs (api/cut.hpp): parsing, validation and canonical text of several planes, the
// kept spans of a ray against an independent point test, and the "removes everything" check
// against analytic boxes.
//
// Tolerances: kept spans are compared with the point test at sample parameters farther than
// 1e-6 m from every span end (double rounding of s0 / ds at coordinates of 1e3 m is ~1e-13 m).
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "api/cut.hpp"
#include "api/plan.hpp"

namespace geoslice::api {
namespace {

// Metres: samples within 1 um of a span's end (spans from double ray-plane intersections)
// are not compared.
constexpr double kNearEndM = 1e-6;

Result<ViewPlan> plan(const Params& p) {
    static const Crs crs = Crs::local();
    return parseViewPlan(p, "m", crs);
}

void expectError(const Params& p, const std::string& needle) {
    auto r = plan(p);
    ASSERT_FALSE(r) << "accepted: " << (r ? r.value().canonical() : "");
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
}

TEST(Cut, RepeatedPlaneAndPlanesHaveOneCanonicalForm) {
    const Params repeated{{"plane", "1,0,0,-10;0,2,0,-40"}, {"cut", "intersection"}, {"view", "perspective"}};
    const Params list{{"planes", "0,1,0,-20;1,0,0,-10"}, {"cut", "intersection"}, {"view", "perspective"}};
    auto a = plan(repeated), b = plan(list);
    ASSERT_TRUE(a) << a.error().message;
    ASSERT_TRUE(b) << b.error().message;
    EXPECT_EQ(a.value().canonical(), b.value().canonical());
    EXPECT_NE(a.value().canonical().find("planes=0,1,0,-20;1,0,0,-10&cut=intersection"), std::string::npos)
        << a.value().canonical();
    // The section id of a cut-out decodes to the same definition (canonical text is a fixed point).
    const std::string sid = encodeSectionId(a.value().section);
    const Crs crs = Crs::local();
    auto back = decodeSectionId(sid, [&](const std::string&) { return &crs; });
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back.value().canonical(), a.value().section.canonical());
    // One plane keeps its old canonical form, with or without `cut`.
    auto one = plan({{"plane", "0,1,0,-5"}, {"cut", "intersection"}, {"view", "perspective"}});
    ASSERT_TRUE(one);
    EXPECT_EQ(one.value().section.canonical().find("cut"), std::string::npos);
    EXPECT_NE(one.value().section.canonical().find("&plane=0,1,0,-5"), std::string::npos);
    auto modes = plan({{"planes", "1,0,0,0;0,1,0,0"}, {"cut", "union"}, {"view", "perspective"}});
    ASSERT_TRUE(modes);
    EXPECT_NE(modes.value().canonical(), a.value().canonical());
}

TEST(Cut, BadPlaneListsAreErrorsNamingTheParameter) {
    const std::string six = "1,0,0,1;0,1,0,1;0,0,1,1;-1,0,0,1;0,-1,0,1;0,0,-1,1";
    EXPECT_TRUE(plan({{"planes", six}, {"cut", "intersection"}, {"view", "perspective"}}));
    expectError({{"planes", six + ";1,1,0,0"}, {"cut", "intersection"}, {"view", "perspective"}},
                "parameter 'planes': 7 planes given, at most 6");
    expectError({{"plane", "1,0,0,1;0,nan,0,1"}, {"cut", "union"}, {"view", "perspective"}}, "parameter 'plane'");
    expectError({{"planes", "1,0,0,1;0,0,0,1"}, {"cut", "union"}, {"view", "perspective"}}, "plane 2");
    expectError({{"planes", "1,0,0,1;2,0,0,2"}, {"cut", "union"}, {"view", "perspective"}},
                "planes 1 and 2 are the same plane");
    expectError({{"planes", "1,0,0,1;0,1,0,1"}, {"view", "perspective"}}, "parameter 'cut': required");
    expectError({{"planes", "1,0,0,1;0,1,0,1"}, {"cut", "both"}, {"view", "perspective"}}, "parameter 'cut'");
    expectError({{"planes", "1,0,0,1;0,1,0,1"}, {"plane", "1,0,0,1"}, {"cut", "union"}}, "not both");
    expectError({{"planes", "1,0,0,1;0,1,0,1"}, {"cut", "union"}}, "perspective views only");
    expectError({{"elevation", "10"}, {"cut", "union"}}, "parameter 'cut'");
    expectError({{"planes", "1,0,0,1;;0,1,0,1"}, {"cut", "union"}, {"view", "perspective"}}, "plane 2");
    expectError({{"planes", "1,0,0,1e300;0,1,0,1"}, {"cut", "union"}, {"view", "perspective"}}, "plane 1");
}

// The kept spans of rays against the point test, for random cut-outs of 1..6 planes.
TEST(Cut, KeptSpansAgreeWithThePointTest) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::size_t samples = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        CutOut cut;
        cut.mode = trial % 2 ? CutMode::Union : CutMode::Intersection;
        const int n = 1 + trial % 6;
        for (int i = 0; i < n; ++i) {
            glm::dvec3 normal{u(rng), u(rng), u(rng)};
            if (i == 0 && trial % 5 == 0) normal = {0.0, 0.0, 1.0};  // rays parallel to a plane below
            normal = glm::normalize(normal);
            cut.planes.push_back({normal, 300.0 * u(rng)});
        }
        const glm::dvec3 origin{1000.0 * u(rng), 1000.0 * u(rng), trial % 5 == 0 ? 0.0 : 1000.0 * u(rng)};
        glm::dvec3 dir{u(rng), u(rng), trial % 5 == 0 ? 0.0 : u(rng)};
        dir = glm::normalize(dir);
        const auto spans = cut.keptSpans(origin, dir);
        ASSERT_LE(spans.size(), 2u);
        for (std::size_t i = 0; i < spans.size(); ++i) {
            EXPECT_LT(spans[i].from, spans[i].to);
            EXPECT_GE(spans[i].from, 0.0);
            if (i) {
                EXPECT_LT(spans[i - 1].to, spans[i].from);
            }
        }
        for (int k = 0; k < 200; ++k) {
            const double t = 4000.0 * double(k) / 200.0 + 0.37;
            bool nearEnd = false, inSpan = false;
            for (const auto& s : spans) {
                nearEnd = nearEnd || std::abs(t - s.from) < kNearEndM || std::abs(t - s.to) < kNearEndM;
                inSpan = inSpan || (t >= s.from && t <= s.to);
            }
            if (nearEnd) continue;
            // Independent of CutOut: the kept test written out from the definition.
            const glm::dvec3 p = origin + t * dir;
            bool all = true, any = false;
            for (const auto& pl : cut.planes) {
                const bool keptBy = glm::dot(pl.normal, p) + pl.d >= 0.0;
                all = all && keptBy;
                any = any || keptBy;
            }
            const bool kept = cut.mode == CutMode::Union || n == 1 ? all : any;
            EXPECT_EQ(inSpan, kept) << "trial " << trial << " t " << t;
            EXPECT_EQ(cut.keeps(p), kept);
            ++samples;
        }
    }
    EXPECT_GT(samples, 390000u);
}

TEST(Cut, RemovesEverythingIsAnError) {
    Aabb box;
    box.extend({35500000.0, 3380000.0, -100.0});
    box.extend({35501000.0, 3381000.0, 500.0});
    const glm::dvec3 c = box.centre();
    auto planeAt = [&](glm::dvec3 n, glm::dvec3 through) {
        n = glm::normalize(n);
        return Plane{n, -glm::dot(n, through)};
    };
    // A wedge and an octant taken out of the middle: kept.
    CutOut octant{{planeAt({-1, 0, 0}, c), planeAt({0, -1, 0}, c), planeAt({0, 0, -1}, c)}, CutMode::Intersection};
    EXPECT_TRUE(checkCutKeepsSomething("planes", octant, box));
    // An "octant" whose removed region holds the whole box: every plane's removed side beyond it.
    CutOut all{{planeAt({1, 0, 0}, box.max + 1.0), planeAt({0, 1, 0}, box.max + 1.0)}, CutMode::Intersection};
    auto e = checkCutKeepsSomething("planes", all, box);
    ASSERT_FALSE(e);
    EXPECT_NE(e.error().message.find("parameter 'planes': the cut removes the whole model"), std::string::npos)
        << e.error().message;
    // Union: a small tetrahedron kept inside the box, no corner of the box kept: something is kept.
    const glm::dvec3 t0 = c + glm::dvec3(-10.0), t1 = c + glm::dvec3(10.0, 0, 0), t2 = c + glm::dvec3(0, 10.0, 0),
                     t3 = c + glm::dvec3(0, 0, 10.0);
    auto face = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 d, glm::dvec3 opposite) {
        glm::dvec3 n = glm::normalize(glm::cross(b - a, d - a));
        if (glm::dot(n, opposite - a) < 0) n = -n;  // kept side towards the fourth vertex
        return Plane{n, -glm::dot(n, a)};
    };
    CutOut tetra{{face(t0, t1, t2, t3), face(t0, t1, t3, t2), face(t0, t2, t3, t1), face(t1, t2, t3, t0)},
                 CutMode::Union};
    for (int i = 0; i < 8; ++i)
        EXPECT_FALSE(
            tetra.keeps({i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z}));
    EXPECT_TRUE(checkCutKeepsSomething("planes", tetra, box));
    // The same tetrahedron moved out of the box: nothing kept.
    const glm::dvec3 away(0.0, 0.0, 2000.0);
    CutOut far{{face(t0 + away, t1 + away, t2 + away, t3 + away), face(t0 + away, t1 + away, t3 + away, t2 + away),
                face(t0 + away, t2 + away, t3 + away, t1 + away), face(t1 + away, t2 + away, t3 + away, t0 + away)},
               CutMode::Union};
    EXPECT_FALSE(checkCutKeepsSomething("planes", far, box));
    // Two parallel planes keeping a slab beside the box.
    CutOut slab{{planeAt({1, 0, 0}, box.max + 10.0), planeAt({-1, 0, 0}, box.max + 20.0)}, CutMode::Union};
    EXPECT_FALSE(checkCutKeepsSomething("planes", slab, box));
    // One plane: its kept side beyond the box.
    CutOut one{{planeAt({0, 0, 1}, box.max + 1.0)}, CutMode::Union};
    EXPECT_FALSE(checkCutKeepsSomething("plane", one, box));
}

}  // namespace
}  // namespace geoslice::api
