// The GL cell buffer of perspective views coloured by a block model (issue 15 item 2: the ID
// buffer and the pixel query agree at every pixel for block properties as for records), for
// box grids (the class texture, renderer/passes/block_texture.hpp, and the cells' pieces) and
// curvilinear SGrid grids (the cells' pieces, renderer/passes/block_caps.hpp).
//
// Scene: a box orebody (record 2) nested in a box host (record 1) at a Gauss-Kruger easting,
// a 20 x 20 x 20 block grid of 10 m cells over the host clipped by the orebody (grade =
// i + 0.5 j - 0.3 k, classes < 9, 9 - 11, 11 - 13, 13 - 15, >= 15; one cell with no value), and
// cut-outs of three oblique planes through the orebody (cut=union: an octant kept;
// cut=intersection: an octant taken out) and one plane, seen from the removed side; drawn by
// the render worker with no anti-aliasing. Oracle, for 1,000 random pixels whose ray's first
// kept point inside the host lies inside the orebody past its surface (a cap of the
// orebody): that point, from the pixel centre's ray (view/camera.hpp pixelRay) and the
// planes and boxes in closed form; its cell by brute force (box grid: the floor of its grid
// coordinates; SGrid: every tetrahedron of every cell, no locator). Compared exactly: the ID
// buffer's record, the cell buffer, the exact pixel query's cell (no cached image), the
// cached query's cell (from the cell buffer) and the colour (the class's, or the body's own
// where the cell has no value).
// Skipped, with their reason: points within 5 cm of a cell face (the oracle's cell differs
// 5 cm to either side along x, y or z), of the orebody's surface or of another plane. The
// GPU interpolates the point in float32 in the model's local frame (steps of ~3e-5 m over
// this 200 m model) from a float32 view matrix (~1e-4 m at 400 m from the eye); 5 cm is
// far outside both, and a wrong cell anywhere inside the band's complement fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "api/catalog.hpp"
#include "api/pixel_query.hpp"
#include "api/plan.hpp"
#include "model/blocks/block_model.hpp"
#include "section/blocks/block_section.hpp"
#include "tests/gl/gl_test_util.hpp"
#include "tests/unit/test_meshes.hpp"
#include "view/camera.hpp"
#include "workers/gl_worker.hpp"

using namespace geoslice;

