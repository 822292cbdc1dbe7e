// The render cache: everything between "this request needs these bytes" and the bytes.
// It owns the cache keys (one function per kind of answer below), their ETags, the two
// LRUs (encoded answers; ID buffers for pixel queries), the coalescing of identical
// concurrent requests and the deadline a request waits for its render. It hands renders
// to the render workers (workers/render_pool.hpp) and returns a typed outcome:
//   ok                    the encoded bytes with their content type and ETag
//   Unavailable           queue full, memory budget taken, shutting down (503 + Retry-After)
//   DeadlineExceeded      the deadline passed or the client went away (504)
//   any other ErrorCode   the render's own error, or OutOfRange for a render larger than
//                         the whole memory budget
// Control flow reads only the ErrorCode, never a message. HTTP statuses are server/'s
// business (server/respond.hpp).
//
// Threads: every member may be called from any HTTP handler thread; render functions run
// on a render worker. The LRUs and the coalescer each lock their own mutex.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "api/catalog.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "model/result.hpp"
#include "server/lru_cache.hpp"
#include "server/metrics.hpp"
#include "workers/render_pool.hpp"

namespace geoslice::server {

// An encoded image, document or JSON body, as cached and served.
struct Encoded {
    std::string body;
    std::string contentType;
    std::string etag;  // quoted, as sent
    std::size_t bytes() const { return body.size() + etag.size() + contentType.size(); }
};

// What a query needs of a rendered view: the ID buffer and the pixel mapping.
struct IdBuffer {
    api::ViewImage view;  // rgba cleared
    std::size_t bytes() const { return view.bytes(); }
};

using Rendered = Result<std::shared_ptr<const Encoded>>;

// Bytes as whole MiB rounded up, for messages ("this render needs about 12 MiB").
inline std::string roundedMiB(std::size_t bytes) { return std::to_string((bytes + (std::size_t(1) << 20) - 1) >> 20); }
// Runs on a render worker; `cancel` is set when every request waiting for it left.
using RenderFn = std::function<Rendered(workers::WorkerState&, const std::atomic<bool>& cancel)>;

// Cache keys: the model's version, then the canonical form of what was asked. Two requests
// that mean the same thing get the same key; a new model version never meets old answers.
namespace cache_key {
std::string view(const api::CatalogModel& m, const api::ViewPlan& plan);  // also the ID buffer's key
std::string image(const std::string& viewKey, const std::string& extension, int quality);
// `form`: "svg", "geojson-world", "dxf-plane", ...: the format and its coordinate space.
std::string vector(const api::CatalogModel& m, const api::ViewPlan& plan, const std::string& form);
std::string sheet(const api::CatalogModel& m, const std::string& sheetCanonical, const std::string& extension,
                  int quality);
std::string tile(const api::CatalogModel& m, const api::SectionDef& def, int z, long long x, long long y,
                 const std::string& extension);
std::string legend(const api::CatalogModel& m, const api::SectionDef& def, const PropertyClasses* classes);
std::string reserves(const api::CatalogModel& m, const std::string& requestCanonical);
std::string queryBatch(const api::CatalogModel& m, const api::ViewPlan& plan, const std::string& pixelsJson);
// 3D Tiles: `what` is "tileset.json" or a tile's file name ("12.glb").
std::string tiles3d(const api::CatalogModel& m, const std::string& what);
}  // namespace cache_key

// Shares one computation among identical concurrent requests. `T` is the result type
// (copied out to each waiter: use a shared_ptr). Any thread; one mutex.
template <class T>
class Coalescer {
public:
    struct Ticket {
        std::shared_future<T> future;
        workers::CancelFlag cancel;  // the shared job's flag
        std::uint64_t id = 0;        // this computation (a key may be computed again later)
        bool leader = false;         // the caller created it: it must submit the work and make sure
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
        e.cancel = workers::makeCancelFlag();
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
        workers::CancelFlag cancel;
        std::uint64_t id = 0;
        int waiters = 1;
    };
    mutable std::mutex mutex_;
    std::map<std::string, Entry> pending_;      // guarded by mutex_
    std::uint64_t coalesced_ = 0, nextId_ = 0;  // guarded by mutex_
};

class RenderCache {
public:
    // budgetBytes: 3/4 for encoded answers, 1/4 for ID buffers. deadlineMs: how long a
    // request waits for its render. `metrics` must outlive this cache, and `pool` must be
    // stopped (its workers joined) before this cache is destroyed: a job still does its
    // bookkeeping here after its waiters have their answer.
    RenderCache(std::size_t budgetBytes, int deadlineMs, workers::RenderPool& pool, Metrics& metrics);

    // The ETag of a key (quoted, strong).
    static std::string etagOf(const std::string& key);

    // A cached answer, or null. `kind` (e.g. "image", "tile"): count the hit or miss in
    // geoslice_cache_total under that label; null: not counted.
    std::shared_ptr<const Encoded> find(const std::string& key, const char* kind = nullptr);
    // The ID buffer of a rendered view (cache_key::view), or null; counted as cache="ids".
    std::shared_ptr<const IdBuffer> findIds(const std::string& viewKey);
    // Keeps a rendered view's IDs for later pixel queries (its colour is dropped). Any thread.
    void keepIds(const std::string& viewKey, api::ViewImage&& view);

    // Runs `render` on a render worker, coalesced with identical requests by `key`, and
    // waits until it is done, the deadline passes or `clientGone` is set; the render is
    // cancelled when the last request waiting for it leaves. `memoryBytes`: its estimated
    // peak (admission). `gl`: the render uses the worker's GL context (only then is the
    // context rebuilt after an overrun). `keep`: cache the answer under `key`.
    Rendered render(const std::string& key, RenderFn render, std::size_t memoryBytes, bool gl,
                    const std::atomic<bool>& clientGone, bool keep = true);

    std::size_t usedBytes() const { return images_.usedBytes() + idBuffers_.usedBytes(); }
    std::size_t entries() const { return images_.entries() + idBuffers_.entries(); }
    std::uint64_t coalesced() const { return coalescer_.coalesced(); }

private:
    Error refusal(workers::Admission admission, std::size_t memoryBytes);
    LruCache<Encoded> images_;
    LruCache<IdBuffer> idBuffers_;
    Coalescer<std::shared_ptr<const Rendered>> coalescer_;
    const int deadlineMs_;
    workers::RenderPool& pool_;
    Metrics& metrics_;
};

}  // namespace geoslice::server
