// The slicing pass against the exact oracle (section/rays/classify.hpp): for an orthographic
// profile of a plane, the ID at each pixel centre must equal Classifier::classify(world point
// of that pixel on the plane). Compared on pixels whose oracle 3x3 neighbourhood is one
// body: within a pixel of a boundary the rasteriser's and the oracle's float32 rounding may
// fall either side, and the pixel footprint straddles two bodies anyway. Tolerance: >= 99.9%
// of those pixels agree. A failing comparison writes the actual and expected ID images
// (PGM) into the working directory.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>

#include "gl_test_util.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/slice_renderer.hpp"
#include "section/rays/classify.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

constexpr std::size_t kTriangles = 50000;
constexpr int kSize = 256;
constexpr double kMinAgreement = 0.999;

struct Agreement {
    std::size_t compared = 0, agree = 0, oracleBodies = 0;
    double fraction() const { return compared ? double(agree) / double(compared) : 0.0; }
};

void writePgm(const std::string& path, const std::vector<RecordId>& ids, int w, int h) {
    std::ofstream f(path, std::ios::binary);
    f << "P5\n" << w << " " << h << "\n255\n";
    for (RecordId id : ids) f.put(char(std::uint8_t(id * 23u)));
}

// World points of the pixel centres of a profile image, row 0 at the top.
std::vector<RecordId> oracleProfile(const Classifier& c, const ProfileCamera& view, int w, int h) {
    std::vector<glm::dvec3> pts(std::size_t(w) * std::size_t(h));
    for (int r = 0; r < h; ++r)
        for (int col = 0; col < w; ++col)
            pts[std::size_t(r) * std::size_t(w) + std::size_t(col)] = pixelRay(view, w, h, col + 0.5, r + 0.5).origin;
    std::vector<RecordId> ids(pts.size());
    c.classifyBatch(pts.data(), pts.size(), ids.data(), 2);
    return ids;
}

// `valid` (optional) masks pixels that have a defined oracle value.
Agreement compare(const std::vector<RecordId>& actual, const std::vector<RecordId>& oracle, int w, int h,
                  const std::vector<char>* valid = nullptr) {
    Agreement a;
    for (int r = 1; r + 1 < h; ++r)
        for (int col = 1; col + 1 < w; ++col) {
            const std::size_t i = std::size_t(r) * std::size_t(w) + std::size_t(col);
            const RecordId id = oracle[i];
            if (id == kNoRecord) continue;
            bool uniform = true;
            for (int dr = -1; dr <= 1 && uniform; ++dr)
                for (int dc = -1; dc <= 1 && uniform; ++dc) {
                    const std::size_t j = std::size_t(r + dr) * std::size_t(w) + std::size_t(col + dc);
                    uniform = oracle[j] == id && (!valid || (*valid)[j]);
                }
            if (!uniform) continue;
            ++a.compared;
            a.agree += actual[i] == id ? 1 : 0;
            if (actual[i] != id && std::getenv("GEOSLICE_GL_VERBOSE"))
                std::printf("  mismatch at (%d, %d): rendered %u, oracle %u\n", col, r, actual[i], id);
        }
    for (RecordId id : oracle) a.oracleBodies += id != kNoRecord ? 1 : 0;
    return a;
}

WorldPlane randomPlane(std::mt19937_64& rng, const Aabb& b) {
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0.2, 0.8);
    glm::dvec3 n;
    do n = glm::dvec3(g(rng), g(rng), g(rng));
    while (glm::length(n) < 1e-3);
    n = glm::normalize(n);
    const glm::dvec3 p = b.min + glm::dvec3(u(rng), u(rng), u(rng)) * b.size();
    return {n.x, n.y, n.z, -glm::dot(n, p)};
}

class SliceOracle : public ::testing::Test {
protected:
    void load(OreVariant ore, std::uint64_t seed, const char* crs = nullptr, std::size_t triangles = kTriangles) {
        ctx = makeContext();
        ASSERT_TRUE(ctx);
        std::printf("[ gl       ] %s\n", ctx->info().describe().c_str());
        model = syntheticModel(triangles, ore, seed, crs);
        auto c = Classifier::build(model);
        ASSERT_TRUE(c.ok()) << c.error().message;
        classifier = std::move(c).value();
        auto g = GpuModel::upload(*ctx, model);
        ASSERT_TRUE(g.ok()) << g.error().message;
        gpu = std::move(g).value();
        auto r = SliceRenderer::create(*ctx);
        ASSERT_TRUE(r.ok()) << r.error().message;
        renderer = std::move(r).value();
    }

