// PROJ contexts for many threads (internal to model/; only model/crs/crs.cpp includes it).
//
// A PROJ context (PJ_CONTEXT) and every PJ object made in it may be used by one thread at
// a time, and building a PJ from the database costs tens to hundreds of microseconds while
// transforming one point with it costs about a microsecond. So the pool hands a caller a
// slot (one context plus the PJ objects already built in it, by key) for the length of one
// call and takes it back afterwards. Slots are made on demand, so there are as many as
// calls ever ran at once (a handful on an HTTP server, since each call is microseconds),
// and they live until the process ends.
//
// Every context has network access off (proj_context_set_enable_network(ctx, 0), which
// also overrides PROJ_NETWORK=ON in the environment) and logging off (errors are read
// back with proj_context_errno and returned as geoslice errors).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>

#include <proj.h>

namespace geoslice::proj {

class Slot {
public:
    Slot();
    ~Slot();
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;

    PJ_CONTEXT* ctx() const { return ctx_; }
    // The PJ cached under `key` in this slot, built by `make(ctx)` on first use; null when
    // `make` returned null (then nothing is cached and lastError() says why).
    template <class Make>
    PJ* get(std::uint64_t key, Make&& make) {
        if (auto it = objects_.find(key); it != objects_.end()) return it->second;
        PJ* p = make(ctx_);
        if (p) objects_.emplace(key, p);
        return p;
    }
    // PROJ's message for the context's last error, or "unknown PROJ error".
    std::string lastError() const;

private:
    PJ_CONTEXT* ctx_ = nullptr;
    std::unordered_map<std::uint64_t, PJ*> objects_;
};

// A slot held for the lifetime of this object.
class Lease {
public:
    Lease();
    ~Lease();
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    Slot& operator*() const { return *slot_; }
    Slot* operator->() const { return slot_.get(); }

private:
    std::unique_ptr<Slot> slot_;
};

// A small number per distinct text (a CRS definition or an operation pipeline), the same
// for the life of the process, for cache keys. Thread-safe.
std::uint32_t intern(const std::string& text);

// Cache keys: what is built, from which interned texts.
enum class ObjectKind : std::uint64_t { Crs = 1, CrsToCrs = 2, Pipeline = 3 };
inline std::uint64_t key(ObjectKind kind, std::uint32_t a, std::uint32_t b = 0) {
    return (static_cast<std::uint64_t>(kind) << 60) | (static_cast<std::uint64_t>(a) << 30) | b;
}

// Whether the contexts the pool makes allow network access (always false; for tests).
bool networkEnabled();

}  // namespace geoslice::proj
