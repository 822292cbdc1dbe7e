// Golden images of the slicing pass on tiny synthetic models (tests/data/goldens/README.md).
// ID buffers compare exactly (ids stored as RGBA8 PNG: r,g,b = id bytes, low first, a = 255).
// Colour images compare per pixel: a pixel fails when any channel differs by more than
// kMaxChannelDiff (covers rounding of lighting and polygon-edge coverage between Mesa
// versions); the test fails when more than kMaxFailingFraction of pixels fail (an edge moved
// by one pixel along a few boundaries). UPDATE_GOLDENS=1 rewrites the expected files. A
// failure writes <case>.<kind>.actual.png and <case>.<kind>.diff.png (red = failing pixel,
// grey = the expected image dimmed) into GEOSLICE_GOLDEN_OUT in the build tree.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "gl_test_util.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/image_encode.hpp"
#include "renderer/slice_renderer.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

constexpr int kMaxChannelDiff = 24;
constexpr double kMaxFailingFraction = 0.005;
constexpr int kW = 96, kH = 64;

bool updating() {
    const char* u = std::getenv("UPDATE_GOLDENS");
    return u && std::string(u) == "1";
}

std::string goldenPath(const std::string& name) { return std::string(GEOSLICE_GOLDEN_DIR) + "/" + name + ".png"; }

std::vector<std::uint8_t> idsToRgba(const std::vector<RecordId>& ids) {
    std::vector<std::uint8_t> px(ids.size() * 4);
    for (std::size_t i = 0; i < ids.size(); ++i) {
        EXPECT_LT(ids[i], 1u << 24) << "an id too large for the golden encoding";
        px[4 * i] = std::uint8_t(ids[i] & 0xff);
        px[4 * i + 1] = std::uint8_t((ids[i] >> 8) & 0xff);
        px[4 * i + 2] = std::uint8_t((ids[i] >> 16) & 0xff);
        px[4 * i + 3] = 255;
    }
    return px;
}

void writeFailure(const std::string& name, const std::vector<std::uint8_t>& actual,
                  const std::vector<std::uint8_t>& diff, int w, int h) {
    std::filesystem::create_directories(GEOSLICE_GOLDEN_OUT);
    const std::string base = std::string(GEOSLICE_GOLDEN_OUT) + "/" + name;
    EXPECT_TRUE(writeImage(base + ".actual.png", actual.data(), w, h).ok());
    EXPECT_TRUE(writeImage(base + ".diff.png", diff.data(), w, h).ok());
    std::printf("[ golden   ] %s failed: wrote %s.actual.png and %s.diff.png\n", name.c_str(), base.c_str(),
                base.c_str());
}

// exact: every byte equal (ids). Otherwise the colour thresholds above.
void compareGolden(const std::string& name, const std::vector<std::uint8_t>& actual, int w, int h, bool exact) {
    const std::string path = goldenPath(name);
    if (updating()) {
        ASSERT_TRUE(writeImage(path, actual.data(), w, h).ok()) << path;
        std::printf("[ golden   ] rewrote %s\n", path.c_str());
        return;
    }
    auto expected = readPngRgba(path);
    ASSERT_TRUE(expected.ok()) << expected.error().message << " (run with UPDATE_GOLDENS=1 to create it)";
    ASSERT_EQ(expected->width, w) << path;
    ASSERT_EQ(expected->height, h) << path;
    std::vector<std::uint8_t> diff(actual.size());
    std::size_t failing = 0;
    int maxDiff = 0;
    for (std::size_t i = 0; i < actual.size(); i += 4) {
        int d = 0;
        for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(int(actual[i + c]) - int(expected->rgba[i + c])));
        maxDiff = std::max(maxDiff, d);
        const bool fail = exact ? d != 0 : d > kMaxChannelDiff;
        failing += fail;
        const std::uint8_t grey =
            std::uint8_t((expected->rgba[i] / 4 + expected->rgba[i + 1] / 4 + expected->rgba[i + 2] / 4) / 3 * 2 + 64);
        diff[i] = fail ? 255 : grey;
        diff[i + 1] = fail ? 0 : grey;
        diff[i + 2] = fail ? 0 : grey;
        diff[i + 3] = 255;
    }
    const double fraction = double(failing) / double(std::size_t(w) * h);
    const bool ok = exact ? failing == 0 : fraction <= kMaxFailingFraction;
    std::printf("[ golden   ] %s: %zu failing pixels (%.3f%%), max channel diff %d\n", name.c_str(), failing,
                100.0 * fraction, maxDiff);
    if (!ok) writeFailure(name, actual, diff, w, h);
    EXPECT_TRUE(ok) << name << ": " << failing << " pixels differ"
                    << (exact ? " (ids must match exactly)" : " beyond the colour threshold");
}

