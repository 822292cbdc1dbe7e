// Issue 4 item 8: the slicing pass takes each fragment's record id from the baked index
// texture T_ID at its interpolated UV (caps included) and colours it by that record.
// Oracles: (1) a per-body bake holds each part's own record, so the ID buffer must equal the
// one drawn with one uniform record per part (same GpuModel, bakedIds off, so the geometry
// is identical; and the model's own upload); (2) a grade-field bake over a block holds the
// class record exactly where the surface point lies in the block, found from the depth
// buffer.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "bake/bake.hpp"
#include "bake/package.hpp"
#include "model/io/loaders.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/slice_renderer.hpp"
#include "tests/gl/gl_test_util.hpp"

namespace geoslice {
namespace {

using test::makeContext;
using test::syntheticModel;

constexpr int kSize = 256;
constexpr std::size_t kTriangles = 30000;

struct Compare {
    std::size_t compared = 0, agree = 0;
    double fraction() const { return compared ? double(agree) / double(compared) : 0.0; }
};

// Pixels where either image shows geology; agree when the ids are equal.
Compare compareIds(const std::vector<RecordId>& a, const std::vector<RecordId>& b) {
    Compare c;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        if (a[i] == kNoRecord && b[i] == kNoRecord) continue;
        ++c.compared;
        c.agree += a[i] == b[i];
    }
    return c;
}

class BakedIds : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        ctx = makeContext().release();
        if (!ctx) return;
        model = new Model(syntheticModel(kTriangles, OreVariant::Nested, 5));
        bake::BakeOptions o;
        o.pack.width = o.pack.height = 1024;
        o.threads = 2;
        auto b = bake::bakeModel(*model, o);
        EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.error().message);
        if (b.ok()) baked = new bake::BakedModel(std::move(b).value());
        auto r = SliceRenderer::create(*ctx);
        EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
        if (r.ok()) renderer = std::move(r).value().release();
    }
    static void TearDownTestSuite() {
        delete renderer;
        delete baked;
        delete model;
        delete ctx;
        renderer = nullptr, baked = nullptr, model = nullptr, ctx = nullptr;
    }
    void SetUp() override { ASSERT_TRUE(ctx && model && baked && renderer); }

    static SliceRequest profileRequest() {
        const Aabb b = model->bounds();
        const WorldPlane plane(0.0, 1.0, 0.0, -b.centre().y);
        SliceRequest req;
        req.width = req.height = kSize;
        req.planes = {plane};
        req.view = profileAround(plane, b, kSize, kSize);
        req.antiAlias = AntiAlias::None;
        return req;
    }
    static SliceRequest perspectiveRequest(bool cut) {
        const Aabb b = model->bounds();
        const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, 1.0, 0.15));
        PerspectiveCamera pv;
        pv.target = b.centre();
        pv.eye = b.centre() - n * (1.6 * glm::length(b.size())) + glm::dvec3(900.0, 0.0, 1500.0);
        pv.fovYDegrees = 35.0;
        SliceRequest req;
        req.width = req.height = kSize;
        if (cut) req.planes = {WorldPlane(n.x, n.y, n.z, -glm::dot(n, b.centre()))};
        req.view = pv;
        req.antiAlias = AntiAlias::None;
        return req;
    }

    static GlContext* ctx;
    static Model* model;
    static bake::BakedModel* baked;
    static SliceRenderer* renderer;
};
GlContext* BakedIds::ctx = nullptr;
Model* BakedIds::model = nullptr;
bake::BakedModel* BakedIds::baked = nullptr;
SliceRenderer* BakedIds::renderer = nullptr;

