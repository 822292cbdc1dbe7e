// Colouring pixels by a block model (section/blocks/block_raster.cpp): the walk along each row of a
// plane's pixels must give, at every pixel, the cell that the per-pixel rule gives
// (BlockModel::cellAt of the pixel centre, the function the pixel query calls), bit for bit.
// The hard cases are built in: sections lying exactly on cell faces, pixel centres on faces
// (pixel size a fraction of the cell), frames reaching past the grid, pixels of 10 µm around a
// cell corner (every pixel near a face), rotated grid axes, and Gauss-Kruger magnitudes (3.5e7 m,
// where a double's step is 7e-9 m and the rounding of each pixel centre decides which side
// of a face it falls). Exact comparisons: the walk's claim is equality, so no tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>

#include "api/catalog.hpp"
#include "api/pixel_query.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "model/blocks/block_model.hpp"
#include "model/model.hpp"
#include "section/blocks/block_section.hpp"
#include "section/cut/polyline.hpp"
#include "test_meshes.hpp"
#include "view/view_frame.hpp"

using namespace geoslice;

namespace {

constexpr RecordId kClip = 7, kOther = 9;

BlockModel boxGrid(const glm::dvec3& origin, const std::array<glm::dvec3, 3>& axis, const std::array<double, 3>& size,
                   const std::array<std::size_t, 3>& dims) {
    BlockModel b;
    b.source = "test";
    b.origin = origin;
    b.axis = axis;
    b.size = size;
    b.dims = dims;
    BlockProperty grade{"grade", "g/t", {}};
    for (std::size_t c = 0; c < b.cellCount(); ++c) {
        const auto ijk = b.ijk(c);
        // Neighbours differ in class often; every 13th cell has no value.
        grade.values.push_back(c % 13 == 5 ? std::nan("") : double((ijk[0] * 7 + ijk[1] * 3 + ijk[2] * 5) % 6));
    }
    b.properties.push_back(std::move(grade));
    return b;
}

// Colours W x H pixels (world point worldAt(i, j)) with and without the walk on `lines` and
// checks every pixel against the rule. Records: mostly the clipping body, with a few other
// records and background pixels in every row so runs start and stop anywhere. Returns the
// number of pixels given a cell.
std::size_t expectWalkIsTheRule(const BlockModel& b, const std::function<glm::dvec3(int, int)>& worldAt,
                                const std::vector<RowLine>& lines, int W, int H, const std::string& what) {
    const std::size_t n = std::size_t(W) * std::size_t(H);
    std::vector<std::uint32_t> ids(n, kClip);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const std::size_t p = std::size_t(j) * std::size_t(W) + std::size_t(i);
            if ((i * 7 + j * 3) % 29 == 0) ids[p] = kOther;
            if ((i + 2 * j) % 41 == 1) ids[p] = kNoRecord;
        }
    auto classes = makePropertyClasses(0, "viridis", {1.0, 2.0, 3.0, 4.0, 5.0});
    EXPECT_TRUE(classes.ok());
    const std::vector<RecordId> clip{kClip};
    std::vector<std::uint8_t> rgbaWalk(4 * n, 17), rgbaRule(4 * n, 17);
    std::vector<std::uint32_t> cellsWalk(n, 99), cellsRule(n, 99);
    colourPixelsByBlocks(b, classes.value(), clip, worldAt, W, H, ids.data(), rgbaWalk.data(), cellsWalk.data(), lines);
    colourPixelsByBlocks(b, classes.value(), clip, worldAt, W, H, ids.data(), rgbaRule.data(), cellsRule.data());
    std::size_t withCell = 0, mismatches = 0;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const std::size_t p = std::size_t(j) * std::size_t(W) + std::size_t(i);
            const std::size_t rule = ids[p] == kClip ? b.cellAt(worldAt(i, j)) : BlockModel::kNoCell;
            const std::uint32_t expected = rule == BlockModel::kNoCell ? 0u : std::uint32_t(rule + 1);
            withCell += expected != 0;
            if (cellsWalk[p] != expected || cellsRule[p] != expected) {
                if (++mismatches <= 5)
                    ADD_FAILURE() << what << ": pixel " << i << "," << j << " walk " << cellsWalk[p] << " rule "
                                  << cellsRule[p] << " cellAt " << expected;
            }
        }
    EXPECT_EQ(mismatches, 0u) << what;
    EXPECT_TRUE(rgbaWalk == rgbaRule) << what << ": colours differ";
    return withCell;
}

