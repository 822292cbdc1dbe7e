// Per-point cost of the coordinate conversions a query answer makes (api/view.cpp
// writeWorldPoint): the projected point to lon/lat on its own datum, and to WGS 84 through
// the model's chosen transformation; plus cs2cs-style conversions (`geoslice coords`).
// Each on 1 thread and on N threads at once (PROJ contexts come from a pool,
// model/crs/proj_pool.hpp). Prints one JSON document; medians of 5 runs, ns per point.
//   bench_crs [--points 200000] [--threads 2]
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_util.hpp"
#include "model/crs/crs.hpp"

using namespace geoslice;

namespace {

// Median over 5 runs of ns per point, `threads` threads each doing `points` calls.
double nsPerPoint(int points, int threads, const std::function<bool(int)>& call) {
    std::vector<double> runs;
    for (int run = 0; run < 5; ++run) {
        std::atomic<int> failures{0};
        const double t0 = bench::nowSeconds();
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t)
            pool.emplace_back([&, t] {
                for (int i = 0; i < points; ++i)
                    if (!call(i + t)) ++failures;
            });
        for (auto& th : pool) th.join();
        const double dt = bench::nowSeconds() - t0;
        if (failures.load() != 0) std::fprintf(stderr, "bench_crs: %d failed conversions\n", failures.load());
        runs.push_back(dt * 1e9 / points);  // wall time per point per thread
    }
    std::sort(runs.begin(), runs.end());
    return runs[runs.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    int points = 200000, threads = 2;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--points")) points = std::atoi(argv[i + 1]);
        if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
    }
    const Crs gk = Crs::fromEpsg(4523).value(), lv95 = Crs::fromEpsg(2056).value(),
              nad27 = Crs::fromEpsg(26711).value(), lv03 = Crs::fromEpsg(21781).value(),
              wgs84 = Crs::fromEpsg(4326).value();
    const CrsTransform la = CrsTransform::forArea(nad27, wgs84, {-118.6, 33.7, -117.6, 34.4}).value();
    const CrsTransform swiss = CrsTransform::forArea(lv95, wgs84, {7.3, 46.8, 7.6, 47.0}).value();

    struct Case {
        const char* name;
        std::function<bool(int)> call;
    };
    const std::vector<Case> cases = {
        {"cgcs2000_gk_to_lonlat_geographiclib",
         [&](int i) { return gk.toLonLat(35500000.0 + i % 1000, 3388000.0 + i % 777).ok(); }},
        {"lv95_to_lonlat_proj", [&](int i) { return lv95.toLonLat(2600000.0 + i % 1000, 1200000.0 + i % 777).ok(); }},
        {"lv95_to_wgs84_transform",
         [&](int i) {
             return swiss.apply({2600000.0 + i % 1000, 1200000.0, 500.0}).ok();
         }},
        {"nad27_utm11_to_wgs84_transform",
         [&](int i) {
             return la.apply({380000.0 + i % 1000, 3770000.0 + i % 777, 0.0}).ok();
         }},
        {"query_answer_nad27_lonlat_plus_wgs84",
         [&](int i) {
             const double x = 380000.0 + i % 1000, y = 3770000.0 + i % 777;
             return nad27.toLonLat(x, y).ok() && la.apply({x, y, 0.0}).ok();
         }},
        {"coords_lv03_to_lv95_crs_to_crs",
         [&](int i) {
             return convertPoint(lv03, lv95, {600000.0 + i % 1000, 200000.0, 0.0}).ok();
         }},
    };
    std::printf("{\n  \"points\": %d,\n  \"threads\": %d,\n  \"ns_per_point\": {\n", points, threads);
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const double one = nsPerPoint(points, 1, cases[k].call);
        const double many = nsPerPoint(points, threads, cases[k].call);
        std::printf("    \"%s\": {\"1_thread\": %.0f, \"%d_threads\": %.0f}%s\n", cases[k].name, one, threads, many,
                    k + 1 < cases.size() ? "," : "");
    }
    std::printf("  }\n}\n");
    return 0;
}
