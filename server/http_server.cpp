#include "server/http_server.hpp"

#include <malloc.h>

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <mutex>
#include <regex>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "api/legend.hpp"
#include "api/openapi.hpp"
#include "api/plan.hpp"
#include "api/reserves.hpp"
#include "api/sheet.hpp"
#include "api/view.hpp"
#include "model/version.hpp"
#include "print/sheet_date.hpp"
#include "renderer/image_encode.hpp"
#include "server/gl_status.hpp"
#include "server/gl_worker.hpp"
#include "server/http_transport.hpp"
#include "server/lru_cache.hpp"
#include "server/metrics.hpp"
#include "server/render_pool.hpp"
#include "server/web_assets.hpp"

namespace geoslice::server {
namespace {

using Clock = std::chrono::steady_clock;
using Json = nlohmann::ordered_json;

// An encoded image or JSON body, as cached and served.
struct Encoded {
    std::string body;
    std::string contentType;
    std::string etag;
    std::size_t bytes() const { return body.size() + etag.size() + contentType.size(); }
};

// What a query needs of a rendered view: the ID buffer and the pixel mapping.
struct IdBuffer {
    api::ViewImage view;  // rgba cleared
    std::size_t bytes() const { return view.bytes(); }
};

int httpStatus(ErrorCode code) {
    switch (code) {
        case ErrorCode::InvalidArgument:
        case ErrorCode::ParseError:
        case ErrorCode::OutOfRange:
            return 400;
        case ErrorCode::NotFound:
            return 404;
        case ErrorCode::Unsupported:
            return 422;
        case ErrorCode::Unavailable:
            return 503;
        case ErrorCode::DeadlineExceeded:
            return 504;
        case ErrorCode::IoError:
        case ErrorCode::Internal:
            return 500;
    }
    return 500;
}

const char* statusTitle(int status) {
    switch (status) {
        case 400:
            return "Bad Request";
        case 404:
            return "Not Found";
        case 405:
            return "Method Not Allowed";
        case 413:
            return "Content Too Large";
        case 415:
            return "Unsupported Media Type";
        case 422:
            return "Unprocessable Content";
        case 500:
            return "Internal Server Error";
        case 503:
            return "Service Unavailable";
        case 504:
            return "Gateway Timeout";
        default:
            return "Error";
    }
}

void problem(HttpResponse& res, int status, const std::string& detail, const std::string& instance,
             const char* code = nullptr) {
    Json j;
    j["type"] = "about:blank";
    j["title"] = statusTitle(status);
    j["status"] = status;
    j["detail"] = detail;
    j["instance"] = instance;
    if (code) j["code"] = code;
    res.status = status;
    res.set_content(j.dump(), "application/problem+json");
}

// An error as an answer: its status, and Retry-After when the server lacks capacity now.
void problem(HttpResponse& res, const Error& e, const std::string& instance) {
    if (e.code == ErrorCode::Unavailable) res.set_header("Retry-After", "1");
    problem(res, httpStatus(e.code), e.message, instance, errorCodeName(e.code));
}

// A POST body must be JSON (application/json or a +json type): 415 otherwise.
bool requireJsonBody(const HttpRequest& req, HttpResponse& res) {
    std::string type = req.get_header_value("Content-Type");
    type = type.substr(0, type.find(';'));
    while (!type.empty() && type.back() == ' ') type.pop_back();
    for (char& c : type) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (type == "application/json" || (type.size() > 5 && type.compare(type.size() - 5, 5, "+json") == 0)) return true;
    problem(res, 415,
            "header 'Content-Type': '" + type.substr(0, 80) + "' is not application/json; the body must be JSON",
            req.path, "unsupported_media_type");
    return false;
}

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

// Estimated peak memory of one render, for admission by memory (issue 11 item 4). Per
// pixel: the colour image and ID buffer kept until encoded (8), the fill's coverage and
// trace buffers (5), the encoder's working copies (WebP: YUVA planes and an ARGB copy, up
// to 12; PNG and JPEG less), and headroom for the allocator (7) = 32; GL views add their
// render targets (RGBA8, R32UI, depth-stencil: 12) and FXAA/read-back copies (8) = 52.
// An 8192^2 WebP was measured at about 2.1 GB (issue 11): 32 B/px gives 2.1 GiB.
constexpr std::size_t kExactBytesPerPixel = 32, kGlBytesPerPixel = 52;
constexpr std::size_t kVectorBytes = std::size_t(32) << 20;      // GeoJSON/SVG of one section
constexpr std::size_t kQueryAnswerBytes = 4096;                  // one pixel's answer and scratch
constexpr std::size_t kTrimAfterBytes = std::size_t(256) << 20;  // trim the heap after larger renders
std::size_t renderBytes(int width, int height, bool gl) {
    return std::size_t(width) * std::size_t(height) * (gl ? kGlBytesPerPixel : kExactBytesPerPixel);
}
std::string mib(std::size_t bytes) { return std::to_string((bytes + (std::size_t(1) << 20) - 1) >> 20); }

void sendJson(HttpResponse& res, const Json& j, int status = 200) {
    res.status = status;
    res.set_content(j.dump(), "application/json");
}

// Query parameters -> api::Params; a parameter given twice is an error (which one wins
// would otherwise depend on the parser), except `plane`, whose values are joined with ';'
// in the order given (a cut-out's planes, api/cut.hpp).
Result<api::Params> toParams(const HttpRequest& req) {
    api::Params p;
    for (const auto& [k, v] : req.params) {
        auto [it, fresh] = p.emplace(k, v);
        if (!fresh && k == "plane")
            it->second += ";" + v;
        else if (!fresh)
            return makeError(ErrorCode::InvalidArgument, "parameter '" + k + "' is given more than once");
    }
    return p;
}

Result<api::Params> jsonToParams(const nlohmann::json& j, const std::string& what) {
    if (!j.is_object()) return makeError(ErrorCode::InvalidArgument, what + " must be a JSON object");
    api::Params p;
    for (const auto& [k, v] : j.items()) {
        if (v.is_string())
            p[k] = v.get<std::string>();
        else if (v.is_number()) {
            const double d = v.get<double>();
            if (!std::isfinite(d)) return makeError(ErrorCode::InvalidArgument, what + ": '" + k + "' is not finite");
            p[k] = v.is_number_float() ? api::formatNumber(d) : v.dump();
        } else if (v.is_array()) {
            // [n, n, ...] -> "n,n,..."; [[n, ...], [n, ...]] (planes) -> "n,...;n,...".
            std::string s;
            for (std::size_t i = 0; i < v.size(); ++i) {
                const auto& x = v[i];
                const bool nested = x.is_array() && v[0].is_array();
                if (!x.is_number() && !nested)
                    return makeError(ErrorCode::InvalidArgument,
                                     what + ": '" + k + "' must be an array of numbers or of arrays of numbers");
                if (i) s += nested ? ';' : ',';
                if (!nested) {
                    s += api::formatNumber(x.get<double>());
                    continue;
                }
                for (std::size_t c = 0; c < x.size(); ++c) {
                    if (!x[c].is_number())
                        return makeError(ErrorCode::InvalidArgument,
                                         what + ": '" + k + "' must be an array of numbers or of arrays of numbers");
                    s += (c ? "," : "") + api::formatNumber(x[c].get<double>());
                }
            }
            p[k] = s;
        } else if (v.is_boolean()) {
            p[k] = v.get<bool>() ? "true" : "false";
        } else {
            return makeError(ErrorCode::InvalidArgument, what + ": '" + k + "' must be a string, number or array");
        }
    }
    return p;
}

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

bool etagMatches(const std::string& ifNoneMatch, const std::string& etag) {
    if (ifNoneMatch.empty()) return false;
    if (ifNoneMatch == "*") return true;
    std::size_t pos = 0;
    while (pos < ifNoneMatch.size()) {
        std::size_t comma = ifNoneMatch.find(',', pos);
        if (comma == std::string::npos) comma = ifNoneMatch.size();
        std::string tag = ifNoneMatch.substr(pos, comma - pos);
        while (!tag.empty() && tag.front() == ' ') tag.erase(tag.begin());
        while (!tag.empty() && tag.back() == ' ') tag.pop_back();
        if (tag == etag) return true;  // strong comparison (a W/ tag never matches)
        pos = comma + 1;
    }
    return false;
}

}  // namespace

struct SectionServer::Impl {
    ServerConfig config;
    api::Catalog catalog;
    Metrics metrics;
    LruCache<Encoded> images;
    LruCache<IdBuffer> idBuffers;
    Coalescer<std::shared_ptr<const Result<std::shared_ptr<const Encoded>>>> coalescer;
    std::unique_ptr<RenderPool> pool;    // declared after what its jobs use: destroyed first
    std::optional<GlBackend> glBackend;  // nullopt: GL disabled
    GlStatus glStatus;                   // written by the probing render worker, read by /readyz (locked)
    std::atomic<bool> draining{false};
    std::atomic<bool> loaded{false};
    std::atomic<bool> loadOk{false};
    std::mutex failedMutex;
    nlohmann::ordered_json failed = nlohmann::ordered_json::array();  // {id, error} of models that did not load
    std::atomic<int> inFlight{0};
    std::thread loader;
    std::mutex stopMutex;
    bool stopped = false;
    std::mutex loadMutex;
    std::condition_variable loadDone;
    struct Route {
        std::string method;
        std::regex pattern;
        std::function<void(const HttpRequest&, HttpResponse&)> fn;
    };
    std::vector<Route> routes;
    std::unique_ptr<HttpTransport> http;  // declared last: its handlers use all of the above

