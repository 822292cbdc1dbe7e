// workers/: the render workers. N threads, each with its own state (and, for perspective views, its own
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
// (section/fill/raster.hpp, renderer/slice_renderer.hpp) and stops within milliseconds.
// stop() drops what is queued and sets the flag of what runs, then joins.
//
// Threads and locks: every member of RenderPool below `mutex_` is guarded by `mutex_`
// (the worker threads, the janitor and submitting threads all take it); a job's own state
// is touched only by the worker running it.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "api/catalog.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "model/result.hpp"

namespace geoslice::workers {

struct GlWorker;  // workers/gl_worker.hpp: the only place that touches GL

// Shared between a request (its transport sets it when the client goes away), the
// coalescer (when every waiter left) and the running job (which reads it). Any thread.
using CancelFlag = std::shared_ptr<std::atomic<bool>>;
inline CancelFlag makeCancelFlag() { return std::make_shared<std::atomic<bool>>(false); }

// How the workers use GL, chosen at start-up (server/config.hpp's --gl and --lod).
struct GlSettings {
    bool enabled = false;          // false: --gl none; perspective views are refused before they queue
    std::string backend = "auto";  // auto|egl-device|egl-surfaceless|osmesa (renderer/gl/gl_context.hpp)
    bool lod = false;              // simplified context geometry in 3D views (CPU backends)
};

// Per-worker state, owned by its thread: only that thread calls its members.
class WorkerState {
public:
    explicit WorkerState(unsigned index, GlSettings gl);
    ~WorkerState();  // releases the GL context on the worker's own thread
    WorkerState(const WorkerState&) = delete;
    WorkerState& operator=(const WorkerState&) = delete;

    unsigned index() const { return index_; }
    // Creates this worker's GL context when it has none. Returns the device it runs on
    // ("<vendor> <renderer> ..."). Errors: GL disabled, or the backend's own, naming it.
    Result<std::string> openGl();
    bool hasGl() const { return gl_ != nullptr; }
    // A perspective view (api::ViewKind::Perspective) with per-body record ids, on this
    // worker's GL context (created on first use). `cancel` may be null.
    Result<api::ViewImage> renderPerspective(const api::CatalogModel& model, const api::ViewPlan& plan,
                                             const std::atomic<bool>* cancel);
    // After an overrun: the context is thrown away and rebuilt by the next GL job.
    void discardGl();
    // After a large render: frees the render targets sized for it (the next render makes them again).
    void trimGl();

private:
    unsigned index_ = 0;
    GlSettings settings_;
    std::unique_ptr<GlWorker> gl_;  // created lazily by the first GL job on this worker
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
    // memoryBudgetBytes: 0 = no memory admission. `gl`: how each worker's context is made.
    RenderPool(unsigned workers, std::size_t queueCapacity, std::size_t memoryBudgetBytes = 0, GlSettings gl = {});
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
    std::deque<RenderJob> queue_;       // guarded by mutex_
    std::vector<std::thread> threads_;  // set in the constructor, joined by stop()
    std::thread janitor_;
    struct Running {
        CancelFlag cancel;
        std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
        bool active = false;
    };
    std::vector<Running> running_;  // guarded by mutex_ (one slot per worker)
    const std::size_t capacity_;
    const std::size_t budget_;
    const GlSettings gl_;
    std::size_t reserved_ = 0;                                         // guarded by mutex_
    std::size_t busy_ = 0;                                             // guarded by mutex_
    std::uint64_t dropped_ = 0, overruns_ = 0, cancelledRunning_ = 0;  // guarded by mutex_
    bool stopping_ = false;                                            // guarded by mutex_
    bool joined_ = false;                                              // guarded by mutex_
    unsigned exited_ = 0;  // worker threads that returned; guarded by mutex_
    std::condition_variable exitedCv_;
};

}  // namespace geoslice::workers
