// The slicing pass's CPU-only pieces, without a GL context: cluster budgets and selection
// (renderer/lod/cluster_selection.hpp), fault-trace segments (renderer/passes/trace_pass.hpp) and the
// readback row flip (renderer/gl/render_target.hpp).
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/gl/render_target.hpp"
#include "renderer/lod/cluster_selection.hpp"
#include "renderer/passes/trace_pass.hpp"

using namespace geoslice;

namespace {

Aabb box(glm::dvec3 lo, glm::dvec3 hi) {
    Aabb b;
    b.extend(lo);
    b.extend(hi);
    return b;
}

// Orthographic frame seeing [-100, 100]^3 (local), no planes.
ClusterFrame wideOrtho() {
    ClusterFrame f;
    f.viewProj = glm::scale(glm::dmat4(1.0), glm::dvec3(0.01));
    f.orthoPixelsPerMetre = 10.0;
    return f;
}

}  // namespace

// Budgets are stored as float: EXPECT_FLOAT_EQ (4 ulps) is the float32 rounding of the
// double expression, nothing more.
TEST(CellBudgets, RemovedSideIsSkippedCrossingCellsStayFullDetail) {
    ClusterFrame f = wideOrtho();
    f.planes = {{-1.0, 0.0, 0.0, 5.0}};  // keeps x <= 5
    f.culls = {1};
    const std::vector<Aabb> cells = {box({0, 0, 0}, {1, 1, 1}), box({10, 0, 0}, {11, 1, 1}),
                                     box({4.5, 0, 0}, {5.5, 1, 1}), Aabb{}};
    std::vector<float> b = cellBudgets(cells, f);
    ASSERT_EQ(b.size(), 4u);
    EXPECT_EQ(b[0], 0.0f);   // kept, no LOD: full detail
    EXPECT_EQ(b[1], -1.0f);  // removed side
    EXPECT_EQ(b[2], 0.0f);   // crossed by the plane
    EXPECT_EQ(b[3], 0.0f);   // empty cell
    f.lod = true;
    b = cellBudgets(cells, f);
    EXPECT_FLOAT_EQ(b[0], 0.1f);  // 1 px at 10 px/m
    EXPECT_EQ(b[1], -1.0f);
    EXPECT_EQ(b[2], 0.0f);  // a cut stays exact
    f.exaggeration = 2.0;   // an error along z is stretched up to 2x
    EXPECT_FLOAT_EQ(cellBudgets(cells, f)[0], 0.05f);
    f.exaggeration = 0.5;  // never looser than unexaggerated
    EXPECT_FLOAT_EQ(cellBudgets(cells, f)[0], 0.1f);
}

TEST(CellBudgets, WithinTheFloatSlackOfThePlaneCountsAsCrossing) {
    ClusterFrame f = wideOrtho();
    f.lod = true;
    f.planes = {{-1.0, 0.0, 0.0, 1.0005}};  // x <= 1.0005: 0.5 mm from the cell, inside the 1 mm slack
    f.culls = {1};
    EXPECT_EQ(cellBudgets({box({0, 0, 0}, {1, 1, 1})}, f)[0], 0.0f);
    f.planes = {{1.0, 0.0, 0.0, -1.0005}};  // x >= 1.0005: removed only beyond the slack
    EXPECT_EQ(cellBudgets({box({0, 0, 0}, {1, 1, 1})}, f)[0], 0.0f);
    f.planes = {{1.0, 0.0, 0.0, -1.1}};
    EXPECT_EQ(cellBudgets({box({0, 0, 0}, {1, 1, 1})}, f)[0], -1.0f);
}

TEST(CellBudgets, OutsideTheViewIsSkipped) {
    ClusterFrame f = wideOrtho();
    const std::vector<Aabb> cells = {box({0, 0, 0}, {1, 1, 1}), box({150, 0, 0}, {160, 1, 1}),
                                     box({95, 0, 0}, {105, 1, 1}), box({0, 0, -300}, {1, 1, -200})};
    const std::vector<float> b = cellBudgets(cells, f);
    EXPECT_EQ(b[0], 0.0f);
    EXPECT_EQ(b[1], -1.0f);  // every corner beyond clip x = w
    EXPECT_EQ(b[2], 0.0f);   // straddles the view's edge
    EXPECT_EQ(b[3], -1.0f);  // beyond clip z = -w
}

TEST(CellBudgets, UnionRemovesOnlyWhatEveryPlaneRemoves) {
    ClusterFrame f = wideOrtho();
    f.unionMode = true;
    f.planes = {{-1.0, 0.0, 0.0, 5.0}, {0.0, -1.0, 0.0, 5.0}};  // x <= 5 or y <= 5
    f.culls = {1, 1};
    const std::vector<Aabb> cells = {box({10, 0, 0}, {11, 1, 1}), box({10, 10, 0}, {11, 11, 1})};
    const std::vector<float> b = cellBudgets(cells, f);
    EXPECT_EQ(b[0], 0.0f);   // kept by y <= 5
    EXPECT_EQ(b[1], -1.0f);  // removed by both
    f.unionMode = false;     // intersection: removed by either
    EXPECT_EQ(cellBudgets(cells, f)[0], -1.0f);
}

