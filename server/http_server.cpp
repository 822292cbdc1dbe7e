#include "server/http_server.hpp"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <sys/stat.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "bake/package.hpp"
#include "server/http_transport.hpp"
#include "server/respond.hpp"
#include "server/router.hpp"
#include "server/routes/routes.hpp"
#include "server/server_state.hpp"

namespace geoslice::server {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

// The server's life cycle: start-up (state, routes, transport), the model loader, the GL
// probe and graceful shutdown. The routes live in server/routes/ (one family per file).
struct SectionServer::Impl {
    ServerState state;
    std::thread loader;
    std::mutex stopMutex;
    bool stopped = false;  // guarded by stopMutex
    std::mutex loadMutex;  // with loadDone: waitUntilLoaded() sleeps until state.loaded
    std::condition_variable loadDone;
    std::unique_ptr<Router> router;
    std::unique_ptr<HttpTransport> http;  // declared last: its handlers use all of the above

    Impl(ServerConfig c, api::AccessKeys keys) : state(std::move(c), std::move(keys)) {}

    // ---- life cycle ----------------------------------------------------------------
    // The models directory entries tried so far (loader thread only): id -> the entry's
    // signature when it was last loaded or refused (entrySignature), so an unchanged entry
    // is not tried again and a changed one is.
    std::map<std::string, std::string> tried;
    std::vector<std::string> skippedBefore;  // entries reported skipped by the last scan
    std::string dirError;                    // why the last scan could not read the directory

    // What changes when a model entry is rewritten: the file's (or a package's manifest's,
    // written last) size, inode and mtime, and with a bake dir its package's manifest there
    // (--no-bake replicas wait for the bake Job to write it). Empty parts for what is missing.
    std::string entrySignature(const std::string& id, const std::string& path) const {
        namespace fs = std::filesystem;
        auto sig = [](fs::path p) {
            std::error_code ec;
            if (fs::is_directory(p, ec)) p /= bake::kManifestFile;
            struct stat s {};
            if (::stat(p.c_str(), &s) != 0) return std::string("-");
            return fmt::format("{}:{}:{}.{}", s.st_size, s.st_ino, s.st_mtim.tv_sec, s.st_mtim.tv_nsec);
        };
        const std::string& bakeDir = state.config.bakeDir;
        // The sidecars read at load (drillholes, exploration lines, context): a changed one loads the
        // model again.
        auto sidecar = [&](const char* ext) { return sig(fs::path(path).replace_extension(ext)); };
        return sig(path) + "|" + (bakeDir.empty() ? "" : sig(fs::path(bakeDir) / id)) + "|" +
               sidecar(".drillholes.json") + "|" + sidecar(".sections.json") + "|" + sidecar(".context.geojson");
    }

    // Replaces the {id, KEY} entries of `list` (failed or warnings) for `id` by `entry`
    // (none when null). Caller holds failedMutex.
    static void replaceEntry(Json& list, const Json& id, Json entry) {
        Json kept = Json::array();
        for (auto& e : list)
            if (e["id"] != id) kept.push_back(std::move(e));
        if (!entry.is_null()) kept.push_back(std::move(entry));
        list = std::move(kept);
    }

