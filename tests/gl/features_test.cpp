// Vertical exaggeration, background and fault traces of the slicing pass
// (renderer/slice_renderer.hpp), each against an independent expectation: the Embree oracle
// for ids under exaggeration, the request's background where no geology is drawn, and the
// analytic fault/plane intersection for traces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gl_test_util.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/slice_renderer.hpp"
#include "section/rays/classify.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

constexpr int kW = 192, kH = 128;
// Metres: a round trip through the exaggeration of a point under 200 m: a few double steps.
constexpr double kSmallRoundTripM = 1e-12;
// |a normalised plane normal| - 1: a few double steps.
constexpr double kUnitNormalTol = 1e-12;
// Metres: a display-space plane equation at points 700 m away, display z up to 3x: rounding.
constexpr double kPlaneEquationM = 1e-9;
// Pixels: a column's height at two exaggerations: +-1 px at each end of either column.
constexpr double kColumnEndsPx = 3.0;

struct Scene {
    std::unique_ptr<GlContext> ctx;
    Model model;
    std::unique_ptr<GpuModel> gpu;
    std::unique_ptr<SliceRenderer> renderer;
    bool ok = false;
    explicit Scene(std::size_t triangles) {
        ctx = makeContext();
        if (!ctx) return;
        model = syntheticModel(triangles, OreVariant::Nested, 5);
        auto g = GpuModel::upload(*ctx, model);
        EXPECT_TRUE(g.ok()) << g.error().message;
        if (!g.ok()) return;
        gpu = std::move(g).value();
        auto r = SliceRenderer::create(*ctx);
        EXPECT_TRUE(r.ok()) << r.error().message;
        if (!r.ok()) return;
        renderer = std::move(r).value();
        ok = true;
    }
};

// A profile request of a vertical plane through the model's centre, seen in display space.
SliceRequest profileRequest(const Model& m, double exaggeration) {
    const glm::dvec3 c = m.bounds().centre();
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.15, 1.0, 0.0));
    const WorldPlane plane(n.x, n.y, n.z, -glm::dot(n, c));
    SliceRequest req;
    req.width = kW;
    req.height = kH;
    req.planes = {plane};
    req.exaggeration.factor = exaggeration;
    req.exaggeration.pivotZ = c.z;
    const VerticalExaggeration& ve = req.exaggeration;
    req.view = profileAround(ve.planeToDisplay(plane), ve.boundsToDisplay(m.bounds()), kW, kH);
    return req;
}

}  // namespace

TEST(VerticalExaggeration, MapsPointsPlanesAndBoundsConsistently) {
    VerticalExaggeration ve{3.0, 100.0};
    const glm::dvec3 w(10.0, 20.0, 150.0);
    const glm::dvec3 d = ve.toDisplay(w);
    EXPECT_DOUBLE_EQ(d.z, 250.0);  // 100 + 3 * 50
    EXPECT_NEAR(glm::length(ve.toWorld(d) - w), 0.0, kSmallRoundTripM);
    // A point on a dipping plane stays on the plane's display image.
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.4, 0.8));
    const WorldPlane p(n.x, n.y, n.z, -glm::dot(n, w));
    const WorldPlane q = ve.planeToDisplay(p);
    EXPECT_NEAR(glm::length(glm::dvec3(q)), 1.0, kUnitNormalTol);
    for (glm::dvec3 t : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)}) {
        const glm::dvec3 along = glm::normalize(t - glm::dot(t, n) * n);
        const glm::dvec3 onPlane = w + 700.0 * along;
        EXPECT_NEAR(glm::dot(glm::dvec3(q), ve.toDisplay(onPlane)) + q.w, 0.0, kPlaneEquationM);
    }
    EXPECT_FALSE(checkExaggeration({0.0, 0.0}).ok());
    EXPECT_FALSE(checkExaggeration({std::nan(""), 0.0}).ok());
    EXPECT_FALSE(checkExaggeration({2.0, INFINITY}).ok());
    EXPECT_FALSE(checkExaggeration({kMaxExaggeration * 2, 0.0}).ok());
    EXPECT_TRUE(checkExaggeration({2.5, -300.0}).ok());
}

