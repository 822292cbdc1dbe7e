#include "server/render_cache.hpp"

#include <malloc.h>

#include <chrono>

#include <spdlog/spdlog.h>

#include "api/params.hpp"

namespace geoslice::server {
namespace {

using Clock = std::chrono::steady_clock;

// After a render estimated above this, the worker gives its buffers back (the GL worker
// kept 1.47 GB after an 8192^2 view): render targets, then the heap's free pages.
constexpr std::size_t kTrimAfterBytes = std::size_t(256) << 20;

}  // namespace

namespace cache_key {

std::string view(const api::CatalogModel& m, const api::ViewPlan& plan) { return m.version + "|" + plan.canonical(); }

std::string image(const std::string& viewKey, const std::string& extension, int quality) {
    return viewKey + "|" + extension + "|q=" + std::to_string(quality);
}

std::string vector(const api::CatalogModel& m, const api::ViewPlan& plan, const std::string& form) {
    return m.version + "|" + plan.canonical() + "|" + form;
}

std::string sheet(const api::CatalogModel& m, const std::string& sheetCanonical, const std::string& extension,
                  int quality) {
    return m.version + "|" + sheetCanonical + "|" + extension + "|q=" + std::to_string(quality);
}

std::string tile(const api::CatalogModel& m, const api::SectionDef& def, int z, long long x, long long y,
                 const std::string& extension) {
    return m.version + "|tile|" + def.canonical() + "|" + std::to_string(z) + "/" + std::to_string(x) + "/" +
           std::to_string(y) + "|" + extension;
}

std::string tiles3d(const api::CatalogModel& m, const std::string& what) {
    return "3dtiles|" + m.id + "|" + m.version + "|" + what;
}

std::string legend(const api::CatalogModel& m, const api::SectionDef& def, const PropertyClasses* classes) {
    std::string key = "legend|" + m.id + "|" + m.version;
    if (def.colour) {
        key += "|" + def.colour->property + "|" + def.colour->ramp;
        if (classes)
            for (double b : classes->breaks) key += "|" + api::formatNumber(b);
    }
    return key;
}

std::string reserves(const api::CatalogModel& m, const std::string& requestCanonical) {
    return m.version + "|reserves|" + requestCanonical;
}

std::string queryBatch(const api::CatalogModel& m, const api::ViewPlan& plan, const std::string& pixelsJson) {
    return m.version + "|query|" + plan.canonical() + "|" + api::hex64(api::fnv1a64(pixelsJson));
}

}  // namespace cache_key

RenderCache::RenderCache(std::size_t budgetBytes, int deadlineMs, workers::RenderPool& pool, Metrics& metrics)
    : images_(budgetBytes * 3 / 4),
      idBuffers_(budgetBytes / 4),
      deadlineMs_(deadlineMs),
      pool_(pool),
      metrics_(metrics) {}

std::string RenderCache::etagOf(const std::string& key) { return "\"" + api::hex64(api::fnv1a64(key)) + "\""; }

std::shared_ptr<const Encoded> RenderCache::find(const std::string& key, const char* kind) {
    auto hit = images_.get(key);
    if (kind)
        metrics_.count("geoslice_cache_total",
                       std::string("cache=\"") + kind + "\",result=\"" + (hit ? "hit" : "miss") + "\"");
    return hit;
}

std::shared_ptr<const IdBuffer> RenderCache::findIds(const std::string& viewKey) {
    auto hit = idBuffers_.get(viewKey);
    metrics_.count("geoslice_cache_total", hit ? "cache=\"ids\",result=\"hit\"" : "cache=\"ids\",result=\"miss\"");
    return hit;
}

void RenderCache::keepIds(const std::string& viewKey, api::ViewImage&& v) {
    auto ids = std::make_shared<IdBuffer>();
    v.rgba.clear();
    v.rgba.shrink_to_fit();
    ids->view = std::move(v);
    idBuffers_.put(viewKey, std::move(ids));
}

Error RenderCache::refusal(workers::Admission admission, std::size_t memoryBytes) {
    using workers::Admission;
    switch (admission) {
        case Admission::Queued:
            break;
        case Admission::QueueFull:
            metrics_.count("geoslice_queue_rejections_total", "reason=\"queue\"");
            return makeError(ErrorCode::Unavailable,
                             "the render queue is full (" + std::to_string(pool_.capacity()) + " jobs); retry shortly");
        case Admission::OverMemory:
            metrics_.count("geoslice_queue_rejections_total", "reason=\"memory\"");
            return makeError(ErrorCode::Unavailable, "this render needs about " + roundedMiB(memoryBytes) +
                                                         " MiB and the memory budget (" +
                                                         roundedMiB(pool_.memoryBudget()) +
                                                         " MiB) is taken by renders under way; retry shortly");
        case Admission::TooLarge:
            metrics_.count("geoslice_queue_rejections_total", "reason=\"too_large\"");
            return makeError(ErrorCode::OutOfRange,
                             "parameter 'size': this render needs about " + roundedMiB(memoryBytes) +
                                 " MiB, more than the server's whole memory budget of " +
                                 roundedMiB(pool_.memoryBudget()) + " MiB; ask for fewer pixels");
        case Admission::Stopping:
            return makeError(ErrorCode::Unavailable, "the server is shutting down");
    }
    return makeError(ErrorCode::Internal, "render admission: unknown outcome");
}

Rendered RenderCache::render(const std::string& key, RenderFn render, std::size_t memoryBytes, bool gl,
                             const std::atomic<bool>& clientGone, bool keep) {
    const auto deadline = Clock::now() + std::chrono::milliseconds(deadlineMs_);
    auto ticket = coalescer_.join(key);
    if (ticket.leader) {
        workers::RenderJob job;
        job.cancel = ticket.cancel;
        job.deadline = deadline;
        job.memoryBytes = memoryBytes;
        job.run = [this, key, id = ticket.id, gl, keep, memoryBytes, render = std::move(render)](
                      workers::WorkerState& w, const std::atomic<bool>& cancel) {
            const auto t0 = Clock::now();
            Rendered r = makeError(ErrorCode::Internal, "render threw");
            try {
                r = render(w, cancel);
            } catch (const std::exception& e) {
                r = makeError(ErrorCode::Internal, std::string("render failed: ") + e.what());
            }
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            if (ms > deadlineMs_) {
                spdlog::warn("event=render_overrun key_hash={} ms={:.1f} deadline_ms={} cancelled={} gl_rebuilt={}",
                             api::hex64(api::fnv1a64(key)), ms, deadlineMs_, cancel.load(), gl && w.hasGl());
                if (gl) w.discardGl();  // a GL context that overran is rebuilt by the next GL job
            }
            if (memoryBytes >= kTrimAfterBytes) {
                if (gl) w.trimGl();
                malloc_trim(0);
            }
            if (r && keep) images_.put(key, r.value());
            coalescer_.finish(key, id, std::make_shared<const Rendered>(std::move(r)));
        };
        job.drop = [this, key, id = ticket.id](const Error& e) {
            coalescer_.finish(key, id, std::make_shared<const Rendered>(e));
        };
        if (const workers::Admission a = pool_.submit(std::move(job)); a != workers::Admission::Queued) {
            Error refused = refusal(a, memoryBytes);
            coalescer_.leave(key, ticket.id);
            coalescer_.finish(key, ticket.id, std::make_shared<const Rendered>(refused));
            return refused;
        }
    }
    // Wait in slices, so that a client that goes away is noticed within them.
    while (ticket.future.wait_for(std::chrono::milliseconds(10)) != std::future_status::ready) {
        if (clientGone.load(std::memory_order_relaxed)) {
            coalescer_.leave(key, ticket.id);
            metrics_.count("geoslice_render_waits_abandoned_total", "");
            return makeError(ErrorCode::DeadlineExceeded, "the client went away; its render was cancelled");
        }
        if (Clock::now() >= deadline) {
            coalescer_.leave(key, ticket.id);
            metrics_.count("geoslice_deadline_exceeded_total", "");
            return makeError(ErrorCode::DeadlineExceeded,
                             "the render did not finish within the deadline of " + std::to_string(deadlineMs_) +
                                 " ms; it is cancelled unless another request still waits for it");
        }
    }
    return *ticket.future.get();
}

}  // namespace geoslice::server
