// GET /v1/models/{id}/reserves[.csv] (api/reserves.hpp, the same document as `geoslice
// reserves --json`): computed on a render worker like every other model-sized job, cached
// by model version + the canonical request (plane, cut-offs, format).
#include <chrono>

#include "api/reserves.hpp"
#include "model/json_text.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {
namespace {

// The answer to a reserves request (on a render worker).
Result<std::string> reservesBody(const api::CatalogModel& m, const api::ReservesRequest& r) {
    auto figures = computeReserves(m.model, r.plane);
    if (!figures) return figures.error();
    if (!r.cutoffs)
        return r.csv ? api::reservesCsv(m.model, figures.value())
                     : jsonText(api::reservesJson(m.model, figures.value(), m.id));
    auto property = api::gradeProperty(m.model, r.property);
    if (!property) return property.error();
    auto table = computeGradeTonnage(m.model, property.value(), *r.cutoffs, r.plane);
    if (!table) return table.error();
    if (r.csv) return api::gradeTonnageCsv(m.model, table.value());
    auto doc = api::reservesJson(m.model, figures.value(), m.id);
    doc["grade_tonnage"] = api::gradeTonnageJson(m.model, table.value());
    return jsonText(doc);
}

void reserves(ServerState& st, const HttpRequest& req, HttpResponse& res, bool csvPath) {
    auto m = findModel(st, req.matches[1], res, req.path);
    if (!m) return;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    auto rr = api::parseReservesRequest(params.value(), csvPath);
    if (!rr) return problem(res, rr.error(), req.path);
    const std::string key = cache_key::reserves(*m, rr.value().canonical());
    if (auto hit = st.cache->find(key, "reserves")) return sendEncoded(req, res, *hit);
    auto result = st.cache->render(
        key,
        [&st, m, r = rr.value(), etag = RenderCache::etagOf(key)](workers::WorkerState&,
                                                                  const std::atomic<bool>&) -> Rendered {
            const auto t0 = std::chrono::steady_clock::now();
            auto body = reservesBody(*m, r);
            if (!body) return body.error();
            st.metrics.render("reserves", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            return documentEntry(std::move(body.value()),
                                 r.csv ? "text/csv; charset=utf-8; header=present" : "application/json", etag);
        },
        kVectorBytes, false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

}  // namespace

void addReservesRoutes(Router& router, ServerState& st) {
    router.add("GET", "/v1/models/{id}/reserves", "/v1/models/([^/]+)/reserves",
               [&st](const HttpRequest& req, HttpResponse& res) { reserves(st, req, res, false); });
    router.add("GET", "/v1/models/{id}/reserves.csv", "/v1/models/([^/]+)/reserves\\.csv",
               [&st](const HttpRequest& req, HttpResponse& res) { reserves(st, req, res, true); });
}

}  // namespace geoslice::server