// Ids keep their meaning: the exaggerated profile's pixel (c, r) shows the body at
// toWorld(display point of that pixel). Same tolerance and neighbourhood rule as
// tests/gl/slice_test.cpp: >= 99.9% of pixels whose 3x3 oracle neighbourhood is one body.
TEST(VerticalExaggeration, ProfileIdsMatchTheOracleAtTrueWorldPoints) {
    Scene s(20000);
    ASSERT_TRUE(s.ok);
    auto classifier = Classifier::build(s.model);
    ASSERT_TRUE(classifier.ok()) << classifier.error().message;
    for (double f : {1.0, 2.5, 0.5}) {
        SliceRequest req = profileRequest(s.model, f);
        req.readColour = false;
        auto img = s.renderer->render(*s.gpu, req);
        ASSERT_TRUE(img.ok()) << img.error().message;
        const ProfileCamera& view = std::get<ProfileCamera>(req.view);
        std::vector<glm::dvec3> pts(std::size_t(kW) * kH);
        for (int r = 0; r < kH; ++r)
            for (int c = 0; c < kW; ++c)
                pts[std::size_t(r) * kW + std::size_t(c)] =
                    req.exaggeration.toWorld(pixelRay(view, kW, kH, c + 0.5, r + 0.5).origin);
        std::vector<RecordId> oracle(pts.size());
        (*classifier)->classifyBatch(pts.data(), pts.size(), oracle.data(), 2);
        std::size_t compared = 0, agree = 0;
        for (int r = 1; r + 1 < kH; ++r)
            for (int c = 1; c + 1 < kW; ++c) {
                const RecordId id = oracle[std::size_t(r) * kW + std::size_t(c)];
                if (id == kNoRecord) continue;
                bool uniform = true;
                for (int dr = -1; dr <= 1; ++dr)
                    for (int dc = -1; dc <= 1; ++dc)
                        uniform = uniform && oracle[std::size_t(r + dr) * kW + std::size_t(c + dc)] == id;
                if (!uniform) continue;
                ++compared;
                agree += img->idAt(c, r) == id;
            }
        std::printf("[ exagg    ] factor %.1f: %zu/%zu agree\n", f, agree, compared);
        EXPECT_GT(compared, 2000u);
        EXPECT_GE(double(agree), 0.999 * double(compared)) << "factor " << f;
    }
}

TEST(VerticalExaggeration, StretchesThePictureVertically) {
    Scene s(5000);
    ASSERT_TRUE(s.ok);
    // The same display frame for both factors: the section's vertical extent in pixels
    // grows with the factor (the frame is fitted to factor 1 with room above and below).
    SliceRequest one = profileRequest(s.model, 1.0);
    ProfileCamera frame = std::get<ProfileCamera>(one.view);
    const double vc = 0.5 * (frame.rect.v0 + frame.rect.v1), vh = frame.rect.v1 - frame.rect.v0;
    frame.rect.v0 = vc - 1.5 * vh, frame.rect.v1 = vc + 1.5 * vh;
    auto rows = [&](double f) {
        SliceRequest req = profileRequest(s.model, f);
        ProfileCamera v = frame;
        v.plane = std::get<ProfileCamera>(req.view).plane;  // vertical plane: unchanged by f
        req.view = v;
        auto img = s.renderer->render(*s.gpu, req);
        EXPECT_TRUE(img.ok());
        int top = kH, bottom = -1;
        for (int r = 0; r < kH; ++r)
            if (img->idAt(kW / 2, r) != kNoRecord) top = std::min(top, r), bottom = std::max(bottom, r);
        return bottom - top + 1;
    };
    const int r1 = rows(1.0), r2 = rows(2.0);
    std::printf("[ exagg    ] column height %d px at factor 1, %d px at factor 2\n", r1, r2);
    ASSERT_GT(r1, 10);
    EXPECT_NEAR(double(r2), 2.0 * double(r1), kColumnEndsPx);  // +-1 px at each end of either column
}

