// GL caps coloured by a block model (renderer/passes/block_texture.hpp) against the profile
// engine's rule: a box orebody nested in a box host, a 20 x 20 x 20 grid of 10 m cells with
// grade = i + 0.5 j - 0.3 k clipped by the orebody, classes < 3, 3 - 6, 6 - 9, 9 - 12, >= 12.
// A perspective view cut by one oblique plane, no anti-aliasing. Oracle for every one of
// 1,000 random pixels whose id is the orebody: the pixel's view ray (from the image's own
// viewProj, in double) meets the plane at a world point; BlockModel::cellAt and
// PropertyClasses::colourOf there (colourPixelsByBlocks' rule) give the expected colour,
// compared exactly. Tolerance: pixels whose point lies within 1 % of a cell (0.1 m) of a cell
// face, or within 0.1 m of the orebody's outline, are skipped (the shader interpolates the
// point in float; the rasteriser's coverage at the outline is not the polygon's).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "api/catalog.hpp"
#include "api/plan.hpp"
#include "model/blocks/block_model.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/passes/block_texture.hpp"
#include "renderer/slice_renderer.hpp"
#include "section/blocks/block_section.hpp"
#include "tests/gl/gl_test_util.hpp"
#include "tests/unit/test_meshes.hpp"
#include "workers/gl_worker.hpp"

using namespace geoslice;