    explicit Impl(ServerConfig c)
        : config(std::move(c)),
          images(config.cacheMiB * (std::size_t(1) << 20) * 3 / 4),
          idBuffers(config.cacheMiB * (std::size_t(1) << 20) / 4) {}

    // ---- helpers -------------------------------------------------------------------
    std::shared_ptr<const api::CatalogModel> model(const std::string& id, HttpResponse& res,
                                                   const std::string& instance) {
        if (!api::isValidModelId(id)) {
            problem(res, 404, "model id '" + id.substr(0, 80) + "' is not a valid id ([A-Za-z0-9][A-Za-z0-9._-]{0,63})",
                    instance, "not_found");
            return nullptr;
        }
        auto m = catalog.find(id);
        if (!m) {
            if (!loaded) {
                res.set_header("Retry-After", "2");
                problem(res, 503, "models are still loading; model '" + id + "' is not available yet", instance);
            } else {
                problem(res, 404, "no model '" + id + "'", instance, "not_found");
            }
        }
        return m;
    }

    void sendEncoded(const HttpRequest& req, HttpResponse& res, const Encoded& e) {
        res.set_header("ETag", e.etag);
        res.set_header("Cache-Control", "public, max-age=86400");
        if (etagMatches(req.get_header_value("If-None-Match"), e.etag)) {
            res.status = 304;
            return;
        }
        res.status = 200;
        res.set_content(e.body, e.contentType);
    }

    // Runs `render` on a worker (coalesced by `key`) and waits until it is done, the
    // deadline passes or the client goes away (req.cancelled, set by the transport); the
    // render is cancelled when the last request waiting for it leaves. Typed errors:
    // Unavailable (queue full, memory budget spent: 503 + Retry-After), DeadlineExceeded
    // (504), OutOfRange (larger than the whole memory budget), or the render's own.
    // `gl`: the render uses the worker's GL context (only then is it rebuilt after an overrun).
    using Rendered = Result<std::shared_ptr<const Encoded>>;
    using RenderFn = std::function<Rendered(WorkerState&, const std::atomic<bool>& cancel)>;
    Rendered renderCoalesced(const std::string& key, RenderFn render, std::size_t memoryBytes, bool gl,
                             const HttpRequest& req, bool cache = true) {
        const auto deadline = Clock::now() + std::chrono::milliseconds(config.deadlineMs);
        auto ticket = coalescer.join(key);
        if (ticket.leader) {
            RenderJob job;
            job.cancel = ticket.cancel;
            job.deadline = deadline;
            job.memoryBytes = memoryBytes;
            job.run = [this, key, id = ticket.id, gl, cache, memoryBytes, render = std::move(render)](
                          WorkerState& w, const std::atomic<bool>& cancel) {
                const auto t0 = Clock::now();
                Rendered r = makeError(ErrorCode::Internal, "render threw");
                try {
                    r = render(w, cancel);
                } catch (const std::exception& e) {
                    r = makeError(ErrorCode::Internal, std::string("render failed: ") + e.what());
                }
                const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                if (ms > config.deadlineMs) {
                    spdlog::warn("event=render_overrun key_hash={} ms={:.1f} deadline_ms={} cancelled={} gl_rebuilt={}",
                                 api::hex64(api::fnv1a64(key)), ms, config.deadlineMs, cancel.load(), gl && w.gl);
                    metrics.count("geoslice_render_overruns_total", "");
                    if (gl) w.gl.reset();  // a GL context that overran is rebuilt by the next GL job
                }
                if (memoryBytes >= kTrimAfterBytes) {
                    // Give the buffers of a large image back (the GL worker kept 1.47 GB after
                    // an 8192^2 view): render targets, then the heap's free pages.
                    if (gl && w.gl) w.gl->trim();
                    malloc_trim(0);
                }
                if (r && cache) images.put(key, r.value());
                coalescer.finish(key, id, std::make_shared<const Rendered>(std::move(r)));
            };
            job.drop = [this, key, id = ticket.id](const Error& e) {
                metrics.count("geoslice_renders_dropped_total", "");
                coalescer.finish(key, id, std::make_shared<const Rendered>(e));
            };
            Error refused;
            switch (pool->submit(std::move(job))) {
                case Admission::Queued:
                    break;
                case Admission::QueueFull:
                    metrics.count("geoslice_queue_rejections_total", "reason=\"queue\"");
                    refused = makeError(
                        ErrorCode::Unavailable,
                        "the render queue is full (" + std::to_string(pool->capacity()) + " jobs); retry shortly");
                    break;
                case Admission::OverMemory:
                    metrics.count("geoslice_queue_rejections_total", "reason=\"memory\"");
                    refused = makeError(ErrorCode::Unavailable, "this render needs about " + mib(memoryBytes) +
                                                                    " MiB and the memory budget (" +
                                                                    mib(pool->memoryBudget()) +
                                                                    " MiB) is taken by renders under way; retry "
                                                                    "shortly");
                    break;
                case Admission::TooLarge:
                    metrics.count("geoslice_queue_rejections_total", "reason=\"too_large\"");
                    refused = makeError(ErrorCode::OutOfRange,
                                        "parameter 'size': this render needs about " + mib(memoryBytes) +
                                            " MiB, more than the server's whole memory budget of " +
                                            mib(pool->memoryBudget()) + " MiB; ask for fewer pixels");
                    break;
                case Admission::Stopping:
                    refused = makeError(ErrorCode::Unavailable, "the server is shutting down");
                    break;
            }
            if (!refused.message.empty()) {
                coalescer.leave(key, ticket.id);
                coalescer.finish(key, ticket.id, std::make_shared<const Rendered>(refused));
                return refused;
            }
        }
        // Wait in slices, so that a client that goes away is noticed within them.
        while (ticket.future.wait_for(std::chrono::milliseconds(10)) != std::future_status::ready) {
            if (req.isCancelled()) {
                coalescer.leave(key, ticket.id);
                metrics.count("geoslice_requests_abandoned_total", "");
                return makeError(ErrorCode::DeadlineExceeded, "the client went away; its render was cancelled");
            }
            if (Clock::now() >= deadline) {
                coalescer.leave(key, ticket.id);
                metrics.count("geoslice_deadline_exceeded_total", "");
                return makeError(ErrorCode::DeadlineExceeded,
                                 "the render did not finish within the deadline of " +
                                     std::to_string(config.deadlineMs) +
                                     " ms; it is cancelled unless another request still waits for it");
            }
        }
        return *ticket.future.get();
    }

