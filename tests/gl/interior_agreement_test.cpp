// Deep inside a formation the GL profile and the exact section must agree on every pixel.
// A pixel whose 5x5 neighbourhood in the exact section is one body is an interior pixel:
// there the renderer has no boundary to round, so any disagreement is a bug (pixels that
// touch a boundary may differ, triangle coverage against polygon coverage).
//
// The model: a stack of thin layers (30 m) gently folded along x (z = f(x) + c y, so every
// grid quad is planar and two triangulations of one contact are the same surface), each layer
// a closed prism, at Gauss-Kruger-like coordinates (easting 35,500,000 m). Its contacts are
// either shared triangle for triangle (as RINGMesh regions share their boundary surfaces) or
// triangulated differently on their two sides (row counts and diagonals). Profiles nearly
// along x see a ray run far inside one layer and graze a crest of the contact below it: a
// fold, where the rasterizer's subpixel snap decided coverage on one side of the fold while
// llvmpipe interpolated depth on the other, and the wrong layer's back face won
// (docs/design/renderer.md, "Coverage and depth from one position").
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "model/mesh/validate.hpp"
#include "renderer/slice_renderer.hpp"
#include "section/cut/contours.hpp"
#include "section/fill/raster.hpp"
#include "section/index/section_index.hpp"
#include "tests/common/random_plane.hpp"
#include "tests/gl/gl_test_util.hpp"

using namespace geoslice;