    // Renders the profile of `plane` framed on `frame` and compares with the oracle.
    Agreement profile(const WorldPlane& plane, const Aabb& frame, ClipMethod clip, const std::string& tag) {
        SliceRequest req;
        req.width = req.height = kSize;
        req.planes = {plane};
        req.clip = clip;
        const ProfileCamera view = profileAround(plane, frame, kSize, kSize);
        req.view = view;
        req.readColour = false;
        auto img = renderer->render(*gpu, req);
        EXPECT_TRUE(img.ok()) << img.error().message;
        if (!img.ok()) return {};
        const std::vector<RecordId> oracle = oracleProfile(*classifier, view, kSize, kSize);
        Agreement a = compare(img->ids, oracle, kSize, kSize);
        std::printf("[ %-8s ] %s plane (%.3f %.3f %.3f %.1f): %zu/%zu agree (%.4f%%), %.1f ms draw, %.2f ms read\n",
                    tag.c_str(), clipMethodName(clip), plane.x, plane.y, plane.z, plane.w, a.agree, a.compared,
                    100.0 * a.fraction(), img->drawMs, img->readbackMs);
        if (a.fraction() < kMinAgreement) {
            writePgm("gl_fail_" + tag + "_actual.pgm", img->ids, kSize, kSize);
            writePgm("gl_fail_" + tag + "_oracle.pgm", oracle, kSize, kSize);
        }
        return a;
    }

    // The oracle of a perspective view from the removed side: where the ray through a pixel
    // centre crosses the plane (world, double), the record there; invalid where the ray does
    // not reach the plane from the removed side.
    std::vector<RecordId> perspectiveOracle(const glm::dmat4& viewProj, const WorldPlane& plane, int side,
                                            std::vector<char>& valid) const {
        const glm::dvec3 n(plane);
        const glm::dmat4 inv = glm::inverse(viewProj);
        std::vector<glm::dvec3> pts(std::size_t(side) * std::size_t(side));
        valid.assign(pts.size(), 0);
        for (int r = 0; r < side; ++r)
            for (int c = 0; c < side; ++c) {
                const double x = 2.0 * (c + 0.5) / side - 1.0, y = 1.0 - 2.0 * (r + 0.5) / side;
                glm::dvec4 a = inv * glm::dvec4(x, y, -1.0, 1.0), e = inv * glm::dvec4(x, y, 1.0, 1.0);
                const glm::dvec3 p0 = glm::dvec3(a) / a.w + model.origin, p1 = glm::dvec3(e) / e.w + model.origin;
                const double s0 = glm::dot(n, p0) + plane.w, s1 = glm::dot(n, p1) + plane.w;
                const std::size_t i = std::size_t(r) * std::size_t(side) + std::size_t(c);
                if (s0 >= 0.0 || s1 <= 0.0) continue;
                pts[i] = p0 + (p1 - p0) * (s0 / (s0 - s1));
                valid[i] = 1;
            }
        std::vector<RecordId> oracle(pts.size());
        classifier->classifyBatch(pts.data(), pts.size(), oracle.data(), 2);
        for (std::size_t i = 0; i < oracle.size(); ++i)
            if (!valid[i]) oracle[i] = kNoRecord;
        return oracle;
    }

    const Part* lens() const {
        for (const Part& p : model.bodies)
            if (p.report.parent >= 0 || p.name.find("orebody") != std::string::npos) return &p;
        return nullptr;
    }

    std::unique_ptr<GlContext> ctx;
    Model model;
    std::unique_ptr<Classifier> classifier;
    std::unique_ptr<GpuModel> gpu;
    std::unique_ptr<SliceRenderer> renderer;
};

}  // namespace

TEST_F(SliceOracle, RandomPlanesMatchTheOracle) {
    load(OreVariant::Nested, 7);
    ASSERT_TRUE(gpu);
    std::mt19937_64 rng(20240611);
    for (int i = 0; i < 6; ++i) {
        const WorldPlane plane = randomPlane(rng, model.bounds());
        const ClipMethod clip = i % 2 ? ClipMethod::Discard : ClipMethod::ClipDistance;
        Agreement a = profile(plane, model.bounds(), clip, "random" + std::to_string(i));
        if (a.compared < 2000) continue;  // the plane barely touches the model
        EXPECT_GE(a.fraction(), kMinAgreement) << "plane " << i;
    }
}

