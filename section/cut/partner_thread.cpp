#include "section/cut/partner_thread.hpp"

namespace geoslice {

PartnerThread& PartnerThread::forThisThread() {
    thread_local PartnerThread partner;
    return partner;
}

void PartnerThread::post(std::uint32_t state) {
    if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
    state_.store(state, std::memory_order_release);
    state_.notify_one();
}

void PartnerThread::loop() {
    for (;;) {
        state_.wait(kIdle, std::memory_order_acquire);
        std::uint32_t s = kPosted;
        // Claim the task; fails when the owner withdrew it (back to kIdle) or quits.
        if (!state_.compare_exchange_strong(s, kRunning, std::memory_order_acq_rel)) {
            if (s == kQuit) return;
            continue;
        }
        fn_(arg_);
        state_.store(kDone, std::memory_order_release);
        state_.notify_one();
        // Sleep until the owner has seen kDone (it resets to kIdle) or posts again.
        state_.wait(kDone, std::memory_order_acquire);
    }
}

bool PartnerThread::wait() {
    std::uint32_t s = kPosted;
    if (state_.compare_exchange_strong(s, kIdle, std::memory_order_acq_rel)) return false;  // withdrawn
    for (s = state_.load(std::memory_order_acquire); s != kDone; s = state_.load(std::memory_order_acquire))
        state_.wait(s, std::memory_order_acquire);
    state_.store(kIdle, std::memory_order_release);
    state_.notify_one();
    return true;
}

PartnerThread::~PartnerThread() {
    if (!thread_.joinable()) return;
    state_.store(kQuit, std::memory_order_release);
    state_.notify_one();
    thread_.join();
}

}  // namespace geoslice
