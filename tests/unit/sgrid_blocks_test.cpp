// SGrid (curvilinear) block models (issue 15): the six-tetrahedron split, point location,
// cell ∩ plane polygons, exact cell ∩ body volumes and grade-tonnage, against independent
// oracles:
//  - an SGrid whose points are exactly a Voxet's lattice gives the Voxet's answers (cells
//    under points, polygon areas per cell, volumes per cell, grade-tonnage tables);
//  - an affinely sheared grid: cell ∩ (affine image of a box) = |det A| x the overlap of
//    boxes in grid parameters, per cell; the cell under a point = the floor of its
//    parameters; tonnage = analytic volume x density;
//  - a curved analytic grid: 1,000 random pixels of a coloured section against a brute-force
//    point-in-tetrahedron search over every cell, and cell volumes summing to the body's;
//  - malformed grids (non-finite point, inverted and flat cells, point properties) refused
//    naming the cell; a real-format .sg group file (POINTS_FILE + PROP_FILE, written here).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <set>

#include "api/catalog.hpp"
#include "api/pixel_query.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "model/blocks/block_model.hpp"
#include "model/blocks/cell_locator.hpp"
#include "model/io/loaders.hpp"
#include "section/blocks/block_reserves.hpp"
#include "section/blocks/block_section.hpp"
#include "section/cut/contours.hpp"
#include "section/volumes/reserves.hpp"
#include "test_meshes.hpp"
#include "tests/common/gocad_samples.hpp"
#include "tests/common/sgrid_grids.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

// Tolerances, each with its reason (the tests' coordinates are ~1000 m unless said).
// Determinants and clipped pieces of ~10 m cells at ~1000 m: rounding ~1e-13 relative.
constexpr double kCellVolumeTolM3 = 1e-9;   // one 350 m³ cell's volume two ways
constexpr double kPolygonAreaTolM2 = 1e-8;  // one cell's cut, box vs its 6 tetrahedra's (~100 m²)
constexpr double kCellClipTolM3 = 1e-7;     // one cell ∩ body, box path vs tetrahedra (clipped pieces)
constexpr double kSumRelTol = 1e-9;         // a sum over cells of the above, relative
// At Gauss-Kruger eastings (3.5e7 m) the corners' own float step is 4e-9 m, so one cell ∩ body
// volume (~500 m³) carries about that step x a face's area: 1e-6 m³.
constexpr double kGkCellClipTolM3 = 1e-6;
constexpr double kGradeTol = 1e-9;          // a mean grade (g/t), a ratio of sums above
constexpr double kSphereSumRelTol = 1e-10;  // ~10^5 clipped pieces of ~10 m, against meshVolume
constexpr double kPieceAreaTolM2 = 1e-9;    // a piece's area vs its cell's polygons (~40 m², 100 m coordinates)

double overlap1(double a0, double a1, double b0, double b1) {
    return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
}

double orient(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    return glm::dot(b - a, glm::cross(c - a, d - a));
}

// Brute force over every cell and tetrahedron (no locator): the cells whose tetrahedron
// holds p strictly (every orientation of p against a face agrees with the tetrahedron's, by
// more than `margin` of its volume). Returns kNoCell when none, and how many held it.
std::size_t bruteCell(const BlockModel& b, const glm::dvec3& p, double margin, int& holders) {
    std::size_t found = BlockModel::kNoCell;
    holders = 0;
    for (std::size_t c = 0; c < b.cellCount(); ++c) {
        const auto k = b.cellCorners(c);
        bool in = false;
        for (const auto& t : kCellTets) {
            const glm::dvec3 &A = k[std::size_t(t[0])], &B = k[std::size_t(t[1])], &C = k[std::size_t(t[2])],
                             &D = k[std::size_t(t[3])];
            const double v = orient(A, B, C, D);
            const double s[4] = {orient(p, B, C, D), orient(A, p, C, D), orient(A, B, p, D), orient(A, B, C, p)};
            bool all = true;
            for (double x : s) all = all && x / v > margin;
            in = in || all;
        }
        if (in) {
            found = c;
            ++holders;
        }
    }
    return found;
}