    Result<std::shared_ptr<const Encoded>> encode(const api::ViewImage& v, ImageFormat format, int quality,
                                                  const std::string& etag, const std::atomic<bool>* cancel = nullptr) {
        EncodeOptions eo;
        eo.cancel = cancel;
        if (quality > 0) {
            eo.jpegQuality = quality;
            eo.webpQuality = quality;
        }
        auto bytes = encodeImage(v.rgba.data(), v.width, v.height, format, eo);
        if (!bytes) return bytes.error();
        auto e = std::make_shared<Encoded>();
        e->body.assign(reinterpret_cast<const char*>(bytes.value().data()), bytes.value().size());
        e->contentType = mimeType(format);
        e->etag = etag;
        return std::shared_ptr<const Encoded>(std::move(e));
    }

    void keepIds(const std::string& key, api::ViewImage&& v) {
        auto ids = std::make_shared<IdBuffer>();
        v.rgba.clear();
        v.rgba.shrink_to_fit();
        ids->view = std::move(v);
        idBuffers.put(key, std::move(ids));
    }

    // Everything about a view that can be wrong, checked without rendering: for profile
    // views the plane against the model and the frame's pixel size (api::profileMapping),
    // for perspective views that GL is on. Errors name the parameter.
    Status validateView(const api::CatalogModel& m, const api::ViewPlan& plan) {
        if (auto classes = api::blockClasses(m, plan.section); !classes) return classes.error();
        if (plan.view == api::ViewKind::Perspective) {
            if (auto s = api::checkPerspectiveCut(m, plan); !s) return s;
            if (plan.section.colour)
                return makeError(ErrorCode::Unsupported,
                                 "parameter 'colour': perspective (GL) views are not coloured by block properties "
                                 "yet; profile views, tiles, GeoJSON and SVG are");
            if (!glBackend)
                return makeError(ErrorCode::Unsupported,
                                 "parameter 'view': perspective views need GL, which is disabled on this server (--gl "
                                 "none)");
            return {};
        }
        auto mapping = api::profileMapping(m, plan);
        if (!mapping) return mapping.error();
        return {};
    }

    static std::vector<std::string_view> withNames(std::vector<std::string_view> names,
                                                   std::initializer_list<std::string_view> more) {
        names.insert(names.end(), more.begin(), more.end());
        return names;
    }

    // ---- routes ------------------------------------------------------------------
    void route(const char* method, const std::string& name, const std::string& pattern,
               std::function<void(const HttpRequest&, HttpResponse&)> fn) {
        auto wrapped = [this, name, method, fn = std::move(fn)](const HttpRequest& req, HttpResponse& res) {
            const auto t0 = Clock::now();
            ++inFlight;
            if (draining) {
                res.set_header("Connection", "close");
                res.set_header("Retry-After", "1");
                problem(res, 503, "the server is shutting down", req.path);
            } else {
                try {
                    fn(req, res);
                } catch (const std::exception& e) {
                    spdlog::error("event=handler_exception route={} what={}", name, e.what());
                    problem(res, 500, std::string("internal error: ") + e.what(), req.path, "internal");
                }
            }
            const double s = std::chrono::duration<double>(Clock::now() - t0).count();
            metrics.request(name, method, res.status, s);
            spdlog::debug("event=request method={} route={} path={} status={} ms={:.3f}", method, name, req.path,
                          res.status, s * 1e3);
            --inFlight;
        };
        routes.push_back({method, std::regex(pattern), std::move(wrapped)});
    }

    // Runs on a transport handler thread: the route whose method and pattern match the
    // whole path, else 404; OPTIONS answers any path (CORS preflight).
    void dispatch(HttpRequest& req, HttpResponse& res) {
        const std::string& cors = config.cors;
        if (req.method == "OPTIONS") {
            if (!cors.empty()) {
                res.set_header("Access-Control-Allow-Methods", "GET, POST, OPTIONS");
                res.set_header("Access-Control-Allow-Headers", "Content-Type, If-None-Match");
                res.set_header("Access-Control-Max-Age", "86400");
            }
            res.status = 204;
        } else {
            const Route* found = nullptr;
            std::smatch m;
            for (const auto& r : routes)
                if (r.method == req.method && std::regex_match(req.path, m, r.pattern)) {
                    found = &r;
                    break;
                }
            if (found) {
                req.matches.clear();
                for (const auto& group : m) req.matches.push_back(group.str());
                found->fn(req, res);
            } else {
                problem(res, 404, "no route for " + req.method + " " + req.path, req.path, "not_found");
            }
        }
        res.set_header("X-Content-Type-Options", "nosniff");
        // Operational routes are for the operator's probes and scrapers, not for browsers
        // on other origins: no CORS there.
        const bool operational = req.path == "/metrics" || req.path == "/readyz";
        if (!cors.empty() && !operational) {
            res.set_header("Access-Control-Allow-Origin", cors);
            res.set_header("Access-Control-Expose-Headers", "ETag, Retry-After");
        }
    }