TEST(SliceRequestErrors, BadExaggerationAndTraceWidthAreErrors) {
    Scene s(2000);
    ASSERT_TRUE(s.ok);
    SliceRequest req = profileRequest(s.model, 1.0);
    req.exaggeration.factor = -1.0;
    auto img = s.renderer->render(*s.gpu, req);
    ASSERT_FALSE(img.ok());
    EXPECT_EQ(img.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(img.error().message.find("exaggeration"), std::string::npos);
    req.exaggeration.factor = 1.0;
    req.traceWidth = std::nanf("");
    img = s.renderer->render(*s.gpu, req);
    ASSERT_FALSE(img.ok());
    EXPECT_NE(img.error().message.find("trace width"), std::string::npos);
}

TEST(Background, ColourAndTransparentFillEveryEmptyPixelExactly) {
    Scene s(2000);
    ASSERT_TRUE(s.ok);
    for (Rgba8 bg : {Rgba8{0, 0, 0, 0}, Rgba8{12, 200, 99, 255}, Rgba8{255, 255, 255, 128}}) {
        SliceRequest req = profileRequest(s.model, 1.0);
        req.antiAlias = AntiAlias::None;  // FXAA blends the section's rim into the background
        req.background = bg;
        auto img = s.renderer->render(*s.gpu, req);
        ASSERT_TRUE(img.ok());
        std::size_t empty = 0, wrong = 0;
        for (int r = 0; r < kH; ++r)
            for (int c = 0; c < kW; ++c) {
                if (img->idAt(c, r) != kNoRecord) continue;
                ++empty;
                const std::uint8_t* p = &img->rgba[(std::size_t(r) * kW + std::size_t(c)) * 4];
                wrong += p[0] != bg.r || p[1] != bg.g || p[2] != bg.b || p[3] != bg.a;
            }
        EXPECT_GT(empty, 500u);  // the profile frame has a margin and the terrain is not flat
        EXPECT_EQ(wrong, 0u);
    }
}

// The synthetic model's faults cross a north-facing vertical plane through the centre.
// Traces: (1) never change ids; (2) change colour only near the analytic intersection of
// the fault triangles with the plane (within 1.5 px of a projected segment); (3) cover it.
TEST(FaultTraces, DrawnOnTheCutInColourOnly) {
    Scene s(20000);
    ASSERT_TRUE(s.ok);
    ASSERT_FALSE(s.gpu->surfaceTriangles().empty()) << "the synthetic model should have faults";
    SliceRequest req = profileRequest(s.model, 1.0);
    req.antiAlias = AntiAlias::None;  // exact colours
    req.drawTraces = false;
    auto plain = s.renderer->render(*s.gpu, req);
    req.drawTraces = true;
    req.traceColour = Rgba8{255, 0, 255, 255};
    auto traced = s.renderer->render(*s.gpu, req);
    ASSERT_TRUE(plain.ok() && traced.ok());
    EXPECT_GT(traced->traceSegments, 10u);
    EXPECT_EQ(plain->ids, traced->ids);

    // Analytic traces: each surface triangle cut by the plane, projected to pixels.
    const WorldPlane plane = normalizePlane(req.planes[0]).value();
    const glm::dvec4 local = planeToLocal(plane, s.model.origin);
    const auto& tris = s.gpu->surfaceTriangles();
    std::vector<std::pair<glm::dvec2, glm::dvec2>> segs;
    auto toPixel = [&](const glm::dvec3& q) {
        const glm::dvec4 clip = traced->viewProj * glm::dvec4(q, 1.0);
        return glm::dvec2((clip.x / clip.w * 0.5 + 0.5) * kW, (0.5 - clip.y / clip.w * 0.5) * kH);
    };
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
        glm::dvec3 v[3] = {tris[t], tris[t + 1], tris[t + 2]};
        double d[3];
        for (int k = 0; k < 3; ++k) d[k] = glm::dot(glm::dvec3(local), v[k]) + local.w;
        std::vector<glm::dvec3> ends;
        for (int e = 0; e < 3; ++e) {
            const int a = e, b = (e + 1) % 3;
            if ((d[a] >= 0) != (d[b] >= 0)) ends.push_back(v[a] + (v[b] - v[a]) * (d[a] / (d[a] - d[b])));
        }
        if (ends.size() == 2) segs.push_back({toPixel(ends[0]), toPixel(ends[1])});
    }
    ASSERT_FALSE(segs.empty());
    auto distToTrace = [&](glm::dvec2 p) {
        double best = 1e30;
        for (const auto& [a, b] : segs) {
            const glm::dvec2 ab = b - a;
            const double t = glm::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-12), 0.0, 1.0);
            best = std::min(best, glm::length(p - (a + t * ab)));
        }
        return best;
    };
    std::size_t changed = 0, farChanged = 0;
    for (int r = 0; r < kH; ++r)
        for (int c = 0; c < kW; ++c) {
            const std::size_t i = (std::size_t(r) * kW + std::size_t(c)) * 4;
            if (std::equal(&plain->rgba[i], &plain->rgba[i] + 4, &traced->rgba[i])) continue;
            ++changed;
            const std::uint8_t* p = &traced->rgba[i];
            EXPECT_TRUE(p[0] == 255 && p[1] == 0 && p[2] == 255) << "a changed pixel has the trace colour";
            farChanged += distToTrace({c + 0.5, r + 0.5}) > 1.5;
        }
    // Pixels along the traces that lie on a cut face (id != 0) and away from its rim should
    // mostly be drawn: sample each segment at 1 px steps.
    std::size_t samples = 0, hit = 0;
    for (const auto& [a, b] : segs) {
        const int steps = std::max(1, int(glm::length(b - a)));
        for (int k = 0; k <= steps; ++k) {
            const glm::dvec2 p = a + (b - a) * (double(k) / steps);
            const int c = int(p.x), r = int(p.y);
            if (c < 2 || r < 2 || c >= kW - 2 || r >= kH - 2) continue;
            bool inside = true;
            for (int dr = -2; dr <= 2; ++dr)
                for (int dc = -2; dc <= 2; ++dc) inside = inside && traced->idAt(c + dc, r + dr) != kNoRecord;
            if (!inside) continue;
            ++samples;
            bool near = false;
            for (int dr = -1; dr <= 1; ++dr)
                for (int dc = -1; dc <= 1; ++dc) {
                    const std::uint8_t* q = &traced->rgba[(std::size_t(r + dr) * kW + std::size_t(c + dc)) * 4];
                    near = near || (q[0] == 255 && q[1] == 0 && q[2] == 255);
                }
            hit += near;
        }
    }
    std::printf("[ traces   ] %zu segments, %zu changed pixels (%zu farther than 1.5 px), %zu/%zu samples hit\n",
                traced->traceSegments, changed, farChanged, hit, samples);
    EXPECT_GT(changed, 40u);
    EXPECT_EQ(farChanged, 0u);
    EXPECT_GT(samples, 40u);
    EXPECT_GE(double(hit), 0.98 * double(samples));
}