// The paper's caps fail here: a lens inside its host without a hole. The inner body wins.
TEST_F(SliceOracle, NestedLensWins) {
    load(OreVariant::Nested, 3);
    const Part* ore = lens();
    ASSERT_NE(ore, nullptr);
    ASSERT_GE(ore->report.parent, 0) << "the nested variant's lens must have a container";
    const Aabb lb = ore->mesh.bounds();
    Aabb frame = lb;
    frame.extend(lb.centre() + 1.5 * (lb.max - lb.centre()));
    frame.extend(lb.centre() + 1.5 * (lb.min - lb.centre()));
    for (glm::dvec3 n : {glm::dvec3(0, 1, 0), glm::dvec3(0.6, -0.7, 0.2), glm::dvec3(0.1, 0.2, -0.97)}) {
        n = glm::normalize(n);
        const WorldPlane plane(n.x, n.y, n.z, -glm::dot(n, lb.centre()));
        for (ClipMethod clip : {ClipMethod::ClipDistance, ClipMethod::Discard}) {
            Agreement a = profile(plane, frame, clip, std::string("lens_") + clipMethodName(clip));
            EXPECT_GT(a.compared, 5000u);
            EXPECT_GE(a.fraction(), kMinAgreement);
        }
    }
}

TEST_F(SliceOracle, PartitionLensMatches) {
    load(OreVariant::Partition, 3);
    const Part* ore = lens();
    ASSERT_NE(ore, nullptr);
    const Aabb lb = ore->mesh.bounds();
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, 0.9, 0.1));
    const WorldPlane plane(n.x, n.y, n.z, -glm::dot(n, lb.centre()));
    Agreement a = profile(plane, lb, ClipMethod::ClipDistance, "partition");
    EXPECT_GT(a.compared, 5000u);
    EXPECT_GE(a.fraction(), kMinAgreement);
}

// A perspective view from the removed side: where the pixel's ray crosses the plane inside a
// body, the ID is the oracle's record of that crossing point.
TEST_F(SliceOracle, PerspectiveCutMatchesTheOracle) {
    load(OreVariant::Nested, 11);
    const Aabb b = model.bounds();
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, 1.0, 0.15));
    const glm::dvec3 centre = b.centre();
    const WorldPlane plane(n.x, n.y, n.z, -glm::dot(n, centre));
    PerspectiveCamera pv;
    pv.target = centre;
    pv.eye = centre - n * (1.6 * glm::length(b.size())) + glm::dvec3(900.0, 0.0, 1500.0);
    pv.fovYDegrees = 35.0;
    SliceRequest req;
    req.width = req.height = kSize;
    req.planes = {plane};
    req.view = pv;
    req.lod = SliceRequest::Lod::Off;  // the exact pass; level of detail is checked below
    auto img = renderer->render(*gpu, req);
    ASSERT_TRUE(img.ok()) << img.error().message;
    std::vector<char> valid;
    const std::vector<RecordId> oracle = perspectiveOracle(img->viewProj, plane, kSize, valid);
    Agreement a = compare(img->ids, oracle, kSize, kSize, &valid);
    std::printf("[ persp    ] %zu/%zu agree (%.4f%%), %.1f ms draw\n", a.agree, a.compared, 100.0 * a.fraction(),
                img->drawMs);
    EXPECT_GT(a.compared, 5000u);
    EXPECT_GE(a.fraction(), kMinAgreement);
    // Level of detail (the llvmpipe default for 3D views): clusters the plane crosses stay
    // exact, but where a simplified thin layer lies just behind the cut its back face can
    // swap with its neighbour's. Measured 99.3% here (256 px: a pixel is ~25 m of error);
    // bound 99%.
    req.lod = SliceRequest::Lod::On;
    auto lodImg = renderer->render(*gpu, req);
    ASSERT_TRUE(lodImg.ok()) << lodImg.error().message;
    if (lodImg->lodUsed) {
        const Agreement l = compare(lodImg->ids, oracle, kSize, kSize, &valid);
        std::printf("[ persp    ] LOD: %zu/%zu agree (%.4f%%), %zu/%zu triangles\n", l.agree, l.compared,
                    100.0 * l.fraction(), lodImg->trianglesDrawn, img->trianglesDrawn);
        EXPECT_GE(l.fraction(), 0.99);
    }
    if (a.fraction() < kMinAgreement) {
        writePgm("gl_fail_persp_actual.pgm", img->ids, kSize, kSize);
        writePgm("gl_fail_persp_oracle.pgm", oracle, kSize, kSize);
    }
}

