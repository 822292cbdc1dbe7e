// What the route handlers share: the configuration, the model catalog, metrics, the render
// workers and the render cache, and the server's life-cycle flags. One instance per
// SectionServer, built by start() before the transport serves (server/http_server.cpp).
//
// Threads and locks: handlers read and call into it from any handler thread. `config` and
// `keys` are immutable; the catalog, metrics, GL status, render pool and render cache lock inside;
// the flags are atomics; `failed`, `skipped` and `warnings` are guarded by `failedMutex`.
#pragma once

#include <atomic>
#include <future>
#include <map>
#include <memory>
#include <mutex>

#include <nlohmann/json.hpp>

#include "api/access_keys.hpp"
#include "api/catalog.hpp"
#include "renderer/tiles3d/tileset3d.hpp"
#include "server/config.hpp"
#include "server/metrics.hpp"
#include "server/render_cache.hpp"
#include "workers/gl_status.hpp"
#include "workers/render_pool.hpp"

namespace geoslice::server {

struct ServerState {
    ServerState(ServerConfig c, api::AccessKeys k) : config(std::move(c)), keys(std::move(k)) {}

    const ServerConfig config;
    const api::AccessKeys keys;  // API keys (none: authentication off); HttpRequest::key points in here
    const bool glEnabled = config.gl != "none";
    api::Catalog catalog;
    // Sections saved through the API (config.sectionsDir); null when saving is off.
    const std::unique_ptr<const api::SavedSectionStore> savedSections =
        config.sectionsDir.empty() ? nullptr : std::make_unique<const api::SavedSectionStore>(config.sectionsDir);
    Metrics metrics;
    workers::GlStatus glStatus;  // written by the render worker that probes GL, read by /readyz
    // Set by start() before serving: the cache first, then the pool, so that the pool (whose
    // jobs use the cache and metrics) is destroyed first.
    std::unique_ptr<RenderCache> cache;
    std::unique_ptr<workers::RenderPool> pool;
    std::atomic<bool> draining{false};  // shutdown began: new requests get 503
    std::atomic<bool> loaded{false};    // the model loader is done
    std::atomic<bool> loadOk{false};    // ... and every model loaded
    std::atomic<int> inFlight{0};       // requests inside handlers (server/router.hpp)
    std::mutex failedMutex;
    nlohmann::ordered_json failed = nlohmann::ordered_json::array();  // guarded by failedMutex:
                                                                      // {id, error} of models that did not load
    // Guarded by failedMutex: {entry, reason} of models-directory entries not loaded
    // (api::scanModelsDir), and {id, warning} of models served with a warning (a failed bake).
    nlohmann::ordered_json skipped = nlohmann::ordered_json::array();
    nlohmann::ordered_json warnings = nlohmann::ordered_json::array();
    // 3D Tiles hierarchies (server/routes/tiles3d.cpp), built on a render worker at a model's
    // first 3D Tiles request and kept for that model version (one per model id: a new version
    // replaces the old). Guarded by tiles3dMutex; waiters share the one build.
    struct Tiles3dEntry {
        std::string version;
        std::shared_future<Result<std::shared_ptr<const Tileset3d>>> built;
    };
    std::mutex tiles3dMutex;
    std::map<std::string, Tiles3dEntry> tiles3d;
};

}  // namespace geoslice::server
