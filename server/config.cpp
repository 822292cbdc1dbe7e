#include "server/config.hpp"

#include <charconv>

#include <nlohmann/json.hpp>

#include "api/access_keys.hpp"
#include "model/io/loaders.hpp"
#include "model/json_text.hpp"

extern char** environ;

namespace geoslice::server {
namespace {

Status setField(ServerConfig& c, const std::string& key, const std::string& value, const std::string& source) {
    auto number = [&](auto& field, long long lo, long long hi) -> Status {
        long long v = 0;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
        if (ec != std::errc() || end != value.data() + value.size() || v < lo || v > hi)
            return makeError(ErrorCode::InvalidArgument, source + ": '" + key + "' = '" + value +
                                                             "' is not a whole number in " + std::to_string(lo) + ".." +
                                                             std::to_string(hi));
        field = static_cast<std::remove_reference_t<decltype(field)>>(v);
        return {};
    };
    if (key == "host")
        c.host = value;
    else if (key == "port")
        return number(c.port, 0, 65535);
    else if (key == "models")
        c.modelsDir = value;
    else if (key == "gl")
        c.gl = value;
    else if (key == "workers")
        return number(c.workers, 0, 256);
    else if (key == "queue")
        return number(c.queue, 1, 100000);
    else if (key == "httpThreads")
        return number(c.httpThreads, 2, 4096);
    else if (key == "maxConnections")
        return number(c.maxConnections, 16, 1000000);
    else if (key == "headerTimeoutMs")
        return number(c.headerTimeoutMs, 100, 3600000);
    else if (key == "bodyTimeoutMs")
        return number(c.bodyTimeoutMs, 100, 3600000);
    else if (key == "keepAliveMs")
        return number(c.keepAliveMs, 100, 3600000);
    else if (key == "keepAliveRequests")
        return number(c.keepAliveRequests, 1, 1LL << 40);
    else if (key == "sendTimeoutMs")
        return number(c.sendTimeoutMs, 100, 3600000);
    else if (key == "reusePort")
        return number(c.reusePort, 0, 1);
    else if (key == "cacheMiB")
        return number(c.cacheMiB, 0, 1 << 20);
    else if (key == "deadlineMs")
        return number(c.deadlineMs, 1, 3600000);
    else if (key == "shutdownGraceMs")
        return number(c.shutdownGraceMs, 0, 3600000);
    else if (key == "maxBodyBytes")
        return number(c.maxBodyBytes, 1024, 1LL << 30);
    else if (key == "cors" || key == "corsOrigins")
        c.cors = value;
    else if (key == "keysFile")
        c.keysFile = value;
    else if (key == "keys") {
        // Checked here, where the source is known; an empty value is an error (a keys
        // source that is set must not leave the server open).
        if (auto k = api::parseApiKeys(value, source); !k) return k.error();
        c.keys = value;
    } else if (key == "demoTriangles")
        return number(c.demoTriangles, 2000, 20000000);
    else if (key == "logLevel")
        c.logLevel = value;
    else if (key == "memoryBudgetMiB")
        return number(c.memoryBudgetMiB, 0, 1LL << 30);
    else if (key == "readyzPaths")
        return number(c.readyzPaths, 0, 1);
    else if (key == "noBake")
        return number(c.noBake, 0, 1);
    else if (key == "modelsPollMs")
        return number(c.modelsPollMs, 0, 3600000);
    else if (key == "maxModelMiB")
        return number(c.maxModelMiB, 1, 1 << 20);
    else if (key == "tiles3dTriangles")
        return number(c.tiles3dTriangles, 256, 1 << 24);
    else if (key == "bakeDir")
        c.bakeDir = value;
    else if (key == "sectionsDir")
        c.sectionsDir = value;
    else if (key == "lod")
        c.lod = value;
    else
        return makeError(ErrorCode::InvalidArgument, source + ": unknown setting '" + key + "'");
    return {};
}

}  // namespace

Status applyConfigJson(ServerConfig& config, const std::string& configText, const std::string& source) {
    nlohmann::json j = nlohmann::json::parse(configText, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return makeError(ErrorCode::ParseError, source + ": not a JSON object");
    for (const auto& [key, value] : j.items()) {
        std::string text;
        if (value.is_string())
            text = value.get<std::string>();
        else if (value.is_number_integer() || value.is_number_unsigned())
            text = jsonText(value);
        else
            return makeError(ErrorCode::InvalidArgument, source + ": '" + key + "' must be a string or a whole number");
        if (auto s = setField(config, key, text, source); !s) return s;
    }
    return {};
}

Status applyConfigFile(ServerConfig& config, const std::string& path) {
    auto text = readFile(path, 1 << 20);
    if (!text) return text.error();
    return applyConfigJson(config, text.value(), path);
}

Status applyConfigEnv(ServerConfig& config, const std::map<std::string, std::string>& env) {
    static const std::pair<const char*, const char*> names[] = {
        {"GEOSLICE_HOST", "host"},
        {"GEOSLICE_PORT", "port"},
        {"GEOSLICE_MODELS", "models"},
        {"GEOSLICE_BAKE_DIR", "bakeDir"},
        {"GEOSLICE_SECTIONS_DIR", "sectionsDir"},
        {"GEOSLICE_GL", "gl"},
        {"GEOSLICE_LOD", "lod"},
        {"GEOSLICE_WORKERS", "workers"},
        {"GEOSLICE_QUEUE", "queue"},
        {"GEOSLICE_HTTP_THREADS", "httpThreads"},
        {"GEOSLICE_MAX_CONNECTIONS", "maxConnections"},
        {"GEOSLICE_HEADER_TIMEOUT_MS", "headerTimeoutMs"},
        {"GEOSLICE_BODY_TIMEOUT_MS", "bodyTimeoutMs"},
        {"GEOSLICE_KEEP_ALIVE_MS", "keepAliveMs"},
        {"GEOSLICE_KEEP_ALIVE_REQUESTS", "keepAliveRequests"},
        {"GEOSLICE_SEND_TIMEOUT_MS", "sendTimeoutMs"},
        {"GEOSLICE_REUSE_PORT", "reusePort"},
        {"GEOSLICE_CACHE_MIB", "cacheMiB"},
        {"GEOSLICE_DEADLINE_MS", "deadlineMs"},
        {"GEOSLICE_SHUTDOWN_GRACE_MS", "shutdownGraceMs"},
        {"GEOSLICE_MAX_BODY", "maxBodyBytes"},
        {"GEOSLICE_CORS", "cors"},
        {"GEOSLICE_KEYS_FILE", "keysFile"},
        {"GEOSLICE_KEYS", "keys"},
        {"GEOSLICE_MEMORY_BUDGET_MIB", "memoryBudgetMiB"},
        {"GEOSLICE_READYZ_PATHS", "readyzPaths"},
        {"GEOSLICE_NO_BAKE", "noBake"},
        {"GEOSLICE_MAX_MODEL_MIB", "maxModelMiB"},
        {"GEOSLICE_MODELS_POLL_MS", "modelsPollMs"},
        {"GEOSLICE_3DTILES_TRIANGLES", "tiles3dTriangles"},
        {"GEOSLICE_DEMO_TRIANGLES", "demoTriangles"},
        {"GEOSLICE_LOG_LEVEL", "logLevel"},
    };
    for (const auto& [var, key] : names)
        if (const auto it = env.find(var); it != env.end())
            if (auto s = setField(config, key, it->second, "environment " + std::string(var)); !s) return s;
    return {};
}

std::map<std::string, std::string> processEnvironment() {
    std::map<std::string, std::string> env;
    for (char** e = environ; e && *e; ++e) {
        const std::string kv(*e);
        const std::size_t eq = kv.find('=');
        if (eq != std::string::npos && kv.rfind("GEOSLICE_", 0) == 0) env[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
    return env;
}

Status checkConfig(const ServerConfig& c) {
    if (c.gl != "auto" && c.gl != "egl-device" && c.gl != "egl-surfaceless" && c.gl != "osmesa" && c.gl != "none")
        return makeError(ErrorCode::InvalidArgument,
                         "gl '" + c.gl + "' is not auto, egl-device, egl-surfaceless, osmesa or none");
    if (c.shutdownGraceMs < 0 || c.shutdownGraceMs > 3600000)
        return makeError(ErrorCode::InvalidArgument,
                         "shutdownGraceMs " + std::to_string(c.shutdownGraceMs) + " is outside 0..3600000 ms");
    if (c.modelsPollMs < 0 || c.modelsPollMs > 3600000)
        return makeError(ErrorCode::InvalidArgument,
                         "modelsPollMs " + std::to_string(c.modelsPollMs) + " is outside 0..3600000 ms");
    if (c.lod != "off" && c.lod != "auto")
        return makeError(ErrorCode::InvalidArgument, "lod '" + c.lod + "' is not off or auto");
    if (c.logLevel != "trace" && c.logLevel != "debug" && c.logLevel != "info" && c.logLevel != "warn" &&
        c.logLevel != "error" && c.logLevel != "off")
        return makeError(ErrorCode::InvalidArgument,
                         "logLevel '" + c.logLevel + "' is not trace|debug|info|warn|error|off");
    if (auto p = corsPolicy(c); !p) return p.error();
    return {};
}

std::string CorsPolicy::allowOrigin(std::string_view requestOrigin) const {
    switch (mode) {
        case Mode::Off:
            return {};
        case Mode::Any:
            return "*";
        case Mode::List:
            // Browsers send the serialized origin (RFC 6454 6.2): compared as sent, exactly.
            for (const std::string& o : origins)
                if (o == requestOrigin) return o;
            return {};
    }
    return {};
}

std::string CorsPolicy::describe() const {
    if (mode == Mode::Off) return "off";
    if (mode == Mode::Any) return "*";
    std::string out;
    for (const std::string& o : origins) out += (out.empty() ? "" : ",") + o;
    return out;
}

Result<CorsPolicy> corsPolicy(const ServerConfig& c) {
    CorsPolicy p;
    const std::string v = c.cors == "auto" ? (c.modelsDir.empty() ? "*" : "none") : c.cors;
    if (v.empty() || v == "none") return p;
    if (v == "*") {
        p.mode = CorsPolicy::Mode::Any;
        return p;
    }
    p.mode = CorsPolicy::Mode::List;
    std::size_t pos = 0;
    while (pos <= v.size()) {
        std::size_t comma = v.find(',', pos);
        if (comma == std::string::npos) comma = v.size();
        std::string o = v.substr(pos, comma - pos);
        pos = comma + 1;
        while (!o.empty() && (o.front() == ' ' || o.front() == '\t')) o.erase(o.begin());
        while (!o.empty() && (o.back() == ' ' || o.back() == '\t')) o.pop_back();
        if (!o.empty() && o.back() == '/') o.pop_back();
        for (char& ch : o)
            if (ch >= 'A' && ch <= 'Z') ch = char(ch - 'A' + 'a');
        const std::size_t scheme = o.rfind("https://", 0) == 0 ? 8 : o.rfind("http://", 0) == 0 ? 7 : 0;
        const std::string host = scheme ? o.substr(scheme) : "";
        const bool ok = scheme && !host.empty() && host.find_first_of("/?#@ *\\\"'") == std::string::npos;
        if (!ok)
            return makeError(ErrorCode::InvalidArgument,
                             "corsOrigins: '" + o.substr(0, 200) +
                                 "' is not an origin (http:// or https://, a host and an optional :port, no path); "
                                 "use '*' alone for every origin or 'none'");
        p.origins.push_back(o);
        if (comma == v.size()) break;
    }
    return p;
}

}  // namespace geoslice::server