TEST(CellBudgets, PastAConvexCutsExitStaysFullDetail) {
    ClusterFrame f = wideOrtho();
    f.lod = true;
    f.planes = {{-1.0, 0.0, 0.0, 5.0}, {0.0, -1.0, 0.0, 5.0}};
    f.culls = {0, 1};  // the first plane does not cull: cells past it are witnesses
    const std::vector<Aabb> cells = {box({10, 0, 0}, {11, 1, 1}), box({0, 0, 0}, {1, 1, 1})};
    const std::vector<float> b = cellBudgets(cells, f);
    EXPECT_EQ(b[0], 0.0f);
    EXPECT_FLOAT_EQ(b[1], 0.1f);
}

TEST(CellBudgets, PerspectiveScalesWithTheNearestDisplayDistance) {
    ClusterFrame f;
    f.lod = true;
    f.perspective = true;
    f.perspPixelsPerMetre = 100.0;
    f.eyeDisplayLocal = {0.5, 0.5, -10.0};
    f.viewProj = glm::scale(glm::dmat4(1.0), glm::dvec3(0.01));
    const std::vector<Aabb> cells = {box({0, 0, 0}, {1, 1, 1}), box({0, 0, -10.5}, {1, 1, -9.5})};
    std::vector<float> b = cellBudgets(cells, f);
    EXPECT_FLOAT_EQ(b[0], 0.1f);  // 10 m away: 10 px/m
    EXPECT_EQ(b[1], 0.0f);        // the eye inside the cell: full detail
    f.exaggeration = 2.0;         // display z of cell 0 is [0, 2]: still 10 m, error / 2
    f.eyeDisplayLocal = {0.5, 0.5, -10.0};
    b = cellBudgets(cells, f);
    EXPECT_FLOAT_EQ(b[0], 0.05f);
}

TEST(CullingPlanes, OnlyAConvexCutSparesPlanes) {
    const std::vector<glm::dvec4> planes = {{-1.0, 0.0, 0.0, 5.0}, {0.0, -1.0, 0.0, 5.0}};
    EXPECT_EQ(cullingPlanes(planes, false, nullptr), (std::vector<std::uint8_t>{1, 1}));
    EXPECT_EQ(cullingPlanes(planes, true, nullptr), (std::vector<std::uint8_t>{0, 0}));  // profile
    const glm::dvec3 eye(20.0, 0.0, 0.0);  // removed side of the first plane only
    EXPECT_EQ(cullingPlanes(planes, true, &eye), (std::vector<std::uint8_t>{1, 0}));
}

namespace {

// Four clusters in cells 0..3, level 0 contiguous (30 indices each), levels 1 and 2 with
// errors 0.5 and 2 m elsewhere in the index buffer.
GpuModel::DrawPart fourClusters() {
    GpuModel::DrawPart p;
    p.baseVertex = 7;
    for (std::uint32_t i = 0; i < 4; ++i) {
        GpuModel::DrawPart::Cluster c;
        c.cell = i;
        c.levels = 3;
        c.first[0] = 30 * i, c.count[0] = 30;
        c.first[1] = 1000 + 100 * i, c.count[1] = 9, c.error[1] = 0.5f;
        c.first[2] = 2000 + 100 * i, c.count[2] = 3, c.error[2] = 2.0f;
        p.clusters.push_back(c);
    }
    return p;
}

}  // namespace

TEST(ClusterSelection, CoarsestAllowedLevelAndMergedFullRanges) {
    const GpuModel::DrawPart p = fourClusters();
    ClusterSelection s;
    s.select(p, {0.0f, 0.0f, -1.0f, 1.0f}, true, 1.0);
    ASSERT_EQ(s.full.counts.size(), 1u);  // clusters 0 and 1 are one range
    EXPECT_EQ(s.full.counts[0], 60);
    EXPECT_EQ(s.full.firstIndex(0), 0u);
    EXPECT_EQ(s.full.baseVertices[0], 7);
    EXPECT_EQ(s.skipped, 1u);
    EXPECT_TRUE(s.anySimplified);
    // Cluster 3 at level 1 (0.5 <= 1 < 2), pushed 2 x 0.5 = 1 m: bucket 9 holds (0.5, 1].
    for (int k = 0; k <= ClusterSelection::kShiftBuckets; ++k)
        EXPECT_EQ(s.pushed[std::size_t(k)].counts.size(), k == 9 ? 1u : 0u) << k;
    EXPECT_EQ(s.pushed[9].firstIndex(0), 1300u);
    EXPECT_EQ(s.pushed[9].counts[0], 9);
    // Exaggeration 4 pushes 4 m: bucket 11 holds (2, 4].
    s.select(p, {0.0f, 0.0f, -1.0f, 1.0f}, true, 4.0);
    EXPECT_EQ(s.pushed[11].counts.size(), 1u);
    EXPECT_TRUE(s.pushed[9].empty());  // the previous selection is gone
    // A gap between full-detail clusters keeps two ranges; a large budget reaches level 2.
    s.select(p, {0.0f, 5.0f, 0.0f, 0.0f}, true, 1.0);
    EXPECT_EQ(s.full.counts, (std::vector<GLsizei>{30, 60}));
    EXPECT_EQ(s.full.firstIndex(1), 60u);
    EXPECT_EQ(s.pushed[11].counts, (std::vector<GLsizei>{3}));  // 2 x 2 m = 4 m
    EXPECT_EQ(s.skipped, 0u);
}

