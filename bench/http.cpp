// bench_http: the HTTP section server end to end over loopback, with its own keep-alive
// client threads (cpp-httplib), plus the work a query costs inside the server.
//
//   bench_http [--sizes L1,L4] [--seconds 3] [--connections 4] [--gl none|auto|egl-device|egl-surfaceless|osmesa]
//
// Per model size it starts a real SectionServer on 127.0.0.1 (models from a temporary
// directory holding the generated model), then measures, each for `seconds`:
//   section_jpeg_1024   GET section.jpg 1024x1024, a new plane every request (nothing cached)
//   perspective_jpeg_1024  (with --gl other than none) the same as a perspective view: the
//                       GL renderer on the render workers, a new plane every request
//   tile_cold           GET 256x256 tiles never asked before (render + encode)
//   tile_cached         GET the same 64 tiles again (LRU hits)
//   query_uncached      GET query of views never rendered (exact ray at the pixel)
//   query_cached        GET query of a rendered view (its cached ID buffer)
// and reports p50/p99 latency (ms) and throughput (requests/s). `inside_query_us` times
// api::queryPixel alone (no HTTP), cached and uncached, and the parse of the request.
// Prints one JSON document.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "api/pixel_query.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "bench/bench_util.hpp"
#include "model/io/gltf/gltf_io.hpp"
#include "model/synthetic/synthetic.hpp"
#include "server/http_server.hpp"