    void addRoutes() {
        // The web client: index.html is revalidated on every load (no-cache + ETag); the
        // other assets are fetched with ?v=<build id> by the page and cached for a day.
        auto sendAsset = [](const HttpRequest& req, HttpResponse& res, const WebAsset* a, bool revalidate) {
            if (!a) return problem(res, 404, "no web asset '" + req.path.substr(0, 120) + "'", req.path, "not_found");
            res.set_header("ETag", std::string(a->etag));
            res.set_header("Cache-Control", revalidate ? "no-cache" : "public, max-age=86400");
            res.set_header("X-Content-Type-Options", "nosniff");
            if (etagMatches(req.get_header_value("If-None-Match"), std::string(a->etag))) {
                res.status = 304;
                return;
            }
            res.set_content(std::string(a->body), std::string(a->contentType));
        };
        route("GET", "/", "/", [sendAsset](const HttpRequest& req, HttpResponse& res) {
            sendAsset(req, res, findWebAsset("index.html"), true);
        });
        route("GET", "/web/{asset}", "/web/([A-Za-z0-9._/-]+)", [sendAsset](const HttpRequest& req, HttpResponse& res) {
            sendAsset(req, res, findWebAsset(req.matches[1]), false);
        });
        route("GET", "/healthz", "/healthz", [this](const HttpRequest&, HttpResponse& res) {
            sendJson(res, Json{{"status", "ok"}, {"version", kVersion}});
        });
        route("GET", "/readyz", "/readyz", [this](const HttpRequest&, HttpResponse& res) {
            // Ready once loading is done and at least one model is in: a broken file in the
            // models directory is reported here and in the logs, not a reason to stay unready.
            const bool modelsReady = loaded && catalog.size() > 0;
            const GlStatus::Snapshot gl = glStatus.get();
            const bool glOk = !glBackend || gl.ready;
            Json failures;
            {
                std::lock_guard lock(failedMutex);
                failures = failed;
            }
            if (!config.readyzPaths)
                for (auto& f : failures)
                    if (f.contains("error") && f["error"].is_string())
                        f["error"] = redactPaths(f["error"].get<std::string>());
            // Renders: overruns are counted; when every worker is running past its deadline
            // the server cannot take work and says so.
            const PoolStats ps = pool->stats();
            const bool workersOk = ps.overrunningNow < pool->workers();
            Json renders{{"queued", ps.queued},
                         {"busy", ps.busy},
                         {"overruns", ps.overruns},
                         {"overrunningNow", ps.overrunningNow},
                         {"dropped", ps.dropped},
                         {"cancelledWhileRunning", ps.cancelledRunning},
                         {"memoryBudgetMiB", pool->memoryBudget() >> 20},
                         {"memoryReservedMiB", ps.reservedBytes >> 20}};
            Json j{{"ready", modelsReady && glOk && workersOk},
                   {"models", {{"loaded", catalog.size()}, {"done", bool(loaded)}, {"failed", failures}}},
                   {"gl", {{"enabled", bool(glBackend)}, {"ready", gl.ready}, {"device", gl.device}}},
                   {"workers", pool->workers()},
                   {"renders", std::move(renders)}};
            sendJson(res, j, modelsReady && glOk && workersOk ? 200 : 503);
        });
        route("GET", "/metrics", "/metrics", [this](const HttpRequest&, HttpResponse& res) {
            res.set_content(metrics.text(), "text/plain; version=0.0.4");
        });
        route("GET", "/openapi.json", "/openapi\\.json",
              [](const HttpRequest&, HttpResponse& res) { sendJson(res, api::openApiDocument(kVersion)); });
        route("GET", "/v1/models", "/v1/models", [this](const HttpRequest&, HttpResponse& res) {
            Json list = Json::array();
            for (const auto& m : catalog.list()) {
                Json s = m->summary();
                s.erase("legend");
                list.push_back(std::move(s));
            }
            sendJson(res, Json{{"models", std::move(list)}, {"loading", !loaded}});
        });
        route("GET", "/v1/models/{id}", "/v1/models/([^/]+)", [this](const HttpRequest& req, HttpResponse& res) {
            auto m = model(req.matches[1], res, req.path);
            if (m) sendJson(res, m->summary());
        });
        route("GET", "/v1/models/{id}/legend.png", "/v1/models/([^/]+)/legend\\.png",
              [this](const HttpRequest& req, HttpResponse& res) {
                  auto m = model(req.matches[1], res, req.path);
                  if (!m) return;
                  // colour=PROP[&breaks=..&ramp=..]: the rows of that block-property colouring too.
                  auto params = toParams(req);
                  if (!params) return problem(res, params.error(), req.path);
                  if (auto s = api::checkKnownParams(params.value(), {"colour", "breaks", "ramp"}); !s)
                      return problem(res, s.error(), req.path);
                  auto colour = api::parseBlockColouring(params.value());
                  if (!colour) return problem(res, colour.error(), req.path);
                  api::SectionDef def;
                  def.colour = colour.value();
                  auto classes = api::blockClasses(*m, def);
                  if (!classes) return problem(res, classes.error(), req.path);
                  std::string key = "legend|" + m->id + "|" + m->version;
                  if (def.colour) {
                      key += "|" + def.colour->property + "|" + def.colour->ramp;
                      for (double b : classes.value()->breaks) key += "|" + api::formatNumber(b);
                  }
                  if (auto hit = images.get(key)) return sendEncoded(req, res, *hit);
                  // Drawn and encoded on a render worker (the threading rule: HTTP threads
                  // only wait), coalesced and cached like every other image.
                  auto result = renderCoalesced(
                      key,
                      [this, m, classes = classes.value(), etag = quoted(api::hex64(api::fnv1a64(key)))](
                          WorkerState&, const std::atomic<bool>& cancel) -> Rendered {
                          const auto t0 = Clock::now();
                          api::LegendImage legend = api::renderLegend(*m, 2, classes ? &*classes : nullptr);
                          api::ViewImage v;
                          v.width = legend.width;
                          v.height = legend.height;
                          v.rgba = std::move(legend.rgba);
                          metrics.render("legend", std::chrono::duration<double>(Clock::now() - t0).count());
                          return encode(v, ImageFormat::Png, 0, etag, &cancel);
                      },
                      kVectorBytes, false, req);
                  if (!result) return problem(res, result.error(), req.path);
                  sendEncoded(req, res, *result.value());
              });
        route("GET", "/v1/models/{id}/section.{format}", "/v1/models/([^/]+)/section\\.([A-Za-z0-9]+)",
              [this](const HttpRequest& req, HttpResponse& res) { sectionImage(req, res); });
        route("GET", "/v1/models/{id}/query", "/v1/models/([^/]+)/query",
              [this](const HttpRequest& req, HttpResponse& res) { queryGet(req, res); });
        route("POST", "/v1/models/{id}/query", "/v1/models/([^/]+)/query",
              [this](const HttpRequest& req, HttpResponse& res) { queryPost(req, res); });
        route("GET", "/v1/models/{id}/borehole", "/v1/models/([^/]+)/borehole",
              [this](const HttpRequest& req, HttpResponse& res) {
                  auto m = model(req.matches[1], res, req.path);
                  if (!m) return;
                  auto params = toParams(req);
                  if (!params) return problem(res, params.error(), req.path);
                  if (auto s = api::checkKnownParams(params.value(), {"x", "y", "lon", "lat"}); !s)
                      return problem(res, s.error(), req.path);
                  auto j = api::boreholeAt(*m, params.value());
                  if (!j) return problem(res, j.error(), req.path);
                  sendJson(res, j.value());
              });
        route("GET", "/v1/models/{id}/reserves", "/v1/models/([^/]+)/reserves",
              [this](const HttpRequest& req, HttpResponse& res) { reserves(req, res, false); });
        route("GET", "/v1/models/{id}/reserves.csv", "/v1/models/([^/]+)/reserves\\.csv",
              [this](const HttpRequest& req, HttpResponse& res) { reserves(req, res, true); });
        route("POST", "/v1/models/{id}/sections", "/v1/models/([^/]+)/sections",
              [this](const HttpRequest& req, HttpResponse& res) { defineSection(req, res); });
        route("GET", "/v1/sections/{sid}", "/v1/sections/([A-Za-z0-9_-]+)",
              [this](const HttpRequest& req, HttpResponse& res) { describeSection(req, res); });
        route("GET", "/v1/sections/{sid}/tiles/{z}/{x}/{y}.{format}",
              "/v1/sections/([A-Za-z0-9_-]+)/tiles/(-?[0-9]+)/(-?[0-9]+)/(-?[0-9]+)\\.([A-Za-z0-9]+)",
              [this](const HttpRequest& req, HttpResponse& res) { tile(req, res); });
    }

    Result<int> qualityParam(const api::Params& params) {
        if (const auto q = api::param(params, "quality")) {
            auto v = api::parseInteger("quality", *q, 1, 100);
            if (!v) return v.error();
            return int(v.value());
        }
        return 0;
    }

