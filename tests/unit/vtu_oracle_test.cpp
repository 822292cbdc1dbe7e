// The .vtu reader against an independent oracle: the generated tetrahedral model of
// tests/common/tet_model.hpp (a lens that touches itself along an edge and at a point, and
// a variant whose formations overlap and leave gaps of centimetres) is written as .vtu in
// every encoding, loaded, and compared with point-in-tetrahedron (plain double, here) at
// random points (Classifier::classify) and at pixel centres of exact sections (the ID
// buffer), and its formation volumes (reserves) with the summed tetrahedron volumes.
//
// Tolerances:
//  - volumes: 1e-9 relative (the bar); the divergence sum over ~2,000 boundary
//    triangles of 10 m rounds at ~1e-13 relative;
//  - agreement: >= 99.99 % of all points, and 100 % of points farther than the
//    classifier's stated tolerance (Classifier::tolerance(), section/rays/classify.hpp: 1e-6 x
//    the largest local coordinate + 0.1 mm, from the float32 local frame) from every
//    formation boundary. Where formations overlap, the oracle applies the section engine's
//    rule (the deepest nested, then the latest body); in a gap it says "no formation".
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "model/io/loaders.hpp"
#include "section/cut/contours.hpp"
#include "section/fill/raster.hpp"
#include "section/index/section_index.hpp"
#include "section/rays/classify.hpp"
#include "section/volumes/reserves.hpp"
#include "tests/common/random_plane.hpp"
#include "tests/common/tet_model.hpp"
#include "tests/common/tolerances.hpp"

using geoslice::test::kShellVsCellSumRelTol;  // relative, a shell volume against its cells sum
                                              // (tests/common/tolerances.hpp)
#include "tests/common/vtu_writer.hpp"

