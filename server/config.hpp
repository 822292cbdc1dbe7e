// Server configuration: built-in defaults, then a JSON config file, then GEOSLICE_*
// environment variables, then command-line flags (each later source wins).
// clang-format off
//
//   key (JSON)         env                            flag                    default
//   host               GEOSLICE_HOST                  --host                  0.0.0.0
//   port               GEOSLICE_PORT                  --port                  8080 (0 = any free port)
//   models             GEOSLICE_MODELS                --models                "" (none: the demo model)
//   bakeDir            GEOSLICE_BAKE_DIR              --bake-dir              "" (raw models are not baked)
//   sectionsDir        GEOSLICE_SECTIONS_DIR          --sections-dir          "" (sections are not saved through
//                                                                             the API; api/saved_sections.hpp)
//   gl                 GEOSLICE_GL                    --gl                    auto (auto|egl-device|egl-surfaceless|osmesa|none)
//   lod                GEOSLICE_LOD                   --lod                   off (auto: simplified context geometry in 3D
//                                                                             views on CPU backends)
//   workers            GEOSLICE_WORKERS               --workers               number of cores
//   queue              GEOSLICE_QUEUE                 --queue                 64 jobs
//   httpThreads        GEOSLICE_HTTP_THREADS          --http-threads          128 (requests handled at once)
//   maxConnections     GEOSLICE_MAX_CONNECTIONS       --max-connections       10000 (then the longest-waiting idle
//                                                                             one closes, else 503)
//   headerTimeoutMs    GEOSLICE_HEADER_TIMEOUT_MS     --header-timeout-ms     10000 (whole header, from its first byte)
//   bodyTimeoutMs      GEOSLICE_BODY_TIMEOUT_MS       --body-timeout-ms       10000 (whole request body)
//   keepAliveMs        GEOSLICE_KEEP_ALIVE_MS         --keep-alive-ms         5000 (idle keep-alive connection)
//   keepAliveRequests  GEOSLICE_KEEP_ALIVE_REQUESTS   --keep-alive-requests   10000 (per connection)
//   sendTimeoutMs      GEOSLICE_SEND_TIMEOUT_MS       --send-timeout-ms       10000 (per 8 MiB of answer)
//   reusePort          GEOSLICE_REUSE_PORT            --reuse-port            0 (1: SO_REUSEPORT, share the port)
//   cacheMiB           GEOSLICE_CACHE_MIB             --cache-mib             512
//   deadlineMs         GEOSLICE_DEADLINE_MS           --deadline-ms           10000
//   shutdownGraceMs    GEOSLICE_SHUTDOWN_GRACE_MS     --shutdown-grace-ms     10000 (after SIGTERM, in-flight requests
//                                                                             may finish within this, capped by
//                                                                             deadlineMs; then renders are cancelled)
//   maxBodyBytes       GEOSLICE_MAX_BODY              --max-body              1048576
//   corsOrigins        GEOSLICE_CORS                  --cors-origins          auto: * for the demo (no models), none
//                                                                             with --models; none | * | a list of
//                                                                             origins (https://a.example,http://b:8000)
//                                                                             whose Origin is echoed, with Vary: Origin
//                                                                             (JSON key "cors" and flag --cors: the same)
//   keysFile           GEOSLICE_KEYS_FILE             --keys                  "" (API keys, one "NAME KEY MODELS" a line:
//                                                                             api/access_keys.hpp; any key turns
//                                                                             authentication on for the model routes)
//   keys               GEOSLICE_KEYS                                          "" (the same entries inline, ';' between
//                                                                             them; added to the keys file's)
//   demoTriangles      GEOSLICE_DEMO_TRIANGLES        --demo-triangles        200000
//   logLevel           GEOSLICE_LOG_LEVEL             --log-level             info
//   memoryBudgetMiB    GEOSLICE_MEMORY_BUDGET_MIB     --memory-budget-mib     4096 (estimated memory of queued and
//                                                                             running renders; beyond it 503 +
//                                                                             Retry-After; 0 = no limit); in a
//                                                                             cgroup with a memory limit, half of it
//                                                                             when left at 4096 (cacheMiB: an eighth)
//   readyzPaths        GEOSLICE_READYZ_PATHS          --readyz-paths          0 (1: /readyz shows absolute file
//                                                                             paths in model errors)
//   noBake             GEOSLICE_NO_BAKE               --no-bake               0 (1: never bake; a model without a
//                                                                             current baked package is refused and
//                                                                             named in /readyz: read-only volumes)
//   modelsPollMs       GEOSLICE_MODELS_POLL_MS        --models-poll-ms        2000 (the models directory is scanned
//                                                                             again this often: new or changed models
//                                                                             load, a new version replaces the old
//                                                                             once its ray scene is built; 0 = never)
//   maxModelMiB        GEOSLICE_MAX_MODEL_MIB         --max-model-mib         1024 (largest model file read, MiB,
//                                                                             1..1048576: a file is read whole and
//                                                                             parsed in memory; a larger one is
//                                                                             skipped from its size, named in /readyz)
//   tiles3dTriangles   GEOSLICE_3DTILES_TRIANGLES     --3dtiles-triangles     16384 (about this many triangles per leaf
//                                                                             tile of /3dtiles/, 256..16777216)
// clang-format on
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "model/result.hpp"

