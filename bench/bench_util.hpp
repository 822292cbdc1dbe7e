// Small helpers shared by the benchmarks: model sizes, wall and CPU clocks, resident
// memory, medians.
#pragma once

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "model/synthetic/synthetic.hpp"

namespace geoslice::bench {

inline double nowSeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Peak resident set of this process so far, MiB.
inline double peakRssMiB() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;
}

// "L1".."L4" (the paper's Table 1 sizes) or a plain triangle count.
inline std::size_t triangleCountFor(const std::string& size) {
    if (auto n = namedModelSize(size)) return *n;
    return std::stoul(size);
}

// Resident set now, MiB (Linux /proc/self/statm; 4 KiB pages).
inline double currentRssMiB() {
    FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0.0;
    long pages = 0, rss = 0;
    if (std::fscanf(f, "%ld %ld", &pages, &rss) != 2) rss = 0;
    std::fclose(f);
    return double(rss) * 4096.0 / (1024.0 * 1024.0);
}

// Resets the process's peak RSS (Linux: "5" to clear_refs), so VmHWM measures one phase.
inline void resetPeakRss() {
    if (FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
        std::fputs("5", f);
        std::fclose(f);
    }
}
inline double peakRssSinceResetMiB() {
    FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return 0.0;
    char line[256];
    double kb = 0.0;
    while (std::fgets(line, sizeof line, f))
        if (!std::strncmp(line, "VmHWM:", 6)) kb = std::atof(line + 6);
    std::fclose(f);
    return kb / 1024.0;
}

// CPU time of this thread (s): on a shared machine it shows the cost without the waiting.
inline double threadCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
inline double processCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// The load average (1, 5, 15 minutes) as "a b c" from /proc/loadavg ("0.00 0.00 0.00" when
// unreadable): benchmarks print it, the machine being shared.
inline std::string loadAverage() {
    double l[3] = {0, 0, 0};
    if (FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (std::fscanf(f, "%lf %lf %lf", &l[0], &l[1], &l[2]) != 3) l[0] = l[1] = l[2] = 0;
        std::fclose(f);
    }
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f %.2f %.2f", l[0], l[1], l[2]);
    return buf;
}

inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace geoslice::bench