// The affine map of the sheared grid: parameters (grid metres) -> world.
struct Affine {
    glm::dmat3 A{glm::dvec3(1.0, 0.2, 0.05), glm::dvec3(0.3, 0.9, -0.1), glm::dvec3(0.25, -0.15, 1.1)};
    glm::dvec3 t{35500000.0, 3388000.0, 200.0};  // a Gauss-Kruger easting: large coordinates
    glm::dvec3 operator()(const glm::dvec3& q) const { return t + A * q; }
    glm::dvec3 inverse(const glm::dvec3& w) const { return glm::inverse(A) * (w - t); }
};

Mesh affineBox(const Affine& f, const glm::dvec3& lo, const glm::dvec3& hi) {
    Mesh m = boxMesh(lo, hi);
    for (glm::dvec3& p : m.positions) p = f(p);
    if (glm::determinant(f.A) < 0.0) reverse(m);
    return m;
}

}  // namespace

TEST(SGridBlocks, SixTetrahedraTileEveryCellAndMatchAcrossFaces) {
    // Unit cube: six positive tetrahedra of volume 1/6 each (exact in binary).
    glm::dvec3 unit[8];
    for (int c = 0; c < 8; ++c) unit[c] = {double(c & 1), double((c >> 1) & 1), double(c >> 2)};
    for (const auto& t : kCellTets) EXPECT_EQ(orient(unit[t[0]], unit[t[1]], unit[t[2]], unit[t[3]]), 1.0);
    // Conformity: on every face shared by two cells, the triangles the two cells' tetrahedra
    // put on it are the same (as sets of lattice corners).
    const Grid g = sgridOf(
        2, 2, 2, [](int i, int j, int k) { return glm::dvec3(i, j, k); }, [](int, int, int) { return 1.0; });
    auto b = blockModelFromGrid(g);
    ASSERT_TRUE(b.ok()) << b.error().message;
    auto faceTriangles = [&](std::size_t cell, int axis, int side) {
        std::vector<std::array<std::size_t, 3>> out;
        for (const auto& t : kCellTets) {
            std::vector<std::size_t> on;
            for (int v : t)
                if (((v >> axis) & 1) == side) on.push_back(b->cornerIndex(cell, v));
            if (on.size() == 3) {
                std::sort(on.begin(), on.end());
                out.push_back({on[0], on[1], on[2]});
            }
        }
        std::sort(out.begin(), out.end());
        return out;
    };
    for (int axis = 0; axis < 3; ++axis) {
        const std::size_t lo = 0, hi = axis == 0   ? b->linear(1, 0, 0)
                                       : axis == 1 ? b->linear(0, 1, 0)
                                                   : b->linear(0, 0, 1);
        const auto a = faceTriangles(lo, axis, 1), c = faceTriangles(hi, axis, 0);
        EXPECT_EQ(a.size(), 2u);
        EXPECT_EQ(a, c) << "axis " << axis;
    }
}

