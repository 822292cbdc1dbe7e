// Precision and limits: the same model at the origin and at Gauss-Kruger coordinates
// (EPSG:4523, eastings ~35,500,000 m, where float32 has 4 m steps) gives identical ID
// buffers, because only local coordinates (world - origin, in double) reach the GPU; and
// sizes beyond the device's limits fail with a clear error.
#include <gtest/gtest.h>

#include <random>

#include "gl_test_util.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/slice_renderer.hpp"

using namespace geoslice;
using namespace geoslice::test;

TEST(Precision, OriginAndGaussKrugerGiveIdenticalIds) {
    auto ctx = makeContext();
    ASSERT_TRUE(ctx);
    Model gk = syntheticModel(20000, OreVariant::Nested, 5, "EPSG:4523");
    ASSERT_GT(gk.origin.x, 35'000'000.0);
    // The same geometry moved to the origin. gk.origin is whole metres and every easting lies
    // within a factor 2 of it, so world - origin is exact in double (Sterbenz).
    Model near = gk;
    const glm::dvec3 shift = gk.origin;
    for (auto* list : {&near.bodies, &near.surfaces})
        for (Part& p : *list)
            for (glm::dvec3& v : p.mesh.positions) v -= shift;
    near.recentre();
    ASSERT_EQ(near.origin, glm::dvec3(0.0));

    auto gpuGk = GpuModel::upload(*ctx, gk);
    auto gpuNear = GpuModel::upload(*ctx, near);
    ASSERT_TRUE(gpuGk.ok() && gpuNear.ok());
    auto renderer = SliceRenderer::create(*ctx);
    ASSERT_TRUE(renderer.ok());
    std::mt19937_64 rng(99);
    std::normal_distribution<double> g;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3 n = glm::normalize(glm::dvec3(g(rng), g(rng), 0.3 * g(rng)));
        const glm::dvec3 pNear = near.bounds().centre() + glm::dvec3(g(rng), g(rng), g(rng)) * 200.0;
        const WorldPlane planeNear(n.x, n.y, n.z, -glm::dot(n, pNear));
        const WorldPlane planeGk(n.x, n.y, n.z, planeNear.w - glm::dot(n, shift));
        SliceRequest a, b;
        a.width = a.height = b.width = b.height = 192;
        a.readColour = b.readColour = false;
        a.planes = {planeGk};
        a.view = profileAround(planeGk, gk.bounds(), a.width, a.height);
        b.planes = {planeNear};
        b.view = profileAround(planeNear, near.bounds(), b.width, b.height);
        auto ia = (*renderer)->render(**gpuGk, a);
        auto ib = (*renderer)->render(**gpuNear, b);
        ASSERT_TRUE(ia.ok() && ib.ok());
        std::size_t differ = 0, body = 0;
        for (std::size_t k = 0; k < ia->ids.size(); ++k) {
            differ += ia->ids[k] != ib->ids[k];
            body += ia->ids[k] != kNoRecord;
        }
        EXPECT_GT(body, 1000u);
        EXPECT_EQ(differ, 0u) << "plane " << i << ": " << differ << " of " << ia->ids.size() << " pixels differ";
    }
}

TEST(Limits, SizesBeyondTheDeviceFailClearly) {
    auto ctx = makeContext();
    ASSERT_TRUE(ctx);
    auto renderer = SliceRenderer::create(*ctx);
    ASSERT_TRUE(renderer.ok());
    EXPECT_TRUE((*renderer)->checkSize(1, 1).ok());
    EXPECT_TRUE((*renderer)->checkSize(kMaxImageSide, 16).ok());
    for (auto [w, h] : {std::pair{kMaxImageSide + 1, 16}, std::pair{16, 100000}, std::pair{0, 16}, std::pair{16, -3}}) {
        Status s = (*renderer)->checkSize(w, h);
        ASSERT_FALSE(s.ok()) << w << "x" << h;
        EXPECT_EQ(s.error().code, ErrorCode::OutOfRange);
        EXPECT_NE(s.error().message.find(std::to_string(w) + "x" + std::to_string(h)), std::string::npos)
            << s.error().message;
        EXPECT_NE(s.error().message.find("8192"), std::string::npos) << s.error().message;
    }
    Model m = syntheticModel(2000);
    auto gpu = GpuModel::upload(*ctx, m);
    ASSERT_TRUE(gpu.ok());
    SliceRequest req;
    req.width = kMaxImageSide + 1;
    req.height = 8;
    auto img = (*renderer)->render(**gpu, req);
    ASSERT_FALSE(img.ok());
    EXPECT_EQ(img.error().code, ErrorCode::OutOfRange);
    req.width = 8;
    req.planes.assign(kMaxPlanes + 1, WorldPlane(0, 0, 1, 0));
    img = (*renderer)->render(**gpu, req);
    ASSERT_FALSE(img.ok());
    EXPECT_EQ(img.error().code, ErrorCode::InvalidArgument);
}

TEST(Limits, UnionWithClipDistanceFallsBackToDiscard) {
    auto ctx = makeContext();
    ASSERT_TRUE(ctx);
    auto renderer = SliceRenderer::create(*ctx);
    ASSERT_TRUE(renderer.ok());
    Model m = syntheticModel(2000);
    auto gpu = GpuModel::upload(*ctx, m);
    ASSERT_TRUE(gpu.ok());
    const glm::dvec3 c = m.bounds().centre();
    SliceRequest req;
    req.width = req.height = 32;
    req.planes = {WorldPlane(1, 0, 0, -c.x), WorldPlane(0, 1, 0, -c.y)};
    req.combine = PlaneCombine::Union;
    req.view = PerspectiveCamera{c + glm::dvec3(-5000, -5000, 3000), c, {0, 0, 1}, 40.0};
    auto img = (*renderer)->render(**gpu, req);
    ASSERT_TRUE(img.ok()) << img.error().message;
    EXPECT_EQ(img->clipUsed, ClipMethod::Discard);
    // Two planes keeping their intersection: discard too (the fragment stage fills the caps of
    // rays that leave the kept region inside a body); one plane keeps gl_ClipDistance.
    req.combine = PlaneCombine::Intersection;
    img = (*renderer)->render(**gpu, req);
    ASSERT_TRUE(img.ok());
    EXPECT_EQ(img->clipUsed, ClipMethod::Discard);
    req.planes.resize(1);
    img = (*renderer)->render(**gpu, req);
    ASSERT_TRUE(img.ok());
    EXPECT_EQ(img->clipUsed, ClipMethod::ClipDistance);
}
