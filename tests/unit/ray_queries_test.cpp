// The ray scene built after the model is served (section/rays/ray_queries.hpp, issue 13 item 4):
// a query that arrives before the scene is built waits for it and gets the same bytes as the
// same query afterwards (pixel queries of a profile view without a cached image, of a
// perspective view, of a polyline view, and a borehole); one whose deadline passes first, or
// whose client goes away, gets DeadlineExceeded naming the ray scene; destroying a model while
// its scene builds (a server stopping during start-up) cancels the build and returns.
// Oracle: the answer of the same query once the scene is built (no tolerance: equal bytes).
// The build is held back deterministically by RayBuild::Deferred: nothing builds until the
// test calls rays->start().
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "api/borehole.hpp"
#include "api/catalog.hpp"
#include "api/pixel_query.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "section/rays/ray_queries.hpp"

namespace geoslice::api {
namespace {

using namespace std::chrono_literals;

Model demoMine(std::size_t triangles) {
    SyntheticOptions o;
    o.triangles = triangles;
    o.seed = 1;
    o.crs = Crs::fromEpsg(4523).value();
    o.atLonLat = glm::dvec2(105.05, 30.62);
    Model m = generateSynthetic(o).value();
    validate(m);
    return m;
}

std::shared_ptr<const CatalogModel> deferred(std::size_t triangles = 20000) {
    auto m = catalogModelOf("demo", demoMine(triangles), "v1", RayBuild::Deferred);
    EXPECT_TRUE(m) << m.error().message;
    return m ? m.value() : nullptr;
}

ViewPlan plan(const CatalogModel& m, const Params& p) {
    auto r = parseViewPlan(p, m.id, m.model.crs);
    EXPECT_TRUE(r) << r.error().message;
    return r ? r.value() : ViewPlan{};
}

// The queries under test, each as a function of the wait it is given.
struct Case {
    const char* name;
    std::function<Result<std::string>(const CatalogModel&, const RayWait&)> run;
};

std::vector<Case> cases(const CatalogModel& m) {
    const glm::dvec3 c = m.index->bounds.centre();
    const std::string cx = std::to_string(c.x), cy = std::to_string(c.y), cz = std::to_string(c.z);
    const ViewPlan profile = plan(m, {{"plane", "0,1,0,-" + cy}, {"size", "64x48"}});
    const ViewPlan line = plan(m, {{"line", std::to_string(c.x - 500) + "," + std::to_string(c.y - 300) + "," +
                                                std::to_string(c.x + 500) + "," + std::to_string(c.y + 300)},
                                   {"size", "64x48"}});
    const ViewPlan persp = plan(m, {{"plane", "-1,0,0," + cx},
                                    {"view", "perspective"},
                                    {"eye", std::to_string(c.x + 4700) + "," + std::to_string(c.y - 5300) + ",4500"},
                                    {"target", cx + "," + cy + "," + cz},
                                    {"size", "64x48"}});
    return {
        {"profile",
         [profile](const CatalogModel& mm, const RayWait& w) { return queryPixel(mm, profile, 30, 30, nullptr, w); }},
        {"line", [line](const CatalogModel& mm, const RayWait& w) { return queryPixel(mm, line, 32, 30, nullptr, w); }},
        {"perspective",
         [persp](const CatalogModel& mm, const RayWait& w) { return queryPixel(mm, persp, 32, 24, nullptr, w); }},
        {"borehole",
         [cx, cy](const CatalogModel& mm, const RayWait& w) -> Result<std::string> {
             auto j = boreholeAt(mm, {{"x", cx}, {"y", cy}}, w);
             if (!j) return j.error();
             return j.value().dump();
         }},
    };
}

}  // namespace

TEST(RayQueries, AQueryBeforeTheSceneIsBuiltWaitsAndGetsTheSameBytes) {
    auto early = deferred();
    auto late = deferred();
    ASSERT_TRUE(early && late);
    late->rays->start();
    for (const Case& k : cases(*early)) {
        SCOPED_TRACE(k.name);
        ASSERT_EQ(early->rays->state(), RayQueries::State::NotStarted);
        auto pending = std::async(std::launch::async, [&] { return k.run(*early, RayWait{}); });
        // Nothing builds the scene yet: the query must still be waiting.
        EXPECT_EQ(pending.wait_for(100ms), std::future_status::timeout);
        early->rays->start();
        auto got = pending.get();
        ASSERT_TRUE(got) << got.error().message;
        EXPECT_EQ(early->rays->state(), RayQueries::State::Ready);
        // The same query on the same model afterwards, and on a model whose scene was built first.
        auto after = k.run(*early, RayWait{});
        auto other = k.run(*late, RayWait{});
        ASSERT_TRUE(after && other);
        EXPECT_EQ(got.value(), after.value());
        EXPECT_EQ(got.value(), other.value());
        EXPECT_NE(got.value().find("\"record\""), std::string::npos) << got.value();
        early = deferred();  // the next case starts before a build again
        ASSERT_TRUE(early);
    }
}

TEST(RayQueries, DeadlineOrCancellationBeforeTheBuildIsDeadlineExceeded) {
    auto m = deferred();
    ASSERT_TRUE(m);
    for (const Case& k : cases(*m)) {
        SCOPED_TRACE(k.name);
        const auto t0 = std::chrono::steady_clock::now();
        auto r = k.run(*m, RayWait{t0 + 50ms, nullptr});
        ASSERT_FALSE(r);
        EXPECT_EQ(r.error().code, ErrorCode::DeadlineExceeded);
        EXPECT_NE(r.error().message.find("ray scene"), std::string::npos) << r.error().message;
        EXPECT_GE(std::chrono::steady_clock::now() - t0, 50ms);
        std::atomic<bool> gone{true};
        auto c = k.run(*m, RayWait{std::chrono::steady_clock::time_point::max(), &gone});
        ASSERT_FALSE(c);
        EXPECT_EQ(c.error().code, ErrorCode::DeadlineExceeded);
    }
    // Profile queries with a cached ID buffer never need the scene.
    const ViewPlan p = plan(*m, {{"plane", "0,1,0,-" + std::to_string(m->index->bounds.centre().y)}, {"size", "8x8"}});
    ViewImage cached;
    cached.width = 8;
    cached.height = 8;
    cached.ids.assign(64, 7);
    auto a = answerPixel(*m, p, 3, 3, &cached, RayWait{std::chrono::steady_clock::now(), nullptr});
    ASSERT_TRUE(a) << a.error().message;
    EXPECT_EQ(a.value().record, 7u);
}

TEST(RayQueries, DestroyingAModelWhileItsSceneBuildsIsClean) {
    // A model large enough that its scene takes a while to build; destroyed at several moments
    // of the build (the destructor cancels through Embree's progress monitor and joins).
    const Model big = demoMine(400000);
    for (int delayMs : {0, 5, 20, 60}) {
        auto rays = RayQueries::create(big);
        rays->start();
        std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
        rays.reset();
    }
    // A cancelled RayScene build says so.
    std::atomic<bool> cancel{true};
    RaySceneOptions o;
    o.cancel = &cancel;
    auto scene = RayScene::build(big, o);
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().code, ErrorCode::DeadlineExceeded);
    EXPECT_NE(scene.error().message.find("cancelled"), std::string::npos);
    // And a whole catalog model, destroyed at once after its load started the build.
    auto m = catalogModelOf("demo", demoMine(200000), "v1", RayBuild::Now);
    ASSERT_TRUE(m) << m.error().message;
    m = makeError(ErrorCode::Internal, "dropped");
}

}  // namespace geoslice::api