TEST(SGridBlocks, ARegularSGridGivesTheVoxetsAnswers) {
    // A rotated Voxet (cell-centred, 10 x 8 x 6 cells of 10 x 7 x 5 m) and the SGrid with the
    // same lattice points and values.
    Grid vox;
    vox.type = "Voxet";
    vox.name = "v";
    vox.dims[0] = 11;
    vox.dims[1] = 9;
    vox.dims[2] = 7;
    vox.cellCentred = true;
    vox.origin = {1000.0, 2000.0, 100.0};
    const double c = std::cos(0.4), s = std::sin(0.4);
    vox.step[0] = 10.0 * glm::dvec3(c, s, 0);
    vox.step[1] = 7.0 * glm::dvec3(-s, c, 0);
    vox.step[2] = {0, 0, 5.0};
    auto gradeOf = [](int i, int j, int k) { return 0.1 * i + 0.7 * j + 1.3 * k + 0.05 * ((i * 7 + j * 3 + k) % 5); };
    GridProperty gp{"grade", "g/t", std::nullopt, {}};
    for (int k = 0; k < 6; ++k)
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 10; ++i) gp.values.push_back(float(gradeOf(i, j, k)));
    vox.properties.push_back(gp);
    const Grid sg = sgridOf(
        10, 8, 6,
        [&](int i, int j, int k) {
            return vox.origin + double(i) * vox.step[0] + double(j) * vox.step[1] + double(k) * vox.step[2];
        },
        gradeOf);
    auto bv = blockModelFromGrid(vox);
    auto bs = blockModelFromGrid(sg);
    ASSERT_TRUE(bv.ok()) << bv.error().message;
    ASSERT_TRUE(bs.ok()) << bs.error().message;
    ASSERT_EQ(bs->shape, CellShape::Hexahedron);
    ASSERT_EQ(bs->cellCount(), bv->cellCount());
    for (std::size_t cell = 0; cell < bv->cellCount(); ++cell) {
        ASSERT_EQ(bs->properties[0].values[cell], bv->properties[0].values[cell]);
        // 1e-9 m³ of 350 m³: rounding of determinants of ~1000 m coordinates.
        EXPECT_NEAR(bs->cellVolume(cell), 350.0, kCellVolumeTolM3);
    }

    // Points: the same cell wherever the point is farther than 1e-7 m from a cell face (the
    // box rule is half-open, the tetrahedra's "deepest"; they differ only on faces).
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.05, 1.05);
    int compared = 0;
    for (int n = 0; n < 2000; ++n) {
        const glm::dvec3 q{u(rng) * 100.0, u(rng) * 56.0, u(rng) * 30.0};  // grid metres
        const glm::dvec3 w = bv->toWorld(q);
        const glm::dvec3 g = bv->toGrid(w);
        bool nearFace = false;
        for (int a = 0; a < 3; ++a) {
            const double f = g[a] / bv->size[std::size_t(a)];
            nearFace = nearFace || std::abs(f - std::round(f)) * bv->size[std::size_t(a)] < 1e-7;
        }
        if (nearFace) continue;
        ++compared;
        std::size_t hint = BlockModel::kNoCell;
        ASSERT_EQ(bs->cellAt(w), bv->cellAt(w)) << "point " << q.x << "," << q.y << "," << q.z;
        ASSERT_EQ(bs->cellAt(w, hint), bv->cellAt(w));
    }
    EXPECT_GT(compared, 1900);

    // Cell ∩ plane: each cell's tetrahedra's polygons add up to the box cell's polygon.
    for (const Plane& pl : {Plane{glm::normalize(glm::dvec3(0.3, 0.8, 0.45)), 0.0}, horizontalPlane(117.5)}) {
        Plane p = pl;
        if (p.d == 0.0) p.d = -glm::dot(p.normal, bv->toWorld({50, 28, 15}));
        const SectionFrame frame = makeSectionFrame(p, {1000, 2000, 100});
        auto pv = cellPolygons(bv.value(), frame);
        auto ps = cellPolygons(bs.value(), frame);
        ASSERT_TRUE(pv.ok() && ps.ok());
        std::map<std::size_t, double> av, as;
        for (const CellPolygon& cp : pv.value()) av[cp.cell] += ringArea(cp.ring);
        for (const CellPolygon& cp : ps.value()) as[cp.cell] += ringArea(cp.ring);
        ASSERT_GT(av.size(), 20u);
        for (const auto& [cell, area] : av) EXPECT_NEAR(as[cell], area, kPolygonAreaTolM2) << "cell " << cell;
        for (const auto& [cell, area] : as) EXPECT_TRUE(av.count(cell) || area < 1e-8) << "cell " << cell;
    }

    // Volumes: a box body off the grid planes and a sphere, whole and on the kept side of a plane.
    const Mesh box = boxMesh({1000.0 - 13.3, 2000.0 + 4.4, 107.7}, {1000.0 + 61.1, 2000.0 + 57.9, 121.3});
    const Mesh sphere = sphereMesh(bv->toWorld({47, 31, 14}), 13.5);
    const Plane cut{glm::normalize(glm::dvec3(0.2, -0.5, 0.8)), 0.0};
    Plane kept = cut;
    kept.d = -glm::dot(cut.normal, bv->toWorld({50, 28, 14}));
    for (const Mesh* body : {&box, &sphere}) {
        for (int withPlane = 0; withPlane < 2; ++withPlane) {
            const auto vv = withPlane ? cellBodyVolumes(bv.value(), *body, kept) : cellBodyVolumes(bv.value(), *body);
            const auto vs = withPlane ? cellBodyVolumes(bs.value(), *body, kept) : cellBodyVolumes(bs.value(), *body);
            std::map<std::size_t, double> mv, ms;
            for (const CellVolume& cv : vv) mv[cv.cell] = cv.volume;
            for (const CellVolume& cv : vs) ms[cv.cell] = cv.volume;
            ASSERT_GT(mv.size(), 10u);
            double tv = 0.0, ts = 0.0;
            // 1e-7 m³ of 350 m³ cells: rounding of clipped pieces at 1000 m coordinates.
            for (const auto& [cell, v] : mv)
                EXPECT_NEAR(ms[cell], v, kCellClipTolM3) << "cell " << cell << " plane " << withPlane;
            for (const auto& [cell, v] : ms) {
                EXPECT_NEAR(mv[cell], v, kCellClipTolM3) << "cell " << cell << " plane " << withPlane;
                ts += v;
            }
            for (const auto& [cell, v] : mv) tv += v;
            EXPECT_NEAR(ts, tv, kSumRelTol * tv);
        }
    }
}