TEST(ClusterSelection, GroupsReplaceTheirMembersOnlyWhenEveryMemberAllowsThem) {
    GpuModel::DrawPart p = fourClusters();
    p.groups.push_back({5000, 12, 0.8f, {0, 1}});
    ClusterSelection s;
    s.select(p, {1.0f, 1.0f, 0.0f, 0.0f}, true, 1.0);
    EXPECT_EQ(s.pushed[10].counts, (std::vector<GLsizei>{12}));  // 1.6 m: (1, 2]
    EXPECT_EQ(s.pushed[10].firstIndex(0), 5000u);
    EXPECT_TRUE(s.pushed[9].empty());
    EXPECT_EQ(s.full.counts, (std::vector<GLsizei>{60}));  // clusters 2 and 3
    EXPECT_EQ(s.full.firstIndex(0), 60u);
    // Not allowed (a union or a convex cut): members at their own level 1.
    s.select(p, {1.0f, 1.0f, 0.0f, 0.0f}, false, 1.0);
    EXPECT_EQ(s.pushed[9].counts.size(), 2u);
    EXPECT_TRUE(s.pushed[10].empty());
    // A member at full detail (a cut) or below the group's error keeps the group out.
    s.select(p, {1.0f, 0.0f, 0.0f, 0.0f}, true, 1.0);
    EXPECT_TRUE(s.pushed[10].empty());
    s.select(p, {1.0f, 0.6f, 0.0f, 0.0f}, true, 1.0);
    EXPECT_TRUE(s.pushed[10].empty());
    EXPECT_EQ(s.pushed[9].counts.size(), 2u);
}

// Float32 end points of order 1: 1e-6 is about 8 float steps.
TEST(TraceSegments, CutFacesClippedByTheOtherPlanes) {
    const std::vector<glm::vec3> tri = {{0, 0, -1}, {2, 0, 1}, {0, 2, 1}};
    auto near = [](glm::vec3 a, glm::vec3 b) { return glm::length(a - b) < 1e-6f; };
    std::vector<glm::vec3> out;
    traceSegments(tri, {{0.0, 0.0, 1.0, 0.0}}, false, out);  // z = 0
    ASSERT_EQ(out.size(), 2u);
    EXPECT_TRUE(near(out[0], {1, 0, 0}));
    EXPECT_TRUE(near(out[1], {0, 1, 0}));
    const std::vector<glm::dvec4> two = {{0.0, 0.0, 1.0, 0.0}, {1.0, 0.0, 0.0, -0.5}};  // z >= 0, x >= 0.5
    out.clear();
    traceSegments(tri, two, false, out);
    ASSERT_EQ(out.size(), 4u);
    EXPECT_TRUE(near(out[0], {1, 0, 0}));  // z = 0 where x >= 0.5
    EXPECT_TRUE(near(out[1], {0.5f, 0.5f, 0}));
    EXPECT_TRUE(near(out[2], {0.5f, 0.5f, 0}));  // x = 0.5 where z >= 0
    EXPECT_TRUE(near(out[3], {0.5f, 1.5f, 1}));
    out.clear();
    traceSegments(tri, two, true, out);  // union: each cut face where the other plane removes
    ASSERT_EQ(out.size(), 4u);
    EXPECT_TRUE(near(out[0], {0.5f, 0.5f, 0}));
    EXPECT_TRUE(near(out[1], {0, 1, 0}));
    EXPECT_TRUE(near(out[2], {0.5f, 0, -0.5f}));
    EXPECT_TRUE(near(out[3], {0.5f, 0.5f, 0}));
    out.clear();
    traceSegments(tri, {{0.0, 0.0, 1.0, 5.0}}, false, out);  // misses
    EXPECT_TRUE(out.empty());
}

TEST(RenderTarget, FlipRowsPutsRowZeroAtTheTop) {
    const std::vector<int> in = {1, 2, 3, 4, 5, 6};  // 1 wide, 3 high, 2 channels, bottom row first
    std::vector<int> out;
    flipRows(in, out, 1, 3, 2);
    EXPECT_EQ(out, (std::vector<int>{5, 6, 3, 4, 1, 2}));
}