namespace {

constexpr double kWidth = 3000.0, kDepth = 2000.0, kThickness = 30.0;
constexpr int kLayers = 14, kColumns = 121;
const glm::dvec3 kOffset(35'500'000.0, 3'390'000.0, 0.0);

double horizon(int k, double x, double y) { return k * kThickness + 12.0 * std::sin(x / 200.0 + 0.4) + 0.04 * y; }

// Contacts shared triangle for triangle (as RINGMesh regions share their boundary surfaces)
// or triangulated differently on the two sides (rows and diagonals).
enum class Contacts { Shared, Different };

// Rows of a layer's top (k + 1) or bottom (k).
int topRows(int k, Contacts c) { return c == Contacts::Shared ? 5 + 3 * ((k + 1) % 4) : 5 + 3 * (k % 4); }
int bottomRows(int k, Contacts c) { return c == Contacts::Shared ? 5 + 3 * (k % 4) : 7 + 2 * (k % 3); }

// One layer: a closed prism between horizons k and k + 1, outward triangles.
Part layer(int k, Contacts contacts) {
    Part p;
    p.name = "layer " + std::to_string(k);
    p.kind = PartKind::Body;
    p.kindDeclared = true;
    p.record = RecordId(k + 1);
    Mesh& m = p.mesh;
    auto grid = [&](int h, int rows) {
        const std::uint32_t base = std::uint32_t(m.positions.size());
        for (int i = 0; i < kColumns; ++i)
            for (int j = 0; j < rows; ++j) {
                const double x = kWidth * i / (kColumns - 1), y = kDepth * j / (rows - 1);
                m.positions.push_back(kOffset + glm::dvec3(x, y, horizon(h, x, y)));
            }
        return base;
    };
    const int rb = bottomRows(k, contacts), rt = topRows(k, contacts);
    const bool sameDiagonal = contacts == Contacts::Shared;
    const std::uint32_t b = grid(k, rb), t = grid(k + 1, rt);
    auto at = [&](std::uint32_t base, int rows, int i, int j) { return base + std::uint32_t(i * rows + j); };
    auto tri = [&](std::uint32_t a, std::uint32_t c, std::uint32_t d, const glm::dvec3& out) {
        const glm::dvec3 n = glm::cross(m.positions[c] - m.positions[a], m.positions[d] - m.positions[a]);
        if (glm::dot(n, out) < 0.0) std::swap(c, d);
        m.indices.insert(m.indices.end(), {a, c, d});
    };
    // Top and bottom: one diagonal (shared contacts) or opposite ones.
    for (int i = 0; i + 1 < kColumns; ++i) {
        for (int j = 0; j + 1 < rb; ++j) {
            const std::uint32_t q[4] = {at(b, rb, i, j), at(b, rb, i + 1, j), at(b, rb, i + 1, j + 1),
                                        at(b, rb, i, j + 1)};
            tri(q[0], q[1], q[2], {0, 0, -1});
            tri(q[0], q[2], q[3], {0, 0, -1});
        }
        for (int j = 0; j + 1 < rt; ++j) {
            const std::uint32_t q[4] = {at(t, rt, i, j), at(t, rt, i + 1, j), at(t, rt, i + 1, j + 1),
                                        at(t, rt, i, j + 1)};
            if (sameDiagonal) {
                tri(q[0], q[1], q[2], {0, 0, 1});
                tri(q[0], q[2], q[3], {0, 0, 1});
            } else {
                tri(q[0], q[1], q[3], {0, 0, 1});
                tri(q[1], q[2], q[3], {0, 0, 1});
            }
        }
    }
    // Walls at y = 0 and y = kDepth: quads between the first/last rows.
    for (int i = 0; i + 1 < kColumns; ++i)
        for (int side = 0; side < 2; ++side) {
            const int jb = side ? rb - 1 : 0, jt = side ? rt - 1 : 0;
            const glm::dvec3 out(0, side ? 1 : -1, 0);
            tri(at(b, rb, i, jb), at(b, rb, i + 1, jb), at(t, rt, i + 1, jt), out);
            tri(at(b, rb, i, jb), at(t, rt, i + 1, jt), at(t, rt, i, jt), out);
        }
    // Walls at x = 0 and x = kWidth: a zipper between rows of different counts.
    for (int side = 0; side < 2; ++side) {
        const int i = side ? kColumns - 1 : 0;
        const glm::dvec3 out(side ? 1 : -1, 0, 0);
        int jb = 0, jt = 0;
        while (jb + 1 < rb || jt + 1 < rt) {
            const double yb = jb + 1 < rb ? double(jb + 1) / (rb - 1) : 2.0;
            const double yt = jt + 1 < rt ? double(jt + 1) / (rt - 1) : 2.0;
            if (yb <= yt) {
                tri(at(b, rb, i, jb), at(b, rb, i, jb + 1), at(t, rt, i, jt), out);
                ++jb;
            } else {
                tri(at(b, rb, i, jb), at(t, rt, i, jt + 1), at(t, rt, i, jt), out);
                ++jt;
            }
        }
    }
    return p;
}

Model thinLayers(Contacts contacts) {
    Model model;
    model.name = "thin folded layers";
    for (int k = 0; k < kLayers; ++k) model.bodies.push_back(layer(k, contacts));
    model.recentre();
    validate(model);
    return model;
}

struct Agreement {
    std::size_t compared = 0, disagree = 0;
};

// Renders kPlanes profiles of `model` and counts the interior pixels and those that disagree.
Agreement interiorAgreement(const Model& model) {
    constexpr int kSize = 640, kPlanes = 24, kRadius = 2;
    Agreement out;
    auto ctx = test::makeContext();
    if (!ctx) return out;
    auto gpu = GpuModel::upload(*ctx, model);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    auto renderer = SliceRenderer::create(*ctx);
    EXPECT_TRUE(renderer.ok()) << renderer.error().message;
    auto index = buildSectionIndex(model);
    EXPECT_TRUE(index.ok()) << index.error().message;
    if (!gpu.ok() || !renderer.ok() || !index.ok()) return out;
    std::mt19937_64 rng(2026);
    for (int k = 0; k < kPlanes; ++k) {
        // Every other plane vertical and nearly along x: its view rays graze the folds' crests.
        Plane plane = test::randomPlane(model.bounds(), rng, k);
        if (k % 2 == 0) {
            const double a = 0.02 * (k - kPlanes / 2) / kPlanes;
            const glm::dvec3 n(std::cos(a), std::sin(a), 0.0);
            plane = Plane{n, -glm::dot(n, model.bounds().centre() + glm::dvec3(300.0 * (k - kPlanes / 2) / kPlanes))};
        }
        const WorldPlane wp(plane.normal.x, plane.normal.y, plane.normal.z, plane.d);
        SliceRequest req;
        req.width = req.height = kSize;
        req.planes = {wp};
        req.view = profileAround(wp, model.bounds(), kSize, kSize);
        req.readColour = false;
        req.antiAlias = AntiAlias::None;
        req.drawTraces = false;
        auto gl = (*renderer)->render(*gpu.value(), req);
        EXPECT_TRUE(gl.ok()) << gl.error().message;
        auto section = computeSection(*index.value(), plane);
        EXPECT_TRUE(section.ok()) << section.error().message;
        if (!gl.ok() || !section.ok()) return out;
        RasterOptions ro;
        ro.colour = false;
        ro.traces = false;
        auto exact =
            rasterizeSection(*index.value(), section.value(), std::get<ProfileCamera>(req.view).rect, kSize, kSize, ro);
        EXPECT_TRUE(exact.ok()) << exact.error().message;
        if (!exact.ok()) return out;
        const auto& e = exact->ids;
        for (int y = kRadius; y + kRadius < kSize; ++y)
            for (int x = kRadius; x + kRadius < kSize; ++x) {
                const std::uint32_t id = e[std::size_t(y) * kSize + std::size_t(x)];
                bool interior = id != kNoRecord;
                for (int dy = -kRadius; dy <= kRadius && interior; ++dy)
                    for (int dx = -kRadius; dx <= kRadius && interior; ++dx)
                        interior = e[std::size_t(y + dy) * kSize + std::size_t(x + dx)] == id;
                if (!interior) continue;
                ++out.compared;
                if (gl->idAt(x, y) == id) continue;
                ++out.disagree;
                std::printf("[ interior ] plane %d pixel (%d, %d): GL %u, exact %u\n", k, x, y, gl->idAt(x, y), id);
            }
    }
    return out;
}

}  // namespace

