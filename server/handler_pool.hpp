// The transport's handler pool (private to server/http_transport.cpp and
// server/http_connection.cpp): a fixed number of threads running queued request handlers in
// order of arrival; routes may block on render workers, so handlers never run on I/O threads.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace geoslice::server::transport_detail {

class HandlerPool {
public:
    explicit HandlerPool(unsigned threads) {
        for (unsigned i = 0; i < std::max(1u, threads); ++i) threads_.emplace_back([this] { run(); });
    }
    ~HandlerPool() { stop(); }
    void submit(std::function<void()> job) {
        {
            std::lock_guard lock(mutex_);
            queue_.push_back(std::move(job));
        }
        ready_.notify_one();
    }
    std::size_t pending() const {
        std::lock_guard lock(mutex_);
        return queue_.size() + busy_;
    }
    // Runs what is queued, then joins.
    void stop() {
        {
            std::lock_guard lock(mutex_);
            stopping_ = true;
        }
        ready_.notify_all();
        for (auto& t : threads_)
            if (t.joinable()) t.join();
    }

private:
    void run() {
        std::unique_lock lock(mutex_);
        while (true) {
            ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
            if (queue_.empty()) return;
            auto job = std::move(queue_.front());
            queue_.pop_front();
            ++busy_;
            lock.unlock();
            try {
                job();
            } catch (...) {
                // A job answers its own errors (the connection's last catch); nothing may
                // leave a pool thread, which would end the process.
            }
            lock.lock();
            --busy_;
        }
    }
    mutable std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<std::function<void()>> queue_;  // guarded by mutex_
    std::vector<std::thread> threads_;         // set by the constructor, joined by stop()
    std::size_t busy_ = 0;                     // guarded by mutex_
    bool stopping_ = false;                    // guarded by mutex_
};

}  // namespace geoslice::server::transport_detail
