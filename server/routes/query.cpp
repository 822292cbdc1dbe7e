// Pixel queries: GET /v1/models/{id}/query?<view>&px=&py= (one pixel, on the handler
// thread: one exact ray, or a lookup in the view's cached ID buffer; a ray waits for the
// model's ray scene within the request deadline, routes/common.hpp rayWait) and POST (a batch of
// pixels of one view, on a render worker like a render: queue, deadline, cancellation,
// memory admission; at most kMaxBatchPixels pixels and kMaxBatchAnswerBytes of answer).
#include "api/pixel_query.hpp"
#include "api/request.hpp"
#include "model/json_text.hpp"
#include "model/view_limits.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {
namespace {

void queryGet(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req.matches[1], res, req.path);
    if (!m) return;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), withNames(api::viewParamNames(), {"px", "py"})); !s)
        return problem(res, s.error(), req.path);
    auto plan = api::parseViewPlan(params.value(), m->id, m->model.crs);
    if (!plan) return problem(res, plan.error(), req.path);
    auto pixel = api::parseQueryPixel(params.value());
    if (!pixel) return problem(res, pixel.error(), req.path);
    auto cached = st.cache->findIds(cache_key::view(*m, plan.value()));
    auto j = api::queryPixel(*m, plan.value(), pixel.value().x, pixel.value().y, cached ? &cached->view : nullptr,
                             rayWait(st, req));
    if (!j) return problem(res, j.error(), req.path);
    res.status = 200;
    res.set_content(j.value(), "application/json");
}

void queryPost(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req.matches[1], res, req.path);
    if (!m) return;
    if (!requireJsonBody(req, res)) return;
    auto batch = api::parseQueryBatch(req.body, api::viewParamNames());
    if (!batch) return problem(res, batch.error(), req.path);
    auto plan = api::parseViewPlan(batch.value().view, m->id, m->model.crs);
    if (!plan) return problem(res, plan.error(), req.path);
    if (auto s = validateView(st, *m, plan.value()); !s) return problem(res, s.error(), req.path);
    auto pixels = api::parseBatchPixels(batch.value().pixels);
    if (!pixels) return problem(res, pixels.error(), req.path);
    const std::size_t count = pixels.value().size();
    // Keyed by the request itself: identical concurrent batches share one answer.
    const std::string key = cache_key::queryBatch(*m, plan.value(), jsonText(batch.value().pixels));
    auto result = st.cache->render(
        key,
        [&st, m, plan = plan.value(), pixels = std::move(pixels.value())](workers::WorkerState&,
                                                                          const std::atomic<bool>& cancel) -> Rendered {
            auto cached = st.cache->findIds(cache_key::view(*m, plan));
            // Waits for the model's rays at most a deadline (cancel turns true when the last
            // request waiting for this answer leaves).
            const api::RayWait wait{std::chrono::steady_clock::now() + std::chrono::milliseconds(st.config.deadlineMs),
                                    &cancel};
            auto e = std::make_shared<Encoded>();
            std::string& out = e->body;
            out = "{\"results\":[";
            for (std::size_t i = 0; i < pixels.size(); ++i) {
                if ((i & 63) == 0)
                    if (auto c = checkCancel(&cancel); !c) return c.error();
                auto a = api::answerPixel(*m, plan, pixels[i].x, pixels[i].y, cached ? &cached->view : nullptr, wait);
                if (!a)
                    return makeError(a.error().code,
                                     "field 'pixels': pixels[" + std::to_string(i) + "]: " + a.error().message);
                if (i) out += ',';
                api::writeQueryAnswer(*m, a.value(), out);
                if (out.size() > kMaxBatchAnswerBytes)
                    return makeError(ErrorCode::OutOfRange,
                                     "field 'pixels': the answer passed " + roundedMiB(kMaxBatchAnswerBytes) +
                                         " MiB after " + std::to_string(i + 1) + " pixels; ask for fewer pixels");
            }
            out += "]}";
            e->contentType = "application/json";
            return std::shared_ptr<const Encoded>(std::move(e));
        },
        count* kQueryAnswerBytes, false, *req.cancelled, false);
    if (!result) return problem(res, result.error(), req.path);
    res.status = 200;
    res.set_content(result.value()->body, "application/json");
}

}  // namespace

void addQueryRoutes(Router& router, ServerState& st) {
    router.add("GET", "/v1/models/{id}/query", "/v1/models/([^/]+)/query",
               [&st](const HttpRequest& req, HttpResponse& res) { queryGet(st, req, res); });
    router.add("POST", "/v1/models/{id}/query", "/v1/models/([^/]+)/query",
               [&st](const HttpRequest& req, HttpResponse& res) { queryPost(st, req, res); });
}

}  // namespace geoslice::server
