// A least-recently-used cache with a byte budget. Values are shared_ptr<const V>, so a
// reader keeps its value alive while it is evicted. V must have `std::size_t bytes() const`.
// Thread-safety: every member locks one mutex; lookups are O(1).
#pragma once

#include <atomic>
#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

namespace geoslice::server {

template <class V>
class LruCache {
public:
    explicit LruCache(std::size_t budgetBytes) : budget_(budgetBytes) {}

    std::shared_ptr<const V> get(const std::string& key) {
        std::lock_guard lock(mutex_);
        const auto it = map_.find(key);
        if (it == map_.end()) {
            ++misses_;
            return nullptr;
        }
        order_.splice(order_.begin(), order_, it->second);
        ++hits_;
        return it->second->value;
    }

    // Inserts or replaces; a value larger than the whole budget is not kept.
    void put(const std::string& key, std::shared_ptr<const V> value) {
        const std::size_t size = value->bytes() + key.size() + kOverhead;
        std::lock_guard lock(mutex_);
        if (const auto it = map_.find(key); it != map_.end()) {
            used_ -= it->second->size;
            order_.erase(it->second);
            map_.erase(it);
        }
        if (size > budget_) return;
        order_.push_front(Node{key, std::move(value), size});
        map_.emplace(key, order_.begin());
        used_ += size;
        while (used_ > budget_ && !order_.empty()) {
            const Node& last = order_.back();
            used_ -= last.size;
            map_.erase(last.key);
            order_.pop_back();
            ++evictions_;
        }
    }

    std::size_t usedBytes() const {
        std::lock_guard lock(mutex_);
        return used_;
    }
    std::size_t entries() const {
        std::lock_guard lock(mutex_);
        return map_.size();
    }
    std::size_t budgetBytes() const { return budget_; }
    std::uint64_t hits() const { return hits_; }
    std::uint64_t misses() const { return misses_; }
    std::uint64_t evictions() const { return evictions_; }

private:
    static constexpr std::size_t kOverhead = 96;  // node, map slot, key header
    struct Node {
        std::string key;
        std::shared_ptr<const V> value;
        std::size_t size;
    };
    mutable std::mutex mutex_;
    std::list<Node> order_;                                                    // guarded by mutex_; most recent first
    std::unordered_map<std::string, typename std::list<Node>::iterator> map_;  // guarded by mutex_
    const std::size_t budget_;
    std::size_t used_ = 0;  // guarded by mutex_
    std::atomic<std::uint64_t> hits_{0}, misses_{0}, evictions_{0};
};

}  // namespace geoslice::server
