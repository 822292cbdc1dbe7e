// Prometheus metrics (text exposition format 0.0.4): requests per route and status,
// latency histograms per route, render-time histograms per kind, counters, and gauges read at
// scrape time (queue depth, cache bytes). Every family the server exports is declared in one
// table in metrics.cpp with its type and help, and is exported from start (an unlabelled
// counter at 0), so that `promtool check metrics` passes and dashboards never see a family
// appear. Cumulative counts are counters named *_total; gauges are levels only.
// Thread-safety: all members lock.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace geoslice::server {

class Histogram {
public:
    static constexpr std::array<double, 14> kBounds = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05,
                                                       0.1,    0.25,  0.5,    1.0,   2.5,  5.0,   10.0};
    void observe(double seconds);
    void write(std::string& out, const std::string& name, const std::string& labels) const;

private:
    std::array<std::uint64_t, kBounds.size()> counts_{};
    std::uint64_t count_ = 0;
    double sum_ = 0.0;
};

class Metrics {
public:
    void request(const std::string& route, const std::string& method, int status, double seconds);
    void render(const std::string& kind, double seconds);
    // Adds n to a counter of the table in metrics.cpp (an unknown name throws: declare it there).
    void count(const std::string& name, const std::string& labels, std::uint64_t n = 1);
    // Binds a counter or gauge of the table to a value read when /metrics is scraped (a count
    // kept elsewhere, such as the transport's). An unknown name throws.
    void read(const std::string& name, std::function<double()> value);
    // The HTTP method as a label: the standard methods, or "other" (a client chooses it).
    static std::string methodLabel(const std::string& method);

    static constexpr const char* kContentType = "text/plain; version=0.0.4; charset=utf-8";

    std::string text() const;

private:
    // Every member below is guarded by mutex_.
    mutable std::mutex mutex_;
    std::map<std::string, std::uint64_t> requests_;                         // labels -> count
    std::map<std::string, Histogram> latency_;                              // labels -> histogram
    std::map<std::string, Histogram> renders_;                              // labels -> histogram
    std::map<std::string, std::map<std::string, std::uint64_t>> counters_;  // name -> labels -> count
    std::map<std::string, std::function<double()>> reads_;                  // name -> value at scrape
};

}  // namespace geoslice::server