class Golden : public ::testing::Test {
protected:
    void SetUp() override {
        ctx = makeContext();
        ASSERT_TRUE(ctx);
        model = syntheticModel(2000, OreVariant::Nested, 4);
        auto g = GpuModel::upload(*ctx, model);
        ASSERT_TRUE(g.ok()) << g.error().message;
        gpu = std::move(g).value();
        auto r = SliceRenderer::create(*ctx);
        ASSERT_TRUE(r.ok()) << r.error().message;
        renderer = std::move(r).value();
    }
    void check(const std::string& name, const SliceRequest& req) {
        auto img = renderer->render(*gpu, req);
        ASSERT_TRUE(img.ok()) << img.error().message;
        compareGolden(name + ".ids", idsToRgba(img->ids), req.width, req.height, true);
        compareGolden(name + ".colour", img->rgba, req.width, req.height, false);
    }
    WorldPlane planeThroughCentre(glm::dvec3 n) const {
        n = glm::normalize(n);
        return {n.x, n.y, n.z, -glm::dot(n, model.bounds().centre())};
    }
    std::unique_ptr<GlContext> ctx;
    Model model;
    std::unique_ptr<GpuModel> gpu;
    std::unique_ptr<SliceRenderer> renderer;
};

}  // namespace

TEST_F(Golden, ProfileOfADippingPlane) {
    SliceRequest req;
    req.width = kW;
    req.height = kH;
    req.planes = {planeThroughCentre({0.2, 1.0, 0.1})};
    req.view = profileAround(req.planes[0], model.bounds(), kW, kH);
    req.background = Rgba8{255, 255, 255, 255};
    req.antiAlias = AntiAlias::None;
    check("profile_dipping", req);
}

TEST_F(Golden, PerspectiveWedgeWithTracesAndExaggeration) {
    SliceRequest req;
    req.width = kW;
    req.height = kH;
    req.planes = {planeThroughCentre({0.0, 1.0, 0.0}), planeThroughCentre({1.0, 0.3, 0.0})};
    req.combine = PlaneCombine::Union;
    req.exaggeration = {2.0, model.bounds().centre().z};
    const glm::dvec3 c = req.exaggeration.toDisplay(model.bounds().centre());
    req.view = PerspectiveView{c + glm::dvec3(-6000.0, -7000.0, 5000.0), c, {0, 0, 1}, 40.0};
    req.background = Rgba8{40, 60, 90, 255};
    req.antiAlias = AntiAlias::Fxaa;
    check("perspective_wedge_fxaa", req);
}

TEST_F(Golden, TransparentProfileDiscard) {
    SliceRequest req;
    req.width = kW;
    req.height = kH;
    req.clip = ClipMethod::Discard;
    req.planes = {planeThroughCentre({1.0, 0.0, 0.0})};
    req.view = profileAround(req.planes[0], model.bounds(), kW, kH);
    req.antiAlias = AntiAlias::None;
    check("profile_transparent_discard", req);
}