namespace geoslice {
namespace {

testing::VtuGrid toVtu(const VolumeMesh& m) {
    testing::VtuGrid g;
    g.points = m.positions;
    testing::VtuGrid::Array formation{"formation", "Int32", 1, {}};
    for (std::size_t c = 0; c < m.cellCount(); ++c) {
        g.types.push_back(static_cast<std::uint8_t>(m.cellTypes[c]));
        for (std::uint32_t k = m.cellOffsets[c]; k < m.cellOffsets[c + 1]; ++k)
            g.connectivity.push_back(m.cellVertices[k]);
        g.offsets.push_back(static_cast<std::int64_t>(g.connectivity.size()));
        formation.values.push_back(m.cellRegions[c] + 1);  // record ids 1..4
    }
    g.cellData.push_back(std::move(formation));
    return g;
}

// Point -> the formations (record ids) whose tetrahedra contain it: a uniform bucket grid
// over the tetrahedra's boxes, then test::pointInTet (double, inclusive).
class TetOracle {
public:
    explicit TetOracle(const VolumeMesh& m) : m_(m) {
        for (const auto& p : m.positions) box_.extend(p);
        cell_ = (box_.max - box_.min) / double(kN);
        buckets_.resize(std::size_t(kN) * kN * kN);
        for (std::size_t c = 0; c < m.cellCount(); ++c) {
            Aabb b;
            for (std::uint32_t k = m.cellOffsets[c]; k < m.cellOffsets[c + 1]; ++k)
                b.extend(m.positions[m.cellVertices[k]]);
            const glm::ivec3 lo = bucketOf(b.min), hi = bucketOf(b.max);
            for (int z = lo.z; z <= hi.z; ++z)
                for (int y = lo.y; y <= hi.y; ++y)
                    for (int x = lo.x; x <= hi.x; ++x)
                        buckets_[index(x, y, z)].push_back(static_cast<std::uint32_t>(c));
        }
    }
    std::set<RecordId> at(const glm::dvec3& p) const {
        std::set<RecordId> out;
        if (p.x < box_.min.x || p.y < box_.min.y || p.z < box_.min.z || p.x > box_.max.x || p.y > box_.max.y ||
            p.z > box_.max.z)
            return out;
        const glm::ivec3 b = bucketOf(p);
        for (const std::uint32_t c : buckets_[index(b.x, b.y, b.z)]) {
            const std::uint32_t* v = &m_.cellVertices[m_.cellOffsets[c]];
            if (test::pointInTet(p, m_.positions[v[0]], m_.positions[v[1]], m_.positions[v[2]], m_.positions[v[3]]))
                out.insert(static_cast<RecordId>(m_.cellRegions[c] + 1));
        }
        return out;
    }
    const Aabb& bounds() const { return box_; }

private:
    static constexpr int kN = 24;
    glm::ivec3 bucketOf(const glm::dvec3& p) const {
        glm::ivec3 i = glm::ivec3(glm::floor((p - box_.min) / cell_));
        return glm::clamp(i, glm::ivec3(0), glm::ivec3(kN - 1));
    }
    std::size_t index(int x, int y, int z) const {
        return (std::size_t(z) * kN + std::size_t(y)) * kN + std::size_t(x);
    }
    const VolumeMesh& m_;
    Aabb box_;
    glm::dvec3 cell_;
    std::vector<std::vector<std::uint32_t>> buckets_;
};

// Distance from p to triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return glm::length(p - a);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return glm::length(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return glm::length(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double denom = 1.0 / (va + vb + vc);
    return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

// Distance from p to the nearest formation boundary (every body triangle; brute force, so
// only called for the few points that disagree).
double distanceToBoundary(const Model& m, const glm::dvec3& p) {
    double best = INFINITY;
    for (const auto& b : m.bodies)
        for (std::size_t t = 0; t < b.mesh.indices.size(); t += 3)
            best = std::min(best, pointTriangleDistance(p, b.mesh.positions[b.mesh.indices[t]],
                                                        b.mesh.positions[b.mesh.indices[t + 1]],
                                                        b.mesh.positions[b.mesh.indices[t + 2]]));
    return best;
}

struct Tally {
    std::size_t total = 0, agree = 0, farDisagree = 0;
    double worstDistance = 0;  // of a disagreement, metres
    // truth: the formations whose tetrahedra contain p; the expected record is the section
    // engine's pick among their bodies (greatest nesting depth, then latest body).
    void add(const Model& m, double band, const glm::dvec3& p, const std::set<RecordId>& truth, RecordId got) {
        ++total;
        int best = -1;
        for (std::size_t b = 0; b < m.bodies.size(); ++b) {
            if (!truth.count(m.bodies[b].record)) continue;
            if (best < 0 || m.bodies[b].report.nestingDepth >= m.bodies[std::size_t(best)].report.nestingDepth)
                best = static_cast<int>(b);
        }
        const RecordId expected = best < 0 ? kNoRecord : m.bodies[std::size_t(best)].record;
        if (got == expected) {
            ++agree;
            return;
        }
        const double d = distanceToBoundary(m, p);
        worstDistance = std::max(worstDistance, d);
        farDisagree += d > band;
    }
};

struct Case {
    const char* label;
    test::TetModelOptions options;
};

TEST(VtuOracle, TetModelInEveryEncodingAgreesWithPointInTetrahedron) {
    std::vector<Case> cases(2);
    cases[0].label = "pinch-outs";
    cases[0].options.origin = glm::dvec3(35500000.0, 3388000.0, -400.0);  // a Gauss-Kruger position
    cases[1].label = "pinch-outs + 2 cm overlaps and gaps";
    cases[1].options = cases[0].options;
    cases[1].options.overlap = 0.02;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.label);
        const test::TetModel tm = test::tetLayeredModel(c.options);
        const testing::VtuGrid grid = toVtu(tm.mesh);

        // Every encoding gives the same model.
        std::optional<Model> first;
        for (const auto& e : testing::allVtuEncodings()) {
            auto m = parseVtu(testing::writeVtu(grid, e), "tet_model.vtu");
            ASSERT_TRUE(m) << e.label() << ": " << m.error().message;
            if (!first) {
                first = std::move(m.value());
                continue;
            }
            ASSERT_EQ(m->bodies.size(), first->bodies.size()) << e.label();
            for (std::size_t b = 0; b < first->bodies.size(); ++b) {
                EXPECT_EQ(m->bodies[b].mesh.positions, first->bodies[b].mesh.positions) << e.label();
                EXPECT_EQ(m->bodies[b].mesh.indices, first->bodies[b].mesh.indices) << e.label();
            }
        }
        const Model& model = *first;
        ASSERT_EQ(model.bodies.size(), 4u);
        EXPECT_FALSE(model.validation.hasErrors());
        for (const auto& b : model.bodies) EXPECT_TRUE(b.report.closed) << b.name;

