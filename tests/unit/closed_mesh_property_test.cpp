// Property test of closed meshes: every generated solid (tests/common/closed_mesh_cases.hpp:
// boxes, n-gon prisms, bipyramids, a frame of genus 1, nested cavities, bodies touching at an
// edge or a vertex; any winding per shell, any triangulation, shuffled and welded or not, at
// small and Gauss-Kruger coordinates) loads closed with the right shells and the closed-form
// volume, and the model path answers as the solid says: classify inside and outside, section
// areas of axis-aligned planes, info's volume equal to reserves'. Tolerances: kRelTol (1e-9
// relative) in the header, where it is argued.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <random>
#include <string>

#include "tests/common/closed_mesh_cases.hpp"

using namespace geoslice;
using namespace geoslice::test::closed;

namespace {

constexpr int kCases = 420;
constexpr std::uint64_t kSeed = 0x5EC7105ull;

std::string failureText(const Case& cs, const std::vector<std::string>& fails) {
    std::string s = cs.params.text() + "\n";
    for (const auto& f : fails) s += "  " + f + "\n";
    return s;
}

}  // namespace

TEST(ClosedMeshProperty, GeneratedSolidsLoadAndAnswerAsTheirClosedForms) {
    std::mt19937_64 rng(kSeed);
    std::array<int, kShapeCount> perShape{}, failedPerShape{};
    int failed = 0, wrongWound = 0, gk = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kCases; ++i) {
        const CaseParams p = drawParams(rng);
        const Case cs = makeCase(p);
        ++perShape[static_cast<std::size_t>(cs.params.shape)];
        wrongWound += cs.anyWrong;
        gk += cs.params.offsetKind == 2;
        std::mt19937_64 checkRng(p.seed ^ 0x9E3779B97F4A7C15ull);
        const auto fails = checkCase(cs, checkRng);
        if (!fails.empty()) ++failedPerShape[static_cast<std::size_t>(cs.params.shape)];
        if (!fails.empty() && ++failed <= 10) ADD_FAILURE() << "case " << i << ": " << failureText(cs, fails);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("closed-mesh property: %d cases in %.2f s (%d with a shell wound wrong, %d at Gauss-Kruger offsets)",
                kCases, seconds, wrongWound, gk);
    for (int s = 0; s < kShapeCount; ++s)
        std::printf("%s %s %d (%d failed)", s ? "," : ";", shapeName(static_cast<Shape>(s)),
                    perShape[static_cast<std::size_t>(s)], failedPerShape[static_cast<std::size_t>(s)]);
    std::printf("\n");
    EXPECT_EQ(failed, 0);
    for (int s = 0; s < kShapeCount; ++s) EXPECT_GE(perShape[static_cast<std::size_t>(s)], 20) << shapeName(Shape(s));
}

// Every shape with every winding of its shells, at Gauss-Kruger coordinates, welded and as a
// triangle soup: the combinations the random draw might leave out.
TEST(ClosedMeshProperty, EveryWindingOfEveryShape) {
    int cases = 0;
    for (int shape = 0; shape < kShapeCount; ++shape)
        for (std::uint32_t flips = 0; flips < 8; ++flips)
            for (Weld weld : {Weld::Position, Weld::Soup}) {
                CaseParams p;
                p.shape = static_cast<Shape>(shape);
                p.offsetKind = 2;
                p.size = glm::dvec3(120.0, 80.0, 60.0);
                p.axisPerm = static_cast<int>(flips % 6);
                p.mirror = static_cast<int>(flips);
                p.windingFlips = flips;
                p.weld = weld;
                p.sides = 7;
                p.extraLines = 2;
                p.variant = 1;
                p.seed = 1000u * static_cast<unsigned>(shape) + flips;
                const Case cs = makeCase(p);
                std::mt19937_64 rng(p.seed);
                const auto fails = checkCase(cs, rng);
                EXPECT_TRUE(fails.empty()) << failureText(cs, fails);
                ++cases;
            }
    EXPECT_EQ(cases, kShapeCount * 16);
}

// The 0..10 cube of the bug report, wound inward: one shell, 1000 m3, no split anywhere.
TEST(ClosedMeshProperty, InwardCubeOfTheReport) {
    CaseParams p;
    p.shape = Shape::Box;
    p.size = glm::dvec3(10.0);
    p.windingFlips = 1;
    p.extraLines = 0;
    const Case cs = makeCase(p);
    ASSERT_EQ(cs.bounds.min, glm::dvec3(0.0));
    ASSERT_EQ(cs.bounds.max, glm::dvec3(10.0));
    std::mt19937_64 rng(7);
    const auto fails = checkCase(cs, rng, 4);
    EXPECT_TRUE(fails.empty()) << failureText(cs, fails);
    Mesh m = cs.mesh;
    const MeshReport r = analyseMesh(m, true);
    EXPECT_TRUE(r.flipped);
    EXPECT_EQ(r.splitEdges, 0u);
    EXPECT_EQ(r.splitVertices, 0u);
    EXPECT_NEAR(r.signedVolume, 1000.0, 1000.0 * kRelTol);
}