namespace geoslice::server {

struct ServerConfig {
    std::string host = "0.0.0.0";
    int port = 8080;
    std::string modelsDir;
    std::string bakeDir;      // bake raw models on first load into bakeDir/<id>/ (reused while unchanged)
    std::string sectionsDir;  // saved sections, sectionsDir/<model id>/<id>.json; shared by replicas
    std::string gl = "auto";
    std::string lod = "off";  // "auto": faster 3D views on llvmpipe, not exact behind cut faces
    unsigned workers = 0;     // 0 = hardware concurrency
    std::size_t queue = 64;
    unsigned httpThreads = 128;
    std::size_t maxConnections = 10000;
    int headerTimeoutMs = 10000;
    int bodyTimeoutMs = 10000;
    int keepAliveMs = 5000;
    std::size_t keepAliveRequests = 10000;
    int sendTimeoutMs = 10000;
    bool reusePort = false;
    std::size_t cacheMiB = 512;
    int deadlineMs = 10000;
    int shutdownGraceMs = 10000;  // SIGTERM: in-flight requests may finish within this (and their deadline)
    std::size_t maxBodyBytes = 1 << 20;
    std::string cors = "auto";  // corsOrigins: auto | none | * | origin,origin,... (corsPolicy)
    std::string keysFile;       // API keys file (api/access_keys.hpp); "" = none
    std::string keys;           // API keys inline (GEOSLICE_KEYS); "" = none
    std::size_t demoTriangles = 200000;
    std::string logLevel = "info";
    std::size_t memoryBudgetMiB = 4096;  // render admission by estimated memory; 0 = off
    bool readyzPaths = false;            // /readyz shows file-system paths (else only file names)
    bool noBake = false;                 // never bake: serve baked packages only (api::loadCatalogModel mayBake)
    int modelsPollMs = 2000;             // scan the models directory again this often (0 = only at start)
    // Largest model file read (MiB): model/io/loaders.hpp kDefaultMaxModelBytes, probeModelFile.
    std::size_t maxModelMiB = 1024;
    std::size_t tiles3dTriangles = 16384;  // renderer/tiles3d/tileset3d.hpp Tiles3dOptions::trianglesPerTile
    // The container's memory limit (server/container_memory.hpp), when one was found: the
    // render budget and the cache were fitted to it where left at their defaults. /readyz.
    std::size_t containerMemoryMiB = 0;
    std::string containerMemorySource;
};

// Applies a JSON object's known keys (unknown keys are an error naming them).
Status applyConfigJson(ServerConfig& config, const std::string& jsonText, const std::string& source);
Status applyConfigFile(ServerConfig& config, const std::string& path);
// Applies GEOSLICE_* variables from `env` (name -> value).
Status applyConfigEnv(ServerConfig& config, const std::map<std::string, std::string>& env);
std::map<std::string, std::string> processEnvironment();
// Range checks; errors name the setting.
Status checkConfig(const ServerConfig& config);

// Which cross-origin pages may read the answers (Access-Control-Allow-Origin).
struct CorsPolicy {
    enum class Mode { Off, Any, List } mode = Mode::Off;
    std::vector<std::string> origins;  // Mode::List: serialized origins, lower case, no trailing '/'

    // The Access-Control-Allow-Origin value for a request with this Origin header: "*", the
    // origin itself when listed, or "" (no CORS headers).
    std::string allowOrigin(std::string_view requestOrigin) const;
    // How the policy reads in logs: "off", "*" or the origins.
    std::string describe() const;
};
// The policy of config.cors: "auto" is "*" for the demo (no models directory: the README's
// demo works from any page) and off once models are served; "none" or "" is off; "*" any
// origin; otherwise origins separated by commas (http or https, host, optional port).
Result<CorsPolicy> corsPolicy(const ServerConfig& config);

}  // namespace geoslice::server