namespace {

// True when the 3x3 neighbourhood of (c, r) holds more than one id (an id edge).
bool nearIdEdge(const SliceImage& img, int c, int r) {
    const RecordId id = img.idAt(c, r);
    for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
            const int cc = std::clamp(c + dc, 0, img.width - 1), rr = std::clamp(r + dr, 0, img.height - 1);
            if (img.idAt(cc, rr) != id) return true;
        }
    return false;
}

}  // namespace

// FXAA (the llvmpipe default): ids untouched; a pixel whose 3x3 neighbourhood has one
// colour is never changed (FXAA acts on local contrast only); most changed pixels are next
// to an id edge (the rest are on the lit terrain seen above the cut), and there are many.
TEST(AntiAliasing, FxaaChangesColourOnlyAtEdgesAndNeverIds) {
    Scene s(20000);
    ASSERT_TRUE(s.ok);
    SliceRequest req = profileRequest(s.model, 1.0);
    req.drawTraces = false;
    req.antiAlias = AntiAlias::None;
    auto plain = s.renderer->render(*s.gpu, req);
    req.antiAlias = AntiAlias::Fxaa;
    auto fxaa = s.renderer->render(*s.gpu, req);
    ASSERT_TRUE(plain.ok() && fxaa.ok());
    EXPECT_EQ(fxaa->aaUsed, AntiAlias::Fxaa);
    EXPECT_EQ(plain->ids, fxaa->ids);
    auto pixel = [&](const SliceImage& img, int c, int r) {
        c = std::clamp(c, 0, kW - 1), r = std::clamp(r, 0, kH - 1);
        return &img.rgba[(std::size_t(r) * kW + std::size_t(c)) * 4];
    };
    std::size_t changed = 0, flatChanged = 0, atIdEdges = 0;
    for (int r = 0; r < kH; ++r)
        for (int c = 0; c < kW; ++c) {
            if (std::equal(pixel(*plain, c, r), pixel(*plain, c, r) + 4, pixel(*fxaa, c, r))) continue;
            ++changed;
            bool flat = true;
            for (int dr = -1; dr <= 1; ++dr)
                for (int dc = -1; dc <= 1; ++dc)
                    flat =
                        flat && std::equal(pixel(*plain, c, r), pixel(*plain, c, r) + 4, pixel(*plain, c + dc, r + dr));
            flatChanged += flat;
            atIdEdges += nearIdEdge(*plain, c, r);
        }
    std::printf("[ fxaa     ] %zu pixels changed, %zu of them at id edges, %zu in flat neighbourhoods\n", changed,
                atIdEdges, flatChanged);
    EXPECT_GT(changed, 100u);
    EXPECT_EQ(flatChanged, 0u);
    EXPECT_GE(double(atIdEdges), 0.6 * double(changed));
}

