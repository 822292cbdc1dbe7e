// bench_concurrent_sections [--size L4] [--planes 40] [--seconds 3] [--clients 1,2,4]: the
// exact section engine (computeSection: BVH, cut, contours) on a busy server. N client
// threads each compute sections of random planes back to back for --seconds, in three modes
// run one after another per N: one thread per section (threads = 1), a partner always
// (threads = 2) and the server's mode (kThreadsWhenIdle: a partner only while a core is idle,
// section/cut/partner_thread.hpp). Prints JSON: sections per second, p50 and p99 latency (ms)
// per N and mode, and the lone request's gain (N = 1: p50 of threads = 1 / p50 of each mode).
// Modes alternate in short rounds so that drifting load falls on all three alike.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "model/json_text.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "section/cut/contours.hpp"
#include "section/index/leaf_order.hpp"
#include "section/index/section_index.hpp"
#include "tests/common/random_plane.hpp"

using namespace geoslice;
using json = nlohmann::ordered_json;

namespace {

struct Mode {
    const char* name;
    unsigned threads;
};
constexpr Mode kModes[] = {{"one_thread", 1}, {"always_two", 2}, {"two_when_idle", kThreadsWhenIdle}};

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(p * double(v.size() - 1) + 0.5))];
}

}  // namespace

int main(int argc, char** argv) {
    std::string size = "L4", clientList = "1,2,4";
    int planeCount = 40;
    double seconds = 3.0;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size"))
            size = argv[i + 1];
        else if (!std::strcmp(argv[i], "--planes"))
            planeCount = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--seconds"))
            seconds = std::stod(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--clients"))
            clientList = argv[i + 1];
    }
    SyntheticOptions so;
    so.triangles = bench::triangleCountFor(size);
    so.crs = Crs::fromEpsg(4523).value();
    auto model = generateSynthetic(so);
    if (!model) {
        std::fprintf(stderr, "%s\n", model.error().message.c_str());
        return 1;
    }
    validate(model.value());
    if (auto s = reorderForSection(model.value()); !s) {
        std::fprintf(stderr, "%s\n", s.error().message.c_str());
        return 1;
    }
    auto index = buildSectionIndex(model.value());
    if (!index) {
        std::fprintf(stderr, "%s\n", index.error().message.c_str());
        return 1;
    }
    const SectionIndex& idx = *index.value();
    std::mt19937_64 rng(42);
    std::vector<Plane> planes;
    while (int(planes.size()) < planeCount) {
        const Plane p = test::randomPlane(model.value().bounds(), rng, int(planes.size() % 3));
        if (computeSection(idx, p)) planes.push_back(p);
    }
    std::vector<int> clients;
    std::stringstream cl(clientList);
    for (std::string c; std::getline(cl, c, ',');) clients.push_back(std::stoi(c));

    json runs = json::array();
    const std::string loadBefore = bench::loadAverage();
    // Short rounds, the modes in turn, until each mode has had `seconds`.
    constexpr double kRound = 0.5;
    for (int n : clients) {
        std::vector<std::vector<double>> lat(std::size(kModes));
        std::vector<double> busy(std::size(kModes), 0.0);
        std::vector<std::size_t> done(std::size(kModes), 0);
        for (double spent = 0.0; spent < seconds; spent += kRound) {
            for (std::size_t m = 0; m < std::size(kModes); ++m) {
                SectionOptions o;
                o.threads = kModes[m].threads;
                std::vector<std::vector<double>> mine(static_cast<std::size_t>(n));
                std::atomic<bool> stop{false};
                const double t0 = bench::nowSeconds();
                std::vector<std::thread> ts;
                for (int c = 0; c < n; ++c)
                    ts.emplace_back([&, c] {
                        std::size_t k = std::size_t(c) * 7;
                        while (!stop.load(std::memory_order_relaxed)) {
                            const double s0 = bench::nowSeconds();
                            auto s = computeSection(idx, planes[k++ % planes.size()], o);
                            if (!s) std::abort();
                            mine[std::size_t(c)].push_back((bench::nowSeconds() - s0) * 1000.0);
                        }
                    });
                std::this_thread::sleep_for(std::chrono::duration<double>(kRound));
                stop = true;
                for (auto& t : ts) t.join();
                busy[m] += bench::nowSeconds() - t0;
                for (auto& v : mine) {
                    done[m] += v.size();
                    lat[m].insert(lat[m].end(), v.begin(), v.end());
                }
            }
        }
        json run{{"clients", n}};
        for (std::size_t m = 0; m < std::size(kModes); ++m)
            run[kModes[m].name] = {{"sections_per_s", double(done[m]) / busy[m]},
                                   {"p50_ms", percentile(lat[m], 0.5)},
                                   {"p99_ms", percentile(lat[m], 0.99)}};
        const double base = run["one_thread"]["p50_ms"].get<double>();
        run["gain_p50_always_two"] = base / run["always_two"]["p50_ms"].get<double>();
        run["gain_p50_two_when_idle"] = base / run["two_when_idle"]["p50_ms"].get<double>();
        run["throughput_two_when_idle_vs_one"] =
            run["two_when_idle"]["sections_per_s"].get<double>() / run["one_thread"]["sections_per_s"].get<double>();
        run["p99_two_when_idle_vs_one"] =
            run["two_when_idle"]["p99_ms"].get<double>() / run["one_thread"]["p99_ms"].get<double>();
        std::fprintf(stderr, "%s\n", jsonText(run).c_str());
        runs.push_back(std::move(run));
    }
    json out{{"benchmark", "concurrent_sections"},
             {"size", size},
             {"triangles", model.value().triangleCount()},
             {"planes", planes.size()},
             {"seconds_per_mode", seconds},
             {"cores", std::thread::hardware_concurrency()},
             {"load_before", loadBefore},
             {"load_after", bench::loadAverage()},
             {"runs", runs}};
    std::printf("%s\n", jsonText(out, 1).c_str());
    return 0;
}
