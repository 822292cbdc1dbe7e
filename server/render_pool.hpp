// Render workers: N threads, each with its own state (and, for perspective views, its own
// GL context, created on that thread and never touched by another), fed by one bounded
// queue. HTTP handler threads never render: they submit a job and wait for its result
// with a deadline. A full queue is refused at once (the handler answers 503 + Retry-After).
//
// Coalescing: identical concurrent requests (same key) share one job and one result.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace geoslice::server {

struct GlWorker;  // server/gl_worker.hpp

// Per-worker state, owned by its thread.
struct WorkerState {
    unsigned index = 0;
    std::unique_ptr<GlWorker> gl;  // created lazily by the first GL job on this worker
    ~WorkerState();
};

class RenderPool {
public:
    RenderPool(unsigned workers, std::size_t queueCapacity);
    ~RenderPool();  // runs the queued jobs, then joins
    RenderPool(const RenderPool&) = delete;
    RenderPool& operator=(const RenderPool&) = delete;

    // Queues a job; false when the queue holds queueCapacity jobs or the pool is stopping.
    bool submit(std::function<void(WorkerState&)> job);
    std::size_t queueDepth() const;
    std::size_t busyWorkers() const;
    unsigned workers() const { return unsigned(threads_.size()); }
    std::size_t capacity() const { return capacity_; }

private:
    void run(unsigned index);
    mutable std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<std::function<void(WorkerState&)>> queue_;
    std::vector<std::thread> threads_;
    std::size_t capacity_;
    std::size_t busy_ = 0;
    bool stopping_ = false;
};

// Shares one computation among identical concurrent requests. `T` is the result type
// (copied out to each waiter: use a shared_ptr).
template <class T>
class Coalescer {
public:
    // Returns the shared future of `key`; `leader` is true when the caller created it and
    // must run the work and then call finish(key, value) exactly once.
    std::shared_future<T> join(const std::string& key, bool& leader) {
        std::lock_guard lock(mutex_);
        if (const auto it = pending_.find(key); it != pending_.end()) {
            leader = false;
            ++coalesced_;
            return it->second.future;
        }
        Entry e;
        e.future = e.promise.get_future().share();
        auto future = e.future;
        pending_.emplace(key, std::move(e));
        leader = true;
        return future;
    }
    void finish(const std::string& key, T value) {
        std::lock_guard lock(mutex_);
        const auto it = pending_.find(key);
        if (it == pending_.end()) return;
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
    };
    mutable std::mutex mutex_;
    std::map<std::string, Entry> pending_;
    std::uint64_t coalesced_ = 0;
};

}  // namespace geoslice::server