// The same for the pixels of a plane's frame (one line a row).
std::size_t expectWalkIsTheRule(const BlockModel& b, const PixelFrame& f, const std::string& what) {
    return expectWalkIsTheRule(
        b, [&](int i, int j) { return f.pixelCentreWorld(i, j); }, {{0, f.width, f.worldPerPixelX()}}, f.width,
        f.height, what);
}

// The same for a polyline section's pixels (a line per leg): chainage s and elevation z.
std::size_t expectWalkIsTheRuleOnALine(const BlockModel& b, const std::vector<glm::dvec2>& points, const FrameRect& r,
                                       int W, int H, const std::string& what) {
    auto line = makeSectionLine(points);
    EXPECT_TRUE(line.ok());
    const double pu = (r.u1 - r.u0) / W, pv = (r.v1 - r.v0) / H;
    auto worldAt = [&](int i, int j) { return line->worldAt(r.u0 + (i + 0.5) * pu, r.v1 - (j + 0.5) * pv); };
    const auto lines = polylineRowLines(
        line.value(), [&](int i) { return r.u0 + (i + 0.5) * pu; }, W, pu);
    EXPECT_EQ(lines.size(), points.size() - 1) << what;  // every leg in the frame
    return expectWalkIsTheRule(b, worldAt, lines, W, H, what);
}

PixelFrame frameOf(const Plane& plane, const glm::dvec3& modelOrigin, const FrameRect& rect, int w, int h) {
    PixelFrame f;
    f.section = makeSectionFrame(plane, modelOrigin);
    f.rect = rect;
    f.width = w;
    f.height = h;
    return f;
}

// u/v of a world point in the section of `plane`.
glm::dvec2 uvOf(const Plane& plane, const glm::dvec3& modelOrigin, const glm::dvec3& world) {
    const SectionFrame s = makeSectionFrame(plane, modelOrigin);
    return s.toPlane(world - modelOrigin);
}

// An SGrid block model of n^3 cells of `cell` metres from `origin`, every interior point's
// elevation moved by bend x cell x a product of sines (bend 0: the lattice itself).
BlockModel sgrid(const glm::dvec3& origin, double cell, int n, double bend) {
    Grid g;
    g.type = "SGrid";
    for (int a = 0; a < 3; ++a) g.dims[a] = std::size_t(n + 1);
    g.cellCentred = true;
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                glm::dvec3 p = origin + cell * glm::dvec3(i, j, k);
                if (k > 0 && k < n) p.z += bend * cell * std::sin(0.9 * i) * std::sin(0.7 * j);
                g.points.push_back(p);
            }
    GridProperty grade{"grade", "g/t", std::nullopt, {}};
    for (int c = 0; c < n * n * n; ++c) grade.values.push_back(c % 13 == 5 ? NAN : float((c * 7) % 6));
    g.properties.push_back(std::move(grade));
    auto b = blockModelFromGrid(g);
    EXPECT_TRUE(b.ok()) << b.error().message;
    return std::move(b.value());
}