namespace {

using namespace geoslice;
using Json = nlohmann::ordered_json;

struct Stats {
    std::size_t requests = 0, errors = 0;
    double seconds = 0.0;
    std::vector<double> latencyMs;
    Json json() const {
        std::vector<double> v = latencyMs;
        std::sort(v.begin(), v.end());
        auto pct = [&](double p) {
            return v.empty() ? 0.0 : v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
        };
        return Json{{"requests", requests},
                    {"errors", errors},
                    {"throughput_rps", seconds > 0 ? double(requests) / seconds : 0.0},
                    {"p50_ms", pct(0.50)},
                    {"p99_ms", pct(0.99)},
                    {"max_ms", v.empty() ? 0.0 : v.back()}};
    }
};

// `connections` keep-alive clients, each asking url(i) for i = its next request number.
Stats load(int port, int connections, double seconds, const std::function<std::string(std::size_t)>& url,
           std::size_t maxRequests = SIZE_MAX) {
    Stats total;
    std::mutex m;
    std::atomic<std::size_t> next{0};
    const double t0 = bench::nowSeconds();
    std::vector<std::thread> threads;
    for (int c = 0; c < connections; ++c)
        threads.emplace_back([&] {
            httplib::Client cl("127.0.0.1", port);
            cl.set_keep_alive(true);
            cl.set_read_timeout(120, 0);
            std::vector<double> lat;
            std::size_t errors = 0;
            while (bench::nowSeconds() - t0 < seconds) {
                const std::size_t i = next++;
                if (i >= maxRequests) break;
                const std::string u = url(i);
                const double a = bench::nowSeconds();
                auto r = cl.Get(u.c_str());
                lat.push_back((bench::nowSeconds() - a) * 1e3);
                if (!r || r->status != 200) ++errors;
            }
            std::lock_guard lock(m);
            total.latencyMs.insert(total.latencyMs.end(), lat.begin(), lat.end());
            total.errors += errors;
        });
    for (auto& t : threads) t.join();
    total.seconds = bench::nowSeconds() - t0;
    total.requests = total.latencyMs.size();
    return total;
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::size_t p = 0;
    while (p <= s.size()) {
        const std::size_t c = std::min(s.find(',', p), s.size());
        if (c > p) out.push_back(s.substr(p, c - p));
        p = c + 1;
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    std::string sizes = "L1,L4", gl = "none";
    double seconds = 3.0;
    int connections = 4;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--sizes")
            sizes = argv[i + 1];
        else if (a == "--seconds")
            seconds = std::atof(argv[i + 1]);
        else if (a == "--connections")
            connections = std::atoi(argv[i + 1]);
        else if (a == "--gl")
            gl = argv[i + 1];
        else {
            std::fprintf(stderr,
                         "usage: bench_http [--sizes L1,L4] [--seconds 3] [--connections 4] "
                         "[--gl none|auto|egl-device|egl-surfaceless|osmesa]\n");
            return 2;
        }
    }
    // The server's log goes to stderr: stdout is the JSON document.
    spdlog::set_default_logger(spdlog::stderr_color_mt("bench_http"));
    spdlog::set_level(spdlog::level::warn);
    Json out;
    out["benchmark"] = "http";
    out["cores"] = std::thread::hardware_concurrency();
    out["seconds_per_case"] = seconds;
    out["connections"] = connections;
    Json results = Json::array();
    for (const std::string& size : split(sizes)) {
        const std::size_t triangles = bench::triangleCountFor(size);
        const auto dir = std::filesystem::temp_directory_path() / ("geoslice_bench_http_" + size);
        std::filesystem::create_directories(dir);
        SyntheticOptions so;
        so.triangles = triangles;
        so.crs = Crs::fromEpsg(4523).value();
        so.atLonLat = glm::dvec2(105.05, 30.62);
        auto model = generateSynthetic(so);
        if (!model) {
            std::fprintf(stderr, "bench_http: %s\n", model.error().message.c_str());
            return 1;
        }
        const std::string path = (dir / "mine.glb").string();
        if (auto s = writeGlb(model.value(), path); !s) {
            std::fprintf(stderr, "bench_http: %s\n", s.error().message.c_str());
            return 1;
        }
        const Aabb bounds = model.value().bounds();
        model = Result<Model>(makeError(ErrorCode::Internal, "released"));

        server::ServerConfig cfg;
        cfg.host = "127.0.0.1";
        cfg.port = 0;
        cfg.modelsDir = dir.string();
        cfg.gl = gl;
        cfg.cacheMiB = 1024;
        server::SectionServer srv(cfg);
        const double tLoad = bench::nowSeconds();
        auto port = srv.start();
        if (!port || !srv.waitUntilLoaded()) {
            std::fprintf(stderr, "bench_http: server failed to start or load\n");
            return 1;
        }
        Json r;
        r["size"] = size;
        r["triangles"] = triangles;
        r["server_load_s"] = bench::nowSeconds() - tLoad;
        const double y0 = bounds.min.y + 0.05 * (bounds.max.y - bounds.min.y);
        const double dy = 0.9 * (bounds.max.y - bounds.min.y);
        auto planeAt = [&](std::size_t i) {
            const double y = y0 + dy * double((i * 7919) % 10007) / 10007.0;
            return "plane=0,1,0," + api::formatNumber(-y);
        };
        // Warm the JIT-free path once (first request pays for page faults).
        (void)load(
            port.value(), 1, 60.0,
            [&](std::size_t) { return "/v1/models/mine/section.jpg?" + planeAt(99999) + "&size=1024x1024"; }, 1);

        r["section_jpeg_1024"] = load(port.value(), 2, seconds, [&](std::size_t i) {
                                     return "/v1/models/mine/section.jpg?" + planeAt(i) + "&size=1024x1024";
                                 }).json();

        if (gl != "none") {
            const std::string warm =
                "/v1/models/mine/section.jpg?" + planeAt(99998) + "&view=perspective&size=1024x1024";
            (void)load(
                port.value(), 1, 60.0, [&](std::size_t) { return warm; }, 1);
            r["perspective_jpeg_1024"] =
                load(port.value(), 2, seconds, [&](std::size_t i) {
                    return "/v1/models/mine/section.jpg?" + planeAt(i) + "&view=perspective&size=1024x1024";
                }).json();
        }

        // Tiles of one section at zoom 6 (64 x 64 grid): cold = each tile once, cached = 64 again.
        httplib::Client cl("127.0.0.1", port.value());
        auto def = cl.Post("/v1/models/mine/sections",
                           "{\"plane\": \"0,1,0," + api::formatNumber(-(y0 + dy / 2)) + "\"}", "application/json");
        const std::string sid = nlohmann::json::parse(def->body)["sid"];
        auto tileUrl = [&](std::size_t i) {
            const std::size_t x = i % 64, yy = 20 + (i / 64) % 24;
            return "/v1/sections/" + sid + "/tiles/6/" + std::to_string(x) + "/" + std::to_string(yy) + ".png";
        };
        r["tile_cold"] = load(port.value(), 2, seconds, tileUrl, 64 * 24).json();
        r["tile_cached"] =
            load(port.value(), connections, seconds, [&](std::size_t i) { return tileUrl(i % 64); }).json();

        // Queries: uncached views (never rendered), then a rendered view's ID buffer.
        const std::string cachedView = planeAt(4242) + "&size=1024x1024";
        (void)cl.Get(("/v1/models/mine/section.jpg?" + cachedView).c_str());
        r["query_uncached"] = load(port.value(), connections, seconds, [&](std::size_t i) {
                                  return "/v1/models/mine/query?" + planeAt(i) +
                                         "&size=1024x1024&px=" + std::to_string(i % 1024) +
                                         "&py=" + std::to_string((i * 37) % 1024);
                              }).json();
        r["query_cached"] = load(port.value(), connections, seconds, [&](std::size_t i) {
                                return "/v1/models/mine/query?" + cachedView + "&px=" + std::to_string(i % 1024) +
                                       "&py=" + std::to_string((i * 37) % 1024);
                            }).json();

        // Inside the server: the query's own work, no HTTP.
        auto m = srv.catalog().find("mine");
        api::Params params;
        params["plane"] = planeAt(4242).substr(6);
        params["size"] = "1024x1024";
        auto plan = api::parseViewPlan(params, "mine", m->model.crs).value();
        auto view = api::renderProfile(*m, plan).value();
        const int n = 20000;
        std::vector<double> parse, cachedUs, rayUs;
        for (int rep = 0; rep < 5; ++rep) {
            double a = bench::nowSeconds();
            for (int i = 0; i < n; ++i) {
                auto p = api::parseViewPlan(params, "mine", m->model.crs);
                if (!p) return 1;
                (void)p.value().canonical();
            }
            parse.push_back((bench::nowSeconds() - a) / n * 1e6);
            a = bench::nowSeconds();
            for (int i = 0; i < n; ++i) (void)api::queryPixel(*m, plan, i % 1024, (i * 37) % 1024, &view);
            cachedUs.push_back((bench::nowSeconds() - a) / n * 1e6);
            a = bench::nowSeconds();
            for (int i = 0; i < n; ++i) (void)api::queryPixel(*m, plan, i % 1024, (i * 37) % 1024, nullptr);
            rayUs.push_back((bench::nowSeconds() - a) / n * 1e6);
        }
        r["inside_query_us"] = {{"parse_and_canonical", bench::median(parse)},
                                {"answer_from_id_buffer", bench::median(cachedUs)},
                                {"answer_from_ray", bench::median(rayUs)}};
        srv.stop();
        std::filesystem::remove_all(dir);
        results.push_back(std::move(r));
    }
    out["results"] = std::move(results);
    out["peak_rss_mib"] = bench::peakRssMiB();
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