TEST(BlockTexture, CapColoursAreTheProfileEnginesClasses) {
    const glm::dvec3 base(35500000.0, 3380000.0, 100.0);
    const glm::dvec3 oreLo = base + glm::dvec3(40.5, 35.5, 45.5), oreHi = base + glm::dvec3(160.5, 170.5, 150.5);
    Model m = test::modelOf({test::makePart("host", PartKind::Body, 1, test::boxMesh(base, base + 200.0)),
                             test::makePart("ore", PartKind::Body, 2, test::boxMesh(oreLo, oreHi))});
    ASSERT_EQ(m.bodies[1].report.parent, 0);
    BlockModel blocks;
    blocks.source = "test grid";
    blocks.origin = base;
    blocks.size = {10.0, 10.0, 10.0};
    blocks.dims = {20, 20, 20};
    BlockProperty grade{"grade", "g/t Au", std::vector<double>(blocks.cellCount())};
    for (std::size_t c = 0; c < blocks.cellCount(); ++c) {
        const auto ijk = blocks.ijk(c);
        grade.values[c] = double(ijk[0]) + 0.5 * double(ijk[1]) - 0.3 * double(ijk[2]);
    }
    // No value in the cell at the orebody's centre (on the cut): there the body's colour.
    grade.values[blocks.linear(10, 10, 9)] = std::nan("");
    blocks.properties.push_back(std::move(grade));
    blocks.clipBodies = {"ore"};
    ASSERT_TRUE(resolveBlockClip(m, blocks).ok());
    auto classes = makePropertyClasses(0, "viridis", {3.0, 6.0, 9.0, 12.0});
    ASSERT_TRUE(classes.ok());

    auto ctx = test::makeContext();
    ASSERT_TRUE(ctx);
    auto gpu = GpuModel::upload(*ctx, m);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    auto renderer = SliceRenderer::create(*ctx);
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    auto texture = BlockTexture::upload(*ctx, blocks, cellClassIndex(blocks, classes.value()), classes->colours,
                                        blockClipRecords(m, blocks));
    ASSERT_TRUE(texture.ok()) << texture.error().message;

    // The eye on the removed side of an oblique plane through the orebody.
    const glm::dvec3 centre = 0.5 * (oreLo + oreHi);
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.45, 0.6, -0.66));
    const WorldPlane plane(n.x, n.y, n.z, -glm::dot(n, centre));
    constexpr int kSize = 320;
    SliceRequest req;
    req.width = req.height = kSize;
    req.planes = {plane};
    req.view = PerspectiveCamera{centre - 320.0 * n + glm::dvec3(25.0, -15.0, 0.0), centre, {0.0, 0.0, 1.0}, 40.0};
    req.antiAlias = AntiAlias::None;
    req.drawTraces = false;
    req.blocks = texture.value().get();
    auto image = (*renderer)->render(*gpu.value(), req);
    ASSERT_TRUE(image.ok()) << image.error().message;

    const glm::dmat4 inv = glm::inverse(image->viewProj);  // clip -> true local frame
    const glm::dvec3 origin = m.origin;
    std::mt19937 rng(15);
    std::uniform_int_distribution<int> px(0, kSize - 1);
    int compared = 0, skipped = 0, noValue = 0, tries = 0;
    std::set<int> seenClasses;
    while (compared + skipped < 1000 && ++tries < 200000) {
        const int i = px(rng), j = px(rng);
        if (image->idAt(i, j) != 2u) continue;
        // The pixel centre's ray in the local frame, then its crossing of the plane (world).
        const double x = 2.0 * (i + 0.5) / kSize - 1.0, y = 1.0 - 2.0 * (j + 0.5) / kSize;
        glm::dvec4 a = inv * glm::dvec4(x, y, -1.0, 1.0), b = inv * glm::dvec4(x, y, 1.0, 1.0);
        const glm::dvec3 p0 = glm::dvec3(a) / a.w + origin, p1 = glm::dvec3(b) / b.w + origin;
        const double s0 = glm::dot(n, p0) + plane.w, s1 = glm::dot(n, p1) + plane.w;
        const glm::dvec3 w = p0 + (p1 - p0) * (s0 / (s0 - s1));
        const glm::dvec3 g = blocks.toGrid(w) / 10.0;
        const glm::dvec3 f = glm::abs(g - glm::round(g));
        const double edge =
            std::min({w.x - oreLo.x, oreHi.x - w.x, w.y - oreLo.y, oreHi.y - w.y, w.z - oreLo.z, oreHi.z - w.z});
        if (std::min({f.x, f.y, f.z}) < 0.01 || edge < 0.1) {
            ++skipped;
            continue;
        }
        ++compared;
        const std::size_t cell = blocks.cellAt(w);
        ASSERT_NE(cell, BlockModel::kNoCell);
        const double value = blocks.properties[0].values[cell];
        const int k = classes->classOf(value);
        const std::uint8_t* got = &image->rgba[4 * (std::size_t(j) * kSize + std::size_t(i))];
        if (k < 0) {
            ++noValue;  // the orebody's own cap colour, not a class colour
            for (const Rgba8& c : classes->colours)
                EXPECT_FALSE(got[0] == c.r && got[1] == c.g && got[2] == c.b) << "pixel " << i << "," << j;
            continue;
        }
        seenClasses.insert(k);
        const Rgba8 want = classes->colours[std::size_t(k)];
        EXPECT_TRUE(got[0] == want.r && got[1] == want.g && got[2] == want.b)
            << "pixel " << i << "," << j << " world " << w.x << "," << w.y << "," << w.z << ": got " << int(got[0])
            << "," << int(got[1]) << "," << int(got[2]) << ", class " << k << " is " << int(want.r) << ","
            << int(want.g) << "," << int(want.b);
    }
    std::printf(
        "[ blocks   ] %d cap pixels compared, %d skipped at cell faces or the outline, %d without value, "
        "%zu classes seen\n",
        compared, skipped, noValue, seenClasses.size());
    EXPECT_GE(compared, 800);
    EXPECT_GE(seenClasses.size(), 3u);
    EXPECT_GT(noValue, 0);
    // Without the texture the same caps are the orebody's own colour.
    req.blocks = nullptr;
    auto plain = (*renderer)->render(*gpu.value(), req);
    ASSERT_TRUE(plain.ok());
    EXPECT_EQ(plain->ids, image->ids);
    // More than 32 clipping records (issue 15: the records are a sorted texture, searched in
    // the shader): with 300 records, the orebody's among them, the image is the same; with
    // 300 records that leave it out, its caps keep the body's colour, as without a texture.
    std::vector<RecordId> many;
    for (RecordId r = 1000; r < 1299; ++r) many.push_back(r);
    many.push_back(2u);
    auto manyTexture =
        BlockTexture::upload(*ctx, blocks, cellClassIndex(blocks, classes.value()), classes->colours, many);
    ASSERT_TRUE(manyTexture.ok()) << manyTexture.error().message;
    req.blocks = manyTexture.value().get();
    auto withMany = (*renderer)->render(*gpu.value(), req);
    ASSERT_TRUE(withMany.ok());
    EXPECT_EQ(withMany->rgba, image->rgba);
    many.back() = 1299u;
    auto otherTexture =
        BlockTexture::upload(*ctx, blocks, cellClassIndex(blocks, classes.value()), classes->colours, many);
    ASSERT_TRUE(otherTexture.ok()) << otherTexture.error().message;
    req.blocks = otherTexture.value().get();
    auto withOthers = (*renderer)->render(*gpu.value(), req);
    ASSERT_TRUE(withOthers.ok());
    EXPECT_EQ(withOthers->rgba, plain->rgba);
    EXPECT_NE(withOthers->rgba, image->rgba);
    req.blocks = nullptr;
    // Bad inputs are errors naming the problem.
    EXPECT_FALSE(BlockTexture::upload(*ctx, blocks, {1, 2, 3}, classes->colours, {}).ok());
    EXPECT_FALSE(BlockTexture::upload(*ctx, blocks, cellClassIndex(blocks, classes.value()), classes->colours,
                                      std::vector<RecordId>(kMaxBlockClipRecords + 1, 2u))
                     .ok());
    // A curvilinear (SGrid) block model is refused by name: a texel per cell addresses boxes only.
    BlockModel curved = blocks;
    curved.shape = CellShape::Hexahedron;
    auto refused = BlockTexture::upload(*ctx, curved, cellClassIndex(blocks, classes.value()), classes->colours, {});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::Unsupported);
    EXPECT_NE(refused.error().message.find("curvilinear"), std::string::npos) << refused.error().message;
}

