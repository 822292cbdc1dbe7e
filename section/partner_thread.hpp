// A second thread kept for the calling thread, for the section engine's two-thread paths
// (section/plane_cut.hpp cutWithBvh, section/contours.hpp assembleContours): starting a
// std::thread per call cost each two-thread section two thread starts (clone, a new stack,
// the scheduler placing it: tens of microseconds each, a few percent of an L4 section).
//
// Each calling thread gets its own partner (thread_local), started on first use and joined
// when the calling thread exits, so concurrent callers (a server's render workers) never
// share or wait for one another's partner. Hand-offs go through atomic wait/notify (futex),
// not spinning: the two threads may share the cores with other work.
// Thread-safety: only the owning (calling) thread may call run and wait on its Job.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>

namespace geoslice {

class PartnerThread {
public:
    // The calling thread's partner.
    static PartnerThread& forThisThread();

    // A task running on the partner; waits for it when it goes out of scope (also when an
    // exception leaves the caller's scope, so the task never outlives what it refers to).
    class Job {
    public:
        explicit Job(PartnerThread* p) : p_(p) {}
        Job(Job&& o) noexcept : p_(o.p_) { o.p_ = nullptr; }
        Job(const Job&) = delete;
        Job& operator=(const Job&) = delete;
        Job& operator=(Job&&) = delete;
        ~Job() { wait(); }
        // Blocks until the task has returned (once; later calls return at once).
        void wait() {
            if (p_) p_->wait();
            p_ = nullptr;
        }

    private:
        PartnerThread* p_;
    };

    // Starts `task` on the partner and returns at once; `task` must outlive the Job. One
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
    enum : std::uint32_t { kIdle = 0, kPosted = 1, kDone = 2, kQuit = 3 };
    void post(std::uint32_t state);
    void loop();
    void wait();

    void (*fn_)(void*) = nullptr;
    void* arg_ = nullptr;
    std::atomic<std::uint32_t> state_{kIdle};
    std::thread thread_;
};

}  // namespace geoslice
