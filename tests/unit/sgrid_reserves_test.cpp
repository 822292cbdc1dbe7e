// Exact cell ∩ body volumes of curvilinear (SGrid) block models from the body's triangles
// near each tetrahedron (section/blocks/block_reserves.hpp, "Hexahedral cells"), against
// independent oracles:
//  - the whole body clipped to every tetrahedron (clippedCellBodyVolumes: clipToConvex +
//    meshVolume), per cell, on random bent lattices with random bodies (convex, rotated,
//    hollow; one lattice left-handed), whole and on the kept side of a plane;
//  - the body's own volume (meshVolume) for the sum over cells when the body is inside the
//    grid;
//  - analytic volumes where every tie of the tie rule comes up: a box whose faces lie on
//    lattice planes and whose corners are lattice points, the Kuhn simplex {x >= y >= z}
//    whose faces lie on the cells' own diagonal planes, an octahedron with its corners on
//    lattice points, a body that is the whole grid; on a regular and on a sheared lattice;
//  - a body and lattice whose tetrahedra x triangles (1.2e9) the former whole-body clip
//    refused (above 1e8): its table now, summing to the body's volume.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "model/blocks/block_model.hpp"
#include "section/blocks/block_reserves.hpp"
#include "section/volumes/reserves.hpp"
#include "test_meshes.hpp"
#include "tests/common/sgrid_grids.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

// Tolerances, each with its reason.
// One cell ∩ body (cells of 4-10 m at coordinates of ~1000 m), two exact methods: both sum
// ~10-100 clipped pieces whose terms carry rounding ~1e-13 of the coordinates x areas;
// the oracle's caps are fans over the whole body's section, so its terms are ~body-sized.
constexpr double kCellTolM3 = 1e-7;
// The same sum over a body's cells against its meshVolume, relative: ~10^4 terms.
constexpr double kSumRelTol = 1e-10;
// One cell of an analytic case (64 m³ cells, 1000 m coordinates): rounding only.
constexpr double kAnalyticCellTolM3 = 1e-9;

std::map<std::size_t, double> byCell(const std::vector<CellVolume>& v) {
    std::map<std::size_t, double> m;
    for (const CellVolume& c : v) m[c.cell] = c.volume;
    return m;
}

// Every cell of either list agrees within `tol` (absent = 0).
void expectSameCells(const std::vector<CellVolume>& got, const std::vector<CellVolume>& want, double tol,
                     const std::string& what) {
    const auto g = byCell(got), w = byCell(want);
    for (const auto& [cell, v] : w) {
        const auto it = g.find(cell);
        EXPECT_NEAR(it == g.end() ? 0.0 : it->second, v, tol) << what << " cell " << cell;
    }
    for (const auto& [cell, v] : g) {
        if (w.count(cell)) continue;
        EXPECT_NEAR(v, 0.0, tol) << what << " cell " << cell << " (not in the oracle)";
    }
}

double sum(const std::vector<CellVolume>& v) {
    double s = 0.0;
    for (const CellVolume& c : v) s += c.volume;
    return s;
}

// A closed, outward mesh of the tetrahedron abcd (either orientation given).
Mesh tetraMesh(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    Mesh m;
    m.positions = {a, b, c, d};
    m.indices = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
    if (meshVolume(m) < 0.0) reverse(m);
    return m;
}

// The octahedron with corners c ± r e_a (outward).
Mesh octahedronMesh(const glm::dvec3& c, double r) {
    Mesh m;
    m.positions = {c + glm::dvec3(r, 0, 0), c - glm::dvec3(r, 0, 0), c + glm::dvec3(0, r, 0),
                   c - glm::dvec3(0, r, 0), c + glm::dvec3(0, 0, r), c - glm::dvec3(0, 0, r)};
    for (int sx = 0; sx < 2; ++sx)
        for (int sy = 0; sy < 2; ++sy)
            for (int sz = 0; sz < 2; ++sz) {
                std::uint32_t x = std::uint32_t(sx), y = std::uint32_t(2 + sy), z = std::uint32_t(4 + sz);
                // Outward when the corners turn counter-clockwise seen from the octant.
                if ((sx + sy + sz) % 2 == 1) std::swap(y, z);
                m.indices.insert(m.indices.end(), {x, y, z});
            }
    return m;
}