TEST(SGridBlocks, AShearedGridsVolumesTonnageAndCellsAreAnalytic) {
    const Affine f;
    const double det = glm::determinant(f.A);
    ASSERT_GT(det, 0.0);
    // 12 x 10 x 8 cells of 10 x 10 x 5 grid metres; grade = i + 0.5 k.
    const Grid g = sgridOf(
        12, 10, 8,
        [&](int i, int j, int k) {
            return f({10.0 * i, 10.0 * j, 5.0 * k});
        },
        [](int i, int, int k) { return i + 0.5 * k; });
    auto b = blockModelFromGrid(g);
    ASSERT_TRUE(b.ok()) << b.error().message;
    // The orebody: the affine image of the box [13.3, 87.1] x [-5, 44.4] x [7.7, 31.9] (grid
    // metres): partly outside the grid in j.
    const glm::dvec3 lo{13.3, -5.0, 7.7}, hi{87.1, 44.4, 31.9};
    Model m = modelOf({makePart("host", PartKind::Body, 1, affineBox(f, {-50, -50, -50}, {200, 200, 100})),
                       makePart("ore", PartKind::Body, 2, affineBox(f, lo, hi))});
    AttributeRecord host{}, ore{};
    host.id = 1;
    host.name = "host";
    ore.id = 2;
    ore.name = "ore";
    ore.density = 2.7;
    m.attributes.put(host);
    m.attributes.put(ore);
    auto vols = cellBodyVolumes(b.value(), m.bodies[1].mesh);
    std::map<std::size_t, double> got;
    for (const CellVolume& cv : vols) got[cv.cell] = cv.volume;
    double total = 0.0;
    std::vector<double> expected(b->cellCount());
    for (std::size_t c = 0; c < b->cellCount(); ++c) {
        const auto [i, j, k] = b->ijk(c);
        expected[c] = det * overlap1(10.0 * double(i), 10.0 * double(i + 1), lo.x, hi.x) *
                      overlap1(10.0 * double(j), 10.0 * double(j + 1), lo.y, hi.y) *
                      overlap1(5.0 * double(k), 5.0 * double(k + 1), lo.z, hi.z);
        // 1e-6 m³ of ~500 m³ cells: rounding of clipped pieces at 3.5e7 m eastings (relative
        // to the body's centre, coordinates of ~100 m remain, but the cells' planes come from
        // corners at 3.5e7 m: a 4e-9 m step).
        EXPECT_NEAR(got[c], expected[c], kGkCellClipTolM3) << "cell " << i << "," << j << "," << k;
        total += expected[c];
    }
    ASSERT_GT(total, 1000.0);

    // Grade-tonnage: tonnage = analytic volume x 2.7 t/m³ above each cut-off.
    BlockModel bm = b.value();
    bm.clipBodies = {"ore"};
    ASSERT_TRUE(resolveBlockClip(m, bm).ok());
    m.blocks = std::make_shared<const BlockModel>(bm);
    auto gt = computeGradeTonnage(m, "grade", {0.0, 3.0, 6.5});
    ASSERT_TRUE(gt.ok()) << gt.error().message;
    ASSERT_EQ(gt->bodies.size(), 1u);
    for (std::size_t r = 0; r < 3; ++r) {
        double v = 0.0, metal = 0.0;
        for (std::size_t c = 0; c < bm.cellCount(); ++c) {
            const double grade = bm.properties[0].values[c];
            if (grade >= gt->cutoffs[r]) {
                v += expected[c];
                metal += expected[c] * 2.7 * grade;
            }
        }
        const GradeTonnageRow& row = gt->bodies[0].rows[r];
        // Relative 1e-9: sums of per-cell rounding above.
        EXPECT_NEAR(row.volume, v, kSumRelTol * total) << "cut-off " << gt->cutoffs[r];
        ASSERT_TRUE(row.tonnage.has_value());
        EXPECT_NEAR(*row.tonnage, 2.7 * v, 2.7 * kSumRelTol * total);
        ASSERT_TRUE(row.meanGrade.has_value());
        EXPECT_NEAR(*row.meanGrade, metal / (2.7 * v), kGradeTol);
    }

    // Points: the cell under a point is the floor of its grid parameters (away from faces).
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.1, 1.1);
    int compared = 0;
    for (int n = 0; n < 2000; ++n) {
        const glm::dvec3 q{u(rng) * 120.0, u(rng) * 100.0, u(rng) * 40.0};
        const glm::dvec3 cellq{q.x / 10.0, q.y / 10.0, q.z / 5.0};
        bool nearFace = false, outside = false;
        for (int a = 0; a < 3; ++a) {
            nearFace = nearFace || std::abs(cellq[a] - std::round(cellq[a])) < 1e-6;
            outside = outside || cellq[a] < 0.0 || cellq[a] >= double(b->dims[std::size_t(a)]);
        }
        if (nearFace) continue;
        ++compared;
        const std::size_t expect =
            outside ? BlockModel::kNoCell : b->linear(std::size_t(cellq.x), std::size_t(cellq.y), std::size_t(cellq.z));
        ASSERT_EQ(b->cellAt(f(q)), expect) << q.x << "," << q.y << "," << q.z;
    }
    EXPECT_GT(compared, 1900);
}

