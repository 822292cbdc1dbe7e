// server/render_cache.hpp without HTTP: a real render pool (workers/render_pool.hpp) and
// render functions that block until the test lets them go, so every outcome is reached on
// purpose: ok (and cached, with its ETag), Unavailable (queue full), DeadlineExceeded
// (deadline, client gone), OutOfRange (larger than the whole memory budget), the render's
// own error, and coalescing (identical concurrent requests share one render).
#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "server/metrics.hpp"
#include "server/render_cache.hpp"
#include "workers/render_pool.hpp"

namespace geoslice::server {
namespace {

using namespace std::chrono_literals;

// A gate render functions wait on (bounded, so a broken test cannot hang).
struct Gate {
    std::promise<void> open;
    std::shared_future<void> opened = open.get_future().share();
    void wait() const { (void)opened.wait_for(10s); }
};

Rendered entry(const std::string& body) {
    auto e = std::make_shared<Encoded>();
    e->body = body;
    e->contentType = "text/plain";
    e->etag = RenderCache::etagOf(body);
    return std::shared_ptr<const Encoded>(std::move(e));
}

// A render cache over a real pool. The pool is stopped first (as ServerState does): its
// workers may still be inside the cache's bookkeeping when a waiter already has its answer.
struct Rig {
    Metrics metrics;
    std::unique_ptr<workers::RenderPool> pool;
    std::unique_ptr<RenderCache> cache;
    Rig(unsigned workers, std::size_t queue, int deadlineMs, std::size_t memoryBudget = 0)
        : pool(std::make_unique<workers::RenderPool>(workers, queue, memoryBudget)),
          cache(std::make_unique<RenderCache>(std::size_t(1) << 20, deadlineMs, *pool, metrics)) {}
    ~Rig() { pool.reset(); }
};

// A render that counts its runs, waits at `gate` (if any) and answers `body`.
RenderFn answer(std::string body, std::atomic<int>* runs = nullptr, const Gate* gate = nullptr) {
    return [body, runs, gate](workers::WorkerState&, const std::atomic<bool>&) -> Rendered {
        if (runs) ++*runs;
        if (gate) gate->wait();
        return entry(body);
    };
}

TEST(RenderCache, RendersOnceThenAnswersFromTheCacheWithAStableETag) {
    Rig rig(1, 4, 5000);
    RenderCache& cache = *rig.cache;
    std::atomic<bool> gone{false};
    std::atomic<int> runs{0};
    EXPECT_EQ(cache.find("k"), nullptr);
    auto r = cache.render("k", answer("bytes", &runs), 1024, false, gone);
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r.value()->body, "bytes");
    auto hit = cache.find("k");
    ASSERT_NE(hit, nullptr);
    EXPECT_EQ(hit->body, "bytes");
    EXPECT_EQ(runs.load(), 1);
    // ETags: quoted, a function of the key alone.
    EXPECT_EQ(RenderCache::etagOf("k"), RenderCache::etagOf("k"));
    EXPECT_NE(RenderCache::etagOf("k"), RenderCache::etagOf("k2"));
    EXPECT_EQ(RenderCache::etagOf("k").front(), '"');
    EXPECT_EQ(RenderCache::etagOf("k").back(), '"');
    // keep = false: answered, not cached.
    auto once = cache.render("q", answer("batch"), 1024, false, gone, false);
    ASSERT_TRUE(once);
    EXPECT_EQ(cache.find("q"), nullptr);
}

TEST(RenderCache, IdenticalConcurrentRequestsShareOneRender) {
    Rig rig(2, 8, 5000);
    RenderCache& cache = *rig.cache;
    std::atomic<bool> gone{false};
    std::atomic<int> runs{0};
    Gate gate;
    constexpr int kWaiters = 4;
    std::vector<std::future<Rendered>> waiters;
    for (int i = 0; i < kWaiters; ++i)
        waiters.push_back(std::async(std::launch::async, [&] {
            return cache.render("same", answer("shared", &runs, &gate), 1024, false, gone);
        }));
    // Every waiter has joined before the render may finish.
    for (int i = 0; i < 500 && cache.coalesced() < kWaiters - 1; ++i) std::this_thread::sleep_for(2ms);
    gate.open.set_value();
    for (auto& w : waiters) {
        auto r = w.get();
        ASSERT_TRUE(r) << r.error().message;
        EXPECT_EQ(r.value()->body, "shared");
    }
    EXPECT_EQ(runs.load(), 1);
    EXPECT_EQ(cache.coalesced(), std::uint64_t(kWaiters - 1));
}

TEST(RenderCache, AFullQueueIsUnavailableAndTooLargeIsOutOfRange) {
    Rig rig(1, 1, 5000, std::size_t(64) << 20);
    RenderCache& cache = *rig.cache;
    workers::RenderPool& pool = *rig.pool;
    std::atomic<bool> gone{false};
    Gate gate;
    // One running (blocked), one queued: the queue (capacity 1) is full.
    auto running =
        std::async(std::launch::async, [&] { return cache.render("a", answer("a", nullptr, &gate), 1, false, gone); });
    for (int i = 0; i < 500 && pool.busyWorkers() == 0; ++i) std::this_thread::sleep_for(2ms);
    auto queued = std::async(std::launch::async, [&] { return cache.render("b", answer("b"), 1, false, gone); });
    for (int i = 0; i < 500 && pool.queueDepth() == 0; ++i) std::this_thread::sleep_for(2ms);
    auto refused = cache.render("c", answer("c"), 1, false, gone);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().code, ErrorCode::Unavailable) << refused.error().message;
    auto huge = cache.render("d", answer("d"), std::size_t(65) << 20, false, gone);
    ASSERT_FALSE(huge);
    EXPECT_EQ(huge.error().code, ErrorCode::OutOfRange) << huge.error().message;
    EXPECT_NE(huge.error().message.find("parameter 'size'"), std::string::npos);
    gate.open.set_value();
    EXPECT_TRUE(running.get());
    EXPECT_TRUE(queued.get());
}

