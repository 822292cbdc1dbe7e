// section/partner_thread.hpp: a task runs on another thread, its writes are seen after the
// Job's wait, each calling thread keeps one partner across many runs, and a Job that goes
// out of scope waits for its task.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "section/partner_thread.hpp"

using namespace geoslice;

TEST(SectionPartnerThread, RunsOnOneKeptThreadAndPublishesItsWrites) {
    PartnerThread& partner = PartnerThread::forThisThread();
    EXPECT_EQ(&partner, &PartnerThread::forThisThread());
    std::thread::id first{};
    for (int round = 0; round < 200; ++round) {
        std::vector<int> data(1000, 0);
        std::thread::id ran;
        auto task = [&] {
            ran = std::this_thread::get_id();
            for (std::size_t i = 0; i < data.size(); ++i) data[i] = round + static_cast<int>(i);
        };
        PartnerThread::Job job = partner.run(task);
        job.wait();
        job.wait();  // a second wait returns at once
        ASSERT_NE(ran, std::this_thread::get_id());
        if (round == 0) first = ran;
        ASSERT_EQ(ran, first) << "round " << round;  // the same thread every time
        for (std::size_t i = 0; i < data.size(); ++i) ASSERT_EQ(data[i], round + static_cast<int>(i));
    }
}

TEST(SectionPartnerThread, EachCallingThreadHasItsOwnAndAJobWaitsWhenItLeavesScope) {
    std::atomic<int> sum{0};
    std::vector<std::thread> callers;
    for (int c = 0; c < 4; ++c)
        callers.emplace_back([&sum] {
            for (int round = 0; round < 50; ++round) {
                int local = 0;
                auto task = [&local] { local = 1; };
                {
                    PartnerThread::Job job = PartnerThread::forThisThread().run(task);
                }  // no explicit wait: the destructor waits
                sum += local;
            }
        });
    for (auto& t : callers) t.join();  // each caller's partner is joined as the caller exits
    EXPECT_EQ(sum.load(), 200);
}
