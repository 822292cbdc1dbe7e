// The two section engines must tell the same story: for the same plane and the same u/v
// frame, the GL slicing pass (renderer/) and the exact CPU engine (section/) give the same
// record id on the cut. The exact engine shows only the plane; the renderer's profile also
// shows geometry beyond the plane where the plane has none (terrain behind the cut), so
// pixels are compared where the exact section has geology and its 3x3 neighbourhood is
// one body (the renderer samples triangle coverage, the section engine polygon coverage,
// so edge pixels may differ by one body).
#include <gtest/gtest.h>

#include <random>

#include "renderer/slice_renderer.hpp"
#include "section/cut/contours.hpp"
#include "section/fill/raster.hpp"
#include "section/index/section_index.hpp"
#include "tests/common/random_plane.hpp"
#include "tests/gl/gl_test_util.hpp"

using namespace geoslice;

TEST(EnginesAgree, RendererAndExactSectionGiveTheSameIds) {
    constexpr int kSize = 256;
    constexpr double kMinAgreement = 0.999;
    Model model = test::syntheticModel(50000, OreVariant::Nested, 3, "EPSG:4523");
    auto ctx = test::makeContext();
    ASSERT_TRUE(ctx);
    auto gpu = GpuModel::upload(*ctx, model);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    auto renderer = SliceRenderer::create(*ctx);
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    auto index = buildSectionIndex(model);
    ASSERT_TRUE(index.ok()) << index.error().message;

    std::mt19937_64 rng(77);
    int checkedPlanes = 0;
    for (int k = 0; k < 6; ++k) {
        const Plane plane = test::randomPlane(model.bounds(), rng, k);
        const WorldPlane wp(plane.normal.x, plane.normal.y, plane.normal.z, plane.d);
        const ProfileCamera view = profileAround(wp, model.bounds(), kSize, kSize);

        SliceRequest req;
        req.width = req.height = kSize;
        req.planes = {wp};
        req.view = view;
        req.readColour = false;
        auto gl = (*renderer)->render(*gpu.value(), req);
        ASSERT_TRUE(gl.ok()) << gl.error().message;

        auto section = computeSection(*index.value(), plane);
        ASSERT_TRUE(section.ok()) << section.error().message;
        RasterOptions ro;
        ro.colour = false;
        const FrameRect rect = view.rect;
        auto exact = rasterizeSection(*index.value(), section.value(), rect, kSize, kSize, ro);
        ASSERT_TRUE(exact.ok()) << exact.error().message;

        std::size_t compared = 0, agree = 0;
        const auto& e = exact->ids;
        for (int y = 1; y + 1 < kSize; ++y)
            for (int x = 1; x + 1 < kSize; ++x) {
                const std::uint32_t id = e[std::size_t(y) * kSize + std::size_t(x)];
                bool uniform = id != 0;
                for (int dy = -1; dy <= 1 && uniform; ++dy)
                    for (int dx = -1; dx <= 1 && uniform; ++dx)
                        uniform = e[std::size_t(y + dy) * kSize + std::size_t(x + dx)] == id;
                if (!uniform) continue;
                ++compared;
                agree += gl->idAt(x, y) == id;
            }
        std::printf("[ engines  ] plane %d: %zu/%zu pixels agree\n", k, agree, compared);
        if (compared < 2000) continue;  // the plane barely touches the model
        ++checkedPlanes;
        EXPECT_GE(double(agree) / double(compared), kMinAgreement) << "plane " << k;
    }
    EXPECT_GE(checkedPlanes, 3);
}