    void sectionImage(const HttpRequest& req, HttpResponse& res) {
        auto m = model(req.matches[1], res, req.path);
        if (!m) return;
        const std::string ext = req.matches[2];
        if (auto sheet = sheetFormat(req, ext); !sheet) {
            return problem(res, sheet.error(), req.path);
        } else if (sheet.value()) {
            return sectionSheet(req, res, *m, *sheet.value(), ext);
        }
        if (ext == "geojson" || ext == "svg") return sectionVector(req, res, *m, ext == "svg");
        auto format = imageFormatFromName(ext);
        if (!format)
            return problem(res, 404,
                           "unknown image format '" + std::string(req.matches[2]) +
                               "': use section.jpg, section.png or section.webp",
                           req.path, "not_found");
        auto params = toParams(req);
        if (!params) return problem(res, params.error(), req.path);
        if (auto s = api::checkKnownParams(params.value(), withNames(api::viewParamNames(), {"quality"})); !s)
            return problem(res, s.error(), req.path);
        auto plan = api::parseViewPlan(params.value(), m->id, m->model.crs);
        if (!plan) return problem(res, plan.error(), req.path);
        auto quality = qualityParam(params.value());
        if (!quality) return problem(res, quality.error(), req.path);
        // The whole view is validated (plane against the model, frame, pixel size) before
        // any cache or ETag is consulted: If-None-Match never answers a bad request.
        if (auto s = validateView(*m, plan.value()); !s) return problem(res, s.error(), req.path);
        const std::string viewKey = m->version + "|" + plan.value().canonical();
        const std::string key = viewKey + "|" + extension(format.value()) + "|q=" + std::to_string(quality.value());
        const std::string etag = quoted(api::hex64(api::fnv1a64(key)));
        if (etagMatches(req.get_header_value("If-None-Match"), etag)) {
            res.set_header("ETag", etag);
            res.set_header("Cache-Control", "public, max-age=86400");
            res.status = 304;
            metrics.count("geoslice_cache_total", "cache=\"etag\",result=\"hit\"");
            return;
        }
        if (auto hit = images.get(key)) {
            metrics.count("geoslice_cache_total", "cache=\"image\",result=\"hit\"");
            return sendEncoded(req, res, *hit);
        }
        metrics.count("geoslice_cache_total", "cache=\"image\",result=\"miss\"");
        const bool perspective = plan.value().view == api::ViewKind::Perspective;
        auto result = renderCoalesced(
            key,
            [this, m, plan = plan.value(), format = format.value(), q = quality.value(), etag, viewKey](
                WorkerState& w, const std::atomic<bool>& cancel) -> Rendered {
                Result<api::ViewImage> view = makeError(ErrorCode::Internal, "no view");
                if (plan.view == api::ViewKind::Perspective) {
                    if (!w.gl) {
                        auto gl = GlWorker::create(*glBackend, config.lod == "auto");
                        if (!gl) return gl.error();
                        w.gl = std::move(gl.value());
                    }
                    view = w.gl->renderPerspective(*m, plan, &cancel);
                } else {
                    view = api::renderProfile(*m, plan, &cancel);
                }
                if (!view) return view.error();
                if (auto c = checkCancel(&cancel); !c) return c.error();
                metrics.render(plan.view == api::ViewKind::Perspective ? "gl" : "section", view.value().renderMs / 1e3);
                auto e = encode(view.value(), format, q, etag, &cancel);
                if (e) keepIds(viewKey, std::move(view.value()));
                return e;
            },
            renderBytes(plan.value().width, plan.value().height, perspective), perspective, req);
        if (!result) return problem(res, result.error(), req.path);
        sendEncoded(req, res, *result.value());
    }

    // Print sheets (api/sheet.hpp, print/): section.pdf, section.svg?layout=print and
    // section.{png,jpg,webp}?decorate=1. nullopt: not a sheet request.
    Result<std::optional<api::SheetFormat>> sheetFormat(const HttpRequest& req, const std::string& ext) {
        const api::SheetFormat format = ext == "pdf"   ? api::SheetFormat::Pdf
                                        : ext == "svg" ? api::SheetFormat::Svg
                                                       : api::SheetFormat::Raster;
        if (ext == "geojson") return std::optional<api::SheetFormat>();
        auto params = toParams(req);
        if (!params) return params.error();
        auto wants = api::wantsSheet(params.value(), format);
        if (!wants) return wants.error();
        return wants.value() ? std::optional<api::SheetFormat>(format) : std::nullopt;
    }

    void sectionSheet(const HttpRequest& req, HttpResponse& res, const api::CatalogModel& m, api::SheetFormat format,
                      const std::string& ext) {
        auto params = toParams(req);
        if (!params) return problem(res, params.error(), req.path);
        auto imageFormat = imageFormatFromName(ext);
        if (format == api::SheetFormat::Raster && !imageFormat) return problem(res, imageFormat.error(), req.path);
        auto known = withNames(api::viewParamNames(), {"quality"});
        known.insert(known.end(), api::sheetParamNames().begin(), api::sheetParamNames().end());
        if (auto s = api::checkKnownParams(params.value(), known); !s) return problem(res, s.error(), req.path);
        auto quality = qualityParam(params.value());
        if (!quality) return problem(res, quality.error(), req.path);
        auto sheet = api::parseSheetRequest(params.value(), m, format, print::todayUtc());
        if (!sheet) return problem(res, sheet.error(), req.path);
        if (auto s = validateView(m, sheet.value().plan); !s) return problem(res, s.error(), req.path);
        const std::string key =
            m.version + "|" + sheet.value().canonical() + "|" + ext + "|q=" + std::to_string(quality.value());
        const std::string etag = quoted(api::hex64(api::fnv1a64(key)));
        if (etagMatches(req.get_header_value("If-None-Match"), etag)) {
            res.set_header("ETag", etag);
            res.set_header("Cache-Control", "public, max-age=86400");
            res.status = 304;
            return;
        }
        if (auto hit = images.get(key)) return sendEncoded(req, res, *hit);
        auto mp = catalog.find(m.id);
        auto result = renderCoalesced(
            key,
            [this, mp, r = sheet.value(), etag, q = quality.value(),
             imageFormat = imageFormat.ok() ? imageFormat.value() : ImageFormat::Png](
                WorkerState&, const std::atomic<bool>& cancel) -> Rendered {
                auto out = api::renderSheet(*mp, r, &cancel);
                if (!out) return out.error();
                metrics.render("sheet", out.value().renderMs / 1e3);
                if (r.format == api::SheetFormat::Raster) {
                    api::ViewImage v;
                    v.width = out.value().width;
                    v.height = out.value().height;
                    v.rgba = std::move(out.value().rgba);
                    return encode(v, imageFormat, q, etag, &cancel);
                }
                auto e = std::make_shared<Encoded>();
                e->body = std::move(out.value().document);
                e->contentType = r.format == api::SheetFormat::Pdf ? "application/pdf" : "image/svg+xml";
                e->etag = etag;
                return std::shared_ptr<const Encoded>(std::move(e));
            },
            std::max(kVectorBytes, sheet.value().memoryBytes()), false, req);
        if (!result) return problem(res, result.error(), req.path);
        sendEncoded(req, res, *result.value());
    }

    void sectionVector(const HttpRequest& req, HttpResponse& res, const api::CatalogModel& m, bool svg) {
        auto params = toParams(req);
        if (!params) return problem(res, params.error(), req.path);
        if (auto s = api::checkKnownParams(params.value(), withNames(api::viewParamNames(), {"space"})); !s)
            return problem(res, s.error(), req.path);
        bool world = false;
        if (const auto space = api::param(params.value(), "space")) {
            if (*space != "plane" && *space != "world")
                return problem(res, 400, "parameter 'space': '" + std::string(*space) + "' is not 'plane' or 'world'",
                               req.path, "invalid_argument");
            world = *space == "world";
        }
        auto plan = api::parseViewPlan(params.value(), m.id, m.model.crs);
        if (!plan) return problem(res, plan.error(), req.path);
        if (auto s = validateView(m, plan.value()); !s) return problem(res, s.error(), req.path);
        const std::string key = m.version + "|" + plan.value().canonical() +
                                (svg     ? "|svg"
                                 : world ? "|geojson-world"
                                         : "|geojson");
        const std::string etag = quoted(api::hex64(api::fnv1a64(key)));
        if (auto hit = images.get(key)) return sendEncoded(req, res, *hit);
        auto mp = catalog.find(m.id);
        auto result = renderCoalesced(
            key,
            [this, mp, plan = plan.value(), svg, world, etag](WorkerState&,
                                                              const std::atomic<bool>& cancel) -> Rendered {
                const auto t0 = Clock::now();
                auto text = api::renderVector(*mp, plan, svg, world, &cancel);
                if (!text) return text.error();
                metrics.render(svg ? "svg" : "geojson", std::chrono::duration<double>(Clock::now() - t0).count());
                auto e = std::make_shared<Encoded>();
                e->body = std::move(text.value());
                e->contentType = svg ? "image/svg+xml" : "application/geo+json";
                e->etag = etag;
                return std::shared_ptr<const Encoded>(std::move(e));
            },
            kVectorBytes, false, req);
        if (!result) return problem(res, result.error(), req.path);
        sendEncoded(req, res, *result.value());
    }

