// A model's drillholes for maps, the model checked against them and the strip log of one hole
// (api/drillhole_check.hpp):
//   GET /v1/models/{id}/drillholes               every hole: collar, depth, trace; the interval columns
//   GET /v1/models/{id}/drillholes/check[.csv]   (format=json|csv, rows=units|contacts)
//   GET /v1/models/{id}/drillholes/{hole}/log
// The check is model-sized work: computed on a render worker like reserves, cached by model
// version + the canonical request. A log is one hole: on the handler thread, like a borehole.
// Hole ids come percent-decoded (the router refuses invalid UTF-8) and are only looked up in
// the database, never used as a path; an unknown one is a 404 that names it (escaped).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "api/drillhole_check.hpp"
#include "model/json_text.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {
namespace {

// Hole ids longer than this are refused before any lookup (no database holds such ids).
constexpr std::size_t kMaxHoleIdBytes = 256;

// The model's drillhole database, or null after answering: 404 when the model has no sidecar,
// 409 when its sidecar did not load (the model is served; the message says why).
const DrillholeDatabase* drillholesOf(const api::CatalogModel& m, const HttpRequest& req, HttpResponse& res) {
    if (m.drillholes) return m.drillholes.get();
    if (!m.drillholeWarning.empty()) {
        problem(res, 409, "model '" + m.id + "': " + m.drillholeWarning, req.path, "drillholes_not_loaded");
        return nullptr;
    }
    problem(res, 404,
            "model '" + m.id + "' has no drillholes: put " + m.id +
                ".drillholes.json beside the model file (docs/drillholes.md)",
            req.path, "not_found");
    return nullptr;
}

void check(ServerState& st, const HttpRequest& req, HttpResponse& res, bool csvPath) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), {"format", "rows"}); !s)
        return problem(res, s.error(), req.path);
    bool csv = csvPath, contacts = false;
    if (const auto f = api::param(params.value(), "format")) {
        if (*f != "json" && *f != "csv")
            return problem(res, 400,
                           "parameter 'format': '" + std::string(f->substr(0, 64)) + "' is not 'json' or 'csv'",
                           req.path, "invalid_argument");
        if (csvPath && *f == "json")
            return problem(res, 400, "parameter 'format': 'json' conflicts with the path check.csv", req.path,
                           "invalid_argument");
        csv = *f == "csv";
    }
    if (const auto r = api::param(params.value(), "rows")) {
        if (*r != "units" && *r != "contacts")
            return problem(res, 400,
                           "parameter 'rows': '" + std::string(r->substr(0, 64)) + "' is not 'units' or 'contacts'",
                           req.path, "invalid_argument");
        if (!csv)
            return problem(res, 400, "parameter 'rows' applies to CSV only (format=csv or check.csv)", req.path,
                           "invalid_argument");
        contacts = *r == "contacts";
    }
    if (!drillholesOf(*m, req, res)) return;
    const std::string canonical =
        std::string("drillholes-check|") + (csv ? (contacts ? "csv-contacts" : "csv") : "json");
    const std::string key = cache_key::reserves(*m, canonical);
    if (auto hit = st.cache->find(key, "drillholes")) return sendEncoded(req, res, *hit);
    auto result = st.cache->render(
        key,
        [&st, m, csv, contacts, etag = RenderCache::etagOf(key)](workers::WorkerState&,
                                                                 const std::atomic<bool>& cancel) -> Rendered {
            const auto t0 = std::chrono::steady_clock::now();
            auto rays = m->rays->wait(std::chrono::steady_clock::time_point::max(), &cancel);
            if (!rays) return rays.error();
            auto c = api::checkDrillholes(m->model, *m->drillholes, *rays.value().tracer);
            if (!c) return c.error();
            std::string body = csv ? api::drillholeCheckCsv(c.value(), contacts)
                                   : jsonText(api::drillholeCheckJson(c.value(), m->id, m->drillholes->source));
            st.metrics.render("drillholes_check",
                              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            return documentEntry(std::move(body), csv ? "text/csv; charset=utf-8; header=present" : "application/json",
                                 etag);
        },
        kVectorBytes, false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

// Every hole for a map or a picker: id, collar, end depth, the collar's azimuth and dip, and
// the desurveyed trace at its nodes (survey stations and the end: minimum-curvature legs are
// arcs, drawn between nodes as chords; with stations 30 m apart a chord is within 1 m of the
// arc for doglegs under 15 degrees), in the model's CRS; and the interval columns a section
// can colour holes by (holecolour=). Model-version data: cached like the check.
void holes(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), {}); !s) return problem(res, s.error(), req.path);
    const DrillholeDatabase* db = drillholesOf(*m, req, res);
    if (!db) return;
    const std::string key = cache_key::reserves(*m, "drillholes-list");
    if (auto hit = st.cache->find(key, "drillholes")) return sendEncoded(req, res, *hit);
    auto result = st.cache->render(
        key,
        [m, db, etag = RenderCache::etagOf(key)](workers::WorkerState&, const std::atomic<bool>&) -> Rendered {
            auto round = [](double v) { return std::round(v * 1000.0) / 1000.0; };  // mm
            auto point = [&round](const glm::dvec3& p) {
                return nlohmann::ordered_json::array({round(p.x), round(p.y), round(p.z)});
            };
            nlohmann::ordered_json j;
            j["model"] = m->id;
            j["version"] = m->version;
            j["crs"] = m->model.crs.isLocal() ? nlohmann::ordered_json() : nlohmann::ordered_json(m->model.crs.id());
            if (!db->conversion.empty()) j["converted"] = db->conversion;
            nlohmann::ordered_json columns = nlohmann::ordered_json::array();
            for (const IntervalTable& t : db->intervals)
                for (const IntervalColumn& c : t.columns)
                    columns.push_back(
                        {{"table", t.name},
                         {"column", c.name},
                         {"kind", c.numeric ? "number" : "text"},
                         {"unit", c.unit.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(c.unit)}});
            j["columns"] = std::move(columns);
            nlohmann::ordered_json holes = nlohmann::ordered_json::array();
            for (const Drillhole& d : db->holes) {
                nlohmann::ordered_json h;
                h["id"] = d.id;
                h["collar"] = point(d.collar);
                const double end = std::isnan(d.totalDepth) ? d.path.depth.back() : d.totalDepth;
                h["depth"] = round(end);
                const glm::dvec3 dir = d.path.direction.empty() ? glm::dvec3(0, 0, -1) : d.path.direction.front();
                const double az = std::atan2(dir.x, dir.y) * 180.0 / std::numbers::pi;
                h["azimuth"] = round(std::fmod(az + 360.0, 360.0));
                h["dip"] = round(std::asin(std::clamp(dir.z, -1.0, 1.0)) * 180.0 / std::numbers::pi);
                nlohmann::ordered_json trace = nlohmann::ordered_json::array();
                for (std::size_t i = 0; i < d.path.position.size() && d.path.depth[i] <= end + 1e-9; ++i)
                    trace.push_back(point(d.path.position[i]));
                if (d.path.depth.empty() || d.path.depth.back() < end - 1e-9) trace.push_back(point(d.path.at(end)));
                h["trace"] = std::move(trace);
                holes.push_back(std::move(h));
            }
            j["holes"] = std::move(holes);
            return documentEntry(jsonText(j), "application/json", etag);
        },
        kVectorBytes, false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

void log(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), {}); !s) return problem(res, s.error(), req.path);
    const std::string id = req.matches[2];
    if (id.size() > kMaxHoleIdBytes)
        return problem(res, 404,
                       "model '" + m->id + "': no drillhole with an id of " + std::to_string(id.size()) +
                           " bytes (ids are at most " + std::to_string(kMaxHoleIdBytes) + ")",
                       req.path, "not_found");
    const DrillholeDatabase* db = drillholesOf(*m, req, res);
    if (!db) return;
    const Drillhole* hole = db->find(id);
    if (!hole) return problem(res, 404, "model '" + m->id + "' has no drillhole '" + id + "'", req.path, "not_found");
    auto rays = m->rays->wait(rayWait(st, req).deadline, rayWait(st, req).cancel);
    if (!rays) return problem(res, rays.error(), req.path);
    auto trace = api::traceHole(*rays.value().tracer, *db, *hole);
    if (!trace) return problem(res, trace.error(), req.path);
    nlohmann::ordered_json j;
    j["model"] = m->id;
    j["version"] = m->version;
    j.update(api::drillholeLogJson(m->model, *db, *hole, trace.value()));
    sendJson(res, j);
}

}  // namespace

void addDrillholeRoutes(Router& router, ServerState& st) {
    router.add("GET", "/v1/models/{id}/drillholes", "/v1/models/([^/]+)/drillholes",
               [&st](const HttpRequest& req, HttpResponse& res) { holes(st, req, res); });
    router.add("GET", "/v1/models/{id}/drillholes/check", "/v1/models/([^/]+)/drillholes/check",
               [&st](const HttpRequest& req, HttpResponse& res) { check(st, req, res, false); });
    router.add("GET", "/v1/models/{id}/drillholes/check.csv", "/v1/models/([^/]+)/drillholes/check\\.csv",
               [&st](const HttpRequest& req, HttpResponse& res) { check(st, req, res, true); });
    // A hole id may hold any character, '/' included (sent as %2F): the id is everything
    // between drillholes/ and the last /log.
    router.add("GET", "/v1/models/{id}/drillholes/{hole}/log", "/v1/models/([^/]+)/drillholes/(.+)/log",
               [&st](const HttpRequest& req, HttpResponse& res) { log(st, req, res); });
}

}  // namespace geoslice::server