    // Loads one model entry and publishes it (a new version replaces the one served).
    // `waitRays`: the model is published only once its ray scene is built (or failed), so a
    // replica that is ready answers every route fast; the first pass publishes at once and
    // /readyz waits for the scenes instead. Returns false when the model did not load.
    bool loadEntry(const std::string& id, const std::string& path, bool waitRays) {
        ServerState& st = state;
        const ServerConfig& config = st.config;
        const std::uint64_t maxFileBytes = std::uint64_t(config.maxModelMiB) << 20;
        auto m = api::loadCatalogModel(id, path, config.bakeDir, !config.noBake,
                                       waitRays ? api::RayBuild::Now : api::RayBuild::Deferred, maxFileBytes);
        if (!m) {
            spdlog::error("event=model_failed id={} path=\"{}\" error=\"{}\"", id, path, m.error().message);
            std::lock_guard lock(st.failedMutex);
            replaceEntry(st.failed, id, Json{{"id", id}, {"error", m.error().message}});
            return false;
        }
        const auto& model = m.value();
        if (waitRays) (void)model->rays->wait(RayQueries::Clock::time_point::max(), &st.draining);
        const auto before = st.catalog.find(id);
        spdlog::info("event={} id={} triangles={} ms={:.0f} version={}{}", before ? "model_reloaded" : "model_loaded",
                     id, model->model.triangleCount(), model->loadMs, model->version,
                     before ? " was=" + before->version : std::string());
        {
            std::lock_guard lock(st.failedMutex);
            replaceEntry(st.failed, id, nullptr);
            replaceEntry(st.warnings, id, nullptr);
            if (!model->loadWarning.empty()) {
                spdlog::warn("event=model_load_warning id={} warning=\"{}\"", id, model->loadWarning);
                st.warnings.push_back({{"id", id}, {"warning", model->loadWarning}});
            }
            if (!model->bakeWarning.empty()) {
                spdlog::warn("event=bake_failed id={} warning=\"{}\"", id, model->bakeWarning);
                st.warnings.push_back({{"id", id}, {"warning", model->bakeWarning}});
            }
            for (const std::string* w : {&model->drillholeWarning, &model->sectionsWarning, &model->contextWarning})
                if (!w->empty()) {
                    spdlog::warn("event=sidecar_not_loaded id={} warning=\"{}\"", id, *w);
                    st.warnings.push_back({{"id", id}, {"warning", *w}});
                }
        }
        if (!model->rebakedFrom.empty())
            spdlog::warn("event=package_rebaked id={} moved_aside=\"{}\"", id, model->rebakedFrom);
        for (const std::string& old : model->deletedCorruptCopies)
            spdlog::info("event=corrupt_copy_deleted id={} path=\"{}\" kept={}", id, old, api::kCorruptCopiesKept);
        const auto& notes = model->model.notes;
        if (auto w = notes.find("crs_warning"); w != notes.end())
            spdlog::warn("event=model_crs_warning id={} warning=\"{}\"", id, w->second);
        st.catalog.add(model);
        // First pass: every model's ray scene builds on a thread of its own as it is served
        // (queries that need one wait for it; /readyz is 503 until all are built).
        model->rays->start();
        return true;
    }

    // One scan of the models directory: entries that are new or changed since they were last
    // tried are loaded. Returns false when the directory could not be read or a model failed.
    bool scanModels(bool firstPass) {
        ServerState& st = state;
        const ServerConfig& config = st.config;
        auto files = api::scanModelsDir(config.modelsDir, std::uint64_t(config.maxModelMiB) << 20);
        if (!files) {
            // Logged when it starts or changes, not at every poll.
            if (dirError != files.error().message) {
                dirError = files.error().message;
                spdlog::error("event=models_dir_failed error=\"{}\"", dirError);
            }
            std::lock_guard lock(st.failedMutex);
            replaceEntry(st.failed, nullptr, Json{{"id", nullptr}, {"error", files.error().message}});
            return false;
        }
        if (!dirError.empty()) {
            dirError.clear();
            std::lock_guard lock(st.failedMutex);
            replaceEntry(st.failed, nullptr, nullptr);
        }
        // Entries that are not loaded (a FIFO, a dangling symlink, a file too large...): named
        // in the log (once) and /readyz, never a reason to block or to stay unready.
        std::vector<std::string> names;
        Json skipped = Json::array();
        for (const api::SkippedEntry& e : files.value().skipped) {
            names.push_back(e.entry + ": " + e.reason);
            if (std::find(skippedBefore.begin(), skippedBefore.end(), names.back()) == skippedBefore.end())
                spdlog::warn("event=models_dir_entry_skipped entry=\"{}\" reason=\"{}\"", e.entry, e.reason);
            skipped.push_back({{"entry", e.entry}, {"reason", e.reason}});
        }
        skippedBefore = std::move(names);
        {
            std::lock_guard lock(st.failedMutex);
            st.skipped = std::move(skipped);
        }
        if (firstPass && files.value().models.empty())
            spdlog::warn("event=models_dir_empty dir=\"{}\" poll_ms={}", config.modelsDir, config.modelsPollMs);
        bool ok = true;
        for (const auto& [id, path] : files.value().models) {
            if (st.draining) break;
            std::string sig = entrySignature(id, path);
            if (auto it = tried.find(id); it != tried.end() && it->second == sig) continue;
            tried[id] = std::move(sig);
            ok = loadEntry(id, path, !firstPass) && ok;
        }
        return ok;
    }

    void loadModels() {
        ServerState& st = state;
        const ServerConfig& config = st.config;
        bool ok = true;
        if (config.modelsDir.empty()) {
            spdlog::info("event=demo_generate triangles={}", config.demoTriangles);
            auto demo = api::makeDemoModel(config.demoTriangles);
            if (demo) {
                spdlog::info("event=model_loaded id=demo triangles={} ms={:.0f}", demo.value()->model.triangleCount(),
                             demo.value()->loadMs);
                st.catalog.add(demo.value());
                demo.value()->rays->start();
            } else {
                ok = false;
                spdlog::error("event=model_failed id=demo error=\"{}\"", demo.error().message);
                std::lock_guard lock(st.failedMutex);
                st.failed.push_back({{"id", "demo"}, {"error", demo.error().message}});
            }
        } else {
            ok = scanModels(true);
        }
        st.loadOk = ok;
        {
            std::lock_guard lock(loadMutex);
            st.loaded = true;
        }
        loadDone.notify_all();
        if (config.modelsDir.empty() || config.modelsPollMs == 0) return;
        // Then the directory is watched: a replica started before the bake Job wrote its
        // packages becomes ready when they appear, and a package baked again (a new version)
        // replaces the one served once its ray scene is built.
        while (!st.draining) {
            const auto until = Clock::now() + std::chrono::milliseconds(config.modelsPollMs);
            while (!st.draining && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(20));
            if (!st.draining) scanModels(false);
        }
    }

