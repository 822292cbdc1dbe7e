// The whole bake on generated models: every random surface point's id fetched through its
// interpolated UV and the nearest texel equals its part's record (100 %, the paper's
// "attribute mapping accuracy"), the output is the same for 1 and 2 threads, and a model
// that does not fit the texture budget gives a clear error.
#include <gtest/gtest.h>

#include <random>

#include "bake/bake.hpp"
#include "tests/common/synthetic_model.hpp"

using namespace geoslice;

namespace {

// Fraction of `samples` random points (area-uniform per part, then parts by triangle count)
// whose fetched id equals the part's record. Interpolation in float, as a GPU does.
double fetchAccuracy(const bake::BakedModel& b, std::size_t samples, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t good = 0, total = 0;
    for (const auto& part : b.parts) {
        const std::size_t tris = part.indices.size() / 3;
        const std::size_t n = std::max<std::size_t>(1, samples * tris / b.stats.triangles);
        std::uniform_int_distribution<std::size_t> pick(0, tris - 1);
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t t = pick(rng);
            double r1 = unit(rng), r2 = unit(rng);
            if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
            const float w1 = float(r1), w2 = float(r2), w0 = 1.0f - w1 - w2;
            const glm::vec2 uv = w0 * part.uvs[part.indices[3 * t]] + w1 * part.uvs[part.indices[3 * t + 1]] +
                                 w2 * part.uvs[part.indices[3 * t + 2]];
            good += bake::fetchId(b.texels.data(), b.width, b.height, b.pages, glm::dvec2(uv)) == part.record;
            ++total;
        }
    }
    return double(good) / double(total);
}

}  // namespace

TEST(BakeAccuracy, SyntheticModelAllPointsFetchTheirRecord) {
    Model m = test::syntheticModel(20000);
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 1024;
    auto b = bake::bakeModel(m, o);
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_EQ(b->pages, 1u);
    EXPECT_EQ(b->stats.triangles, m.triangleCount());
    EXPECT_GT(b->stats.texelUtilisation, 0.3);
    EXPECT_LT(b->stats.distortion.meanAngle, 1.1);
    EXPECT_EQ(fetchAccuracy(b.value(), 200000, 7), 1.0);
}

TEST(BakeAccuracy, SameOutputForOneAndTwoThreads) {
    Model m = test::syntheticModel(8000, OreVariant::Partition, 3);
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 512;
    o.threads = 1;
    auto a = bake::bakeModel(m, o);
    o.threads = 2;
    auto b = bake::bakeModel(m, o);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->texels, b->texels);
    ASSERT_EQ(a->parts.size(), b->parts.size());
    for (std::size_t p = 0; p < a->parts.size(); ++p) {
        EXPECT_EQ(a->parts[p].indices, b->parts[p].indices);
        EXPECT_EQ(a->parts[p].uvs, b->parts[p].uvs);
    }
}

TEST(BakeAccuracy, SeveralPagesKeepFullAccuracy) {
    Model m = test::syntheticModel(8000);
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 512;
    // 0.05 texels per metre: the mine's 4.5e8 m^2 of surface need about 1.1M texels, several pages.
    o.pack.minDensity = 0.05;
    o.pack.maxPages = 4096;
    auto b = bake::bakeModel(m, o);
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_GT(b->pages, 1u);
    EXPECT_DOUBLE_EQ(b->density, 0.05);
    EXPECT_EQ(fetchAccuracy(b.value(), 50000, 9), 1.0);
}

TEST(BakeAccuracy, ModelOverBudgetIsAClearError) {
    Model m = test::syntheticModel(8000);
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 64;
    o.pack.minDensity = 1.0;
    o.pack.maxPages = 2;
    auto b = bake::bakeModel(m, o);
    ASSERT_FALSE(b.ok());
    EXPECT_EQ(b.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(b.error().message.find("does not fit the texture budget"), std::string::npos) << b.error().message;
}

TEST(BakeAccuracy, BadInputIsAnError) {
    Model empty;
    EXPECT_EQ(bake::bakeModel(empty).error().code, ErrorCode::InvalidArgument);
    Model m = test::syntheticModel(2000);
    m.bodies[0].mesh.positions[0].x = std::nan("");
    auto b = bake::bakeModel(m);
    ASSERT_FALSE(b.ok());
    EXPECT_NE(b.error().message.find("non-finite"), std::string::npos);
    m = test::syntheticModel(2000);
    m.bodies[0].mesh.indices[4] = 1u << 30;
    EXPECT_EQ(bake::bakeModel(m).error().code, ErrorCode::InvalidArgument);
    bake::BakeOptions o;
    o.pack.margin = 1;
    EXPECT_EQ(bake::bakeModel(test::syntheticModel(2000), o).error().code, ErrorCode::InvalidArgument);
}
