// The generated tetrahedral model (tests/common/tet_model.hpp: pinch-outs along an edge and
// at a point; a variant whose neighbours overlap or leave gaps of up to 4 cm) built through
// regionBoundaries -> Model -> validate, checked against an independent oracle: point in
// tetrahedron in plain double arithmetic. classify() and the exact section's ID buffer must
// both give the oracle's record:
//   - at >= 99.99 % of random points and pixel centres, and
//   - at 100 % of those farther than the classifier's stated tolerance from every boundary
//     (each disagreement's distance to the nearest boundary triangle is measured);
// body volumes (section/reserves) equal the summed tetrahedron volumes to 1e-9 relative.
// The oracle applies the section engine's rule where bodies overlap: of the regions whose
// tetrahedra contain the point, the deepest (nesting), then the latest body.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>

#include "../common/tet_model.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "model/mesh/volume_mesh.hpp"
#include "section/cut/contours.hpp"
#include "section/fill/raster.hpp"
#include "section/rays/classify.hpp"
#include "section/volumes/reserves.hpp"
#include "tests/common/tolerances.hpp"

using geoslice::test::kShellVsCellSumRelTol;  // relative, a shell volume against its cells sum
                                              // (tests/common/tolerances.hpp)
#include "section/index/section_index.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

// Bodies in region order, declared volumes (as the TSolid / .vtu readers make them).
Model modelOf(const TetModel& tm) {
    auto b = regionBoundaries(tm.mesh, tm.regionCount());
    EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.error().message);
    Model m;
    m.name = "tet";
    for (std::size_t r = 0; r < tm.regionCount(); ++r) {
        Part p;
        p.name = tm.regionNames[r];
        p.kind = PartKind::Body;
        p.kindDeclared = true;
        p.mesh = std::move(b.value()[r]);
        m.bodies.push_back(std::move(p));
    }
    finishLoadedModel(m, /*classifyByClosure=*/true);
    return m;
}

// Point-in-tetrahedron oracle with a per-cell box prefilter.
struct TetOracle {
    const TetModel& tm;
    const Model& model;
    std::vector<Aabb> boxes;
    explicit TetOracle(const TetModel& t, const Model& m) : tm(t), model(m) {
        for (std::size_t c = 0; c < tm.mesh.cellCount(); ++c) {
            Aabb b;
            for (std::uint32_t k = tm.mesh.cellOffsets[c]; k < tm.mesh.cellOffsets[c + 1]; ++k)
                b.extend(tm.mesh.positions[tm.mesh.cellVertices[k]]);
            boxes.push_back(b);
        }
    }
    // Record at p by the section rule, or kNoRecord.
    RecordId operator()(const glm::dvec3& p) const {
        int best = -1;
        for (std::size_t c = 0; c < boxes.size(); ++c) {
            const Aabb& b = boxes[c];
            if (p.x < b.min.x || p.y < b.min.y || p.z < b.min.z || p.x > b.max.x || p.y > b.max.y || p.z > b.max.z)
                continue;
            const std::uint32_t* v = tm.mesh.cellVertices.data() + tm.mesh.cellOffsets[c];
            const auto& P = tm.mesh.positions;
            if (!pointInTet(p, P[v[0]], P[v[1]], P[v[2]], P[v[3]])) continue;
            const int r = tm.mesh.cellRegions[c];
            auto depth = [&](int body) { return model.bodies[static_cast<std::size_t>(body)].report.nestingDepth; };
            if (best < 0 || depth(r) > depth(best) || (depth(r) == depth(best) && r > best)) best = r;
        }
        return best < 0 ? kNoRecord : model.bodies[static_cast<std::size_t>(best)].record;
    }
};

// Distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
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

double distanceToBoundaries(const Model& m, const glm::dvec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const Part& part : m.bodies)
        for (std::size_t t = 0; t < part.mesh.triangleCount(); ++t) {
            const auto& P = part.mesh.positions;
            const auto* i = part.mesh.indices.data() + 3 * t;
            best = std::min(best, pointTriangleDistance(p, P[i[0]], P[i[1]], P[i[2]]));
        }
    return best;
}