TEST(SGridBlocks, ACurvedGridsPixelsMatchABruteForceSearch) {
    // Layers that bend: z = 4 k + 3 sin(x / 25) + 0.02 y (k-dependent amplitude), columns
    // leaning with depth. 14 x 12 x 8 cells.
    auto at = [](int i, int j, int k) {
        const double x = 7.0 * i + 0.4 * k, y = 6.0 * j - 0.3 * k;
        return glm::dvec3(x, y, 4.0 * k + (1.0 + 0.2 * k) * std::sin(x / 25.0) + 0.02 * y);
    };
    const Grid g = sgridOf(14, 12, 8, at, [](int i, int j, int k) { return i + 20 * j + 400 * k; });
    auto b = blockModelFromGrid(g);
    ASSERT_TRUE(b.ok()) << b.error().message;
    // A sphere inside the grid: cell volumes sum to its volume; no cell exceeds its own.
    const Mesh sphere = sphereMesh({49, 35, 16}, 11.0);
    double sum = 0.0;
    for (const CellVolume& cv : cellBodyVolumes(b.value(), sphere)) {
        EXPECT_LE(cv.volume, b->cellVolume(cv.cell) * (1 + 1e-9));
        EXPECT_GT(cv.volume, -1e-9);
        sum += cv.volume;
    }
    // Relative 1e-10: rounding of ~10^5 clipped pieces of ~10 m.
    EXPECT_NEAR(sum, meshVolume(sphere), kSphereSumRelTol * meshVolume(sphere));
    // Cells wholly inside the sphere keep their whole volume.
    const Mesh big = boxMesh({-10, -10, -10}, {200, 200, 200});
    for (const CellVolume& cv : cellBodyVolumes(b.value(), big))
        EXPECT_NEAR(cv.volume, b->cellVolume(cv.cell), kSumRelTol * b->cellVolume(cv.cell));

    // A coloured section through a body covering the grid: 1,000 random pixels.
    Model m = modelOf({makePart("ore", PartKind::Body, 1, boxMesh({-5, -5, -5}, {110, 80, 45}))});
    AttributeRecord ore{};
    ore.id = 1;
    ore.name = "ore";
    m.attributes.put(ore);
    BlockModel bm = b.value();
    ASSERT_TRUE(resolveBlockClip(m, bm).ok());
    m.blocks = std::make_shared<const BlockModel>(bm);
    auto cm = api::catalogModelOf("curved", m, "v1");
    ASSERT_TRUE(cm.ok()) << cm.error().message;
    const api::CatalogModel& model = *cm.value();
    for (const char* plane : {"0.3,0.8,0.2,-40", "0,0,1,-15.5"}) {
        auto plan = api::parseViewPlan({{"plane", plane}, {"colour", "grade"}, {"size", "300x200"}}, "curved", m.crs);
        ASSERT_TRUE(plan.ok()) << plan.error().message;
        auto image = api::renderProfile(model, plan.value());
        ASSERT_TRUE(image.ok()) << image.error().message;
        const api::ViewImage& v = image.value();
        std::mt19937 rng(3);
        std::uniform_int_distribution<int> di(0, v.width - 1), dj(0, v.height - 1);
        int compared = 0, inCells = 0;
        for (int n = 0; n < 1000; ++n) {
            const int i = di(rng), j = dj(rng);
            const std::size_t p = std::size_t(j) * std::size_t(v.width) + std::size_t(i);
            if (v.ids[p] != 1) continue;
            const glm::dvec3 w = v.mapping->worldAt(i, j);
            int holders = 0;
            // Margin 1e-9 of a tetrahedron's volume: points that close to a face are left out.
            const std::size_t brute = bruteCell(bm, w, 1e-9, holders);
            if (holders == 0 && bruteCell(bm, w, -1e-9, holders) != BlockModel::kNoCell) continue;
            ASSERT_LE(holders, 1) << "cells overlap at pixel " << i << "," << j;
            ++compared;
            inCells += brute != BlockModel::kNoCell;
            const std::size_t cell = v.cells[p] == 0 ? BlockModel::kNoCell : v.cells[p] - 1;
            ASSERT_EQ(cell, brute) << "pixel " << i << "," << j;
            auto q = api::answerPixel(model, plan.value(), i, j, nullptr);
            ASSERT_TRUE(q.ok());
            ASSERT_EQ(q->cell, brute) << "query at pixel " << i << "," << j;
            if (brute != BlockModel::kNoCell) {
                const auto ijk = bm.ijk(brute);
                EXPECT_EQ(bm.properties[0].values[brute], double(ijk[0] + 20 * ijk[1] + 400 * ijk[2]));
            }
        }
        EXPECT_GT(compared, 400);  // of 1,000 random pixels, those on the body (about half)
        EXPECT_GT(inCells, 200);
        // The vector pieces: one per cell (its tetrahedra's merged), and where the body
        // covers the whole cut cell, the piece's area is the cell's polygons' area.
        auto section = computeSection(*model.index, plan->section.plane);
        ASSERT_TRUE(section.ok()) << section.error().message;
        auto pieces = blockPieces(bm, section.value());
        auto polys = cellPolygons(bm, section->frame);
        ASSERT_TRUE(pieces.ok() && polys.ok());
        std::map<std::size_t, double> cellArea;
        for (const CellPolygon& cp : polys.value()) cellArea[cp.cell] += ringArea(cp.ring);
        std::set<std::size_t> seen;
        for (const BlockPiece& piece : pieces.value()) {
            EXPECT_TRUE(seen.insert(piece.cell).second) << "two pieces of cell " << piece.cell;
            // 1e-9 m² of ~40 m² pieces: rounding of clipping 100 m coordinates.
            EXPECT_NEAR(piece.area, cellArea[piece.cell], kPieceAreaTolM2) << "cell " << piece.cell;
        }
        EXPECT_EQ(seen.size(), cellArea.size());
    }
}

