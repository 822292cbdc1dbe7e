#include "server/metrics.hpp"

#include <cstdio>

namespace geoslice::server {
namespace {

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

std::string escapeLabel(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '\\' || c == '"') out += '\\';
        if (c == '\n') {
            out += "\\n";
            continue;
        }
        out += c;
    }
    return out;
}

}  // namespace

void Histogram::observe(double seconds) {
    for (std::size_t i = 0; i < kBounds.size(); ++i)
        if (seconds <= kBounds[i]) ++counts_[i];
    ++count_;
    sum_ += seconds;
}

void Histogram::write(std::string& out, const std::string& name, const std::string& labels) const {
    const std::string sep = labels.empty() ? "" : ",";
    for (std::size_t i = 0; i < kBounds.size(); ++i)
        out += name + "_bucket{" + labels + sep + "le=\"" + number(kBounds[i]) + "\"} " + std::to_string(counts_[i]) +
               "\n";
    out += name + "_bucket{" + labels + sep + "le=\"+Inf\"} " + std::to_string(count_) + "\n";
    out += name + "_sum{" + labels + "} " + number(sum_) + "\n";
    out += name + "_count{" + labels + "} " + std::to_string(count_) + "\n";
}

void Metrics::request(const std::string& route, const std::string& method, int status, double seconds) {
    const std::string base = "route=\"" + escapeLabel(route) + "\",method=\"" + method + "\"";
    std::lock_guard lock(mutex_);
    ++requests_[base + ",status=\"" + std::to_string(status) + "\""];
    latency_[base].observe(seconds);
}

void Metrics::render(const std::string& kind, double seconds) {
    std::lock_guard lock(mutex_);
    renders_["kind=\"" + kind + "\""].observe(seconds);
}

void Metrics::count(const std::string& name, const std::string& labels, std::uint64_t n) {
    std::lock_guard lock(mutex_);
    counters_[name][labels] += n;
}

void Metrics::gauge(const std::string& name, const std::string& help, std::function<double()> read) {
    std::lock_guard lock(mutex_);
    gauges_.push_back(Gauge{name, help, std::move(read)});
}

std::string Metrics::text() const {
    std::string out;
    std::lock_guard lock(mutex_);
    out += "# HELP geoslice_http_requests_total HTTP requests by route template, method and status.\n";
    out += "# TYPE geoslice_http_requests_total counter\n";
    for (const auto& [labels, n] : requests_)
        out += "geoslice_http_requests_total{" + labels + "} " + std::to_string(n) + "\n";
    out += "# HELP geoslice_http_request_duration_seconds Time from request parsed to response ready.\n";
    out += "# TYPE geoslice_http_request_duration_seconds histogram\n";
    for (const auto& [labels, h] : latency_) h.write(out, "geoslice_http_request_duration_seconds", labels);
    out += "# HELP geoslice_render_duration_seconds Render time (section engine or GL) before encoding, by kind.\n";
    out += "# TYPE geoslice_render_duration_seconds histogram\n";
    for (const auto& [labels, h] : renders_) h.write(out, "geoslice_render_duration_seconds", labels);
    for (const auto& [name, series] : counters_) {
        out += "# TYPE " + name + " counter\n";
        for (const auto& [labels, n] : series) out += name + "{" + labels + "} " + std::to_string(n) + "\n";
    }
    for (const Gauge& g : gauges_) {
        out += "# HELP " + g.name + " " + g.help + "\n# TYPE " + g.name + " gauge\n";
        out += g.name + " " + number(g.read()) + "\n";
    }
    return out;
}

}  // namespace geoslice::server
