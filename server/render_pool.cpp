#include "server/render_pool.hpp"

#include "server/gl_worker.hpp"

namespace geoslice::server {

WorkerState::~WorkerState() = default;

RenderPool::RenderPool(unsigned workers, std::size_t queueCapacity) : capacity_(queueCapacity) {
    if (workers == 0) workers = 1;
    threads_.reserve(workers);
    for (unsigned i = 0; i < workers; ++i) threads_.emplace_back([this, i] { run(i); });
}

RenderPool::~RenderPool() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    ready_.notify_all();
    for (auto& t : threads_) t.join();
}

bool RenderPool::submit(std::function<void(WorkerState&)> job) {
    {
        std::lock_guard lock(mutex_);
        if (stopping_ || queue_.size() >= capacity_) return false;
        queue_.push_back(std::move(job));
    }
    ready_.notify_one();
    return true;
}

std::size_t RenderPool::queueDepth() const {
    std::lock_guard lock(mutex_);
    return queue_.size();
}

std::size_t RenderPool::busyWorkers() const {
    std::lock_guard lock(mutex_);
    return busy_;
}

void RenderPool::run(unsigned index) {
    WorkerState state;
    state.index = index;
    while (true) {
        std::function<void(WorkerState&)> job;
        {
            std::unique_lock lock(mutex_);
            ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
            if (queue_.empty()) return;  // stopping and drained
            job = std::move(queue_.front());
            queue_.pop_front();
            ++busy_;
        }
        job(state);
        std::lock_guard lock(mutex_);
        --busy_;
    }
}

}  // namespace geoslice::server