// A frame over the grid's section plus 3 pixels a side, with pixels pu x pv whose centres
// fall on `anchor`'s u and v plus whole pixels (so on faces, when the pixel divides the cell).
PixelFrame alignedFrame(const BlockModel& b, const Plane& plane, const glm::dvec3& modelOrigin,
                        const glm::dvec3& anchor, double pu, double pv) {
    const glm::dvec2 a = uvOf(plane, modelOrigin, anchor);
    glm::dvec2 lo(1e300), hi(-1e300);
    for (int c = 0; c < 8; ++c) {
        const glm::dvec2 q =
            uvOf(plane, modelOrigin, b.corner(c & 1 ? b.dims[0] : 0, c & 2 ? b.dims[1] : 0, c & 4 ? b.dims[2] : 0));
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    const double i0 = std::floor((lo.x - a.x) / pu) - 3, i1 = std::ceil((hi.x - a.x) / pu) + 3;
    const double j0 = std::floor((lo.y - a.y) / pv) - 3, j1 = std::ceil((hi.y - a.y) / pv) + 3;
    const FrameRect r{a.x + (i0 - 0.5) * pu, a.y + (j0 - 0.5) * pv, a.x + (i1 + 0.5) * pu, a.y + (j1 + 0.5) * pv};
    return frameOf(plane, modelOrigin, r, int(i1 - i0 + 1), int(j1 - j0 + 1));
}

}  // namespace

TEST(BlockRaster, TheWalkGivesTheRulesCellAtEveryPixelOfBoxGrids) {
    const glm::dvec3 gk{35500000.0, 3388000.0, 150.0};  // Gauss-Kruger magnitudes
    const glm::dvec3 modelOrigin{35500000.0, 3388000.0, 0.0};
    const std::array<double, 3> size{7.0, 5.0, 3.0};
    const std::array<std::size_t, 3> dims{40, 30, 20};
    const BlockModel b = boxGrid(gk, {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)}, size, dims);
    const glm::dvec3 centre = gk + 0.5 * glm::dvec3(280.0, 150.0, 60.0);
    std::size_t total = 0;

    // On faces: a horizontal section on the face z = 150 + 7 x 3, pixels a quarter and a half
    // of a cell with centres on the x and y faces (up to the rounding of each centre), framed
    // past the grid on every side; then just off that face on both sides (a double's step
    // there is 3e-14 m).
    for (double dz : {0.0, -1e-9, 1e-9}) {
        const Plane plane{{0, 0, 1}, -(150.0 + 7 * 3.0) + dz};
        total += expectWalkIsTheRule(b, alignedFrame(b, plane, modelOrigin, gk, 7.0 / 4, 5.0 / 4), "horizontal, face");
        total += expectWalkIsTheRule(b, alignedFrame(b, plane, modelOrigin, gk, 7.0 / 2, 5.0), "horizontal, face 2");
    }
    // Vertical sections on an x face and on a y face, pixel centres on the other faces.
    for (int axis = 0; axis < 2; ++axis) {
        glm::dvec3 n(0.0);
        n[axis] = 1.0;
        const Plane plane{n, -(gk[axis] + 10 * size[std::size_t(axis)])};
        total += expectWalkIsTheRule(b, alignedFrame(b, plane, modelOrigin, gk, size[std::size_t(1 - axis)] / 2, 1.5),
                                     "vertical, face");
    }
    // Oblique planes through the grid, square frames over all of it and then some.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> dir(-1.0, 1.0);
    for (int t = 0; t < 12; ++t) {
        glm::dvec3 n{dir(rng), dir(rng), 0.4 * dir(rng)};
        if (t % 3 == 0) n.z = 0.0;  // vertical, as profiles are
        n = glm::normalize(n);
        const Plane plane{n, -glm::dot(n, centre + glm::dvec3(dir(rng), dir(rng), dir(rng)) * 20.0)};
        const glm::dvec2 c = uvOf(plane, modelOrigin, centre);
        const FrameRect r{c.x - 230.0, c.y - 120.0, c.x + 230.0, c.y + 120.0};
        total += expectWalkIsTheRule(b, frameOf(plane, modelOrigin, r, 307, 171), "oblique " + std::to_string(t));
    }
    // Pixels of 10 µm around a cell corner: every pixel within a few pixels of a face.
    {
        const glm::dvec3 corner = gk + glm::dvec3(7 * 12, 5 * 9, 3 * 4);
        const glm::dvec3 n = glm::normalize(glm::dvec3(0.6, -0.7, 0.2));
        const Plane plane{n, -glm::dot(n, corner)};
        const glm::dvec2 c = uvOf(plane, modelOrigin, corner);
        const FrameRect r{c.x - 32e-5, c.y - 32e-5, c.x + 32e-5, c.y + 32e-5};
        total += expectWalkIsTheRule(b, frameOf(plane, modelOrigin, r, 64, 64), "10 um pixels at a corner");
    }
    EXPECT_GT(total, 100000u);

    // Rotated grid axes (a Voxet's), near the world origin, a section on a rotated face.
    const double a = 0.5235987755982988;  // 30°
    const std::array<glm::dvec3, 3> axes{glm::dvec3(std::cos(a), std::sin(a), 0),
                                         glm::dvec3(-std::sin(a), std::cos(a), 0), glm::dvec3(0, 0, 1)};
    const BlockModel rot = boxGrid({100.0, -50.0, -30.0}, axes, {4.0, 6.0, 2.5}, {30, 25, 16});
    const Plane onFace{axes[0], -glm::dot(axes[0], rot.origin + 12 * 4.0 * axes[0])};
    EXPECT_GT(expectWalkIsTheRule(rot, alignedFrame(rot, onFace, {0, 0, 0}, rot.origin, 1.5, 1.25), "rotated, face"),
              1000u);
    // Polyline sections: a line per leg, legs turning at vertices inside cells and on a face.
    {
        const std::vector<glm::dvec2> pts{{gk.x - 20.0, gk.y + 13.0},
                                          {gk.x + 7 * 11.0, gk.y + 5 * 7.0},
                                          {gk.x + 150.0, gk.y + 121.3},
                                          {gk.x + 301.0, gk.y + 40.0}};
        auto len = makeSectionLine(pts);
        ASSERT_TRUE(len.ok());
        total += expectWalkIsTheRuleOnALine(b, pts, {-5.0, 140.0, len->length() + 5.0, 222.0}, 333, 97, "polyline");
        // Vertices on a face (x = 7 k) and elevations on faces (pixel rows 3 m apart from 150 m).
        const std::vector<glm::dvec2> facePts{
            {gk.x + 7 * 3.0, gk.y + 5 * 2.0}, {gk.x + 7 * 20.0, gk.y + 5 * 2.0}, {gk.x + 7 * 20.0, gk.y + 5 * 25.0}};
        total += expectWalkIsTheRuleOnALine(b, facePts, {-1.5, 148.5, 260.5, 213.5}, 262, 65, "polyline on faces");
    }
    for (int t = 0; t < 4; ++t) {
        const glm::dvec3 n = glm::normalize(glm::dvec3{dir(rng), dir(rng), 0.5 * dir(rng)});
        const glm::dvec3 c = rot.toWorld({60.0, 75.0, 20.0});
        const Plane plane{n, -glm::dot(n, c)};
        const glm::dvec2 cc = uvOf(plane, {0, 0, 0}, c);
        expectWalkIsTheRule(rot, frameOf(plane, {0, 0, 0}, {cc.x - 90, cc.y - 50, cc.x + 90, cc.y + 50}, 250, 139),
                            "rotated oblique " + std::to_string(t));
    }
}

