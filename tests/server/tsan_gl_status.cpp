// Issue 14 (b): the GL device string of /readyz was written by a render worker and read by
// HTTP threads without a lock. workers/gl_status.hpp now guards it; this test drives it the
// way the server does (one worker thread writes, as probeGl() does, while HTTP threads
// read, as /readyz does) in a binary built with ThreadSanitizer, which exits non-zero
// (halt_on_error) on any race. Built only when the tree is not already built with ASan or
// for fuzzing (one sanitizer runtime per binary); under GEOSLICE_TSAN the whole tree is.
#include <atomic>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "workers/gl_status.hpp"

int main() {
    geoslice::workers::GlStatus status;
    std::atomic<bool> done{false};
    std::atomic<long> reads{0}, consistent{0};
    std::vector<std::thread> readers;
    for (int r = 0; r < 4; ++r)
        readers.emplace_back([&] {
            while (!done.load()) {
                const auto s = status.get();
                ++reads;
                // A ready status always names a device; a failed one never is ready.
                consistent += (s.ready ? s.device.rfind("device ", 0) == 0 : true) ? 1 : 0;
            }
        });
    std::thread worker([&] {
        for (int i = 0; i < 20000; ++i) {
            if (i % 2)
                status.set("device " + std::to_string(i) + " with a name longer than the small-string buffer", true);
            else
                status.set("failed: probe " + std::to_string(i), false);
        }
        done = true;
    });
    worker.join();
    for (auto& t : readers) t.join();
    std::printf("tsan_gl_status: %ld reads, %ld consistent\n", reads.load(), consistent.load());
    return reads.load() > 0 && consistent.load() == reads.load() ? 0 : 1;
}