TEST_F(BakedIds, PerBodyBakeMatchesUniformRecords) {
    auto plain = GpuModel::upload(*ctx, *model);
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    auto gpu = GpuModel::upload(*ctx, *model, *baked);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    ASSERT_TRUE((*gpu)->hasIdTexture());
    EXPECT_FALSE((*plain)->hasIdTexture());
    EXPECT_EQ((*gpu)->idTextureBytes(), std::size_t(baked->width) * baked->height * baked->pages * 4);
    std::printf("[ baked    ] %ux%u x %u pages, %zu triangles; GPU: texture %zu B, UVs %zu B, colours %zu B\n",
                baked->width, baked->height, baked->pages, (*gpu)->triangleCount(), (*gpu)->idTextureBytes(),
                (*gpu)->uvBytes(), (*gpu)->colourTableBytes());

    const std::pair<const char*, SliceRequest> cases[] = {
        {"profile", profileRequest()},
        {"persp-cut", perspectiveRequest(true)},
        {"persp-lod", perspectiveRequest(true)},
    };
    for (auto [tag, req] : cases) {
        req.lod = std::string(tag) == "persp-lod" ? SliceRequest::Lod::On : SliceRequest::Lod::Off;
        auto withTexture = renderer->render(**gpu, req);
        ASSERT_TRUE(withTexture.ok()) << withTexture.error().message;
        req.bakedIds = false;
        auto uniform = renderer->render(**gpu, req);
        ASSERT_TRUE(uniform.ok()) << uniform.error().message;
        auto fromModel = renderer->render(**plain, req);
        ASSERT_TRUE(fromModel.ok()) << fromModel.error().message;

        const Compare same = compareIds(withTexture->ids, uniform->ids);
        const Compare vsModel = compareIds(withTexture->ids, fromModel->ids);
        // Colour by the record -> colour table equals the uniform colour of the same record
        // (same geometry, same shading): exact wherever the ids agree.
        std::size_t colourChecked = 0, colourSame = 0;
        for (std::size_t i = 0; i < withTexture->ids.size(); ++i) {
            if (withTexture->ids[i] == kNoRecord || withTexture->ids[i] != uniform->ids[i]) continue;
            ++colourChecked;
            colourSame += std::equal(withTexture->rgba.begin() + std::ptrdiff_t(4 * i),
                                     withTexture->rgba.begin() + std::ptrdiff_t(4 * i + 4),
                                     uniform->rgba.begin() + std::ptrdiff_t(4 * i));
        }
        std::printf(
            "[ baked    ] %-9s ids: %zu/%zu agree with uniform records (%.4f%%), %zu/%zu with the model "
            "upload (%.4f%%); colours %zu/%zu; %.1f ms vs %.1f ms draw\n",
            tag, same.agree, same.compared, 100.0 * same.fraction(), vsModel.agree, vsModel.compared,
            100.0 * vsModel.fraction(), colourSame, colourChecked, withTexture->drawMs, uniform->drawMs);
        EXPECT_GT(same.compared, std::size_t(kSize * kSize / 10)) << tag;
        EXPECT_GE(same.fraction(), 0.999) << tag;
        if (req.lod == SliceRequest::Lod::Off) {
            EXPECT_GE(vsModel.fraction(), 0.999) << tag;
        }
        EXPECT_EQ(colourSame, colourChecked) << tag;
    }
}

TEST_F(BakedIds, EveryFragmentFetches) {
    // Every texel that holds an id set to one new record: a fragment that took its record
    // from the texture shows it; one that fell back to its part's record (texel 0) does not.
    // Without a cut every visible fragment is an exterior face, which always fetches.
    bake::BakedModel marked = *baked;
    const RecordId mark = model->attributes.nextId() + 100;
    for (std::uint32_t& t : marked.texels)
        if (t != kNoRecord) t = mark;
    auto gpu = GpuModel::upload(*ctx, *model, marked);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    for (const bool cut : {false, true}) {
        SliceRequest req = perspectiveRequest(cut);
        req.lod = SliceRequest::Lod::Off;
        auto img = renderer->render(**gpu, req);
        ASSERT_TRUE(img.ok()) << img.error().message;
        std::size_t shown = 0, fetched = 0;
        for (RecordId id : img->ids) {
            shown += id != kNoRecord;
            fetched += id == mark;
        }
        std::printf("[ fetch    ] %s: %zu/%zu pixels took their id from the texture (%.4f%%)\n", cut ? "cut" : "whole",
                    fetched, shown, 100.0 * double(fetched) / double(std::max<std::size_t>(shown, 1)));
        EXPECT_GT(shown, std::size_t(kSize * kSize / 10));
        // With a cut, caps that a nested body's front face draws keep their container's record.
        EXPECT_GE(double(fetched), (cut ? 0.9 : 0.999) * double(shown));
    }
}