// A body rotated about its bounds' centre.
Mesh rotated(Mesh m, const glm::dvec3& axis, double angle) {
    const glm::dvec3 c = m.bounds().centre(), k = glm::normalize(axis);
    for (glm::dvec3& p : m.positions) {
        const glm::dvec3 v = p - c;
        p = c + v * std::cos(angle) + glm::cross(k, v) * std::sin(angle) + k * glm::dot(k, v) * (1 - std::cos(angle));
    }
    return m;
}

}  // namespace

TEST(SGridReserves, TheLocalSumMatchesTheWholeBodyClipOnRandomLatticesAndBodies) {
    std::mt19937 rng(2026);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int round = 0; round < 4; ++round) {
        // 9 x 8 x 7 cells of about 8 x 7 x 5 m at ~1000 m, every point moved by up to 0.2 of a
        // cell along each axis (bent cells; the boundary moves too); the last round's lattice is
        // mirrored (i runs towards -x: a left-handed grid, its tetrahedra negatively oriented).
        const double mirror = round == 3 ? -1.0 : 1.0;
        const glm::dvec3 origin{1000.0 + 100 * u(rng), 2000.0 + 100 * u(rng), 100.0 * u(rng)};
        std::vector<glm::dvec3> jitter(10 * 9 * 8);
        for (glm::dvec3& j : jitter) j = {u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
        const Grid g = sgridOf(
            9, 8, 7,
            [&](int i, int j, int k) {
                const glm::dvec3 d = jitter[std::size_t(i + 10 * (j + 9 * k))] * 0.4;
                return origin + glm::dvec3(mirror * (i + d.x) * 8.0, (j + d.y) * 7.0, (k + d.z) * 5.0);
            },
            [](int i, int j, int k) { return i + j + k; });
        auto b = blockModelFromGrid(g);
        ASSERT_TRUE(b.ok()) << b.error().message;
        const glm::dvec3 mid = origin + glm::dvec3(mirror * 36, 28, 17.5);
        // A sphere inside the grid, a rotated box half out of it, a hollow sphere (a box taken
        // out), a coarse sphere larger than the grid.
        Mesh hollow = sphereMesh(mid + glm::dvec3(3 * u(rng), -2 * u(rng), u(rng)), 14.0, 24, 12);
        Mesh hole = boxMesh(mid - glm::dvec3(4.1, 3.3, 2.7), mid + glm::dvec3(5.2, 2.9, 3.1));
        reverse(hole);
        append(hollow, hole);
        const std::vector<std::pair<std::string, Mesh>> bodies = {
            {"sphere", sphereMesh(mid + glm::dvec3(5 * u(rng), 4 * u(rng), 2 * u(rng)), 11.0 + 3 * u(rng), 32, 16)},
            {"rotated box", rotated(boxMesh(mid + glm::dvec3(-10, -30, -6), mid + glm::dvec3(25, 8, 9)),
                                    {u(rng), u(rng), 1.0}, 0.3 + u(rng))},
            {"hollow sphere", hollow},
            {"large sphere", sphereMesh(mid, 45.0, 16, 8)}};
        const Plane cut{glm::normalize(glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, 1.0)), 0.0};
        Plane kept = cut;
        kept.d = -glm::dot(cut.normal, mid + glm::dvec3(u(rng), u(rng), u(rng)));
        for (const auto& [name, body] : bodies) {
            const std::string what = name + " round " + std::to_string(round);
            const auto local = cellBodyVolumes(b.value(), body);
            ASSERT_GT(local.size(), 10u) << what;
            expectSameCells(local, clippedCellBodyVolumes(b.value(), body), kCellTolM3, what);
            const auto half = cellBodyVolumes(b.value(), body, kept);
            expectSameCells(half, clippedCellBodyVolumes(b.value(), keptSideShell(body, kept)), kCellTolM3,
                            what + " kept side");
            for (const CellVolume& cv : local) {
                EXPECT_GT(cv.volume, -kCellTolM3) << what;
                EXPECT_LT(cv.volume, b->cellVolume(cv.cell) + kCellTolM3) << what;
            }
            if (name == "sphere" || name == "hollow sphere") {
                EXPECT_NEAR(sum(local), meshVolume(body), kSumRelTol * meshVolume(body)) << what;
                EXPECT_NEAR(sum(half), meshVolume(body, &kept), kSumRelTol * meshVolume(body)) << what;
            }
        }
    }
}

