#include "model/crs/proj_pool.hpp"

#include <mutex>
#include <vector>

#include "model/result.hpp"

namespace geoslice::proj {
namespace {

class Pool {
public:
    std::unique_ptr<Slot> take() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!free_.empty()) {
                auto s = std::move(free_.back());
                free_.pop_back();
                return s;
            }
        }
        return std::make_unique<Slot>();  // outside the lock: a context opens proj.db
    }
    void give(std::unique_ptr<Slot> s) {
        std::lock_guard<std::mutex> lock(mutex_);
        free_.push_back(std::move(s));
    }

private:
    std::mutex mutex_;
    std::vector<std::unique_ptr<Slot>> free_;
};

Pool& pool() {
    // Never destroyed: threads that outlive main() (detached HTTP workers) may still hold
    // or return slots while static destructors run.
    static Pool* p = new Pool;
    return *p;
}

struct Interned {
    std::mutex mutex;
    std::unordered_map<std::string, std::uint32_t> ids;
};

Interned& interned() {
    static Interned* t = new Interned;
    return *t;
}

}  // namespace

Slot::Slot() : ctx_(proj_context_create()) {
    GS_ASSERT(ctx_ != nullptr, "proj_context_create failed (out of memory)");
    proj_context_set_enable_network(ctx_, 0);
    proj_log_level(ctx_, PJ_LOG_NONE);
}

Slot::~Slot() {
    for (auto& [k, p] : objects_) proj_destroy(p);
    proj_context_destroy(ctx_);
}

std::string Slot::lastError() const {
    const int e = proj_context_errno(ctx_);
    const char* s = e ? proj_context_errno_string(ctx_, e) : nullptr;
    return s ? std::string(s) : std::string("unknown PROJ error");
}

Lease::Lease() : slot_(pool().take()) {}
Lease::~Lease() { pool().give(std::move(slot_)); }

std::uint32_t intern(const std::string& text) {
    Interned& t = interned();
    std::lock_guard<std::mutex> lock(t.mutex);
    const auto [it, fresh] = t.ids.emplace(text, static_cast<std::uint32_t>(t.ids.size() + 1));
    GS_ASSERT(it->second < (1u << 30), "too many distinct PROJ definitions");
    return it->second;
}

bool networkEnabled() {
    Lease lease;
    return proj_context_is_network_enabled(lease->ctx()) != 0;
}

}  // namespace geoslice::proj