TEST(BlockRaster, TheWalkGivesTheRulesCellAtEveryPixelOfCurvilinearGrids) {
    // Hexahedral cells: the walk follows the barycentric coordinates in each tetrahedron of
    // the cell. A lattice SGrid (faces planar, sections through them: the tie rule of cellAt
    // decides every pixel on a face) and a bent one, at Gauss-Kruger magnitudes.
    const glm::dvec3 gk{35500000.0, 3388000.0, 150.0};
    const glm::dvec3 modelOrigin{35500000.0, 3388000.0, 0.0};
    std::size_t total = 0;
    for (double bend : {0.0, 0.3}) {
        const BlockModel b = sgrid(gk, 8.0, 14, bend);
        const std::string what = bend == 0.0 ? "lattice SGrid" : "bent SGrid";
        // On faces: z on a lattice plane (bent: only the top and bottom are), x on a face with
        // pixel centres on the y and z faces.
        total += expectWalkIsTheRule(
            b, alignedFrame(b, Plane{{0, 0, 1}, -(150.0 + 8 * 5.0)}, modelOrigin, gk, 2.0, 2.0), what + ", horizontal");
        total += expectWalkIsTheRule(b, alignedFrame(b, Plane{{1, 0, 0}, -(gk.x + 8 * 6.0)}, modelOrigin, gk, 2.0, 1.0),
                                     what + ", vertical");
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> dir(-1.0, 1.0);
        for (int t = 0; t < 6; ++t) {
            glm::dvec3 n{dir(rng), dir(rng), 0.5 * dir(rng)};
            if (t % 2 == 0) n.z = 0.0;
            n = glm::normalize(n);
            const Plane plane{n, -glm::dot(n, gk + glm::dvec3(56.0 + 9 * dir(rng), 56.0 + 9 * dir(rng), 56.0))};
            total += expectWalkIsTheRule(b, alignedFrame(b, plane, modelOrigin, gk, 0.7, 0.6),
                                         what + ", oblique " + std::to_string(t));
        }
        const std::vector<glm::dvec2> pts{
            {gk.x - 3.0, gk.y + 8 * 4.0}, {gk.x + 8 * 6.0, gk.y + 8 * 9.5}, {gk.x + 121.0, gk.y + 17.0}};
        total += expectWalkIsTheRuleOnALine(b, pts, {-2.0, 148.0, 170.0, 264.0}, 172, 116, what + ", polyline");
    }
    EXPECT_GT(total, 100000u);
}