    // Reserves (api/reserves.hpp, the same document as `geoslice reserves --json`): computed
    // on a render worker like every other model-sized job, cached by model version + the
    // canonical plane + format.
    void reserves(const HttpRequest& req, HttpResponse& res, bool csvPath) {
        auto m = model(req.matches[1], res, req.path);
        if (!m) return;
        auto params = toParams(req);
        if (!params) return problem(res, params.error(), req.path);
        auto rr = api::parseReservesRequest(params.value(), csvPath);
        if (!rr) return problem(res, rr.error(), req.path);
        const std::string key = m->version + "|reserves|" + rr.value().canonical();
        const std::string etag = quoted(api::hex64(api::fnv1a64(key)));
        if (auto hit = images.get(key)) {
            metrics.count("geoslice_cache_total", "cache=\"reserves\",result=\"hit\"");
            return sendEncoded(req, res, *hit);
        }
        metrics.count("geoslice_cache_total", "cache=\"reserves\",result=\"miss\"");
        auto result = renderCoalesced(
            key,
            [this, m, r = rr.value(), etag](WorkerState&, const std::atomic<bool>&) -> Rendered {
                const auto t0 = Clock::now();
                auto figures = computeReserves(m->model, r.plane);
                if (!figures) return figures.error();
                auto e = std::make_shared<Encoded>();
                if (r.cutoffs) {
                    auto property = api::gradeProperty(m->model, r.property);
                    if (!property) return property.error();
                    auto table = computeGradeTonnage(m->model, property.value(), *r.cutoffs, r.plane);
                    if (!table) return table.error();
                    if (r.csv) {
                        e->body = api::gradeTonnageCsv(m->model, table.value());
                    } else {
                        auto doc = api::reservesJson(m->model, figures.value(), m->id);
                        doc["grade_tonnage"] = api::gradeTonnageJson(m->model, table.value());
                        e->body = doc.dump();
                    }
                } else {
                    e->body = r.csv ? api::reservesCsv(m->model, figures.value())
                                    : api::reservesJson(m->model, figures.value(), m->id).dump();
                }
                e->contentType = r.csv ? "text/csv; charset=utf-8; header=present" : "application/json";
                e->etag = etag;
                metrics.render("reserves", std::chrono::duration<double>(Clock::now() - t0).count());
                return std::shared_ptr<const Encoded>(std::move(e));
            },
            kVectorBytes, false, req);
        if (!result) return problem(res, result.error(), req.path);
        sendEncoded(req, res, *result.value());
    }

    Result<std::string> answerQuery(const api::CatalogModel& m, const api::Params& params, const api::ViewPlan& plan) {
        const auto px = api::param(params, "px");
        const auto py = api::param(params, "py");
        if (!px || !py) return makeError(ErrorCode::InvalidArgument, "query: give the pixel as 'px' and 'py'");
        auto x = api::parseInteger("px", *px, -(1LL << 40), 1LL << 40);
        if (!x) return x.error();
        auto y = api::parseInteger("py", *py, -(1LL << 40), 1LL << 40);
        if (!y) return y.error();
        auto cached = idBuffers.get(m.version + "|" + plan.canonical());
        metrics.count("geoslice_cache_total",
                      cached ? "cache=\"ids\",result=\"hit\"" : "cache=\"ids\",result=\"miss\"");
        return api::queryPixel(m, plan, x.value(), y.value(), cached ? &cached->view : nullptr);
    }

    void queryGet(const HttpRequest& req, HttpResponse& res) {
        auto m = model(req.matches[1], res, req.path);
        if (!m) return;
        auto params = toParams(req);
        if (!params) return problem(res, params.error(), req.path);
        if (auto s = api::checkKnownParams(params.value(), withNames(api::viewParamNames(), {"px", "py"})); !s)
            return problem(res, s.error(), req.path);
        auto plan = api::parseViewPlan(params.value(), m->id, m->model.crs);
        if (!plan) return problem(res, plan.error(), req.path);
        auto j = answerQuery(*m, params.value(), plan.value());
        if (!j) return problem(res, j.error(), req.path);
        res.status = 200;
        res.set_content(j.value(), "application/json");
    }

    // POST /query: a batch of pixels of one view, answered on a render worker like a
    // render (queue, deadline, cancellation, memory admission), at most kMaxBatchPixels
    // pixels and kMaxBatchAnswerBytes of answer.
    void queryPost(const HttpRequest& req, HttpResponse& res) {
        auto m = model(req.matches[1], res, req.path);
        if (!m) return;
        if (!requireJsonBody(req, res)) return;
        const nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
        if (body.is_discarded() || !body.is_object())
            return problem(res, 400, "the body is not a JSON object", req.path, "parse_error");
        for (const auto& [k, v] : body.items())
            if (k != "view" && k != "pixels")
                return problem(res, 400, "unknown field '" + k.substr(0, 64) + "' in the body; known: view, pixels",
                               req.path, "invalid_argument");
        if (!body.contains("view") || !body.contains("pixels") || !body["pixels"].is_array())
            return problem(res, 400,
                           "the body needs 'view' (an object of view parameters) and 'pixels' ([[px, py], ...])",
                           req.path, "invalid_argument");
        if (body["pixels"].size() > kMaxBatchPixels)
            return problem(res, 400,
                           "field 'pixels': at most " + std::to_string(kMaxBatchPixels) + " pixels per batch, got " +
                               std::to_string(body["pixels"].size()),
                           req.path, "out_of_range");
        auto params = jsonToParams(body["view"], "'view'");
        if (!params) return problem(res, params.error(), req.path);
        if (auto s = api::checkKnownParams(params.value(), api::viewParamNames()); !s)
            return problem(res, makeError(s.error().code, "field 'view': " + s.error().message), req.path);
        auto plan = api::parseViewPlan(params.value(), m->id, m->model.crs);
        if (!plan) return problem(res, plan.error(), req.path);
        if (auto s = validateView(*m, plan.value()); !s) return problem(res, s.error(), req.path);
        std::vector<std::pair<long long, long long>> pixels;
        pixels.reserve(body["pixels"].size());
        for (const auto& p : body["pixels"]) {
            if (!p.is_array() || p.size() != 2 || !p[0].is_number_integer() || !p[1].is_number_integer())
                return problem(
                    res, 400,
                    "field 'pixels': pixels[" + std::to_string(pixels.size()) + "] is not [px, py] with whole numbers",
                    req.path, "invalid_argument");
            pixels.emplace_back(p[0].get<long long>(), p[1].get<long long>());
        }
        // Keyed by the request itself: identical concurrent batches share one answer.
        const std::string key =
            m->version + "|query|" + plan.value().canonical() + "|" + api::hex64(api::fnv1a64(body["pixels"].dump()));
        auto result = renderCoalesced(
            key,
            [this, m, plan = plan.value(), pixels = std::move(pixels)](WorkerState&,
                                                                       const std::atomic<bool>& cancel) -> Rendered {
                auto cached = idBuffers.get(m->version + "|" + plan.canonical());
                auto e = std::make_shared<Encoded>();
                std::string& out = e->body;
                out = "{\"results\":[";
                for (std::size_t i = 0; i < pixels.size(); ++i) {
                    if ((i & 63) == 0)
                        if (auto c = checkCancel(&cancel); !c) return c.error();
                    auto a =
                        api::answerPixel(*m, plan, pixels[i].first, pixels[i].second, cached ? &cached->view : nullptr);
                    if (!a)
                        return makeError(a.error().code,
                                         "field 'pixels': pixels[" + std::to_string(i) + "]: " + a.error().message);
                    if (i) out += ',';
                    api::writeQueryAnswer(*m, a.value(), out);
                    if (out.size() > kMaxBatchAnswerBytes)
                        return makeError(ErrorCode::OutOfRange,
                                         "field 'pixels': the answer passed " + mib(kMaxBatchAnswerBytes) +
                                             " MiB after " + std::to_string(i + 1) + " pixels; ask for fewer pixels");
                }
                out += "]}";
                e->contentType = "application/json";
                return std::shared_ptr<const Encoded>(std::move(e));
            },
            body["pixels"].size() * kQueryAnswerBytes, false, req, false);
        if (!result) return problem(res, result.error(), req.path);
        res.status = 200;
        res.set_content(result.value()->body, "application/json");
    }