TEST_F(BakedIds, FieldBakeShowsGradeClasses) {
    // One block over the west half of the model: texels whose point lies in it get the field
    // record of their part, the rest keep the part's record.
    const Aabb b = model->bounds();
    bake::BlockModel blocks;
    blocks.name = "Au_gpt";
    const glm::dvec3 size = b.size();
    const double westEdge = b.min.x + 0.5 * size.x;
    blocks.centres.push_back({b.min.x + 0.25 * size.x - 0.5, b.centre().y, b.centre().z});
    blocks.sizes.push_back({0.5 * size.x + 1.0, 2.0 * size.y + 2.0, 2.0 * size.z + 2.0});
    blocks.values.push_back(3.0);
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 1024;
    o.threads = 2;
    o.field.blocks = &blocks;
    auto field = bake::bakeModel(*model, o);
    ASSERT_TRUE(field.ok()) << field.error().message;
    std::map<RecordId, RecordId> parentOf;
    for (const AttributeRecord& r : field->fieldRecords) parentOf[r.id] = r.extra.at("parent").get<RecordId>();
    ASSERT_FALSE(parentOf.empty());

    auto plain = GpuModel::upload(*ctx, *model);
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    auto gpu = GpuModel::upload(*ctx, *model, *field);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;

    // Whole model, no cut: every visible pixel is an exterior face whose point the depth
    // buffer gives. Expected id: the field record when the point is west of the block's east
    // face by more than the margin, the part's record when east of it by more.
    SliceRequest req = perspectiveRequest(false);
    req.lod = SliceRequest::Lod::Off;
    req.readDepth = true;
    auto img = renderer->render(**gpu, req);
    ASSERT_TRUE(img.ok()) << img.error().message;
    auto ref = renderer->render(**plain, req);
    ASSERT_TRUE(ref.ok()) << ref.error().message;
    const glm::dmat4 inv = glm::inverse(img->viewProj);
    const double margin = 3.0 / field->density + 0.01 * size.x;  // texels of the bake + depth precision
    std::size_t checked = 0, agree = 0, fieldPixels = 0;
    for (int row = 0; row < kSize; ++row)
        for (int col = 0; col < kSize; ++col) {
            const std::size_t i = std::size_t(row) * kSize + std::size_t(col);
            if (ref->ids[i] == kNoRecord || img->depth[i] >= 1.0f) continue;
            const glm::dvec4 ndc(2.0 * (col + 0.5) / kSize - 1.0, 1.0 - 2.0 * (row + 0.5) / kSize,
                                 2.0 * double(img->depth[i]) - 1.0, 1.0);
            const glm::dvec4 h = inv * ndc;
            const double x = h.x / h.w + model->origin.x;
            if (std::abs(x - westEdge) < margin) continue;
            ++checked;
            RecordId expected = ref->ids[i];
            if (x < westEdge)
                for (const auto& [id, parent] : parentOf)
                    if (parent == ref->ids[i]) expected = id;
            agree += img->ids[i] == expected;
            fieldPixels += parentOf.count(img->ids[i]);
        }
    std::printf("[ field    ] exterior: %zu/%zu pixels as the block predicts (%.4f%%), %zu show a field record\n",
                agree, checked, 100.0 * double(agree) / double(std::max<std::size_t>(checked, 1)), fieldPixels);
    EXPECT_GT(fieldPixels, std::size_t(kSize * kSize / 50));
    EXPECT_GT(checked, fieldPixels + std::size_t(kSize * kSize / 50));
    EXPECT_GE(double(agree), 0.999 * double(checked));

    // A cut through the block: the caps fetch too (their far surface's class); every pixel is
    // its part's record or that record's field record, and field records show up.
    SliceRequest cut = profileRequest();
    auto cutImg = renderer->render(**gpu, cut);
    ASSERT_TRUE(cutImg.ok()) << cutImg.error().message;
    auto cutRef = renderer->render(**plain, cut);
    ASSERT_TRUE(cutRef.ok()) << cutRef.error().message;
    std::size_t consistent = 0, compared = 0, cutField = 0;
    for (std::size_t i = 0; i < cutImg->ids.size(); ++i) {
        if (cutImg->ids[i] == kNoRecord && cutRef->ids[i] == kNoRecord) continue;
        ++compared;
        const auto it = parentOf.find(cutImg->ids[i]);
        const RecordId shown = it == parentOf.end() ? cutImg->ids[i] : it->second;
        cutField += it != parentOf.end();
        consistent += shown == cutRef->ids[i];
    }
    std::printf("[ field    ] profile: %zu/%zu pixels are their part or its class, %zu show a field record\n",
                consistent, compared, cutField);
    EXPECT_GT(cutField, std::size_t(kSize * kSize / 50));
    EXPECT_GE(double(consistent), 0.999 * double(compared));
}