TEST(RenderCache, DeadlinesAndVanishedClientsAreDeadlineExceededAndCancelTheRender) {
    Rig rig(1, 4, 100);  // 100 ms deadline
    RenderCache& cache = *rig.cache;
    workers::RenderPool& pool = *rig.pool;
    std::atomic<bool> gone{false};
    std::atomic<bool> sawCancel{false};
    // A render that runs until it is cancelled (bounded at 5 s).
    auto untilCancelled = [&](workers::WorkerState&, const std::atomic<bool>& cancel) -> Rendered {
        for (int i = 0; i < 2500 && !cancel.load(); ++i) std::this_thread::sleep_for(2ms);
        sawCancel = cancel.load();
        return makeError(ErrorCode::DeadlineExceeded, "cancelled");
    };
    const auto t0 = std::chrono::steady_clock::now();
    auto late = cache.render("slow", untilCancelled, 1, false, gone);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_FALSE(late);
    EXPECT_EQ(late.error().code, ErrorCode::DeadlineExceeded) << late.error().message;
    // Noticed within the 10 ms wait slices after the 100 ms deadline; 2 s of slack for a
    // loaded machine (the bound is that it returns at all, not a timing).
    EXPECT_GE(ms, 100.0);
    EXPECT_LT(ms, 2100.0);
    for (int i = 0; i < 1000 && pool.busyWorkers() > 0; ++i) std::this_thread::sleep_for(2ms);
    EXPECT_TRUE(sawCancel.load());  // the only waiter left: the render was cancelled

    // A client that goes away: the same outcome, and the render is cancelled.
    sawCancel = false;
    gone = true;
    auto left = cache.render("slow2", untilCancelled, 1, false, gone);
    ASSERT_FALSE(left);
    EXPECT_EQ(left.error().code, ErrorCode::DeadlineExceeded);
    EXPECT_NE(left.error().message.find("client went away"), std::string::npos);
    for (int i = 0; i < 1000 && pool.busyWorkers() > 0; ++i) std::this_thread::sleep_for(2ms);
    EXPECT_TRUE(sawCancel.load());
}

TEST(RenderCache, ARendersOwnErrorAndExceptionsComeBackTyped) {
    Rig rig(1, 4, 5000);
    RenderCache& cache = *rig.cache;
    std::atomic<bool> gone{false};
    auto bad = cache.render(
        "bad",
        [](workers::WorkerState&, const std::atomic<bool>&) -> Rendered {
            return makeError(ErrorCode::InvalidArgument, "parameter 'plane': misses the model");
        },
        1, false, gone);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(cache.find("bad"), nullptr);  // errors are not cached
    auto threw = cache.render(
        "throws", [](workers::WorkerState&, const std::atomic<bool>&) -> Rendered { throw std::runtime_error("boom"); },
        1, false, gone);
    ASSERT_FALSE(threw);
    EXPECT_EQ(threw.error().code, ErrorCode::Internal);
    EXPECT_NE(threw.error().message.find("boom"), std::string::npos);
}

}  // namespace
}  // namespace geoslice::server
