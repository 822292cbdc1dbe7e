// Incremental re-bake of one part: the changed part's points all fetch its (new) record,
// every other part keeps its UVs, triangles and texels bit for bit, and a part that no longer
// fits the free space goes to a new page, or, over the page budget, is an error that leaves the
// bake unchanged.
#include <gtest/gtest.h>

#include <random>

#include "bake/bake.hpp"
#include "tests/common/synthetic_model.hpp"

using namespace geoslice;

namespace {

// True when texel (page, x, y) lies in the padded rectangle of one of part p's charts.
bool inPartRects(const bake::BakedModel& b, std::uint32_t p, std::uint32_t page, std::uint32_t x, std::uint32_t y) {
    for (const auto& c : b.charts)
        if (c.part == p && c.rect.page == page && x + 1 >= c.rect.x && x <= c.rect.x + c.rect.w && y + 1 >= c.rect.y &&
            y <= c.rect.y + c.rect.h)
            return true;
    return false;
}

}  // namespace

TEST(BakeRebake, ChangedPartIsExactAndOthersUntouched) {
    Model m = test::syntheticModel(8000);
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 1024;
    auto full = bake::bakeModel(m, o);
    ASSERT_TRUE(full.ok()) << full.error().message;
    const bake::BakedModel before = full.value();
    // Change body 3: lift it by 4 m, stretch it 2 % east, give it a new record.
    const std::size_t p = 3;
    Part& body = m.bodies[before.parts[p].source];
    for (auto& q : body.mesh.positions) q = {q.x * 1.02, q.y, q.z + 4.0};
    body.record = 777;
    bake::BakedModel after = before;
    auto s = bake::rebakePart(m, p, after, o);
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_EQ(after.parts[p].record, 777u);
    EXPECT_EQ(bake::partIdAccuracy(after, p, 20000, 1), 1.0);
    for (std::size_t q = 0; q < after.parts.size(); ++q) {
        if (q == p) continue;
        EXPECT_EQ(after.parts[q].uvs, before.parts[q].uvs) << q;
        EXPECT_EQ(after.parts[q].indices, before.parts[q].indices) << q;
        EXPECT_EQ(bake::partIdAccuracy(after, q, 2000, q), 1.0) << q;
    }
    // Outside the part's old and new rectangles, not one texel changed.
    std::size_t changedOutside = 0;
    for (std::uint32_t pg = 0; pg < after.pages; ++pg)
        for (std::uint32_t y = 0; y < after.height; ++y)
            for (std::uint32_t x = 0; x < after.width; ++x) {
                const std::size_t i = (std::size_t(pg) * after.height + y) * after.width + x;
                if (after.texels[i] != before.texels[i] && !inPartRects(before, p, pg, x, y) &&
                    !inPartRects(after, p, pg, x, y))
                    ++changedOutside;
            }
    EXPECT_EQ(changedOutside, 0u);
    EXPECT_GT(std::count(after.texels.begin(), after.texels.end(), 777u), 0);
}

TEST(BakeRebake, NoRoomOpensAPageOrIsAnErrorThatLeavesTheBake) {
    Model m = test::syntheticModel(4000);
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 256;
    o.pack.minDensity = 0.001;  // one page, packed at the largest density that fits
    auto full = bake::bakeModel(m, o);
    ASSERT_TRUE(full.ok()) << full.error().message;
    ASSERT_EQ(full->pages, 1u);
    // Grow the largest body 3x in plan: its charts need about 9x the texels it had.
    std::size_t p = 0;
    for (std::size_t i = 0; i < full->parts.size(); ++i)
        if (full->parts[i].indices.size() > full->parts[p].indices.size() && full->parts[i].source < m.bodies.size())
            p = i;
    Part& body = m.bodies[full->parts[p].source];
    const glm::dvec3 c = body.mesh.bounds().centre();
    for (auto& q : body.mesh.positions) q = c + glm::dvec3(3.0, 3.0, 1.0) * (q - c);
    bake::BakedModel copy = full.value();
    copy.pack.maxPages = 1;  // the budget of an existing bake is its own
    auto s = bake::rebakePart(m, p, copy, o);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(s.error().message.find("bake the model in full again"), std::string::npos) << s.error().message;
    EXPECT_EQ(copy.texels, full->texels);
    // With a page to spare, the grown body goes to a new page and all its points are exact.
    copy.pack.maxPages = 4;
    ASSERT_TRUE(bake::rebakePart(m, p, copy, o).ok());
    EXPECT_GT(copy.pages, 1u);
    EXPECT_EQ(bake::partIdAccuracy(copy, p, 20000, 3), 1.0);
    EXPECT_EQ(bake::rebakePart(m, 999, copy, o).error().code, ErrorCode::InvalidArgument);
}
