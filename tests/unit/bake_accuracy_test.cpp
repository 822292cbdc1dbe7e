// The whole bake on generated models: every random surface point's id fetched through its
// interpolated UV and the nearest texel equals its part's record (100 %, the paper's
// "attribute mapping accuracy"), the output is the same for 1 and 2 threads, and a model
// that does not fit the texture budget gives a clear error.
#include <gtest/gtest.h>

#include <filesystem>

#include <unistd.h>

#include "bake/bake.hpp"
#include "bake/package.hpp"
#include "tests/common/synthetic_model.hpp"

using namespace geoslice;

namespace {

// The benchmark's sampler (bake::sampleIdAccuracy): the fraction of about `samples` random
// points (area-uniform per part, parts by triangle count) whose fetched id equals the part's
// record. Interpolation in float, as a GPU does.
double fetchAccuracy(const bake::BakedModel& b, std::size_t samples, std::uint64_t seed) {
    const bake::IdAccuracy a = bake::sampleIdAccuracy(b, samples, seed);
    EXPECT_GE(a.points, samples);
    return a.fraction();
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

// The benchmark samples the loaded package, the tests the fresh bake: the one sampler gives
// the same points and answers on both (the package keeps the float UVs and texels bit for
// bit), and it can fail: a cleared texture, or one part's texels cleared, is counted exactly.
TEST(BakeAccuracy, OneSamplerForBakeAndPackageThatCountsWrongIds) {
    Model m = test::syntheticModel(4000);
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 512;
    auto b = bake::bakeModel(m, o);
    ASSERT_TRUE(b.ok()) << b.error().message;
    const auto dir = std::filesystem::temp_directory_path() / ("geoslice_accuracy_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    ASSERT_TRUE(bake::writePackage(m, b.value(), dir.string()).ok());
    auto pkg = bake::loadPackage(dir.string());
    ASSERT_TRUE(pkg.ok()) << pkg.error().message;
    const bake::IdAccuracy fromBake = bake::sampleIdAccuracy(b.value(), 30000, 5);
    const bake::IdAccuracy fromPackage = bake::sampleIdAccuracy(pkg.value(), 30000, 5);
    EXPECT_EQ(fromBake.points, fromPackage.points);
    EXPECT_EQ(fromBake.correct, fromBake.points);
    EXPECT_EQ(fromPackage.correct, fromPackage.points);

    // Clearing the texels of part 0's record fails exactly the points drawn on the parts with
    // that record: ceil(30000 x triangles / all triangles) each.
    ASSERT_GE(b->parts.size(), 2u);
    const RecordId cleared = b->parts[0].record;
    std::size_t triangles = 0, lost = 0;
    for (const auto& p : b->parts) triangles += p.indices.size() / 3;
    for (const auto& p : b->parts)
        if (p.record == cleared) lost += (30000 * (p.indices.size() / 3) + triangles - 1) / triangles;
    bake::BakedModel copy = b.value();
    for (auto& t : copy.texels)
        if (t == cleared) t = kNoRecord;
    const bake::IdAccuracy afterClear = bake::sampleIdAccuracy(copy, 30000, 5);
    EXPECT_EQ(afterClear.points, fromBake.points);
    EXPECT_EQ(afterClear.correct, fromBake.points - lost);
    EXPECT_GT(lost, 0u);
    std::fill(pkg->texels.begin(), pkg->texels.end(), kNoRecord);
    EXPECT_EQ(bake::sampleIdAccuracy(pkg.value(), 30000, 5).correct, 0u);
    std::filesystem::remove_all(dir);
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