// Agreement counts. The distance to the nearest boundary is computed for disagreements
// only (brute force over all boundary triangles): each must lie within the tolerance.
struct Tally {
    std::size_t checked = 0, agree = 0, farDisagree = 0;
    double worstDisagreementDistance = 0.0;
    void add(bool same, const Model& m, const glm::dvec3& p, double tolerance) {
        ++checked;
        agree += same;
        if (same) return;
        const double d = distanceToBoundaries(m, p);
        farDisagree += d > tolerance;
        worstDisagreementDistance = std::max(worstDisagreementDistance, d);
    }
    double percent() const { return 100.0 * double(agree) / double(checked); }
};

void report(const std::string& what, const Tally& t, double tol) {
    std::printf(
        "  %-40s %zu checked, %.4f %% agree, %zu disagree (nearest boundary at most %.3g mm; %zu farther "
        "than the %.3g mm tolerance)\n",
        what.c_str(), t.checked, t.percent(), t.checked - t.agree, t.worstDisagreementDistance * 1e3, t.farDisagree,
        tol * 1e3);
}

void checkModel(const TetModelOptions& options, const char* label) {
    SCOPED_TRACE(label);
    const TetModel tm = tetLayeredModel(options);
    Model m = modelOf(tm);
    ASSERT_FALSE(m.validation.hasErrors());
    for (const auto& i : m.validation.issues) std::printf("  [%s] %s: %s\n", label, i.part.c_str(), i.message.c_str());
    ASSERT_EQ(m.bodies.size(), tm.regionCount());
    for (const Part& b : m.bodies) {
        EXPECT_TRUE(b.report.closed) << b.name;
        EXPECT_TRUE(b.report.consistentlyOriented) << b.name;
    }
    // The lens: three cubes, touching along an edge and at a point -> three shells.
    EXPECT_EQ(m.bodies[3].report.components, 3u);
    EXPECT_EQ(m.bodies[3].report.splitEdges, 1u);
    EXPECT_GE(m.bodies[3].report.splitVertices, 3u);  // both ends of the edge, and the point
    EXPECT_EQ(m.bodies[1].report.splitEdges, 1u);     // the sandstone around it
    // After validation the split is physical: the index topology alone (no welding by
    // position) is a closed 2-manifold, every edge used by exactly two triangles.
    for (const Part& b : m.bodies) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
        for (std::size_t t = 0; t < b.mesh.triangleCount(); ++t)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t u = b.mesh.indices[3 * t + std::size_t(k)],
                                    v = b.mesh.indices[3 * t + std::size_t(k + 1) % 3];
                ++uses[{std::min(u, v), std::max(u, v)}];
            }
        std::size_t bad = 0;
        for (const auto& [e, n] : uses) bad += n != 2;
        EXPECT_EQ(bad, 0u) << b.name;
    }

    // Volumes: reserves' divergence-theorem volume per body equals the summed tetrahedron
    // volumes; 1e-9 relative (sums of ~10^3 products of 100 m coordinates round at ~1e-14).
    std::vector<double> tetVolumes(tm.regionCount(), 0.0);
    for (std::size_t c = 0; c < tm.mesh.cellCount(); ++c)
        tetVolumes[static_cast<std::size_t>(tm.mesh.cellRegions[c])] += std::abs(cellVolume(tm.mesh, c));
    double worstVolume = 0.0;
    for (std::size_t r = 0; r < tm.regionCount(); ++r) {
        const double v = meshVolume(m.bodies[r].mesh);
        EXPECT_NEAR(v, tetVolumes[r], kShellVsCellSumRelTol * tetVolumes[r]) << tm.regionNames[r];
        worstVolume = std::max(worstVolume, std::abs(v - tetVolumes[r]) / tetVolumes[r]);
    }
    std::printf("  [%s] body volumes vs summed tetrahedra: worst relative error %.3g\n", label, worstVolume);

    auto cls = Classifier::build(m);
    ASSERT_TRUE(cls.ok());
    const double tol = (*cls)->tolerance();
    const TetOracle oracle(tm, m);

    // Random points in the model's box, grown by 2 m so that some lie outside every body.
    const Aabb box = m.bounds();
    std::mt19937_64 rng(20261123);
    std::uniform_real_distribution<double> ux(box.min.x - 2, box.max.x + 2), uy(box.min.y - 2, box.max.y + 2),
        uz(box.min.z - 2, box.max.z + 2);
    const std::size_t n = 100000;
    std::vector<glm::dvec3> pts(n);
    for (auto& p : pts) p = {ux(rng), uy(rng), uz(rng)};
    std::vector<RecordId> ids(n);
    (*cls)->classifyBatch(pts.data(), n, ids.data(), 2);
    Tally points;
    for (std::size_t i = 0; i < n; ++i) points.add(ids[i] == oracle(pts[i]), m, pts[i], tol);
    report(std::string(label) + " classify vs oracle, random points", points, tol);
    EXPECT_GE(points.percent(), 99.99);
    EXPECT_EQ(points.farDisagree, 0u);

    // Section ID buffers: planes across the layers, through the pinch edge (horizontal at
    // mid-height of the lens: its two cubes' squares touch at a corner), through the point
    // touch, and oblique. Pixel centres vs oracle, and vs classify.
    auto index = buildSectionIndex(m);
    ASSERT_TRUE(index.ok());
    const double a = std::floor(options.nz / 3.0) * options.cell;  // lens base height
    const glm::dvec3 o = options.origin;
    std::vector<Plane> planes = {
        horizontalPlane(o.z + a + 0.5 * options.cell),                     // across the pinch edge
        horizontalPlane(o.z + a + 1.0 * options.cell + 0.013),             // 13 mm above the point touch
        makePlane(1, 0, 0, -(o.x + 35.3)).value(),                         // vertical, across the lens
        makePlane(0, 1, 0, -(o.y + 41.7)).value(),                         // vertical, through the point touch
        makePlane(1, -1, 0.05, -(o.x - o.y) - 0.05 * (o.z + 25)).value(),  // near the pinch edge's diagonal
        makePlane(0.3, 0.5, 0.81, -(0.3 * o.x + 0.5 * o.y + 0.81 * o.z) - 60).value(),  // oblique
    };
    Tally pixels, pixelsVsClassify;
    const int W = 256, H = 256;
    for (const Plane& plane : planes) {
        auto s = computeSection(*index.value(), plane);
        ASSERT_TRUE(s.ok()) << s.error().message;
        for (const BodySection& b : s->bodies) EXPECT_EQ(b.openChains, 0u) << m.bodies[b.part].name;
        const FrameRect rect = fitFrame(s.value(), W, H, 0.05);
        RasterOptions ro;
        ro.colour = false;
        auto img = rasterizeSection(*index.value(), s.value(), rect, W, H, ro);
        ASSERT_TRUE(img.ok());
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i) {
                const glm::dvec3 p = img->frame.pixelCentreWorld(i, j);
                const RecordId id = img->ids[std::size_t(j) * W + std::size_t(i)];
                const RecordId truth = oracle(p);
                pixels.add(id == truth, m, p, tol);
                pixelsVsClassify.add(id == (*cls)->classify(p), m, p, tol);
            }
    }
    report(std::string(label) + " section IDs vs oracle, pixel centres", pixels, tol);
    report(std::string(label) + " section IDs vs classify", pixelsVsClassify, tol);
    EXPECT_GE(pixels.percent(), 99.99);
    EXPECT_GE(pixelsVsClassify.percent(), 99.99);
    EXPECT_EQ(pixels.farDisagree, 0u);
    EXPECT_EQ(pixelsVsClassify.farDisagree, 0u);
}

}  // namespace

TEST(TetOracle, PinchOutsSharedVertices) {
    TetModelOptions o;
    checkModel(o, "shared");
}

TEST(TetOracle, PinchOutsInvertedCellsFarFromOrigin) {
    // Half the tetrahedra inverted (as some exporters write), at Gauss-Kruger coordinates.
    TetModelOptions o;
    o.invertOdd = true;
    o.origin = {35500000.0, 3388000.0, -500.0};
    checkModel(o, "inverted, GK");
}

TEST(TetOracle, CentimetreOverlapsAndGaps) {
    TetModelOptions o;
    o.overlap = 0.02;  // neighbours overlap or part by up to 4 cm
    checkModel(o, "overlap/gap 4 cm");
}
