// What /readyz reports about GL: the device the render workers' contexts run on and
// whether one is ready. Written by the render worker that probes GL (server start), read
// by HTTP threads (/readyz) at any time: every access takes the lock, and readers get a
// copy (issue 14: the device string was written and read without one).
#pragma once

#include <mutex>
#include <string>

namespace geoslice::workers {

class GlStatus {
public:
    struct Snapshot {
        std::string device = "not probed";  // "<vendor> <renderer> ..." or "failed: <reason>"
        bool ready = false;                 // a worker holds a working context
    };

    // Any thread.
    void set(std::string device, bool ready) {
        std::lock_guard lock(mutex_);
        state_.device = std::move(device);
        state_.ready = ready;
    }
    // Any thread: a consistent copy of the device and the ready flag.
    Snapshot get() const {
        std::lock_guard lock(mutex_);
        return state_;
    }

private:
    mutable std::mutex mutex_;
    Snapshot state_;  // guarded by mutex_
};

}  // namespace geoslice::workers