    void defineSection(const HttpRequest& req, HttpResponse& res) {
        auto m = model(req.matches[1], res, req.path);
        if (!m) return;
        if (!requireJsonBody(req, res)) return;
        const nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
        if (body.is_discarded()) return problem(res, 400, "the body is not valid JSON", req.path, "parse_error");
        auto params = jsonToParams(body, "the section definition");
        if (!params) return problem(res, params.error(), req.path);
        if (auto s = api::checkKnownParams(params.value(), api::sectionParamNames()); !s)
            return problem(res, s.error(), req.path);
        auto def = api::parseSectionDef(params.value(), m->id, m->model.crs);
        if (!def) return problem(res, def.error(), req.path);
        auto grid = api::tileGrid(*m, def.value());
        if (!grid) return problem(res, grid.error(), req.path);
        const std::string sid = api::encodeSectionId(def.value());
        Json j;
        j["sid"] = sid;
        j["model"] = m->id;
        j["definition"] = def.value().canonical();
        j["tiles"] = "/v1/sections/" + sid + "/tiles/{z}/{x}/{y}.png";
        j["grid"] = grid.value().describe();
        res.set_header("Location", "/v1/sections/" + sid);
        sendJson(res, j, 201);
    }

    Result<std::pair<std::shared_ptr<const api::CatalogModel>, api::SectionDef>> section(const std::string& sid) {
        auto def = api::decodeSectionId(sid, [this](const std::string& id) -> const Crs* {
            auto m = catalog.find(id);
            return m ? &m->model.crs : nullptr;
        });
        if (!def) return def.error();
        auto m = catalog.find(def.value().model);
        if (!m) return makeError(ErrorCode::NotFound, "section names model '" + def.value().model + "', not loaded");
        return std::make_pair(m, def.value());
    }

    void describeSection(const HttpRequest& req, HttpResponse& res) {
        if (auto p = toParams(req); !p || !api::checkKnownParams(p.value(), {}).ok())
            return problem(res, 400, "this route takes no query parameters", req.path, "invalid_argument");
        auto s = section(req.matches[1]);
        if (!s) return problem(res, s.error(), req.path);
        auto grid = api::tileGrid(*s.value().first, s.value().second);
        if (!grid) return problem(res, grid.error(), req.path);
        sendJson(res, Json{{"sid", std::string(req.matches[1])},
                           {"model", s.value().first->id},
                           {"definition", s.value().second.canonical()},
                           {"grid", grid.value().describe()}});
    }

    void tile(const HttpRequest& req, HttpResponse& res) {
        auto format = imageFormatFromName(std::string(req.matches[5]));
        if (!format)
            return problem(res, 404, "unknown tile format '" + std::string(req.matches[5]) + "'", req.path,
                           "not_found");
        auto z = api::parseInteger("z", std::string(req.matches[2]), 0, 30);
        auto x = api::parseInteger("x", std::string(req.matches[3]), -(1LL << 40), 1LL << 40);
        auto y = api::parseInteger("y", std::string(req.matches[4]), -(1LL << 40), 1LL << 40);
        if (!z || !x || !y) return problem(res, 404, "tile coordinates are out of range", req.path, "not_found");
        if (auto p = toParams(req); !p || !api::checkKnownParams(p.value(), {}).ok())
            return problem(res, 400, "tiles take no query parameters", req.path, "invalid_argument");
        const std::string sid = req.matches[1];
        auto s = section(sid);
        if (!s) return problem(res, s.error(), req.path);
        const auto& [m, def] = s.value();
        // Validated before any cache or ETag is consulted.
        auto grid = api::tileGrid(*m, def);
        if (!grid) return problem(res, grid.error(), req.path);
        if (auto rect = grid.value().tileRect(int(z.value()), x.value(), y.value()); !rect)
            return problem(res, rect.error(), req.path);
        const std::string key = m->version + "|tile|" + def.canonical() + "|" + std::to_string(z.value()) + "/" +
                                std::to_string(x.value()) + "/" + std::to_string(y.value()) + "|" +
                                extension(format.value());
        const std::string etag = quoted(api::hex64(api::fnv1a64(key)));
        if (etagMatches(req.get_header_value("If-None-Match"), etag)) {
            res.set_header("ETag", etag);
            res.set_header("Cache-Control", "public, max-age=86400");
            res.status = 304;
            return;
        }
        if (auto hit = images.get(key)) {
            metrics.count("geoslice_cache_total", "cache=\"tile\",result=\"hit\"");
            return sendEncoded(req, res, *hit);
        }
        metrics.count("geoslice_cache_total", "cache=\"tile\",result=\"miss\"");
        auto result = renderCoalesced(
            key,
            [this, m = m, def = def, g = grid.value(), z = int(z.value()), x = x.value(), y = y.value(),
             format = format.value(), etag](WorkerState&, const std::atomic<bool>& cancel) -> Rendered {
                auto view = api::renderSectionTile(*m, def, g, z, x, y, &cancel);
                if (!view) return view.error();
                metrics.render("tile", view.value().renderMs / 1e3);
                return encode(view.value(), format, 0, etag, &cancel);
            },
            renderBytes(grid.value().tileSize, grid.value().tileSize, false), false, req);
        if (!result) return problem(res, result.error(), req.path);
        sendEncoded(req, res, *result.value());
    }

    // ---- life cycle ----------------------------------------------------------------
    void loadModels() {
        bool ok = true;
        if (config.modelsDir.empty()) {
            spdlog::info("event=demo_generate triangles={}", config.demoTriangles);
            auto demo = api::makeDemoModel(config.demoTriangles);
            if (demo) {
                spdlog::info("event=model_loaded id=demo triangles={} ms={:.0f}", demo.value()->model.triangleCount(),
                             demo.value()->loadMs);
                catalog.add(demo.value());
            } else {
                ok = false;
                spdlog::error("event=model_failed id=demo error=\"{}\"", demo.error().message);
                std::lock_guard lock(failedMutex);
                failed.push_back({{"id", "demo"}, {"error", demo.error().message}});
            }
        } else {
            auto files = api::listModelFiles(config.modelsDir);
            if (!files) {
                ok = false;
                spdlog::error("event=models_dir_failed error=\"{}\"", files.error().message);
                std::lock_guard lock(failedMutex);
                failed.push_back({{"id", nullptr}, {"error", files.error().message}});
            } else {
                if (files.value().empty()) spdlog::warn("event=models_dir_empty dir=\"{}\"", config.modelsDir);
                for (const auto& [id, path] : files.value()) {
                    if (draining) break;
                    auto m = api::loadCatalogModel(id, path, config.bakeDir, !config.noBake);
                    if (m) {
                        spdlog::info("event=model_loaded id={} triangles={} ms={:.0f} version={}", id,
                                     m.value()->model.triangleCount(), m.value()->loadMs, m.value()->version);
                        if (!m.value()->loadWarning.empty())
                            spdlog::warn("event=model_load_warning id={} warning=\"{}\"", id, m.value()->loadWarning);
                        if (!m.value()->rebakedFrom.empty())
                            spdlog::warn("event=package_rebaked id={} moved_aside=\"{}\"", id, m.value()->rebakedFrom);
                        const auto& notes = m.value()->model.notes;
                        if (auto w = notes.find("crs_warning"); w != notes.end())
                            spdlog::warn("event=model_crs_warning id={} warning=\"{}\"", id, w->second);
                        catalog.add(m.value());
                    } else {
                        ok = false;
                        spdlog::error("event=model_failed id={} path=\"{}\" error=\"{}\"", id, path, m.error().message);
                        std::lock_guard lock(failedMutex);
                        failed.push_back({{"id", id}, {"error", m.error().message}});
                    }
                }
            }
        }
        loadOk = ok;
        {
            std::lock_guard lock(loadMutex);
            loaded = true;
        }
        loadDone.notify_all();
    }