TEST(SGridBlocks, MalformedGridsAreRefusedNamingTheCell) {
    auto at = [](int i, int j, int k) { return glm::dvec3(10.0 * i, 10.0 * j, 5.0 * k); };
    auto one = [](int, int, int) { return 1.0; };
    auto err = [](const Grid& g) {
        auto b = blockModelFromGrid(g);
        return b.ok() ? std::string("(accepted)") : b.error().message;
    };
    Grid g = sgridOf(3, 3, 3, at, one);
    ASSERT_TRUE(blockModelFromGrid(g).ok());
    Grid nan = g;
    nan.points[1 + 4 * (2 + 4 * 1)] = {std::nan(""), 0, 0};  // point (1, 2, 1)
    EXPECT_NE(err(nan).find("point (1, 2, 1) is not finite (a corner of cell (1, 2, 1))"), std::string::npos)
        << err(nan);
    Grid inverted = g;
    std::swap(inverted.points[2 + 4 * (1 + 4 * 2)],
              inverted.points[2 + 4 * (1 + 4 * 3)]);  // (2,1,2) <-> (2,1,3): cell (1, 0, 2) is the first to fold
    EXPECT_NE(err(inverted).find("cell (1, 0, 2) is inverted"), std::string::npos) << err(inverted);
    Grid flat = g;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) flat.points[std::size_t(i + 4 * (j + 4 * 2))].z = 5.0;  // layer k = 1 flat
    EXPECT_NE(err(flat).find("cell (0, 0, 1) is flat"), std::string::npos) << err(flat);
    Grid points = g;
    points.cellCentred = false;
    EXPECT_NE(err(points).find("PROP_ALIGNMENT CELLS"), std::string::npos) << err(points);
    Grid thin = sgridOf(3, 3, 0, at, one);
    EXPECT_NE(err(thin).find("1 point(s) along axis 2"), std::string::npos) << err(thin);
}