// MSAA, forced on llvmpipe (Auto would pick it on a GPU): every id is one that the
// single-sample image has within a pixel (a sample's id, never a blend), nearly all ids
// equal, and colour at edges takes values between the flat colours.
TEST(AntiAliasing, MsaaIdsAreSampledNeverBlended) {
    Scene s(20000);
    ASSERT_TRUE(s.ok);
    SliceRequest req = profileRequest(s.model, 1.0);
    req.drawTraces = false;
    req.antiAlias = AntiAlias::None;
    auto plain = s.renderer->render(*s.gpu, req);
    req.antiAlias = AntiAlias::Msaa;
    auto msaa = s.renderer->render(*s.gpu, req);
    ASSERT_TRUE(plain.ok());
    ASSERT_TRUE(msaa.ok()) << msaa.error().message;
    if (msaa->aaUsed != AntiAlias::Msaa) GTEST_SKIP() << "no multisampling on " << s.ctx->info().renderer;
    EXPECT_GE(msaa->samples, 2);
    std::size_t same = 0, foreign = 0, blended = 0;
    for (int r = 0; r < kH; ++r)
        for (int c = 0; c < kW; ++c) {
            const RecordId id = msaa->idAt(c, r);
            same += id == plain->idAt(c, r);
            bool found = false;
            for (int dr = -1; dr <= 1; ++dr)
                for (int dc = -1; dc <= 1; ++dc) {
                    const int cc = std::clamp(c + dc, 0, kW - 1), rr = std::clamp(r + dr, 0, kH - 1);
                    found = found || plain->idAt(cc, rr) == id;
                }
            foreign += !found;
            const std::size_t i = (std::size_t(r) * kW + std::size_t(c)) * 4;
            blended += nearIdEdge(*plain, c, r) && !std::equal(&plain->rgba[i], &plain->rgba[i] + 4, &msaa->rgba[i]);
        }
    std::printf("[ msaa     ] %d samples: %zu/%d ids equal, %zu foreign, %zu edge pixels blended\n", msaa->samples,
                same, kW * kH, foreign, blended);
    EXPECT_EQ(foreign, 0u);
    EXPECT_GE(double(same), 0.97 * kW * kH);
    EXPECT_GT(blended, 100u);
}

