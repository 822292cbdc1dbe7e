// Golden images of the slicing pass, as data (tests/data/goldens/README.md): every case folder
// whose request.json has "runner": "slice" is one test, Golden/Slice.Case/<case>. The request
// names a synthetic model, the image size, the planes (normals through the bounds centre), the
// view (a profile around the first plane, or a perspective eye offset from the centre in
// display space), exaggeration, clipping, anti-aliasing and background; its "outputs" give
// the expected ID buffer (compared exactly, ids stored as RGBA8: r, g, b = id bytes, low
// first, a = 255) and colour image with their tolerances and reasons. The comparison is the
// suites' shared one (tests/common/golden.hpp); UPDATE_GOLDENS=1 rewrites the expected files,
// a failure writes <case>.<output>.actual.png and .diff.png into GEOSLICE_GOLDEN_OUT.
#include <gtest/gtest.h>

#include <string>

#include "gl_test_util.hpp"
#include "image/image_encode.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/slice_renderer.hpp"
#include "tests/common/golden.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

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

glm::dvec3 vec3(const nlohmann::json& j) {
    return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

Rgba8 rgba(const nlohmann::json& j) {
    return {j.at(0).get<std::uint8_t>(), j.at(1).get<std::uint8_t>(), j.at(2).get<std::uint8_t>(),
            j.at(3).get<std::uint8_t>()};
}

OreVariant oreOf(const std::string& s) { return s == "partition" ? OreVariant::Partition : OreVariant::Nested; }

class Slice : public ::testing::TestWithParam<std::string> {};

TEST_P(Slice, Case) {
    const std::string name = GetParam();
    const nlohmann::json r = goldenRequest(name);
    const nlohmann::json& syn = r.at("model").at("synthetic");
    const Model model = syntheticModel(syn.at("triangles").get<std::size_t>(), oreOf(syn.value("ore", "nested")),
                                       syn.value("seed", std::uint64_t(1)));
    auto ctx = makeContext();
    ASSERT_TRUE(ctx);
    auto gpu = GpuModel::upload(*ctx, model);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    auto renderer = SliceRenderer::create(*ctx);
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;

    const glm::dvec3 centre = model.bounds().centre();
    SliceRequest req;
    req.width = r.at("size").at(0).get<int>();
    req.height = r.at("size").at(1).get<int>();
    for (const auto& p : r.at("planes")) {
        const glm::dvec3 n = glm::normalize(vec3(p));
        req.planes.push_back({n.x, n.y, n.z, -glm::dot(n, centre)});
    }
    if (r.value("combine", "intersection") == "union") req.combine = PlaneCombine::Union;
    if (r.value("clip", "") == "discard") req.clip = ClipMethod::Discard;
    if (r.contains("exaggeration")) req.exaggeration = {r.at("exaggeration").get<double>(), centre.z};
    if (r.at("view") == "profile") {
        req.view = profileAround(req.planes[0], model.bounds(), req.width, req.height);
    } else {
        const nlohmann::json& p = r.at("view").at("perspective");
        const glm::dvec3 c = req.exaggeration.toDisplay(centre);
        req.view =
            PerspectiveCamera{c + vec3(p.at("eyeOffset")), c, vec3(p.at("up")), p.at("fovDegrees").get<double>()};
    }
    if (r.contains("background")) req.background = rgba(r.at("background"));
    req.antiAlias = r.value("antiAlias", "none") == "fxaa" ? AntiAlias::Fxaa : AntiAlias::None;

    auto img = renderer.value()->render(*gpu.value(), req);
    ASSERT_TRUE(img.ok()) << img.error().message;
    compareGolden(name, "ids", idsToRgba(img->ids).data(), req.width, req.height, goldenTolerance(r, "ids"),
                  GEOSLICE_GOLDEN_OUT);
    compareGolden(name, "colour", img->rgba.data(), req.width, req.height, goldenTolerance(r, "colour"),
                  GEOSLICE_GOLDEN_OUT);
}

INSTANTIATE_TEST_SUITE_P(Golden, Slice, ::testing::ValuesIn(goldenCases("slice")),
                         [](const ::testing::TestParamInfo<std::string>& c) { return c.param; });

}  // namespace
