#include "server/metrics.hpp"

#include <cstdio>
#include <stdexcept>

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

// Every family /metrics exports: name, type, help. A new metric is added here first.
// `labelled`: its series carry labels, so none is exported before the first event (an
// unlabelled counter or gauge is exported at 0 from start).
struct Family {
    const char* name;
    const char* type;
    const char* help;
    bool labelled = false;
};
constexpr Family kFamilies[] = {
    {"geoslice_http_requests_total", "counter",
     "HTTP requests by route template (\"(unmatched)\" when no route matched), method and status.", true},
    {"geoslice_http_request_duration_seconds", "histogram", "Time from request parsed to response ready, by route.",
     true},
    {"geoslice_render_duration_seconds", "histogram", "Render time (section engine or GL) before encoding, by kind.",
     true},
    {"geoslice_cache_total", "counter", "Cache lookups by cache (images, ids, etag) and result (hit, miss).", true},
    {"geoslice_queue_rejections_total", "counter",
     "Renders refused at admission (503), by reason (queue, memory, too_large).", true},
    {"geoslice_render_overruns_total", "counter", "Render jobs that ran past their deadline."},
    {"geoslice_renders_dropped_total", "counter", "Queued renders dropped: cancelled or past their deadline."},
    {"geoslice_renders_coalesced_total", "counter", "Requests that shared another request's render."},
    {"geoslice_render_waits_abandoned_total", "counter",
     "Requests that stopped waiting for a render because their client went away."},
    {"geoslice_deadline_exceeded_total", "counter", "Requests answered 504: their render missed the deadline."},
    {"geoslice_auth_failures_total", "counter", "Requests refused 401, by reason (missing, invalid, scheme).", true},
    {"geoslice_connections_refused_total", "counter", "Connections answered 503 at the connection cap."},
    {"geoslice_connections_evicted_total", "counter",
     "Connections waiting for a request closed to admit a new one at the cap."},
    {"geoslice_connection_timeouts_total", "counter", "Connections closed by a header, body or send deadline."},
    {"geoslice_requests_abandoned_total", "counter", "Requests whose client went away while being handled."},
    {"geoslice_queue_depth", "gauge", "Render jobs waiting."},
    {"geoslice_renders_overrunning", "gauge", "Render workers running past their deadline now."},
    {"geoslice_render_memory_reserved_bytes", "gauge", "Estimated memory of queued and running renders."},
    {"geoslice_workers_busy", "gauge", "Render workers busy."},
    {"geoslice_requests_in_flight", "gauge", "HTTP requests being handled."},
    {"geoslice_cache_bytes", "gauge", "Bytes held by the image and ID-buffer caches."},
    {"geoslice_cache_entries", "gauge", "Entries in the image and ID-buffer caches."},
    {"geoslice_models_loaded", "gauge", "Models loaded."},
    {"geoslice_ray_scenes_building", "gauge",
     "Models whose ray scene (pixel queries without a cached image, perspective queries, boreholes) is still to "
     "be built."},
    {"geoslice_ray_scenes_ready", "gauge", "Models whose ray scene is built."},
    {"geoslice_ray_scenes_failed", "gauge", "Models whose ray scene failed to build."},
    {"geoslice_connections_open", "gauge", "HTTP connections open."},
};

const Family& family(const std::string& name) {
    for (const Family& f : kFamilies)
        if (name == f.name) return f;
    throw std::logic_error("metric " + name + " is not declared in server/metrics.cpp");
}

void writeFamilyHead(std::string& out, const Family& f) {
    out += std::string("# HELP ") + f.name + " " + f.help + "\n# TYPE " + f.name + " " + f.type + "\n";
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

std::string Metrics::methodLabel(const std::string& method) {
    for (const char* m : {"GET", "HEAD", "POST", "PUT", "DELETE", "PATCH", "OPTIONS"})
        if (method == m) return method;
    return "other";
}

void Metrics::request(const std::string& route, const std::string& method, int status, double seconds) {
    const std::string base = "route=\"" + escapeLabel(route) + "\",method=\"" + methodLabel(method) + "\"";
    std::lock_guard lock(mutex_);
    ++requests_[base + ",status=\"" + std::to_string(status) + "\""];
    latency_[base].observe(seconds);
}

void Metrics::render(const std::string& kind, double seconds) {
    std::lock_guard lock(mutex_);
    renders_["kind=\"" + kind + "\""].observe(seconds);
}

void Metrics::count(const std::string& name, const std::string& labels, std::uint64_t n) {
    if (std::string(family(name).type) != "counter") throw std::logic_error("metric " + name + " is not a counter");
    std::lock_guard lock(mutex_);
    counters_[name][labels] += n;
}

void Metrics::read(const std::string& name, std::function<double()> value) {
    (void)family(name);
    std::lock_guard lock(mutex_);
    reads_[name] = std::move(value);
}

std::string Metrics::text() const {
    std::string out;
    std::lock_guard lock(mutex_);
    for (const Family& f : kFamilies) {
        const std::string name = f.name;
        writeFamilyHead(out, f);
        if (name == "geoslice_http_requests_total") {
            for (const auto& [labels, n] : requests_) out += name + "{" + labels + "} " + std::to_string(n) + "\n";
        } else if (name == "geoslice_http_request_duration_seconds") {
            for (const auto& [labels, h] : latency_) h.write(out, name, labels);
        } else if (name == "geoslice_render_duration_seconds") {
            for (const auto& [labels, h] : renders_) h.write(out, name, labels);
        } else if (const auto r = reads_.find(name); r != reads_.end()) {
            out += name + " " + number(r->second()) + "\n";
        } else if (const auto c = counters_.find(name); c != counters_.end()) {
            for (const auto& [labels, n] : c->second)
                out += name + (labels.empty() ? "" : "{" + labels + "}") + " " + std::to_string(n) + "\n";
        } else if (!f.labelled) {
            out += name + " 0\n";  // not counted yet, or not bound yet during start
        }
    }
    return out;
}

}  // namespace geoslice::server