// Clusters (renderer/gpu_model.hpp): full detail is split exactly into clusters, every
// simplified level is a smaller triangle list with a non-decreasing error, and skipping clusters on the removed side or
// outside the view changes no pixel: the same frames from a one-cell upload are identical.
TEST(Clusters, PartitionTheMeshAndCullingIsExact) {
    auto ctx = makeContext();
    ASSERT_TRUE(ctx);
    Model model = syntheticModel(20000, OreVariant::Nested, 9);
    GpuModel::UploadOptions many;
    many.trianglesPerCell = 256;
    many.maxCells = 4096;
    many.lod = GpuModel::UploadOptions::Lod::On;
    GpuModel::UploadOptions one;
    one.maxCells = 1;
    one.lod = GpuModel::UploadOptions::Lod::Off;
    auto a = GpuModel::upload(*ctx, model, many);
    auto b = GpuModel::upload(*ctx, model, one);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_GT((*a)->cellBounds().size(), 40u);
    EXPECT_EQ((*b)->cellBounds().size(), 1u);
    EXPECT_TRUE((*a)->hasLod());
    std::size_t simplifiedClusters = 0;
    const std::vector<Part*> partsInOrder = [&] {
        std::vector<Part*> v;
        for (Part& p : model.bodies) v.push_back(&p);
        for (Part& p : model.surfaces) v.push_back(&p);
        return v;
    }();
    ASSERT_EQ((*a)->parts().size(), partsInOrder.size());
    for (std::size_t k = 0; k < partsInOrder.size(); ++k) {
        const GpuModel::DrawPart& p = (*a)->parts()[k];
        std::size_t next = p.firstIndex;
        for (const auto& c : p.clusters) {
            EXPECT_EQ(c.first[0], next);  // level 0 of the clusters tiles the part's range
            next += std::size_t(c.count[0]);
            EXPECT_EQ(c.count[0] % 3, 0);
            for (int l = 1; l < c.levels; ++l) {
                ++simplifiedClusters;
                EXPECT_EQ(c.count[l] % 3, 0);
                EXPECT_LT(c.count[l], c.count[l - 1]);
                EXPECT_GE(c.error[l], c.error[l - 1]);
            }
        }
        EXPECT_EQ(next, p.firstIndex + std::size_t(p.indexCount));
        EXPECT_EQ(std::size_t(p.indexCount), partsInOrder[k]->mesh.indices.size());
    }
    EXPECT_GT(simplifiedClusters, 10u);

    auto renderer = SliceRenderer::create(*ctx);
    ASSERT_TRUE(renderer.ok());
    SliceRequest req = profileRequest(model, 1.0);
    req.lod = SliceRequest::Lod::Off;
    req.antiAlias = AntiAlias::None;
    const Aabb bb = model.bounds();
    const glm::dvec3 c = bb.centre();
    for (int view = 0; view < 3; ++view) {
        if (view == 1) req.view = PerspectiveCamera{c + glm::dvec3(-3000, -9000, 4000), c, {0, 0, 1}, 35.0};
        if (view == 2)  // zoomed in: most cells are outside the view
            req.view = PerspectiveCamera{c + glm::dvec3(-300, -1500, 300), c, {0, 0, 1}, 20.0};
        auto ia = (*renderer)->render(**a, req);
        auto ib = (*renderer)->render(**b, req);
        ASSERT_TRUE(ia.ok() && ib.ok());
        std::printf("[ clusters ] view %d: %zu clusters skipped, %zu vs %zu triangles\n", view, ia->clustersSkipped,
                    ia->trianglesDrawn, ib->trianglesDrawn);
        EXPECT_GT(ia->clustersSkipped, 0u);
        EXPECT_LT(ia->trianglesDrawn, ib->trianglesDrawn);
        EXPECT_EQ(ia->ids, ib->ids) << "view " << view;
        EXPECT_EQ(ia->rgba, ib->rgba) << "view " << view;
    }
    // Level of detail on the same 3D view: fewer triangles, ids nearly all equal.
    req.view = PerspectiveCamera{c + glm::dvec3(-3000, -9000, 4000), c, {0, 0, 1}, 35.0};
    auto full = (*renderer)->render(**a, req);
    req.lod = SliceRequest::Lod::On;
    auto lod = (*renderer)->render(**a, req);
    ASSERT_TRUE(full.ok() && lod.ok());
    EXPECT_TRUE(lod->lodUsed);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < full->ids.size(); ++i) differ += full->ids[i] != lod->ids[i];
    std::printf("[ lod      ] %zu vs %zu triangles, %zu of %zu id pixels differ\n", lod->trianglesDrawn,
                full->trianglesDrawn, differ, full->ids.size());
    EXPECT_LT(lod->trianglesDrawn, full->trianglesDrawn);
    EXPECT_LE(double(differ), 0.005 * double(full->ids.size()));
}
