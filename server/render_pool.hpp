// Render workers: N threads, each with its own state (and, for perspective views, its own
// GL context, created on that thread and never touched by another), fed by one bounded
// queue. HTTP handler threads never render: they submit a job and wait for its result
// with a deadline.
//
// Admission: a job is refused at once when the queue holds `queueCapacity` jobs, or when
// its estimated memory plus that of every queued and running job would pass the memory
// budget (the handler answers 503 + Retry-After); a job larger than the whole budget is
// refused for good.
//
// Cancellation: every job carries a cancel flag and a deadline. A queued job whose flag
// is set or whose deadline passed is dropped (a janitor looks every 20 ms, so the queue
// empties within that of its clients leaving); a running job reads its flag in its loops
// (section/raster.hpp, renderer/slice_renderer.hpp) and stops within milliseconds.
// stop() drops what is queued and sets the flag of what runs, then joins.
//
// Coalescing: identical concurrent requests (same key) share one job and one result; the
// job is cancelled when the last of its waiters leaves.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "model/result.hpp"

namespace geoslice::server {

struct GlWorker;  // server/gl_worker.hpp

// Shared between a request (its transport sets it when the client goes away), the
// coalescer (when every waiter left) and the running job (which reads it). Any thread.
using CancelFlag = std::shared_ptr<std::atomic<bool>>;
inline CancelFlag makeCancelFlag() { return std::make_shared<std::atomic<bool>>(false); }

// Per-worker state, owned by its thread.
struct WorkerState {
    unsigned index = 0;
    std::unique_ptr<GlWorker> gl;  // created lazily by the first GL job on this worker
    ~WorkerState();
};

struct RenderJob {
    std::function<void(WorkerState&, const std::atomic<bool>& cancel)> run;
    // Called instead of run when the job is dropped (cancelled or past its deadline while
    // queued, or the pool stops), with the reason; on the dropping thread.
    std::function<void(const Error&)> drop;
    CancelFlag cancel = makeCancelFlag();
    std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
    std::size_t memoryBytes = 0;  // estimated peak memory of the job (colour, ids, encoder...)
};

enum class Admission { Queued, QueueFull, OverMemory, TooLarge, Stopping };

struct PoolStats {
    std::uint64_t dropped = 0;           // queued jobs dropped (cancelled or past their deadline)
    std::uint64_t overruns = 0;          // jobs that ran past their deadline (counted when they end)
    std::uint64_t cancelledRunning = 0;  // running jobs whose flag was set before they ended
    std::size_t queued = 0, busy = 0;
    std::size_t overrunningNow = 0;  // workers whose running job is past its deadline
    std::size_t reservedBytes = 0;   // estimated memory of queued and running jobs
};

class RenderPool {
public:
    // memoryBudgetBytes: 0 = no memory admission.
    RenderPool(unsigned workers, std::size_t queueCapacity, std::size_t memoryBudgetBytes = 0);
    ~RenderPool();  // stop()
    RenderPool(const RenderPool&) = delete;
    RenderPool& operator=(const RenderPool&) = delete;

    Admission submit(RenderJob job);
    // Drops every queued job, sets the flag of every running one and waits up to `wait`
    // for the workers to finish; true when they did (they are then joined). False: a job
    // is stuck in code that cannot be cancelled (a codec's single call); the workers are
    // left running and the caller must end the process instead of destroying the pool.
    bool stop(std::chrono::milliseconds wait = std::chrono::milliseconds::max());

    std::size_t queueDepth() const;
    std::size_t busyWorkers() const;
    PoolStats stats() const;
    unsigned workers() const { return unsigned(threads_.size()); }
    std::size_t capacity() const { return capacity_; }
    std::size_t memoryBudget() const { return budget_; }

private:
    void run(unsigned index);
    void janitor();
    // Moves queued jobs that are cancelled or past their deadline into `out` (lock held).
    void takeExpired(std::vector<RenderJob>& out, std::chrono::steady_clock::time_point now);
    mutable std::mutex mutex_;
    std::condition_variable ready_, janitorWake_;
    std::deque<RenderJob> queue_;
    std::vector<std::thread> threads_;
    std::thread janitor_;
    struct Running {
        CancelFlag cancel;
        std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
        bool active = false;
    };
    std::vector<Running> running_;
    std::size_t capacity_;
    std::size_t budget_;
    std::size_t reserved_ = 0;
    std::size_t busy_ = 0;
    std::uint64_t dropped_ = 0, overruns_ = 0, cancelledRunning_ = 0;
    bool stopping_ = false;
    bool joined_ = false;
    unsigned exited_ = 0;  // worker threads that returned
    std::condition_variable exitedCv_;
};

// Shares one computation among identical concurrent requests. `T` is the result type
// (copied out to each waiter: use a shared_ptr).
template <class T>
class Coalescer {
public:
    struct Ticket {
        std::shared_future<T> future;
        CancelFlag cancel;     // the shared job's flag
        std::uint64_t id = 0;  // this computation (a key may be computed again later)
        bool leader = false;   // the caller created it: it must submit the work and make sure
                               // finish(key, id, value) is called exactly once
    };
    // Joins the computation of `key` under way, or starts one. A computation whose waiters
    // all left (cancelled) is not joined: a new one replaces it.
    Ticket join(const std::string& key) {
        std::lock_guard lock(mutex_);
        if (const auto it = pending_.find(key); it != pending_.end()) {
            if (!it->second.cancel->load()) {
                ++coalesced_;
                ++it->second.waiters;
                return Ticket{it->second.future, it->second.cancel, it->second.id, false};
            }
            pending_.erase(it);  // its job ends on its own; finish() then finds another id
        }
        Entry e;
        e.future = e.promise.get_future().share();
        e.cancel = makeCancelFlag();
        e.id = ++nextId_;
        Ticket t{e.future, e.cancel, e.id, true};
        pending_.emplace(key, std::move(e));
        return t;
    }
    // A waiter gives up (deadline, client gone): the last one to leave cancels the job.
    void leave(const std::string& key, std::uint64_t id) {
        std::lock_guard lock(mutex_);
        const auto it = pending_.find(key);
        if (it == pending_.end() || it->second.id != id) return;
        if (--it->second.waiters == 0) it->second.cancel->store(true);
    }
    void finish(const std::string& key, std::uint64_t id, T value) {
        std::lock_guard lock(mutex_);
        const auto it = pending_.find(key);
        if (it == pending_.end() || it->second.id != id) return;
        it->second.promise.set_value(std::move(value));
        pending_.erase(it);
    }
    std::size_t inFlight() const {
        std::lock_guard lock(mutex_);
        return pending_.size();
    }
    std::uint64_t coalesced() const {
        std::lock_guard lock(mutex_);
        return coalesced_;
    }

private:
    struct Entry {
        std::promise<T> promise;
        std::shared_future<T> future;
        CancelFlag cancel;
        std::uint64_t id = 0;
        int waiters = 1;
    };
    mutable std::mutex mutex_;
    std::map<std::string, Entry> pending_;
    std::uint64_t coalesced_ = 0, nextId_ = 0;
};

}  // namespace geoslice::server
