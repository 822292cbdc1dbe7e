// GET /v1/models/{id}/borehole?x=&y= (or lon=&lat=): the intervals of a vertical line
// through the model (api::boreholeAt), on the handler thread (one ray; it waits for the
// model's ray scene within the request deadline, routes/common.hpp rayWait).
#include "api/borehole.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {

void addBoreholeRoutes(Router& router, ServerState& st) {
    router.add("GET", "/v1/models/{id}/borehole", "/v1/models/([^/]+)/borehole",
               [&st](const HttpRequest& req, HttpResponse& res) {
                   auto m = findModel(st, req, req.matches[1], res);
                   if (!m) return;
                   auto params = queryParams(req);
                   if (!params) return problem(res, params.error(), req.path);
                   if (auto s = api::checkKnownParams(params.value(), {"x", "y", "lon", "lat"}); !s)
                       return problem(res, s.error(), req.path);
                   auto j = api::boreholeAt(*m, params.value(), rayWait(st, req));
                   if (!j) return problem(res, j.error(), req.path);
                   sendJson(res, j.value());
               });
}

}  // namespace geoslice::server
