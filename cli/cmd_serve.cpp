// geoslice serve [--port N] [--models DIR] [--config FILE] [--gl ...]: the HTTP section
// server. Settings: defaults < config file < GEOSLICE_* environment < flags
// (server/config.hpp). SIGINT/SIGTERM shut it down gracefully.
#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <thread>

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include "api/catalog.hpp"
#include "cli/commands.hpp"
#include "server/container_memory.hpp"
#include "server/http_server.hpp"

namespace geoslice::cli {
namespace {

std::atomic<int> gSignal{0};
void onSignal(int sig) { gSignal = sig; }

struct ServeArgs {
    std::string configFile, host, models, bakeDir, sectionsDir, gl, lod, cors, keysFile, logLevel;
    int port = -1, deadlineMs = -1, shutdownGraceMs = -1;
    long long workers = -1, queue = -1, httpThreads = -1, cacheMiB = -1, demoTriangles = -1, maxBody = -1;
    long long memoryBudgetMiB = -1, maxModelMiB = -1, tiles3dTriangles = -1, modelsPollMs = -1;
    bool readyzPaths = false, noBake = false, bakeOnly = false;
    long long maxConnections = -1, headerTimeoutMs = -1, bodyTimeoutMs = -1, keepAliveMs = -1, keepAliveRequests = -1,
              sendTimeoutMs = -1;
    bool reusePort = false;
};

// serve --bake-only: every model of the models directory through the same load as a
// replica's (bake into the bake dir where the package is missing, stale or corrupt, then load
// it as a replica will: checksums, stored validation, BVH, ray scene), one line per model on
// stdout; exit 0 when every model loaded, 1 otherwise. The bake-once Job of
// deploy/kubernetes/geoslice.yaml runs it, so replicas (--no-bake) never bake.
int runBakeOnly(const server::ServerConfig& config) {
    if (config.modelsDir.empty() || config.bakeDir.empty()) {
        std::fprintf(stderr, "geoslice serve: --bake-only needs --models DIR and --bake-dir DIR\n");
        return 2;
    }
    const std::uint64_t maxFileBytes = std::uint64_t(config.maxModelMiB) << 20;
    auto scan = api::scanModelsDir(config.modelsDir, maxFileBytes);
    if (!scan) {
        std::fprintf(stderr, "geoslice serve: %s\n", scan.error().message.c_str());
        return 1;
    }
    for (const api::SkippedEntry& e : scan.value().skipped)
        std::printf("bake: skipped %s: %s\n", e.entry.c_str(), e.reason.c_str());
    const auto& files = scan.value().models;
    int failed = 0;
    for (const auto& [id, path] : files) {
        auto m = api::loadCatalogModel(id, path, config.bakeDir, /*mayBake=*/!config.noBake, api::RayBuild::Now,
                                       maxFileBytes);
        if (!m) {
            ++failed;
            std::printf("bake: %s failed: %s\n", id.c_str(), m.error().message.c_str());
        } else if (!m.value()->bakeWarning.empty()) {
            // --bake-only exists to bake: a model it could not bake is a failure here.
            ++failed;
            std::printf("bake: %s failed: %s\n", id.c_str(), m.value()->bakeWarning.c_str());
        } else {
            std::printf("bake: %s ready (%zu triangles, %.0f ms, version %s)%s%s\n", id.c_str(),
                        m.value()->model.triangleCount(), m.value()->loadMs, m.value()->version.c_str(),
                        m.value()->rebakedFrom.empty() ? "" : "; baked again, was ", m.value()->rebakedFrom.c_str());
        }
        std::fflush(stdout);
    }
    std::printf("bake: %zu models, %d failed\n", files.size(), failed);
    return failed ? 1 : 0;
}

int runServe(const ServeArgs& a) {
    server::ServerConfig config;
    if (!a.configFile.empty())
        if (auto s = server::applyConfigFile(config, a.configFile); !s) {
            std::fprintf(stderr, "geoslice serve: %s\n", s.error().message.c_str());
            return 2;
        }
    if (auto s = server::applyConfigEnv(config, server::processEnvironment()); !s) {
        std::fprintf(stderr, "geoslice serve: %s\n", s.error().message.c_str());
        return 2;
    }
    if (!a.host.empty()) config.host = a.host;
    if (a.port >= 0) config.port = a.port;
    if (!a.models.empty()) config.modelsDir = a.models;
    if (!a.bakeDir.empty()) config.bakeDir = a.bakeDir;
    if (!a.sectionsDir.empty()) config.sectionsDir = a.sectionsDir;
    if (!a.gl.empty()) config.gl = a.gl;
    if (!a.lod.empty()) config.lod = a.lod;
    if (!a.cors.empty()) config.cors = a.cors;
    if (!a.keysFile.empty()) config.keysFile = a.keysFile;
    if (!a.logLevel.empty()) config.logLevel = a.logLevel;
    if (a.deadlineMs > 0) config.deadlineMs = a.deadlineMs;
    if (a.shutdownGraceMs >= 0) config.shutdownGraceMs = a.shutdownGraceMs;
    if (a.workers >= 0) config.workers = unsigned(a.workers);
    if (a.queue > 0) config.queue = std::size_t(a.queue);
    if (a.httpThreads > 0) config.httpThreads = unsigned(a.httpThreads);
    if (a.maxConnections > 0) config.maxConnections = std::size_t(a.maxConnections);
    if (a.headerTimeoutMs > 0) config.headerTimeoutMs = int(a.headerTimeoutMs);
    if (a.bodyTimeoutMs > 0) config.bodyTimeoutMs = int(a.bodyTimeoutMs);
    if (a.keepAliveMs > 0) config.keepAliveMs = int(a.keepAliveMs);
    if (a.keepAliveRequests > 0) config.keepAliveRequests = std::size_t(a.keepAliveRequests);
    if (a.sendTimeoutMs > 0) config.sendTimeoutMs = int(a.sendTimeoutMs);
    if (a.reusePort) config.reusePort = true;
    if (a.cacheMiB >= 0) config.cacheMiB = std::size_t(a.cacheMiB);
    if (a.memoryBudgetMiB >= 0) config.memoryBudgetMiB = std::size_t(a.memoryBudgetMiB);
    if (a.readyzPaths) config.readyzPaths = true;
    if (a.noBake) config.noBake = true;
    if (a.maxModelMiB > 0) config.maxModelMiB = std::size_t(a.maxModelMiB);
    if (a.modelsPollMs >= 0) config.modelsPollMs = int(std::min(a.modelsPollMs, 3600001LL));
    if (a.tiles3dTriangles > 0) config.tiles3dTriangles = std::size_t(a.tiles3dTriangles);
    if (a.demoTriangles > 0) config.demoTriangles = std::size_t(a.demoTriangles);
    if (a.maxBody > 0) config.maxBodyBytes = std::size_t(a.maxBody);
    // Inside a container (or unit) with a memory limit, the render budget and the cache left at
    // their defaults shrink to their shares of it (server/container_memory.hpp).
    if (auto limit = server::containerMemoryLimit()) server::fitToContainer(config, *limit);
    if (auto s = server::checkConfig(config); !s) {
        std::fprintf(stderr, "geoslice serve: %s\n", s.error().message.c_str());
        return 2;
    }
    // A write past a file size limit (RLIMIT_FSIZE) fails with EFBIG and the bake reports it
    // (bake::writeFileAtomically) instead of the process dying of SIGXFSZ.
    std::signal(SIGXFSZ, SIG_IGN);
    if (a.bakeOnly) return runBakeOnly(config);
    // Logs go to stderr (one logfmt line per event); stdout carries only the banner.
    spdlog::set_default_logger(spdlog::stderr_logger_mt("geoslice"));
    spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%eZ level=%l %v", spdlog::pattern_time_type::utc);
    spdlog::set_level(spdlog::level::from_str(config.logLevel));

    server::SectionServer srv(config);
    auto port = srv.start();
    if (!port) {
        std::fprintf(stderr, "geoslice serve: %s\n", port.error().message.c_str());
        return 1;
    }
    std::printf("geoslice serving on http://%s:%d  (try /v1/models, /openapi.json; Ctrl-C stops)\n",
                config.host == "0.0.0.0" ? "localhost" : config.host.c_str(), port.value());
    std::fflush(stdout);
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    while (gSignal == 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    spdlog::info("event=signal signal={}", gSignal.load());
    srv.stop();
    return 0;
}

}  // namespace

void addServe(CLI::App& app, int& exitCode) {
    auto a = std::make_shared<ServeArgs>();
    CLI::App* cmd = app.add_subcommand("serve", "Run the HTTP section server (REST API, tiles, pixel queries)");
    cmd->add_option("--config", a->configFile, "JSON config file (keys as in server/config.hpp)");
    cmd->add_option("--host", a->host, "Address to listen on (default 0.0.0.0)");
    cmd->add_option("--port", a->port, "Port (default 8080; 0 = any free port)");
    cmd->add_option("--models", a->models, "Directory of model files (default: the built-in demo model)");
    cmd->add_option("--bake-dir", a->bakeDir,
                    "Bake raw models on first load into DIR/<id>/ (attribute-indexed texture packages)");
    cmd->add_option("--sections-dir", a->sectionsDir,
                    "Keep sections saved through the API (POST /v1/models/{id}/saved-sections) in DIR/<model id>/, "
                    "a directory shared by every replica (default: saving is off)");
    cmd->add_flag("--no-bake", a->noBake,
                  "Never bake (replicas on a read-only models volume): a model without a current baked package is "
                  "refused and named in /readyz");
    cmd->add_flag("--bake-only", a->bakeOnly,
                  "Bake every model of --models into --bake-dir (where missing, stale or corrupt), load each as a "
                  "replica will, print one line per model and exit (1 if any failed): the bake-once job");
    cmd->add_option("--gl", a->gl, "GL backend for perspective views: auto|egl-device|egl-surfaceless|osmesa|none");
    cmd->add_option("--lod", a->lod,
                    "3D views on CPU backends: off (default, exact) or auto (simplified geometry away from the cut)");
    cmd->add_option("--workers", a->workers, "Render workers (default: number of cores)");
    cmd->add_option("--queue", a->queue, "Render queue capacity (default 64; full -> 503)");
    cmd->add_option("--http-threads", a->httpThreads, "Requests handled at once (default 128)");
    cmd->add_option("--max-connections", a->maxConnections,
                    "Open connections (default 10000; then the longest-waiting idle one closes, else 503)");
    cmd->add_option("--header-timeout-ms", a->headerTimeoutMs,
                    "Deadline for a whole request header, ms (default 10000)");
    cmd->add_option("--body-timeout-ms", a->bodyTimeoutMs, "Deadline for a whole request body, ms (default 10000)");
    cmd->add_option("--keep-alive-ms", a->keepAliveMs, "Idle keep-alive connections close after, ms (default 5000)");
    cmd->add_option("--keep-alive-requests", a->keepAliveRequests, "Requests per connection (default 10000)");
    cmd->add_option("--send-timeout-ms", a->sendTimeoutMs,
                    "Deadline for the client to take an answer, ms per 8 MiB (default 10000)");
    cmd->add_flag("--reuse-port", a->reusePort, "SO_REUSEPORT: share the port with other processes (default: refused)");
    cmd->add_option("--cache-mib", a->cacheMiB, "Cache budget for images and ID buffers, MiB (default 512)");
    cmd->add_option(
        "--memory-budget-mib", a->memoryBudgetMiB,
        "Estimated memory of renders under way, MiB; beyond it 503 + Retry-After (default 4096; 0 = no limit)");
    cmd->add_option("--max-model-mib", a->maxModelMiB,
                    "Largest model file read, MiB (default 1024): a larger one is skipped, named in /readyz");
    cmd->add_option("--models-poll-ms", a->modelsPollMs,
                    "Scan --models again this often, ms (default 2000; 0 = only at start): new or changed models "
                    "load, a replica started before its packages were baked becomes ready when they appear");
    cmd->add_flag("--readyz-paths", a->readyzPaths,
                  "Show absolute file paths in /readyz model errors (default: names only)");
    cmd->add_option("--3dtiles-triangles", a->tiles3dTriangles,
                    "About this many triangles per leaf tile of /3dtiles/ (default 16384)")
        ->check(CLI::Range(256LL, 1LL << 24));
    cmd->add_option("--deadline-ms", a->deadlineMs, "Per-request render deadline, ms (default 10000)");
    cmd->add_option(
        "--shutdown-grace-ms", a->shutdownGraceMs,
        "After SIGTERM, in-flight requests may finish within this (and their deadline), ms (default 10000)");
    cmd->add_option("--max-body", a->maxBody, "Largest request body, bytes (default 1 MiB)");
    cmd->add_option("--cors-origins,--cors", a->cors,
                    "Which web pages on other origins may read answers (CORS): none, *, or origins separated by "
                    "commas (https://maps.example,http://localhost:8000; a listed Origin is echoed with Vary: "
                    "Origin). Default: * for the demo (no --models), none once --models is given");
    cmd->add_option("--keys", a->keysFile,
                    "API keys file (also GEOSLICE_KEYS_FILE; GEOSLICE_KEYS holds entries inline, ';' between "
                    "them): one 'NAME KEY MODELS' a line, MODELS = * or ids separated by commas, '#' comments. "
                    "Any key turns authentication on for every /v1 route: 'Authorization: Bearer KEY' or "
                    "'X-Api-Key: KEY'; none or a wrong one is 401, a model outside the key's list 403. /, /web, "
                    "/healthz, /readyz, /metrics and /openapi.json stay open and name no model");
    cmd->add_option("--demo-triangles", a->demoTriangles, "Size of the generated demo model (default 200000)");
    cmd->add_option("--log-level", a->logLevel, "trace|debug|info|warn|error|off (default info)");
    cmd->callback([a, &exitCode] { exitCode = runServe(*a); });
}

}  // namespace geoslice::cli