// The render worker's perspective views with colour= (what section.jpg?view=perspective&colour=
// draws): the orebody's cut face in class colours, the same view without colour= in none.
TEST(BlockTexture, WorkerPerspectiveViewsAreColoured) {
    const glm::dvec3 base(1000.0, 2000.0, 100.0);
    Model m = test::modelOf(
        {test::makePart("host", PartKind::Body, 1, test::boxMesh(base, base + 200.0)),
         test::makePart("ore", PartKind::Body, 2, test::boxMesh(base + glm::dvec3(40.5), base + glm::dvec3(160.5)))});
    BlockModel blocks;
    blocks.source = "test grid";
    blocks.origin = base;
    blocks.size = {10.0, 10.0, 10.0};
    blocks.dims = {20, 20, 20};
    BlockProperty grade{"grade", "g/t Au", std::vector<double>(blocks.cellCount())};
    for (std::size_t c = 0; c < blocks.cellCount(); ++c) grade.values[c] = double(blocks.ijk(c)[0]);
    blocks.properties.push_back(std::move(grade));
    blocks.clipBodies = {"ore"};
    ASSERT_TRUE(resolveBlockClip(m, blocks).ok());
    m.blocks = std::make_shared<const BlockModel>(std::move(blocks));
    auto cm = api::catalogModelOf("box", m, "v1");
    ASSERT_TRUE(cm.ok()) << cm.error().message;
    auto worker = workers::GlWorker::create(GlBackend::Auto);
    ASSERT_TRUE(worker.ok()) << worker.error().message;
    api::Params params{{"plane", "0.6,0.64,0.48,-2100"},
                       {"view", "perspective"},
                       {"eye", "700,1700,-200"},
                       {"target", "1100,2100,200"},
                       {"size", "160x160"},
                       {"colour", "grade"},
                       {"breaks", "5,10,15"}};
    auto coloured = api::parseViewPlan(params, "box", m.crs);
    ASSERT_TRUE(coloured.ok()) << coloured.error().message;
    params.erase("colour");
    params.erase("breaks");
    auto plainPlan = api::parseViewPlan(params, "box", m.crs);
    ASSERT_TRUE(plainPlan.ok()) << plainPlan.error().message;
    auto classes = makePropertyClasses(0, "viridis", {5.0, 10.0, 15.0});
    ASSERT_TRUE(classes.ok());
    auto countClassPixels = [&](const api::ViewImage& v) {
        std::size_t ore = 0, classed = 0;
        for (std::size_t p = 0; p < v.ids.size(); ++p) {
            if (v.ids[p] != 2u) continue;
            ++ore;
            for (const Rgba8& c : classes->colours)
                if (v.rgba[4 * p] == c.r && v.rgba[4 * p + 1] == c.g && v.rgba[4 * p + 2] == c.b) {
                    ++classed;
                    break;
                }
        }
        return std::pair(ore, classed);
    };
    auto a = worker.value()->renderPerspective(*cm.value(), coloured.value());
    ASSERT_TRUE(a.ok()) << a.error().message;
    auto b = worker.value()->renderPerspective(*cm.value(), plainPlan.value());
    ASSERT_TRUE(b.ok()) << b.error().message;
    const auto [ore, classed] = countClassPixels(a.value());
    std::printf("[ blocks   ] worker view: %zu orebody pixels, %zu in class colours\n", ore, classed);
    EXPECT_GT(ore, 500u);
    // FXAA (llvmpipe) blends the colour at class and body edges only: most pixels keep it.
    EXPECT_GT(double(classed), 0.8 * double(ore));
    EXPECT_EQ(countClassPixels(b.value()).second, 0u);
    EXPECT_EQ(a->ids, b->ids);
}