TEST(BlockRaster, CachedAndFreshQueriesAnswerTheCellOfEveryPixelOfPolylineImages) {
    // Over the API (api::renderProfile, api::answerPixel): a polyline section coloured by a box
    // grid and by a bent SGrid, the cell buffer against the query without the image (the
    // exact classifier and BlockModel::cellAt) at every pixel where the records agree.
    Model m = test::modelOf(
        {test::makePart("host", PartKind::Body, 1, test::boxMesh({0, 0, 0}, {100, 100, 100})),
         test::makePart("ore", PartKind::Body, 2, test::boxMesh({20.5, 20.5, 20.5}, {70.5, 60.5, 50.5}))});
    for (const bool bent : {false, true}) {
        BlockModel b = bent ? sgrid({0.0, 0.0, 0.0}, 10.0, 10, 0.3)
                            : boxGrid({0, 0, 0}, {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)},
                                      {10.0, 10.0, 10.0}, {10, 10, 10});
        b.clipBodies = {"ore"};
        ASSERT_TRUE(resolveBlockClip(m, b).ok());
        m.blocks = std::make_shared<const BlockModel>(std::move(b));
        auto cm = api::catalogModelOf("box", m, "v1");
        ASSERT_TRUE(cm.ok()) << cm.error().message;
        auto plan = api::parseViewPlan(
            {{"line", "10.3,30.2,45.7,47.1,83.9,33.3"}, {"colour", "grade"}, {"breaks", "1,3"}, {"size", "200x90"}},
            "box", m.crs);
        ASSERT_TRUE(plan.ok()) << plan.error().message;
        auto image = api::renderProfile(*cm.value(), plan.value());
        ASSERT_TRUE(image.ok()) << image.error().message;
        const api::ViewImage& v = image.value();
        std::size_t compared = 0, withCell = 0;
        for (int j = 0; j < v.height; ++j)
            for (int i = 0; i < v.width; ++i) {
                const std::size_t p = std::size_t(j) * std::size_t(v.width) + std::size_t(i);
                auto fresh = api::answerPixel(*cm.value(), plan.value(), i, j, nullptr);
                ASSERT_TRUE(fresh.ok());
                if (fresh->record != v.ids[p]) continue;  // the classifier's boundary band
                ++compared;
                const std::size_t cell = v.cells[p] == 0 ? BlockModel::kNoCell : v.cells[p] - 1;
                withCell += cell != BlockModel::kNoCell;
                ASSERT_EQ(fresh->cell, cell) << (bent ? "SGrid " : "box ") << i << "," << j;
            }
        EXPECT_GT(compared, 17000u);
        EXPECT_GT(withCell, 1000u);
    }
}