    void probeGl() {
        if (!state.glEnabled) return;
        // Create one worker's context now, so /readyz can report the device and the first
        // perspective request does not pay for it.
        workers::RenderJob job;
        job.run = [this](workers::WorkerState& w, const std::atomic<bool>&) {
            auto device = w.openGl();
            if (!device) {
                state.glStatus.set("failed: " + device.error().message, false);
                spdlog::warn("event=gl_unavailable error=\"{}\"", device.error().message);
                return;
            }
            spdlog::info("event=gl_ready device=\"{}\"", device.value());
            state.glStatus.set(device.value(), true);
        };
        if (state.pool->submit(std::move(job)) != workers::Admission::Queued)
            state.glStatus.set("failed: the render queue refused the probe", false);
    }
};

SectionServer::SectionServer(ServerConfig config) : config_(std::move(config)) {}

SectionServer::~SectionServer() { stop(); }

api::Catalog& SectionServer::catalog() { return impl_->state.catalog; }

Result<int> SectionServer::start() {
    if (auto s = checkConfig(config_); !s) return s.error();
    auto cors = corsPolicy(config_);
    if (!cors) return cors.error();
    auto keys = api::loadAccessKeys(config_.keysFile, config_.keys);
    if (!keys) return keys.error();
    impl_ = std::make_unique<Impl>(config_, std::move(keys.value()));
    Impl& im = *impl_;
    ServerState& st = im.state;
    workers::GlSettings gl;
    gl.enabled = st.glEnabled;
    gl.backend = config_.gl;
    gl.lod = config_.lod == "auto";
    const unsigned workers = config_.workers ? config_.workers : std::max(1u, std::thread::hardware_concurrency());
    st.pool = std::make_unique<workers::RenderPool>(workers, config_.queue, config_.memoryBudgetMiB << 20, gl);
    st.cache = std::make_unique<RenderCache>(config_.cacheMiB * (std::size_t(1) << 20), config_.deadlineMs, *st.pool,
                                             st.metrics);

    im.router = std::make_unique<Router>(st.metrics, cors.value(), st.keys, st.draining, st.inFlight);
    addAllRoutes(*im.router, st);

    // Values read at scrape time (their families and help: server/metrics.cpp).
    st.metrics.read("geoslice_queue_depth", [&st] { return double(st.pool->queueDepth()); });
    st.metrics.read("geoslice_render_overruns_total", [&st] { return double(st.pool->stats().overruns); });
    st.metrics.read("geoslice_renders_overrunning", [&st] { return double(st.pool->stats().overrunningNow); });
    st.metrics.read("geoslice_renders_dropped_total", [&st] { return double(st.pool->stats().dropped); });
    st.metrics.read("geoslice_render_memory_reserved_bytes", [&st] { return double(st.pool->stats().reservedBytes); });
    st.metrics.read("geoslice_workers_busy", [&st] { return double(st.pool->busyWorkers()); });
    st.metrics.read("geoslice_requests_in_flight", [&st] { return double(st.inFlight.load()); });
    st.metrics.read("geoslice_cache_bytes", [&st] { return double(st.cache->usedBytes()); });
    st.metrics.read("geoslice_cache_entries", [&st] { return double(st.cache->entries()); });
    st.metrics.read("geoslice_renders_coalesced_total", [&st] { return double(st.cache->coalesced()); });
    st.metrics.read("geoslice_models_loaded", [&st] { return double(st.catalog.size()); });
    auto raysIn = [&st](RayQueries::State s) {
        double n = 0;
        for (const auto& m : st.catalog.list()) n += m->rays->state() == s ? 1.0 : 0.0;
        return n;
    };
    st.metrics.read("geoslice_ray_scenes_building",
                    [raysIn] { return raysIn(RayQueries::State::Building) + raysIn(RayQueries::State::NotStarted); });
    st.metrics.read("geoslice_ray_scenes_ready", [raysIn] { return raysIn(RayQueries::State::Ready); });
    st.metrics.read("geoslice_ray_scenes_failed", [raysIn] { return raysIn(RayQueries::State::Failed); });

    TransportConfig tc;
    tc.host = config_.host;
    tc.port = config_.port;
    tc.reusePort = config_.reusePort;
    tc.ioThreads = std::max(1u, std::thread::hardware_concurrency() / 4);
    tc.handlerThreads = config_.httpThreads;
    tc.maxConnections = config_.maxConnections;
    tc.maxBodyBytes = config_.maxBodyBytes;
    tc.headerTimeoutMs = config_.headerTimeoutMs;
    tc.bodyTimeoutMs = config_.bodyTimeoutMs;
    tc.keepAliveMs = config_.keepAliveMs;
    tc.sendTimeoutMs = config_.sendTimeoutMs;
    tc.keepAliveRequests = config_.keepAliveRequests;
    im.http = std::make_unique<HttpTransport>(
        tc, [&im](HttpRequest& req, HttpResponse& res) { im.router->dispatch(req, res); },
        [](HttpResponse& res, int status, const std::string& detail, const std::string& path) {
            problem(res, status, detail, path,
                    status == 503   ? nullptr
                    : status == 413 ? "out_of_range"
                                    : "invalid_argument");
        });
    auto port = im.http->listen();
    if (!port) return port.error();
    port_ = port.value();
    HttpTransport& http = *im.http;
    st.metrics.read("geoslice_connections_open", [&http] { return double(http.stats().open); });
    st.metrics.read("geoslice_connections_refused_total", [&http] { return double(http.stats().rejected); });
    st.metrics.read("geoslice_connections_evicted_total", [&http] { return double(http.stats().evicted); });
    st.metrics.read("geoslice_connection_timeouts_total", [&http] {
        const auto s = http.stats();
        return double(s.headerTimeouts + s.bodyTimeouts + s.sendTimeouts);
    });
    st.metrics.read("geoslice_requests_abandoned_total", [&http] { return double(http.stats().cancelled); });
    http.start();
    im.loader = std::thread([&im] { im.loadModels(); });
    im.probeGl();
    // How many keys, never which.
    spdlog::info(
        "event=listening host={} port={} workers={} http_threads={} max_connections={} gl={} models=\"{}\" "
        "api_keys={} cors=\"{}\"",
        config_.host, port_, workers, tc.handlerThreads, tc.maxConnections, config_.gl,
        config_.modelsDir.empty() ? "demo" : config_.modelsDir, st.keys.size(), cors.value().describe());
    if (!st.keys.enabled() && !config_.modelsDir.empty())
        spdlog::warn(
            "event=no_api_keys warning=\"every client that reaches this port reads every model: give keys with "
            "--keys FILE or GEOSLICE_KEYS_FILE, or keep the port private\"");
    return port_;
}

bool SectionServer::waitUntilLoaded() {
    if (!impl_) return false;
    std::unique_lock lock(impl_->loadMutex);
    impl_->loadDone.wait(lock, [this] { return impl_->state.loaded.load(); });
    lock.unlock();
    for (const auto& m : impl_->state.catalog.list()) (void)m->rays->wait();
    return impl_->state.loadOk;
}

void SectionServer::wait() {
    if (!impl_) return;
    while (true) {
        {
            std::lock_guard lock(impl_->stopMutex);
            if (impl_->stopped) return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

void SectionServer::stop() {
    if (!impl_) return;
    Impl& im = *impl_;
    ServerState& st = im.state;
    std::lock_guard lock(im.stopMutex);
    if (im.stopped) return;
    st.draining = true;
    spdlog::info("event=shutdown_begin in_flight={}", st.inFlight.load());
    // In-flight requests get a grace period to finish (shutdownGraceMs, or the deadline
    // if shorter); then queued renders are dropped and running ones cancelled (they stop
    // within milliseconds), so SIGTERM ends within the grace period plus a second even
    // when a render would run for minutes.
    const auto until = Clock::now() + std::chrono::milliseconds(std::min(config_.deadlineMs, config_.shutdownGraceMs));
    while (st.inFlight > 0 && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!st.pool->stop(std::chrono::milliseconds(1000))) {
        // A render is inside a codec call that cannot be cancelled (libwebp's alpha pass on
        // a huge image): end the process now rather than overrun the grace period.
        spdlog::warn("event=shutdown_forced reason=\"a render did not stop within 1 s of its cancellation\"");
        spdlog::default_logger()->flush();
        std::_Exit(0);
    }
    const auto after = Clock::now() + std::chrono::milliseconds(1000);
    while (st.inFlight > 0 && Clock::now() < after) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    // Answers being written get a second; connections that wait for a request close now.
    if (im.http) im.http->stop(1000);
    if (im.loader.joinable()) im.loader.join();
    st.pool.reset();  // destroys the workers' GL contexts
    im.stopped = true;
    spdlog::info("event=shutdown_done");
}

}  // namespace geoslice::server