namespace {

constexpr double kBandM = 0.05;  // see the header: 5 cm around cell faces, the outline and plane edges

const glm::dvec3 kBase(35500000.0, 3380000.0, 100.0);
const glm::dvec3 kOreLo = kBase + glm::dvec3(40.5, 35.5, 45.5), kOreHi = kBase + glm::dvec3(160.5, 170.5, 150.5);
constexpr int kCells = 20;
constexpr double kCell = 10.0;

double gradeOf(int i, int j, int k) { return double(i) + 0.5 * double(j) - 0.3 * double(k); }
const glm::ivec3 kNoValueCell(10, 10, 9);

// The SGrid's lattice: the box lattice with every interior point's elevation moved by up to
// 3 m (so no cell is a box), the outer faces flat.
glm::dvec3 sgridPoint(int i, int j, int k) {
    glm::dvec3 p = kBase + kCell * glm::dvec3(i, j, k);
    if (k > 0 && k < kCells) p.z += 3.0 * std::sin(0.7 * i + 0.2) * std::cos(0.5 * j - 0.1);
    return p;
}

BlockModel boxGrid() {
    BlockModel blocks;
    blocks.source = "test grid";
    blocks.origin = kBase;
    blocks.size = {kCell, kCell, kCell};
    blocks.dims = {kCells, kCells, kCells};
    BlockProperty grade{"grade", "g/t Au", std::vector<double>(blocks.cellCount())};
    for (std::size_t c = 0; c < blocks.cellCount(); ++c) {
        const auto ijk = blocks.ijk(c);
        grade.values[c] = gradeOf(int(ijk[0]), int(ijk[1]), int(ijk[2]));
    }
    grade.values[blocks.linear(kNoValueCell.x, kNoValueCell.y, kNoValueCell.z)] = std::nan("");
    blocks.properties.push_back(std::move(grade));
    return blocks;
}

BlockModel sgridGrid() {
    Grid g;
    g.type = "SGrid";
    g.name = "sg";
    g.dims[0] = g.dims[1] = g.dims[2] = kCells + 1;
    g.cellCentred = true;
    for (int k = 0; k <= kCells; ++k)
        for (int j = 0; j <= kCells; ++j)
            for (int i = 0; i <= kCells; ++i) g.points.push_back(sgridPoint(i, j, k));
    GridProperty p{"grade", "g/t Au", std::nullopt, {}};
    for (int k = 0; k < kCells; ++k)
        for (int j = 0; j < kCells; ++j)
            for (int i = 0; i < kCells; ++i)
                p.values.push_back(glm::ivec3(i, j, k) == kNoValueCell ? std::nanf("") : float(gradeOf(i, j, k)));
    g.properties.push_back(std::move(p));
    auto b = blockModelFromGrid(g);
    EXPECT_TRUE(b.ok()) << b.error().message;
    return std::move(b).value();
}

double orient(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    return glm::dot(b - a, glm::cross(c - a, d - a));
}

// The oracle's cell: box grid, the floor of the grid coordinates; SGrid, every tetrahedron of
// every cell whose bounds hold p (strictly inside: all four orientations agree). kNoCell
// outside the grid or on a face.
std::size_t oracleCell(const BlockModel& b, const glm::dvec3& p) {
    if (b.shape == CellShape::Box) {
        const glm::dvec3 g = glm::floor((p - kBase) / kCell);
        if (glm::any(glm::lessThan(g, glm::dvec3(0.0))) || glm::any(glm::greaterThanEqual(g, glm::dvec3(kCells))))
            return BlockModel::kNoCell;
        return b.linear(std::size_t(g.x), std::size_t(g.y), std::size_t(g.z));
    }
    std::size_t found = BlockModel::kNoCell;
    for (std::size_t c = 0; c < b.cellCount(); ++c) {
        const auto k = b.cellCorners(c);
        glm::dvec3 lo = k[0], hi = k[0];
        for (const auto& q : k) lo = glm::min(lo, q), hi = glm::max(hi, q);
        if (glm::any(glm::lessThan(p, lo)) || glm::any(glm::greaterThan(p, hi))) continue;
        for (const auto& t : kCellTets) {
            const glm::dvec3 &A = k[std::size_t(t[0])], &B = k[std::size_t(t[1])], &C = k[std::size_t(t[2])],
                             &D = k[std::size_t(t[3])];
            const double v = orient(A, B, C, D);
            if (orient(p, B, C, D) / v > 0.0 && orient(A, p, C, D) / v > 0.0 && orient(A, B, p, D) / v > 0.0 &&
                orient(A, B, C, p) / v > 0.0) {
                if (found != BlockModel::kNoCell && found != c) return BlockModel::kNoCell;  // two cells: a face
                found = c;
            }
        }
    }
    return found;
}

struct CutCase {
    const char* name;
    std::vector<glm::dvec4> planes;  // world (n, d), unit n; a point is on a plane's kept side at n.p + d >= 0
    bool unionCut;                   // cut=union: removed = union of the removed sides (kept: their intersection)
};

bool keptAt(const CutCase& cut, const glm::dvec3& p) {
    bool all = true, any = false;
    for (const auto& pl : cut.planes) {
        const bool k = glm::dot(glm::dvec3(pl), p) + pl.w >= 0.0;
        all = all && k;
        any = any || k;
    }
    return cut.unionCut ? all : any;
}

// The ray's parameter interval inside an axis-aligned box (empty: lo > hi).
glm::dvec2 slab(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi) {
    double t0 = 0.0, t1 = 1e300;
    for (int a = 0; a < 3; ++a) {
        const double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    return {t0, t1};
}

struct CapPoint {
    bool cap = false;  // the first kept point of the host lies inside the orebody, past the host's surface
    glm::dvec3 world{0.0};
    int plane = -1;  // the plane it lies on
};

// The first kept point along the ray inside the host box: the host's entry, or a plane
// crossing where the ray becomes kept (kept sets are bounded by those crossings).
CapPoint firstKeptInHost(const CutCase& cut, const glm::dvec3& o, const glm::dvec3& d) {
    CapPoint out;
    const glm::dvec2 host = slab(o, d, kBase, kBase + 200.0);
    if (!(host.x < host.y)) return out;
    std::vector<std::pair<double, int>> stops{{host.x, -1}};
    for (std::size_t i = 0; i < cut.planes.size(); ++i) {
        const glm::dvec4& pl = cut.planes[i];
        const double t = -(glm::dot(glm::dvec3(pl), o) + pl.w) / glm::dot(glm::dvec3(pl), d);
        if (t > host.x && t < host.y) stops.push_back({t, int(i)});
    }
    std::sort(stops.begin(), stops.end());
    stops.push_back({host.y, -1});
    for (std::size_t s = 0; s + 1 < stops.size(); ++s) {
        if (!keptAt(cut, o + 0.5 * (stops[s].first + stops[s + 1].first) * d)) continue;
        if (stops[s].second < 0) return out;  // the host's own surface: an exterior face
        out.world = o + stops[s].first * d;
        out.plane = stops[s].second;
        const glm::dvec3& w = out.world;
        out.cap = glm::all(glm::greaterThan(w, kOreLo)) && glm::all(glm::lessThan(w, kOreHi));
        return out;
    }
    return out;
}

// Whether `w` lies within kBandM of a cell face (the oracle's cell changes within kBandM),
// of the orebody's surface, or of a plane other than its own.
bool inBand(const BlockModel& b, const CutCase& cut, const CapPoint& c) {
    const glm::dvec3& w = c.world;
    if (glm::any(glm::lessThan(glm::min(w - kOreLo, kOreHi - w), glm::dvec3(kBandM)))) return true;
    for (std::size_t i = 0; i < cut.planes.size(); ++i)
        if (int(i) != c.plane && std::abs(glm::dot(glm::dvec3(cut.planes[i]), w) + cut.planes[i].w) < kBandM)
            return true;
    const std::size_t cell = oracleCell(b, w);
    if (cell == BlockModel::kNoCell) return true;
    for (int a = 0; a < 3; ++a)
        for (double s : {-kBandM, kBandM}) {
            glm::dvec3 q = w;
            q[a] += s;
            if (oracleCell(b, q) != cell) return true;
        }
    return false;
}

std::string planesParam(const CutCase& cut) {
    std::string s;
    for (const auto& pl : cut.planes) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s%.17g,%.17g,%.17g,%.17g", s.empty() ? "" : ";", pl.x, pl.y, pl.z, pl.w);
        s += buf;
    }
    return s;
}

struct Tally {
    int compared = 0, skipped = 0, noValue = 0;
    int bent = 0;  // SGrid: compared pixels whose cell is not the unbent lattice's box cell there
    std::set<int> classes;
};

// 1,000 random cap pixels of `cut` seen from `eye` (see the header), checked exactly.
Tally checkCapPixels(workers::GlWorker& worker, const api::CatalogModel& cm, const CutCase& cut, const glm::dvec3& eye,
                     int size) {
    const BlockModel& blocks = *cm.model.blocks;
    const glm::dvec3 centre = 0.5 * (kOreLo + kOreHi);
    char eyeText[128], targetText[128];
    std::snprintf(eyeText, sizeof eyeText, "%.17g,%.17g,%.17g", eye.x, eye.y, eye.z);
    std::snprintf(targetText, sizeof targetText, "%.17g,%.17g,%.17g", centre.x, centre.y, centre.z);
    api::Params params{{"view", "perspective"}, {"eye", eyeText},
                       {"target", targetText},  {"size", std::to_string(size) + "x" + std::to_string(size)},
                       {"fov", "40"},           {"colour", "grade"},
                       {"breaks", "9,11,13,15"}};
    if (cut.planes.size() == 1) {
        params.emplace("plane", planesParam(cut));
    } else {
        params.emplace("planes", planesParam(cut));
        params.emplace("cut", cut.unionCut ? "union" : "intersection");
    }
    auto plan = api::parseViewPlan(params, cm.id, cm.model.crs);
    EXPECT_TRUE(plan.ok()) << plan.error().message;
    if (!plan.ok()) return {};
    auto view = worker.renderPerspective(cm, plan.value());
    EXPECT_TRUE(view.ok()) << view.error().message;
    if (!view.ok()) return {};
    const api::ViewImage& v = view.value();
    EXPECT_EQ(v.cells.size(), v.ids.size());
    if (v.cells.size() != v.ids.size()) return {};
    auto classes = makePropertyClasses(0, "viridis", {9.0, 11.0, 13.0, 15.0});
    EXPECT_TRUE(classes.ok());
    EXPECT_TRUE(api::exaggerationOf(plan->section, cm.index->bounds).identity());
    const PerspectiveCamera cam = api::displayCamera(plan.value(), cm.index->bounds);
    const Rgba8 oreColour = cm.model.attributes.find(2u) ? cm.model.attributes.find(2u)->colour : Rgba8{};

    std::mt19937 rng(15);
    std::uniform_int_distribution<int> px(0, size - 1);
    Tally t;
    int failures = 0;
    for (int tries = 0; t.compared + t.skipped < 1000 && tries < 400000; ++tries) {
        const int i = px(rng), j = px(rng);
        const PixelRay ray = pixelRay(cam, size, size, i + 0.5, j + 0.5);
        const CapPoint c = firstKeptInHost(cut, ray.origin, glm::normalize(ray.direction));
        if (!c.cap) continue;
        if (inBand(blocks, cut, c)) {
            ++t.skipped;
            continue;
        }
        ++t.compared;
        const std::size_t p = std::size_t(j) * std::size_t(size) + std::size_t(i);
        const std::size_t cell = oracleCell(blocks, c.world);
        const auto ijk = blocks.ijk(cell);
        const std::string where = std::string(cut.name) + " pixel " + std::to_string(i) + "," + std::to_string(j) +
                                  " cell " + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," +
                                  std::to_string(ijk[2]);
        auto exact = api::answerPixel(cm, plan.value(), i, j, nullptr);
        auto cached = api::answerPixel(cm, plan.value(), i, j, &v);
        EXPECT_TRUE(exact.ok() && cached.ok());
        if (!exact.ok() || !cached.ok()) break;
        const std::uint8_t* got = &v.rgba[4 * p];
        const int k = classes->classOf(blocks.properties[0].values[cell]);
        const Rgba8 want = k < 0 ? oreColour : classes->colours[std::size_t(k)];
        if (blocks.shape == CellShape::Hexahedron) {
            const glm::ivec3 box(glm::floor((c.world - kBase) / kCell));
            t.bent += glm::ivec3(ijk[0], ijk[1], ijk[2]) != box;
        }
        if (k < 0)
            ++t.noValue;
        else
            t.classes.insert(k);
        const bool ok = v.ids[p] == 2u && v.cells[p] == std::uint32_t(cell + 1) && exact->cell == cell &&
                        cached->cell == cell && got[0] == want.r && got[1] == want.g && got[2] == want.b;
        EXPECT_TRUE(ok) << where << ": id " << v.ids[p] << ", cell buffer " << v.cells[p] << " (want " << cell + 1
                        << "), exact query " << exact->cell << ", cached query " << cached->cell << ", colour "
                        << int(got[0]) << "," << int(got[1]) << "," << int(got[2]) << " want " << int(want.r) << ","
                        << int(want.g) << "," << int(want.b);
        if (!ok && ++failures >= 10) break;
    }
    std::printf(
        "[ cells    ] %s: %d cap pixels compared, %d in the band, %d without value, %zu classes, %d in a bent cell "
        "other than the box's\n",
        cut.name, t.compared, t.skipped, t.noValue, t.classes.size(), t.bent);
    return t;
}

std::shared_ptr<const api::CatalogModel> sceneWith(BlockModel blocks) {
    Model m = test::modelOf({test::makePart("host", PartKind::Body, 1, test::boxMesh(kBase, kBase + 200.0)),
                             test::makePart("ore", PartKind::Body, 2, test::boxMesh(kOreLo, kOreHi))});
    EXPECT_EQ(m.bodies[1].report.parent, 0);
    blocks.clipBodies = {"ore"};
    EXPECT_TRUE(resolveBlockClip(m, blocks).ok());
    m.blocks = std::make_shared<const BlockModel>(std::move(blocks));
    auto cm = api::catalogModelOf("box", std::move(m), "v1");
    EXPECT_TRUE(cm.ok()) << cm.error().message;
    return cm.ok() ? cm.value() : nullptr;
}

// Three oblique planes through the orebody's centre and the eye on the removed side of all.
std::vector<CutCase> cutCases() {
    const glm::dvec3 c = 0.5 * (kOreLo + kOreHi);
    auto through = [&](glm::dvec3 n) {
        n = glm::normalize(n);
        return glm::dvec4(n, -glm::dot(n, c));
    };
    const glm::dvec4 a = through({0.93, 0.2, 0.11}), b = through({-0.15, 0.95, 0.2}), z = through({0.12, -0.08, -0.97});
    return {{"one plane", {through({0.45, 0.6, -0.66})}, false},
            {"cut=union (octant kept)", {a, b, z}, true},
            {"cut=intersection (octant taken out)", {a, b, z}, false}};
}

glm::dvec3 eyeFor(const CutCase& cut) {
    glm::dvec3 away(0.0);
    for (const auto& pl : cut.planes) away -= glm::dvec3(pl);
    return 0.5 * (kOreLo + kOreHi) + 420.0 * glm::normalize(away) + glm::dvec3(0.0, 0.0, 30.0);
}

void checkAllCuts(const std::shared_ptr<const api::CatalogModel>& cm,
                  workers::GlWorker::BoxBlocks boxBlocks = workers::GlWorker::BoxBlocks::Auto) {
    ASSERT_TRUE(cm);
    auto worker = workers::GlWorker::create(GlBackend::Auto);
    ASSERT_TRUE(worker.ok()) << worker.error().message;
    worker.value()->antiAlias = AntiAlias::None;
    worker.value()->boxBlocks = boxBlocks;
    int noValue = 0, bent = 0;
    // With MSAA the cell buffer is resolved like the ids (one sample's value per pixel): the
    // same cells as without, but where a pixel's samples see two cells or bodies (edges).
    {
        const CutCase cut = cutCases()[0];
        workers::GlWorker& w = *worker.value();
        auto plan = api::parseViewPlan({{"plane", planesParam(cut)},
                                        {"view", "perspective"},
                                        {"eye", "35500000,3379600,400"},
                                        {"target", "35500100,3380100,200"},
                                        {"size", "200x200"},
                                        {"colour", "grade"}},
                                       cm->id, cm->model.crs);
        ASSERT_TRUE(plan.ok()) << plan.error().message;
        auto plain = w.renderPerspective(*cm, plan.value());
        w.antiAlias = AntiAlias::Msaa;
        auto msaa = w.renderPerspective(*cm, plan.value());
        w.antiAlias = AntiAlias::None;
        ASSERT_TRUE(plain.ok()) << plain.error().message;
        ASSERT_TRUE(msaa.ok()) << msaa.error().message;
        ASSERT_EQ(msaa->cells.size(), plain->cells.size());
        std::size_t cellPixels = 0, same = 0;
        for (std::size_t p = 0; p < plain->cells.size(); ++p) {
            cellPixels += plain->cells[p] != 0;
            same += plain->cells[p] != 0 && msaa->cells[p] == plain->cells[p];
        }
        EXPECT_GT(cellPixels, 2000u);
        EXPECT_GT(double(same), 0.95 * double(cellPixels)) << same << " of " << cellPixels;
    }
    for (const CutCase& cut : cutCases()) {
        const Tally t = checkCapPixels(*worker.value(), *cm, cut, eyeFor(cut), 256);
        EXPECT_GE(t.compared, 800) << cut.name;
        EXPECT_GE(t.classes.size(), 3u) << cut.name;
        noValue += t.noValue;
        bent += t.bent;
        if (::testing::Test::HasFailure()) return;
    }
    EXPECT_GT(noValue, 0) << "the cell with no value was never compared";
    if (cm->model.blocks->shape == CellShape::Hexahedron) {
        EXPECT_GT(bent, 100) << "the grid's bend was never seen";
    }
}

}  // namespace

