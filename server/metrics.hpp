// Prometheus metrics (text exposition format 0.0.4): requests per route and status,
// latency histograms per route, render-time histograms per kind, and gauges read at
// scrape time (queue depth, cache bytes and hits). Thread-safety: all members lock.
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
    void count(const std::string& name, const std::string& labels, std::uint64_t n = 1);
    // A gauge read when /metrics is scraped: name, help, value function.
    void gauge(const std::string& name, const std::string& help, std::function<double()> read);

    std::string text() const;

private:
    // Every member below is guarded by mutex_.
    mutable std::mutex mutex_;
    std::map<std::string, std::uint64_t> requests_;                         // labels -> count
    std::map<std::string, Histogram> latency_;                              // labels -> histogram
    std::map<std::string, Histogram> renders_;                              // labels -> histogram
    std::map<std::string, std::map<std::string, std::uint64_t>> counters_;  // name -> labels -> count
    struct Gauge {
        std::string name, help;
        std::function<double()> read;
    };
    std::vector<Gauge> gauges_;
};

}  // namespace geoslice::server