TEST(SGridReserves, BodiesOnLatticePlanesAndPointsGiveTheAnalyticVolumes) {
    // 8^3 cells of 4 m (grid metres), regular and sheared (an affine map: volumes scale by
    // |det A|, and the lattice points are the same function of (i, j, k) as the bodies'
    // corners, so corners coincide bit for bit).
    struct Case {
        std::string name;
        glm::dmat3 A;
    };
    const std::vector<Case> cases = {
        {"regular", glm::dmat3(1.0)},
        {"sheared", glm::dmat3(glm::dvec3(1.0, 0.2, 0.05), glm::dvec3(0.3, 0.9, -0.1), glm::dvec3(0.25, -0.15, 1.1))}};
    const glm::dvec3 t{1000.0, 2000.0, 100.0};
    const double s = 4.0;
    for (const Case& c : cases) {
        auto f = [&](const glm::dvec3& q) { return t + c.A * q; };
        const double det = glm::determinant(c.A);
        const Grid g = sgridOf(
            8, 8, 8, [&](int i, int j, int k) { return f(s * glm::dvec3(i, j, k)); },
            [](int, int, int) { return 1.0; });
        auto b = blockModelFromGrid(g);
        ASSERT_TRUE(b.ok()) << b.error().message;
        const double cell = det * s * s * s;
        auto check = [&](const std::string& what, const Mesh& body, auto fraction) {
            const auto got = byCell(cellBodyVolumes(b.value(), body));
            const auto oracle = clippedCellBodyVolumes(b.value(), body);
            double total = 0.0;
            for (std::size_t id = 0; id < b->cellCount(); ++id) {
                const auto [i, j, k] = b->ijk(id);
                const double want = cell * fraction(int(i), int(j), int(k));
                const auto it = got.find(id);
                EXPECT_NEAR(it == got.end() ? 0.0 : it->second, want, kAnalyticCellTolM3)
                    << c.name << " " << what << " cell " << i << "," << j << "," << k;
                total += want;
            }
            EXPECT_NEAR(sum(oracle), total, kSumRelTol * total) << c.name << " " << what << " (oracle)";
        };
        auto boxBody = [&](const glm::dvec3& lo, const glm::dvec3& hi) {
            Mesh m = boxMesh(s * lo, s * hi);
            for (glm::dvec3& p : m.positions) p = f(p);
            if (det < 0.0) reverse(m);
            return m;
        };
        // A box on lattice planes, corners on lattice points.
        check("box", boxBody({2, 1, 3}, {7, 4, 5}),
              [](int i, int j, int k) { return i >= 2 && i < 7 && j >= 1 && j < 4 && k >= 3 && k < 5 ? 1.0 : 0.0; });
        // The whole grid: every face on the grid's boundary.
        check("whole grid", boxBody({0, 0, 0}, {8, 8, 8}), [](int, int, int) { return 1.0; });
        // Boxes sharing a face (a body split into two closed parts; each measured alone, they
        // tile): the left one.
        check("left box", boxBody({0, 2, 2}, {3, 6, 6}),
              [](int i, int j, int k) { return i < 3 && j >= 2 && j < 6 && k >= 2 && k < 6 ? 1.0 : 0.0; });
        // The Kuhn simplex {8s >= x >= y >= z >= 0}: its faces x = y and y = z lie on the
        // cells' diagonal planes, so a cell holds all of it (i > j > k), half (two indices
        // equal, the third apart), a sixth (all equal: the one tetrahedron 000, e_x, e_x +
        // e_y, 111), or none.
        check("Kuhn simplex", tetraMesh(f({0, 0, 0}), f({8 * s, 0, 0}), f({8 * s, 8 * s, 0}), f({8 * s, 8 * s, 8 * s})),
              [](int i, int j, int k) {
                  if (i < j || j < k) return 0.0;
                  if (i == j && j == k) return 1.0 / 6.0;
                  if (i == j || j == k) return 0.5;
                  return 1.0;
              });
        // An octahedron with its corners on lattice points (faces x + y + z = const cut
        // cells through their corners and edges): only the sum is analytic (4/3 r³), each cell
        // against the whole-body clip.
        Mesh oct = octahedronMesh(s * glm::dvec3(4, 4, 4), 3 * s);
        for (glm::dvec3& p : oct.positions) p = f(p);
        if (det < 0.0) reverse(oct);
        const auto local = cellBodyVolumes(b.value(), oct);
        expectSameCells(local, clippedCellBodyVolumes(b.value(), oct), kCellTolM3, c.name + " octahedron");
        const double octVolume = det * 4.0 / 3.0 * std::pow(3 * s, 3);
        EXPECT_NEAR(sum(local), octVolume, kSumRelTol * octVolume) << c.name;
        // The kept side of a lattice plane (k >= 4) of the box: the box's cells with k >= 4.
        const Mesh box = boxBody({2, 1, 3}, {7, 4, 6});
        const glm::dvec3 n = glm::normalize(glm::cross(c.A[0], c.A[1]));
        const Plane upper{n, -glm::dot(n, f(s * glm::dvec3(0, 0, 4)))};
        const auto half = byCell(cellBodyVolumes(b.value(), box, upper));
        for (std::size_t id = 0; id < b->cellCount(); ++id) {
            const auto [i, j, k] = b->ijk(id);
            const bool in = i >= 2 && i < 7 && j >= 1 && j < 4 && k >= 4 && k < 6;
            const auto it = half.find(id);
            EXPECT_NEAR(it == half.end() ? 0.0 : it->second, in ? cell : 0.0, kAnalyticCellTolM3)
                << c.name << " kept side, cell " << i << "," << j << "," << k;
        }
    }
}