TEST(InteriorAgreement, ThinLayersModelsAreClosedAndHaveTheClosedFormVolumes) {
    for (Contacts c : {Contacts::Shared, Contacts::Different}) {
        const Model model = thinLayers(c);
        ASSERT_EQ(model.bodies.size(), std::size_t(kLayers));
        for (const Part& p : model.bodies) {
            EXPECT_TRUE(p.report.closed) << p.name;
            EXPECT_TRUE(p.report.consistentlyOriented) << p.name;
            // Horizons k and k + 1 differ by kThickness everywhere.
            EXPECT_NEAR(signedVolume(p.mesh), kWidth * kDepth * kThickness, 1e-6 * kWidth * kDepth * kThickness)
                << p.name;
        }
    }
}

// Contacts shared triangle for triangle: before the vertex stage snapped to the rasterizer's
// grid, 23 of 1,275,286 interior pixels disagreed here (and 15 of 10.7 M on 12 planes of the
// RINGMesh geomodel3d at 1800 x 1800); after, none.
TEST(InteriorAgreement, SharedContactsNoInteriorPixelDisagrees) {
    const Agreement a = interiorAgreement(thinLayers(Contacts::Shared));
    std::printf("[ interior ] shared contacts: %zu of %zu interior pixels disagree\n", a.disagree, a.compared);
    EXPECT_GT(a.compared, std::size_t(1000000));
    EXPECT_EQ(a.disagree, 0u);
}

// Contacts triangulated differently on their two sides: the two triangulations of a contact
// are snapped to the subpixel grid separately, so at a crest seen grazing they are no longer
// one surface; a pixel in that band (about 1/512 px wide) can see one body's fold and miss
// the other's. Measured: 22 of 1,275,286 interior pixels without the snap, 14 with it; not
// fixed (docs/design/renderer.md). The bound keeps it from growing.
TEST(InteriorAgreement, DifferentContactsDisagreeOnlyInTheKnownBand) {
    const Agreement a = interiorAgreement(thinLayers(Contacts::Different));
    std::printf("[ interior ] different contacts: %zu of %zu interior pixels disagree\n", a.disagree, a.compared);
    EXPECT_GT(a.compared, std::size_t(1000000));
    EXPECT_LE(a.disagree, 14u);
}