TEST(SGridBlocks, ARealFormatGroupFileIsABlockModel) {
    // A GOCAD group as GOCAD writes it (tests/common/gocad_samples.hpp
    // writeShearedSGridGroup): layer k of the sheared grid holds 18 x 25 x (its z overlap with
    // the orebody) m³: 1800, 2250, 1350, at grade k + 0.5 and density 2.5.
    const auto dir = std::filesystem::temp_directory_path() /
                     ("geoslice_sgrid_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string gp = writeShearedSGridGroup(dir).string();
    auto model = loadModel(gp);
    ASSERT_TRUE(model.ok()) << model.error().message;
    ASSERT_TRUE(model->blocks);
    EXPECT_EQ(model->blocks->shape, CellShape::Hexahedron);
    EXPECT_EQ(model->blocks->cellCount(), 27u);
    auto gt = computeGradeTonnage(model.value(), "grade", {0.0, 1.0, 2.0});
    ASSERT_TRUE(gt.ok()) << gt.error().message;
    ASSERT_EQ(gt->bodies.size(), 1u);
    const double volume[3] = {5400, 3600, 1350}, metal[3] = {2.5 * (1800 * 0.5 + 2250 * 1.5 + 1350 * 2.5),
                                                             2.5 * (2250 * 1.5 + 1350 * 2.5), 2.5 * 1350 * 2.5};
    for (int r = 0; r < 3; ++r) {
        const GradeTonnageRow& row = gt->bodies[0].rows[std::size_t(r)];
        // 1e-9 m³ of 5400: rounding of the clipped pieces (10 m coordinates).
        EXPECT_NEAR(row.volume, volume[r], kSumRelTol * 5400) << r;
        ASSERT_TRUE(row.tonnage && row.meanGrade);
        EXPECT_NEAR(*row.tonnage, 2.5 * volume[r], 2.5 * kSumRelTol * 5400) << r;
        EXPECT_NEAR(*row.meanGrade, metal[r] / (2.5 * volume[r]), kGradeTol) << r;
    }
    EXPECT_EQ(gt->unit, "g/t Au");
    // The cell under a point: (15, 12, 7) is in layer k = 1 (z 5..10) at x - 2 z/5 = 12.2 -> i = 1.
    EXPECT_EQ(model->blocks->cellAt({15, 12, 7}), model->blocks->linear(1, 1, 1));
    std::filesystem::remove_all(dir);
}
