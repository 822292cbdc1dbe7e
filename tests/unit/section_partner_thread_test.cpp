// section/cut/partner_thread.hpp: a task runs on another thread, its writes are seen after the
// Job's wait, each calling thread keeps one partner across many runs, a Job that goes out
// of scope waits for a started task, and a task not started by then is withdrawn, never run.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "section/cut/partner_thread.hpp"

using namespace geoslice;

namespace {

// Blocks until the task has begun on the partner (so wait() cannot withdraw it).
void awaitStart(const std::atomic<int>& started) {
    for (int s = started.load(); s == 0; s = started.load()) started.wait(s);
}

}  // namespace

TEST(SectionPartnerThread, RunsOnOneKeptThreadAndPublishesItsWrites) {
    PartnerThread& partner = PartnerThread::forThisThread();
    EXPECT_EQ(&partner, &PartnerThread::forThisThread());
    std::thread::id first{};
    for (int round = 0; round < 200; ++round) {
        std::vector<int> data(1000, 0);
        std::thread::id ran;
        std::atomic<int> started{0};
        auto task = [&] {
            started.store(1);
            started.notify_one();
            ran = std::this_thread::get_id();
            for (std::size_t i = 0; i < data.size(); ++i) data[i] = round + static_cast<int>(i);
        };
        PartnerThread::Job job = partner.run(task);
        awaitStart(started);
        ASSERT_TRUE(job.wait());
        ASSERT_TRUE(job.wait());  // a second wait returns at once, with the same answer
        ASSERT_NE(ran, std::this_thread::get_id());
        if (round == 0) first = ran;
        ASSERT_EQ(ran, first) << "round " << round;  // the same thread every time
        for (std::size_t i = 0; i < data.size(); ++i) ASSERT_EQ(data[i], round + static_cast<int>(i));
    }
}

TEST(SectionPartnerThread, ATaskNotStartedIsWithdrawnNeverRun) {
    // wait() straight after run(): the task either ran to the end or never runs at all.
    PartnerThread& partner = PartnerThread::forThisThread();
    std::atomic<int> runs{0};
    int reported = 0;
    for (int round = 0; round < 500; ++round) {
        auto task = [&runs] { runs.fetch_add(1); };
        PartnerThread::Job job = partner.run(task);
        reported += job.wait() ? 1 : 0;
    }
    // One more task that surely runs: every earlier one has ended or was withdrawn.
    std::atomic<int> started{0};
    auto last = [&] {
        started.store(1);
        started.notify_one();
    };
    PartnerThread::Job job = partner.run(last);
    awaitStart(started);
    EXPECT_TRUE(job.wait());
    EXPECT_EQ(runs.load(), reported);
}

TEST(SectionPartnerThread, EachCallingThreadHasItsOwnAndAJobWaitsWhenItLeavesScope) {
    std::atomic<int> sum{0};
    std::vector<std::thread> callers;
    for (int c = 0; c < 4; ++c)
        callers.emplace_back([&sum] {
            for (int round = 0; round < 50; ++round) {
                int local = 0;
                std::atomic<int> started{0};
                auto task = [&] {
                    started.store(1);
                    started.notify_one();
                    local = 1;
                };
                {
                    PartnerThread::Job job = PartnerThread::forThisThread().run(task);
                    awaitStart(started);
                }  // no explicit wait: the destructor waits
                sum += local;
            }
        });
    for (auto& t : callers) t.join();  // each caller's partner is joined as the caller exits
    EXPECT_EQ(sum.load(), 200);
}