TEST_F(BakedIds, PackageUploadMatchesTheBake) {
    // What the server holds: a package written, loaded back (mesh.glb as the model, T_ID and
    // UVs from the package). Same geometry and texels as the in-memory bake, so the same ids.
    const std::string dir = ::testing::TempDir() + "geoslice_baked_ids_pkg";
    std::filesystem::remove_all(dir);
    ASSERT_TRUE(bake::writePackage(*model, *baked, dir, 1).ok());
    auto pkg = bake::loadPackage(dir);
    ASSERT_TRUE(pkg.ok()) << pkg.error().message;
    auto pkgModel = loadModel(dir + "/" + bake::kMeshFile);
    ASSERT_TRUE(pkgModel.ok()) << pkgModel.error().message;
    auto fromPackage = GpuModel::upload(*ctx, *pkgModel, *pkg);
    ASSERT_TRUE(fromPackage.ok()) << fromPackage.error().message;
    auto fromBake = GpuModel::upload(*ctx, *model, *baked);
    ASSERT_TRUE(fromBake.ok()) << fromBake.error().message;
    // The package's parts also line up with the model it was baked from.
    auto original = GpuModel::upload(*ctx, *model, *pkg);
    ASSERT_TRUE(original.ok()) << original.error().message;
    for (bool cut : {false, true}) {
        SliceRequest req = cut ? profileRequest() : perspectiveRequest(false);
        req.lod = SliceRequest::Lod::Off;
        auto a = renderer->render(**fromPackage, req);
        ASSERT_TRUE(a.ok()) << a.error().message;
        auto b = renderer->render(**fromBake, req);
        ASSERT_TRUE(b.ok()) << b.error().message;
        auto c = renderer->render(**original, req);
        ASSERT_TRUE(c.ok()) << c.error().message;
        const Compare ab = compareIds(a->ids, b->ids), cb = compareIds(c->ids, b->ids);
        std::printf("[ package  ] %s: %zu/%zu ids as the bake (package model), %zu/%zu (source model)\n",
                    cut ? "profile" : "persp", ab.agree, ab.compared, cb.agree, cb.compared);
        EXPECT_GT(ab.compared, std::size_t(kSize * kSize / 10));
        EXPECT_GE(ab.fraction(), 0.999);
        EXPECT_GE(cb.fraction(), 0.999);
    }
    std::filesystem::remove_all(dir);
}

TEST_F(BakedIds, MismatchedBakeIsRejected) {
    // A bake of another model, and a bake with a part's record changed.
    const Model other = syntheticModel(kTriangles / 2, OreVariant::Nested, 6);
    auto gpu = GpuModel::upload(*ctx, other, *baked);
    ASSERT_FALSE(gpu.ok());
    EXPECT_EQ(gpu.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(gpu.error().message.find("bake"), std::string::npos) << gpu.error().message;

    bake::BakedModel broken = *baked;
    broken.texels.pop_back();
    auto g2 = GpuModel::upload(*ctx, *model, broken);
    ASSERT_FALSE(g2.ok());
    EXPECT_NE(g2.error().message.find("texels"), std::string::npos) << g2.error().message;

    broken = *baked;
    broken.parts[0].uvs.pop_back();
    auto g3 = GpuModel::upload(*ctx, *model, broken);
    ASSERT_FALSE(g3.ok());
    EXPECT_NE(g3.error().message.find("UVs"), std::string::npos) << g3.error().message;
}

}  // namespace
}  // namespace geoslice
