// Issue 11 item 1: the real server (a child process) against the requests that crashed
// or pinned it. Every one must be a 400 naming the parameter, answered at once (a liveness
// bound, not a timing), with the server alive and answering /healthz afterwards.
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/common/serve_process.hpp"

namespace geoslice::test {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// The demo model's east-west section through its centre (northing 3388846 m).
const std::string kPlane = "plane=0,1,0,-3388846";
const std::string kLine = "line=35502500,3388000,35504500,3389000";
const std::string kSection = "/v1/models/demo/section.png?";

class HostileCrash : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        server_ = ServeProcess::start({"--gl", "none", "--demo-triangles", "20000", "--workers", "2"}).release();
        ASSERT_NE(server_, nullptr);
        ASSERT_TRUE(server_->waitReady()) << server_->log();
    }
    static void TearDownTestSuite() {
        delete server_;
        server_ = nullptr;
    }
    static ServeProcess* server_;
};
ServeProcess* HostileCrash::server_ = nullptr;

TEST_F(HostileCrash, CrashAndPinRequestsAre400FastAndLeaveTheServerFast) {
    // Item 1 of issue 11: SIGSEGV (1e-300, 1e-100; plane and line) and a worker pinned for
    // minutes (widths 1e-6..1e-20) on the release server before this fix.
    std::vector<std::string> frames = {"0,1e-300,0,1e-300", "0,1e-100,0,1e-100", "-100,100,1e-7,2e-7"};
    for (const char* w : {"1e-6", "1e-9", "1e-12", "1e-15", "1e-20"})
        frames.push_back(std::string("0,") + w + ",0," + w);
    std::vector<std::string> paths;
    for (const auto& f : frames) {
        paths.push_back(kSection + kPlane + "&size=256x128&frame=" + f);
        paths.push_back(kSection + kLine + "&size=256x128&frame=" + f);
        paths.push_back("/v1/models/demo/section.svg?" + kPlane + "&size=256x128&frame=" + f);
        paths.push_back("/v1/models/demo/query?" + kPlane + "&size=256x128&px=3&py=3&frame=" + f);
    }
    auto cl = server_->client(30);
    for (const auto& p : paths) {
        double best = 1e9;
        for (int i = 0; i < 3; ++i) {
            const auto t0 = Clock::now();
            auto r = cl.Get(p.c_str());
            const double ms = msSince(t0);
            ASSERT_TRUE(r) << p << ": no answer; server log:\n" << server_->log();
            EXPECT_EQ(r->status, 400) << p << "\n" << r->body;
            EXPECT_NE(r->body.find("parameter 'frame'"), std::string::npos) << r->body;
            best = std::min(best, ms);
        }
        // Not a timing figure (benchmarks measure; tests do not): a liveness bound 50x above
        // a normal answer, which a worker pinned for minutes, as before the fix, cannot meet.
        EXPECT_LT(best, 5000.0) << p;
    }
    EXPECT_TRUE(server_->running()) << server_->log();
    EXPECT_LT(healthzMs(*server_), 5000.0);  // answers at all: the server is not pinned
    // And a normal render still works.
    auto ok = cl.Get((kSection + kPlane + "&size=256x128").c_str());
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok->status, 200);
}

}  // namespace
}  // namespace geoslice::test
