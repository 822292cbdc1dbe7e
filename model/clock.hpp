// Milliseconds on the steady clock, the one way geoslice times a stage of its own work (load,
// cut, fill, render) for logs, stats and answers. Benchmarks time with bench/bench_util.hpp.
#pragma once

#include <chrono>

namespace geoslice {

// Milliseconds since `t0` on the steady clock.
inline double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace geoslice