        // Volumes: reserves vs the summed tetrahedra of each formation.
        std::array<double, 5> tetVolume{};
        for (std::size_t t = 0; t < tm.mesh.cellCount(); ++t) {
            const std::uint32_t* v = &tm.mesh.cellVertices[tm.mesh.cellOffsets[t]];
            tetVolume[std::size_t(tm.mesh.cellRegions[t] + 1)] += std::abs(test::tetVolume(
                tm.mesh.positions[v[0]], tm.mesh.positions[v[1]], tm.mesh.positions[v[2]], tm.mesh.positions[v[3]]));
        }
        auto reserves = computeReserves(model);
        ASSERT_TRUE(reserves) << reserves.error().message;
        double worstRel = 0;
        for (const auto& br : reserves->bodies) {
            const double expected = tetVolume[br.record];
            worstRel = std::max(worstRel, std::abs(br.grossVolume - expected) / expected);
            EXPECT_NEAR(br.grossVolume, expected, kShellVsCellSumRelTol * expected) << model.bodies[br.body].name;
        }

        // Random points: classify vs point in tetrahedron.
        const TetOracle oracle(tm.mesh);
        auto classifier = Classifier::build(model);
        ASSERT_TRUE(classifier) << classifier.error().message;
        std::mt19937_64 rng(42);
        const Aabb box = oracle.bounds();
        std::uniform_real_distribution<double> ux(box.min.x, box.max.x), uy(box.min.y, box.max.y),
            uz(box.min.z, box.max.z);
        Tally points;
        std::vector<glm::dvec3> pts(100000);
        for (auto& p : pts) p = {ux(rng), uy(rng), uz(rng)};
        std::vector<RecordId> got(pts.size());
        (*classifier)->classifyBatch(pts.data(), pts.size(), got.data(), 2);
        const double band = (*classifier)->tolerance();
        for (std::size_t i = 0; i < pts.size(); ++i) points.add(model, band, pts[i], oracle.at(pts[i]), got[i]);

        // Exact sections: ID buffer vs point in tetrahedron at pixel centres.
        auto index = buildSectionIndex(model);
        ASSERT_TRUE(index) << index.error().message;
        Tally pixels;
        RasterOptions opt;
        opt.colour = false;
        const int W = 160, H = 120;
        for (int k = 0; k < 20; ++k) {
            const Plane plane = test::randomPlane(model.bounds(), rng, k);
            auto s = computeSection(**index, plane);
            ASSERT_TRUE(s) << s.error().message;
            auto img = rasterizeSection(**index, s.value(), fitFrame(s.value(), W, H), W, H, opt);
            ASSERT_TRUE(img) << img.error().message;
            for (int j = 0; j < H; ++j)
                for (int i = 0; i < W; ++i) {
                    const glm::dvec3 p = img->frame.pixelCentreWorld(i, j);
                    pixels.add(model, band, p, oracle.at(p), img->ids[std::size_t(j) * W + std::size_t(i)]);
                }
        }
        std::printf(
            "[ oracle   ] vtu %s: classify %zu of %zu points agree (%zu disagree farther than %.2f mm, worst %.2f mm "
            "from a boundary); sections %zu of %zu pixels agree (%zu farther, worst %.2f mm); volumes within %.1e\n",
            c.label, points.agree, points.total, points.farDisagree, band * 1e3, points.worstDistance * 1e3,
            pixels.agree, pixels.total, pixels.farDisagree, pixels.worstDistance * 1e3, worstRel);
        EXPECT_GE(double(points.agree), 0.9999 * double(points.total));
        EXPECT_EQ(points.farDisagree, 0u);
        EXPECT_GE(double(pixels.agree), 0.9999 * double(pixels.total));
        EXPECT_EQ(pixels.farDisagree, 0u);
    }
}

}  // namespace
}  // namespace geoslice
