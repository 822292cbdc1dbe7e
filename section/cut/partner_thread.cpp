#include "section/cut/partner_thread.hpp"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>

namespace geoslice {
namespace {

// Cores this process may run on (its affinity mask; at least 1).
int usableCores() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof(set), &set) != 0) return 1;
    return std::max(1, CPU_COUNT(&set));
}

// Runnable threads now, from /proc/loadavg ("0.52 0.58 0.59 2/467 12345": the numerator of
// the fourth field); -1 when it cannot be read.
int runnableThreads() {
    const int fd = ::open("/proc/loadavg", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return -1;
    char buf[128];
    const ssize_t n = ::read(fd, buf, sizeof(buf) - 1);
    ::close(fd);
    if (n <= 0) return -1;
    buf[n] = '\0';
    const char* p = buf;
    for (int field = 0; field < 3; ++field) {
        while (*p && *p != ' ') ++p;
        while (*p == ' ') ++p;
    }
    char* end = nullptr;
    const long running = std::strtol(p, &end, 10);
    return end != p && *end == '/' ? int(running) : -1;
}

}  // namespace

bool PartnerThread::coreIdle() {
    using Clock = std::chrono::steady_clock;
    static const int cores = usableCores();
    if (cores < 2) return false;
    // One sample a millisecond for the whole process: (time in microseconds << 1) | idle.
    static std::atomic<std::int64_t> sample{-1};
    const std::int64_t now =
        std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
    const std::int64_t s = sample.load(std::memory_order_relaxed);
    if (s >= 0 && now - (s >> 1) < 1000) return s & 1;
    const int running = runnableThreads();
    const bool idle = running >= 0 && running < cores;
    sample.store((now << 1) | (idle ? 1 : 0), std::memory_order_relaxed);
    return idle;
}

PartnerThread& PartnerThread::forThisThread() {
    thread_local PartnerThread partner;
    return partner;
}

void PartnerThread::post(std::uint32_t state) {
    if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
    state_.store(state, std::memory_order_release);
    state_.notify_one();
}

void PartnerThread::loop() {
    for (;;) {
        state_.wait(kIdle, std::memory_order_acquire);
        std::uint32_t s = kPosted;
        // Claim the task; fails when the owner withdrew it (back to kIdle) or quits.
        if (!state_.compare_exchange_strong(s, kRunning, std::memory_order_acq_rel)) {
            if (s == kQuit) return;
            continue;
        }
        fn_(arg_);
        state_.store(kDone, std::memory_order_release);
        state_.notify_one();
        // Sleep until the owner has seen kDone (it resets to kIdle) or posts again.
        state_.wait(kDone, std::memory_order_acquire);
    }
}

bool PartnerThread::wait() {
    std::uint32_t s = kPosted;
    if (state_.compare_exchange_strong(s, kIdle, std::memory_order_acq_rel)) return false;  // withdrawn
    for (s = state_.load(std::memory_order_acquire); s != kDone; s = state_.load(std::memory_order_acquire))
        state_.wait(s, std::memory_order_acquire);
    state_.store(kIdle, std::memory_order_release);
    state_.notify_one();
    return true;
}

PartnerThread::~PartnerThread() {
    if (!thread_.joinable()) return;
    state_.store(kQuit, std::memory_order_release);
    state_.notify_one();
    thread_.join();
}

}  // namespace geoslice