    void probeGl() {
        if (!glBackend) return;
        // Create one worker's context now, so /readyz can report the device and the first
        // perspective request does not pay for it.
        RenderJob job;
        job.run = [this](WorkerState& w, const std::atomic<bool>&) {
            auto gl = GlWorker::create(*glBackend, config.lod == "auto");
            if (!gl) {
                glStatus.set("failed: " + gl.error().message, false);
                spdlog::warn("event=gl_unavailable error=\"{}\"", gl.error().message);
                return;
            }
            const std::string device = gl.value()->context->info().describe();
            spdlog::info("event=gl_ready device=\"{}\"", device);
            w.gl = std::move(gl.value());
            glStatus.set(device, true);
        };
        if (pool->submit(std::move(job)) != Admission::Queued)
            glStatus.set("failed: the render queue refused the probe", false);
    }
};

SectionServer::SectionServer(ServerConfig config) : config_(std::move(config)) {}

SectionServer::~SectionServer() { stop(); }

api::Catalog& SectionServer::catalog() { return impl_->catalog; }

Result<int> SectionServer::start() {
    if (auto s = checkConfig(config_); !s) return s.error();
    impl_ = std::make_unique<Impl>(config_);
    Impl& im = *impl_;
    if (config_.gl != "none") im.glBackend = parseGlBackend(config_.gl);
    const unsigned workers = config_.workers ? config_.workers : std::max(1u, std::thread::hardware_concurrency());
    im.pool = std::make_unique<RenderPool>(workers, config_.queue, config_.memoryBudgetMiB << 20);

    im.addRoutes();

    im.metrics.gauge("geoslice_queue_depth", "Render jobs waiting.", [&im] { return double(im.pool->queueDepth()); });
    im.metrics.gauge("geoslice_renders_overrun", "Render jobs that ran past their deadline (total).",
                     [&im] { return double(im.pool->stats().overruns); });
    im.metrics.gauge("geoslice_renders_overrunning", "Render workers running past their deadline now.",
                     [&im] { return double(im.pool->stats().overrunningNow); });
    im.metrics.gauge("geoslice_renders_dropped", "Queued renders dropped: cancelled or past their deadline (total).",
                     [&im] { return double(im.pool->stats().dropped); });
    im.metrics.gauge("geoslice_render_memory_reserved_bytes", "Estimated memory of queued and running renders.",
                     [&im] { return double(im.pool->stats().reservedBytes); });
    im.metrics.gauge("geoslice_workers_busy", "Render workers busy.", [&im] { return double(im.pool->busyWorkers()); });
    im.metrics.gauge("geoslice_requests_in_flight", "HTTP requests being handled.",
                     [&im] { return double(im.inFlight.load()); });
    im.metrics.gauge("geoslice_cache_bytes", "Bytes held by the image and ID-buffer caches.",
                     [&im] { return double(im.images.usedBytes() + im.idBuffers.usedBytes()); });
    im.metrics.gauge("geoslice_cache_entries", "Entries in the image and ID-buffer caches.",
                     [&im] { return double(im.images.entries() + im.idBuffers.entries()); });
    im.metrics.gauge("geoslice_renders_coalesced", "Requests that shared another request's render (total).",
                     [&im] { return double(im.coalescer.coalesced()); });
    im.metrics.gauge("geoslice_models_loaded", "Models loaded.", [&im] { return double(im.catalog.size()); });

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
        tc, [&im](HttpRequest& req, HttpResponse& res) { im.dispatch(req, res); },
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
    im.metrics.gauge("geoslice_connections_open", "HTTP connections open.",
                     [&http] { return double(http.stats().open); });
    im.metrics.gauge("geoslice_connections_refused", "Connections answered 503 at the connection cap (total).",
                     [&http] { return double(http.stats().rejected); });
    im.metrics.gauge("geoslice_connections_evicted",
                     "Connections waiting for a request closed to admit a new one at the cap (total).",
                     [&http] { return double(http.stats().evicted); });
    im.metrics.gauge("geoslice_connection_timeouts", "Connections closed by a header, body or send deadline (total).",
                     [&http] {
                         const auto s = http.stats();
                         return double(s.headerTimeouts + s.bodyTimeouts + s.sendTimeouts);
                     });
    im.metrics.gauge("geoslice_requests_abandoned", "Requests whose client went away while being handled (total).",
                     [&http] { return double(http.stats().cancelled); });
    http.start();
    im.loader = std::thread([&im] { im.loadModels(); });
    im.probeGl();
    spdlog::info("event=listening host={} port={} workers={} http_threads={} max_connections={} gl={} models=\"{}\"",
                 config_.host, port_, workers, tc.handlerThreads, tc.maxConnections, config_.gl,
                 config_.modelsDir.empty() ? "demo" : config_.modelsDir);
    return port_;
}

bool SectionServer::waitUntilLoaded() {
    if (!impl_) return false;
    std::unique_lock lock(impl_->loadMutex);
    impl_->loadDone.wait(lock, [this] { return impl_->loaded.load(); });
    return impl_->loadOk;
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
    std::lock_guard lock(im.stopMutex);
    if (im.stopped) return;
    im.draining = true;
    spdlog::info("event=shutdown_begin in_flight={}", im.inFlight.load());
    // In-flight requests get a grace period to finish (shutdownGraceMs, or the deadline
    // if shorter); then queued renders are dropped and running ones cancelled (they stop
    // within milliseconds), so SIGTERM ends within the grace period plus a second even
    // when a render would run for minutes.
    const auto until = Clock::now() + std::chrono::milliseconds(std::min(config_.deadlineMs, config_.shutdownGraceMs));
    while (im.inFlight > 0 && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!im.pool->stop(std::chrono::milliseconds(1000))) {
        // A render is inside a codec call that cannot be cancelled (libwebp's alpha pass on
        // a huge image): end the process now rather than overrun the grace period.
        spdlog::warn("event=shutdown_forced reason=\"a render did not stop within 1 s of its cancellation\"");
        spdlog::default_logger()->flush();
        std::_Exit(0);
    }
    const auto after = Clock::now() + std::chrono::milliseconds(1000);
    while (im.inFlight > 0 && Clock::now() < after) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    // Answers being written get a second; connections that wait for a request close now.
    if (im.http) im.http->stop(1000);
    if (im.loader.joinable()) im.loader.join();
    im.pool.reset();  // destroys the workers' GL contexts
    im.stopped = true;
    spdlog::info("event=shutdown_done");
}

}  // namespace geoslice::server
