#include "workers/render_pool.hpp"

namespace geoslice::workers {

using Clock = std::chrono::steady_clock;

RenderPool::RenderPool(unsigned workers, std::size_t queueCapacity, std::size_t memoryBudgetBytes, GlSettings gl)
    : capacity_(queueCapacity), budget_(memoryBudgetBytes), gl_(std::move(gl)) {
    if (workers == 0) workers = 1;
    running_.resize(workers);
    threads_.reserve(workers);
    for (unsigned i = 0; i < workers; ++i) threads_.emplace_back([this, i] { run(i); });
    janitor_ = std::thread([this] { janitor(); });
}

RenderPool::~RenderPool() { stop(); }

bool RenderPool::stop(std::chrono::milliseconds wait) {
    std::vector<RenderJob> dropped;
    {
        std::lock_guard lock(mutex_);
        if (joined_) return true;
        stopping_ = true;
        while (!queue_.empty()) {
            reserved_ -= std::min(reserved_, queue_.front().memoryBytes);
            dropped.push_back(std::move(queue_.front()));
            queue_.pop_front();
        }
        dropped_ += dropped.size();
        for (Running& r : running_)
            if (r.active && r.cancel) r.cancel->store(true);
    }
    const Error e = makeError(ErrorCode::Unavailable, "the server is shutting down");
    for (RenderJob& j : dropped) {
        j.cancel->store(true);
        if (j.drop) j.drop(e);
    }
    ready_.notify_all();
    janitorWake_.notify_all();
    {
        std::unique_lock lock(mutex_);
        const bool done = wait == std::chrono::milliseconds::max()
                              ? (exitedCv_.wait(lock, [this] { return exited_ == threads_.size(); }), true)
                              : exitedCv_.wait_for(lock, wait, [this] { return exited_ == threads_.size(); });
        if (!done) return false;
    }
    for (auto& t : threads_) t.join();
    if (janitor_.joinable()) janitor_.join();
    std::lock_guard lock(mutex_);
    joined_ = true;
    return true;
}

Admission RenderPool::submit(RenderJob job) {
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return Admission::Stopping;
        if (budget_ > 0 && job.memoryBytes > budget_) return Admission::TooLarge;
        if (queue_.size() >= capacity_) return Admission::QueueFull;
        if (budget_ > 0 && reserved_ + job.memoryBytes > budget_) return Admission::OverMemory;
        reserved_ += job.memoryBytes;
        queue_.push_back(std::move(job));
    }
    ready_.notify_one();
    return Admission::Queued;
}

std::size_t RenderPool::queueDepth() const {
    std::lock_guard lock(mutex_);
    return queue_.size();
}

std::size_t RenderPool::busyWorkers() const {
    std::lock_guard lock(mutex_);
    return busy_;
}

PoolStats RenderPool::stats() const {
    std::lock_guard lock(mutex_);
    PoolStats s;
    s.dropped = dropped_;
    s.overruns = overruns_;
    s.cancelledRunning = cancelledRunning_;
    s.queued = queue_.size();
    s.busy = busy_;
    s.reservedBytes = reserved_;
    const auto now = Clock::now();
    for (const Running& r : running_) s.overrunningNow += r.active && now > r.deadline;
    return s;
}

void RenderPool::takeExpired(std::vector<RenderJob>& out, Clock::time_point now) {
    for (auto it = queue_.begin(); it != queue_.end();) {
        if (it->cancel->load(std::memory_order_relaxed) || now > it->deadline) {
            reserved_ -= std::min(reserved_, it->memoryBytes);
            out.push_back(std::move(*it));
            it = queue_.erase(it);
            ++dropped_;
        } else {
            ++it;
        }
    }
}

namespace {

void dropAll(std::vector<RenderJob>& jobs) {
    for (RenderJob& j : jobs) {
        const bool cancelled = j.cancel->load();
        if (j.drop)
            j.drop(makeError(ErrorCode::DeadlineExceeded,
                             cancelled
                                 ? "dropped from the render queue: every client waiting for it went away"
                                 : "dropped from the render queue: its deadline passed before a worker was free"));
    }
    jobs.clear();
}

}  // namespace

void RenderPool::janitor() {
    std::vector<RenderJob> expired;
    std::unique_lock lock(mutex_);
    while (!stopping_) {
        janitorWake_.wait_for(lock, std::chrono::milliseconds(20));
        if (stopping_) break;
        takeExpired(expired, Clock::now());
        if (expired.empty()) continue;
        lock.unlock();
        dropAll(expired);
        lock.lock();
    }
}

void RenderPool::run(unsigned index) {
    struct Exit {
        RenderPool* pool;
        ~Exit() {
            std::lock_guard lock(pool->mutex_);
            ++pool->exited_;
            pool->exitedCv_.notify_all();
        }
    } exitMark{this};
    WorkerState state(index, gl_);
    std::vector<RenderJob> expired;
    while (true) {
        RenderJob job;
        {
            std::unique_lock lock(mutex_);
            ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
            if (stopping_) return;  // stop() dropped what was queued
            takeExpired(expired, Clock::now());
            if (queue_.empty()) {
                lock.unlock();
                dropAll(expired);
                continue;
            }
            job = std::move(queue_.front());
            queue_.pop_front();
            ++busy_;
            running_[index] = Running{job.cancel, job.deadline, true};
        }
        dropAll(expired);
        job.run(state, *job.cancel);
        std::lock_guard lock(mutex_);
        --busy_;
        reserved_ -= std::min(reserved_, job.memoryBytes);
        if (Clock::now() > job.deadline) ++overruns_;
        if (job.cancel->load()) ++cancelledRunning_;
        running_[index] = Running{};
    }
}

}  // namespace geoslice::workers