// A box grid both ways: the class texture and the cells' pieces (renderer/passes/block_caps.hpp).
TEST(BlockCells, BoxGridCellBufferIsTheQuerysCell) {
    checkAllCuts(sceneWith(boxGrid()), workers::GlWorker::BoxBlocks::Texture);
    checkAllCuts(sceneWith(boxGrid()), workers::GlWorker::BoxBlocks::Pieces);
}

// The same views of a curvilinear grid: the caps are its cells' exact pieces.
TEST(BlockCells, SGridCapsAreTheExactPieces) {
    BlockModel sg = sgridGrid();
    ASSERT_EQ(sg.shape, CellShape::Hexahedron);
    checkAllCuts(sceneWith(std::move(sg)));
}

// A worker keeps at most kMaxKeptColourings class textures and plane sets of pieces: requests
// with ever new breaks do not grow its GPU memory, and each view is still coloured.
TEST(BlockCells, AWorkerKeepsABoundedNumberOfColourings) {
    for (auto cm : {sceneWith(boxGrid()), sceneWith(sgridGrid())}) {
        ASSERT_TRUE(cm);
        auto worker = workers::GlWorker::create(GlBackend::Auto);
        ASSERT_TRUE(worker.ok()) << worker.error().message;
        workers::GlWorker& w = *worker.value();
        const CutCase cut = cutCases()[0];
        for (int n = 0; n < 12; ++n) {
            auto plan = api::parseViewPlan({{"plane", planesParam(cut)},
                                            {"view", "perspective"},
                                            {"eye", "35500000,3379600,400"},
                                            {"target", "35500100,3380100,200"},
                                            {"size", "64x64"},
                                            {"colour", "grade"},
                                            {"breaks", std::to_string(5 + n) + ",20"}},
                                           cm->id, cm->model.crs);
            ASSERT_TRUE(plan.ok()) << plan.error().message;
            auto v = w.renderPerspective(*cm, plan.value());
            ASSERT_TRUE(v.ok()) << v.error().message;
            EXPECT_GT(std::count_if(v->cells.begin(), v->cells.end(), [](std::uint32_t c) { return c != 0; }), 50);
        }
        EXPECT_LE(w.colourings.size(), workers::GlWorker::kMaxKeptColourings);
        EXPECT_EQ(w.colourings.size(), workers::GlWorker::kMaxKeptColourings);
    }
}