TEST(SGridReserves, ABodyTheWholeBodyClipRefusedHasItsTable) {
    // 24^3 bent cells (82,944 tetrahedra) and a sphere of 14,160 triangles across most of
    // them: 1.2e9 tetrahedra x triangles, refused above 1e8 by the former whole-body clip.
    auto at = [](int i, int j, int k) {
        const double x = 5.0 * i, y = 5.0 * j;
        return glm::dvec3(x, y, 5.0 * k + 1.5 * std::sin(x / 17.0) * std::cos(y / 23.0) * (k > 0 && k < 24));
    };
    const Grid g = sgridOf(24, 24, 24, at, [](int i, int j, int k) { return 0.1 * (i + j + k); });
    auto b = blockModelFromGrid(g);
    ASSERT_TRUE(b.ok()) << b.error().message;
    const Mesh sphere = sphereMesh({60, 60, 60}, 55.0, 120, 60);
    ASSERT_EQ(sphere.triangleCount(), 14160u);
    Model m = modelOf({makePart("ore", PartKind::Body, 1, sphere)});
    AttributeRecord ore{};
    ore.id = 1;
    ore.name = "ore";
    ore.density = 2.5;
    m.attributes.put(ore);
    BlockModel bm = b.value();
    ASSERT_TRUE(resolveBlockClip(m, bm).ok());
    m.blocks = std::make_shared<const BlockModel>(bm);
    auto gt = computeGradeTonnage(m, "grade", {0.0, 2.0, 4.0});
    ASSERT_TRUE(gt.ok()) << gt.error().message;
    ASSERT_EQ(gt->bodies.size(), 1u);
    const double v = meshVolume(m.bodies[0].mesh);
    EXPECT_NEAR(gt->bodies[0].volume, v, kSumRelTol * v);
    EXPECT_NEAR(gt->bodies[0].rows[0].volume, v, kSumRelTol * v);
    ASSERT_TRUE(gt->bodies[0].rows[0].tonnage.has_value());
    EXPECT_NEAR(*gt->bodies[0].rows[0].tonnage, 2.5 * v, 2.5 * kSumRelTol * v);
    // And on the kept side of a plane through the centre: half the sphere (its mesh's half).
    const Plane half{glm::normalize(glm::dvec3(0.3, -0.2, 1.0)), 0.0};
    Plane kept = half;
    kept.d = -glm::dot(half.normal, m.bodies[0].mesh.bounds().centre());
    auto gh = computeGradeTonnage(m, "grade", {0.0}, kept);
    ASSERT_TRUE(gh.ok()) << gh.error().message;
    const double vh = meshVolume(m.bodies[0].mesh, &kept);
    EXPECT_NEAR(gh->bodies[0].volume, vh, kSumRelTol * v);
}
