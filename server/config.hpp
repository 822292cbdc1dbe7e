// Server configuration: built-in defaults, then a JSON config file, then GEOSLICE_*
// environment variables, then command-line flags (each later source wins).
//
//   key (JSON)        env                      flag            default
//   host              GEOSLICE_HOST            --host          0.0.0.0
//   port              GEOSLICE_PORT            --port          8080 (0 = any free port)
//   models            GEOSLICE_MODELS          --models        "" (none: the demo model)
//   bakeDir           GEOSLICE_BAKE_DIR        --bake-dir      "" (raw models are not baked)
//   gl                GEOSLICE_GL              --gl            auto (auto|egl-device|egl-surfaceless|osmesa|none)
//   lod               GEOSLICE_LOD             --lod           off (auto: simplified context geometry in 3D views on CPU backends)
//   workers           GEOSLICE_WORKERS         --workers       number of cores
//   queue             GEOSLICE_QUEUE           --queue         64 jobs
//   httpThreads       GEOSLICE_HTTP_THREADS    --http-threads  128 (connections served at once)
//   cacheMiB          GEOSLICE_CACHE_MIB       --cache-mib     512
//   deadlineMs        GEOSLICE_DEADLINE_MS     --deadline-ms   10000
//   maxBodyBytes      GEOSLICE_MAX_BODY        --max-body      1048576
//   cors              GEOSLICE_CORS            --cors          * ("" = no CORS headers)
//   demoTriangles     GEOSLICE_DEMO_TRIANGLES  --demo-triangles 200000
//   logLevel          GEOSLICE_LOG_LEVEL       --log-level     info
#pragma once

#include <cstddef>
#include <map>
#include <string>

#include "model/result.hpp"

namespace geoslice::server {

struct ServerConfig {
    std::string host = "0.0.0.0";
    int port = 8080;
    std::string modelsDir;
    std::string bakeDir;  // bake raw models on first load into bakeDir/<id>/ (reused while unchanged)
    std::string gl = "auto";
    std::string lod = "off";  // "auto": faster 3D views on llvmpipe, not exact behind cut faces
    unsigned workers = 0;  // 0 = hardware concurrency
    std::size_t queue = 64;
    unsigned httpThreads = 128;
    std::size_t cacheMiB = 512;
    int deadlineMs = 10000;
    std::size_t maxBodyBytes = 1 << 20;
    std::string cors = "*";
    std::size_t demoTriangles = 200000;
    std::string logLevel = "info";
};

// Applies a JSON object's known keys (unknown keys are an error naming them).
Status applyConfigJson(ServerConfig& config, const std::string& jsonText, const std::string& source);
Status applyConfigFile(ServerConfig& config, const std::string& path);
// Applies GEOSLICE_* variables from `env` (name -> value).
Status applyConfigEnv(ServerConfig& config, const std::map<std::string, std::string>& env);
std::map<std::string, std::string> processEnvironment();
// Range checks; errors name the setting.
Status checkConfig(const ServerConfig& config);

}  // namespace geoslice::server
