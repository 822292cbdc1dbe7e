// A second thread kept for the calling thread, for the section engine's two-thread paths
// (section/cut/plane_cut.hpp cutWithBvh, section/cut/contours.hpp assembleContours): starting a
// std::thread per call cost each two-thread section two thread starts (clone, a new stack,
// the scheduler placing it: tens of microseconds each, a few percent of an L4 section).
//
// Each calling thread gets its own partner (thread_local), started on first use and joined
// when the calling thread exits, so concurrent callers (a server's render workers) never
// share or wait for one another's partner. Hand-offs go through atomic wait/notify (futex),
// not spinning: the two threads may share the cores with other work.
//
// A task is help, not a duty: when the caller waits for a task that the partner has not
// started yet (the scheduler has not run it: the cores are busy), the task is withdrawn and
// never runs. So a task may only take shares of work that the caller takes too, from a
// common counter, and the caller must never wait for the partner to take a share.
//
// On a busy machine help costs more than it brings: the partner competes for a core with other
// requests' threads, and a caller whose partner was preempted mid-share waits for the scheduler.
// So callers that run beside other work (a server) offer help only when a core is idle
// (coreIdle, kThreadsWhenIdle below): a lone request gets two threads, concurrent ones one each.
// Thread-safety: only the owning (calling) thread may call run and wait on its Job;
// coreIdle from any thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>

namespace geoslice {

// A thread count for the section engine's two-thread paths (SectionOptions::threads,
// cutWithBvh, assembleContours, the block raster): 2 when a core is idle now (coreIdle), else 1.
constexpr unsigned kThreadsWhenIdle = 0;

class PartnerThread {
public:
    // Whether some core has nothing to run now: the kernel's count of runnable threads
    // (/proc/loadavg's fourth field, this thread included) is below the cores this process
    // may use (sched_getaffinity). Sampled at most once a millisecond for the whole process
    // (a read costs a few microseconds); false where /proc cannot be read.
    static bool coreIdle();
    // `threads` with kThreadsWhenIdle resolved: 2 or 1 by coreIdle(); other values as given.
    static unsigned resolve(unsigned threads) { return threads == kThreadsWhenIdle ? (coreIdle() ? 2u : 1u) : threads; }

    // The calling thread's partner.
    static PartnerThread& forThisThread();

    // A task running on the partner; waits for it when it goes out of scope (also when an
    // exception leaves the caller's scope, so the task never outlives what it refers to).
    class Job {
    public:
        explicit Job(PartnerThread* p) : p_(p) {}
        Job(Job&& o) noexcept : p_(o.p_), ran_(o.ran_) { o.p_ = nullptr; }
        Job(const Job&) = delete;
        Job& operator=(const Job&) = delete;
        Job& operator=(Job&&) = delete;
        ~Job() { wait(); }
        // Withdraws the task if the partner has not started it, else blocks until it has
        // returned (once; later calls return at once). True when the task ran.
        bool wait() {
            const bool ran = p_ ? p_->wait() : ran_;
            p_ = nullptr;
            ran_ = ran;
            return ran;
        }

    private:
        PartnerThread* p_;
        bool ran_ = false;
    };

    // Offers `task` to the partner and returns at once; `task` must outlive the Job. One
    // task at a time per partner.
    template <class F>
    [[nodiscard]] Job run(F& task) {
        fn_ = [](void* t) { (*static_cast<F*>(t))(); };
        arg_ = &task;
        post(kPosted);
        return Job(this);
    }

    PartnerThread(const PartnerThread&) = delete;
    PartnerThread& operator=(const PartnerThread&) = delete;
    ~PartnerThread();

private:
    PartnerThread() = default;
    enum : std::uint32_t { kIdle = 0, kPosted = 1, kRunning = 2, kDone = 3, kQuit = 4 };
    void post(std::uint32_t state);
    void loop();
    bool wait();

    void (*fn_)(void*) = nullptr;
    void* arg_ = nullptr;
    std::atomic<std::uint32_t> state_{kIdle};
    std::thread thread_;
};

}  // namespace geoslice
