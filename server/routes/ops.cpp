// The operator's routes: GET /healthz (alive), /readyz (models in with their ray scenes
// built, GL ready, workers not all overrunning; 503 otherwise; models.failed,
// models.skipped (directory entries not loaded, with the reason) and models.warnings
// (models served unbaked) are reported, never a reason to be unready), /metrics
// (Prometheus text), /openapi.json. All open while API keys are on (probes and scrapers
// carry none), so none of them names a model then: /readyz counts failed, skipped and
// warned models and ray scenes instead of naming them, and /metrics has no model in any
// label (route templates, kinds and counts only).
#include "api/openapi.hpp"
#include "model/version.hpp"
#include "server/respond.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {
namespace {

// Absolute file-system paths in a message, cut to their last component ("/srv/models/a.glb"
// -> ".../a.glb"), for answers that anyone may read (/readyz).
std::string redactPaths(const std::string& s) {
    std::string out;
    std::size_t i = 0;
    while (i < s.size()) {
        const bool starts = s[i] == '/' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\'' || s[i - 1] == '"' ||
                                            s[i - 1] == '(' || s[i - 1] == '=');
        if (!starts) {
            out += s[i++];
            continue;
        }
        std::size_t end = i;
        while (end < s.size() && s[end] != ' ' && s[end] != '\'' && s[end] != '"' && s[end] != ')' && s[end] != ':' &&
               s[end] != ',')
            ++end;
        const std::string path = s.substr(i, end - i);
        const std::size_t slash = path.find_last_of('/');
        out += ".../" + path.substr(slash + 1);
        i = end;
    }
    return out;
}

void readyz(ServerState& st, HttpResponse& res) {
    // Ready once loading is done, at least one model is in, and every served model's ray
    // scene is built (or failed, reported below): a ready replica answers every route fast,
    // pixel queries and boreholes included. A broken file in the models directory is
    // reported here and in the logs, not a reason to stay unready. A replica whose models
    // directory is empty (the bake Job has not written the packages yet) stays unready and
    // keeps looking (modelsPollMs).
    bool raysSettled = true;
    for (const auto& m : st.catalog.list()) {
        const RayQueries::State s = m->rays->state();
        raysSettled = raysSettled && (s == RayQueries::State::Ready || s == RayQueries::State::Failed);
    }
    const bool modelsReady = st.loaded && st.catalog.size() > 0 && raysSettled;
    const workers::GlStatus::Snapshot gl = st.glStatus.get();
    const bool glOk = !st.glEnabled || gl.ready;
    Json failures, skipped, warnings;
    {
        std::lock_guard lock(st.failedMutex);
        failures = st.failed;
        skipped = st.skipped;
        warnings = st.warnings;
    }
    // While API keys are on, model ids are confidential and this route is open: failures,
    // skipped entries, warnings and ray scenes are counted, not named (the log names them).
    const bool anonymous = st.keys.enabled();
    if (anonymous) {
        failures = failures.size();
        skipped = skipped.size();
        warnings = warnings.size();
    }
    if (!st.config.readyzPaths && !anonymous)
        for (Json* list : {&failures, &skipped, &warnings})
            for (auto& f : *list)
                for (const char* key : {"error", "reason", "warning"})
                    if (f.contains(key) && f[key].is_string()) f[key] = redactPaths(f[key].get<std::string>());
    // Renders: overruns are counted; when every worker is running past its deadline the
    // server cannot take work and says so.
    const workers::PoolStats ps = st.pool->stats();
    const bool workersOk = ps.overrunningNow < st.pool->workers();
    Json renders{{"queued", ps.queued},
                 {"busy", ps.busy},
                 {"overruns", ps.overruns},
                 {"overrunningNow", ps.overrunningNow},
                 {"dropped", ps.dropped},
                 {"cancelledWhileRunning", ps.cancelledRunning},
                 {"memoryBudgetMiB", st.pool->memoryBudget() >> 20},
                 {"memoryReservedMiB", ps.reservedBytes >> 20}};
    // Ray scenes (pixel queries without a cached image, perspective queries, boreholes) build
    // as the models are served; a failed one is reported, not a reason to be unready (those
    // queries then answer its error).
    Json rays = Json::object();
    for (const auto& m : st.catalog.list()) {
        const RayQueries::State s = m->rays->state();
        if (anonymous) {
            Json& n = rays[RayQueries::stateName(s)];
            n = n.is_null() ? 1 : n.get<int>() + 1;
            continue;
        }
        Json r{{"state", RayQueries::stateName(s)}, {"seconds", m->rays->buildSeconds()}};
        if (s == RayQueries::State::Failed) r["error"] = m->rays->error();
        rays[m->id] = std::move(r);
    }
    Json j{{"ready", modelsReady && glOk && workersOk},
           {"models",
            {{"loaded", st.catalog.size()},
             {"done", bool(st.loaded)},
             {"pollMs", st.config.modelsDir.empty() ? 0 : st.config.modelsPollMs},
             {"failed", failures},
             {"skipped", skipped},
             {"warnings", warnings}}},
           {"rays", std::move(rays)},
           {"gl", {{"enabled", st.glEnabled}, {"ready", gl.ready}, {"device", gl.device}}},
           {"workers", st.pool->workers()},
           {"renders", std::move(renders)},
           // The memory the server plans with: the container's limit when one was found
           // (server/container_memory.hpp), the render budget and the answer cache.
           {"memory",
            {{"containerLimitMiB", st.config.containerMemoryMiB ? Json(st.config.containerMemoryMiB) : Json(nullptr)},
             {"renderBudgetMiB", st.config.memoryBudgetMiB},
             {"cacheMiB", st.config.cacheMiB}}}};
    sendJson(res, j, modelsReady && glOk && workersOk ? 200 : 503);
}

}  // namespace

void addOpsRoutes(Router& router, ServerState& st) {
    router.add(
        "GET", "/healthz", "/healthz",
        [](const HttpRequest&, HttpResponse& res) {
            sendJson(res, Json{{"status", "ok"}, {"version", kVersion}});
            res.set_header("Cache-Control", "no-store");  // a probe's answer is now or never
        },
        RouteAccess::Open);
    router.add(
        "GET", "/readyz", "/readyz",
        [&st](const HttpRequest&, HttpResponse& res) {
            readyz(st, res);
            res.set_header("Cache-Control", "no-store");
        },
        RouteAccess::Open);
    router.add(
        "GET", "/metrics", "/metrics",
        [&st](const HttpRequest&, HttpResponse& res) {
            res.set_content(st.metrics.text(), Metrics::kContentType);
            res.set_header("Cache-Control", "no-store");
        },
        RouteAccess::Open);
    router.add(
        "GET", "/openapi.json", "/openapi\\.json",
        [](const HttpRequest&, HttpResponse& res) { sendJson(res, api::openApiDocument(kVersion)); },
        RouteAccess::Open);
}

}  // namespace geoslice::server