// Section 3 of issue 3 at full size: an L1 model (500k triangles), 20 random planes, each as
// an orthographic profile and as a perspective view from the removed side, alternating
// clip distance and discard. Same agreement rule as above, per image at full detail;
// images that barely show the cut (< 2000 comparable pixels) are skipped, and at least 30
// of the 40 must count. The perspective views are also drawn with level of detail (when the
// model was uploaded with it, i.e. on llvmpipe): >= 99.5% per image and >= 99.9% over all
// images (measured 99.86% worst, 99.97% overall), since a simplified thin layer just behind
// the cut can swap with its neighbour.
TEST_F(SliceOracle, L1TwentyRandomPlanesProfileAndPerspective) {
    load(OreVariant::Nested, 21, nullptr, *namedModelSize("L1"));
    ASSERT_TRUE(gpu);
    std::mt19937_64 rng(77);
    const Aabb b = model.bounds();
    int counted = 0;
    std::size_t compared = 0, agree = 0, lodCompared = 0, lodAgree = 0, lodDiffer = 0;
    for (int i = 0; i < 20; ++i) {
        const WorldPlane plane = randomPlane(rng, b);
        const ClipMethod clip = i % 2 ? ClipMethod::Discard : ClipMethod::ClipDistance;
        const Agreement ortho = profile(plane, b, clip, "L1_" + std::to_string(i));
        // Perspective: the eye on the removed side, looking at the plane point nearest the
        // model centre from 1.3 model diagonals away, a little off the normal.
        const glm::dvec3 n(plane);
        const glm::dvec3 foot = b.centre() - (glm::dot(n, b.centre()) + plane.w) * n;
        const glm::dvec3 side =
            glm::normalize(glm::cross(n, std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
        const double diag = glm::length(b.size());
        PerspectiveCamera pv;
        pv.target = foot;
        pv.eye = foot - n * (1.3 * diag) + side * (0.25 * diag);
        pv.up = std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
        pv.fovYDegrees = 40.0;
        SliceRequest req;
        req.width = req.height = kSize;
        req.planes = {plane};
        req.clip = clip;
        req.view = pv;
        req.readColour = false;
        req.lod = SliceRequest::Lod::Off;
        auto img = renderer->render(*gpu, req);
        ASSERT_TRUE(img.ok()) << img.error().message;
        std::vector<char> valid;
        const std::vector<RecordId> oracle = perspectiveOracle(img->viewProj, plane, kSize, valid);
        const Agreement persp = compare(img->ids, oracle, kSize, kSize, &valid);
        // The same view with level of detail (simplified clusters away from the cut).
        req.lod = SliceRequest::Lod::On;
        auto lodImg = renderer->render(*gpu, req);
        ASSERT_TRUE(lodImg.ok()) << lodImg.error().message;
        const Agreement lod = compare(lodImg->ids, oracle, kSize, kSize, &valid);
        std::size_t differ = 0;
        for (std::size_t k = 0; k < img->ids.size(); ++k) differ += img->ids[k] != lodImg->ids[k];
        lodCompared += lod.compared;
        lodAgree += lod.agree;
        lodDiffer += differ;
        std::printf(
            "[ L1_%-5d ] perspective: %zu/%zu agree (%.4f%%), %.1f ms draw; LOD %s: %zu/%zu agree, %zu ids "
            "differ from full detail, %zu/%zu triangles, %.1f ms draw\n",
            i, persp.agree, persp.compared, 100.0 * persp.fraction(), img->drawMs,
            lodImg->lodUsed ? "on" : "unavailable", lod.agree, lod.compared, differ, lodImg->trianglesDrawn,
            img->trianglesDrawn, lodImg->drawMs);
        if (gpu->hasLod() && lod.compared >= 2000) {
            EXPECT_GE(lod.fraction(), 0.995) << "plane " << i << " with LOD";
        }
        for (const Agreement* a : {&ortho, &persp}) {
            if (a->compared < 2000) continue;
            ++counted;
            compared += a->compared;
            agree += a->agree;
            EXPECT_GE(a->fraction(), kMinAgreement) << "plane " << i << (a == &ortho ? " profile" : " perspective");
        }
        if (persp.fraction() < kMinAgreement && persp.compared >= 2000) {
            writePgm("gl_fail_L1_persp" + std::to_string(i) + "_actual.pgm", img->ids, kSize, kSize);
            writePgm("gl_fail_L1_persp" + std::to_string(i) + "_oracle.pgm", oracle, kSize, kSize);
        }
    }
    std::printf("[ L1       ] %d images counted, %zu/%zu pixels agree (%.4f%%)\n", counted, agree, compared,
                100.0 * double(agree) / double(std::max<std::size_t>(compared, 1)));
    EXPECT_GE(counted, 30);
    std::printf(
        "[ L1 LOD   ] %zu/%zu pixels agree with the oracle (%.4f%%); %zu of %d id pixels differ from full "
        "detail\n",
        lodAgree, lodCompared, 100.0 * double(lodAgree) / double(std::max<std::size_t>(lodCompared, 1)), lodDiffer,
        20 * kSize * kSize);
    EXPECT_GE(double(lodAgree), kMinAgreement * double(lodCompared));
}
