// section.geojson and section.svg (from section.cpp): the exact section as polygons, in
// plane u/v metres or, with space=world, world coordinates. Computed on a render worker
// (model-sized work), cached by model version + canonical plan + form.
#include <chrono>

#include "api/request.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {

void sectionVector(ServerState& st, const HttpRequest& req, HttpResponse& res, const api::CatalogModel& m, bool svg) {
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), withNames(api::viewParamNames(), {"space"})); !s)
        return problem(res, s.error(), req.path);
    auto world = api::parseWorldSpace(params.value());
    if (!world) return problem(res, world.error(), req.path);
    auto plan = api::parseViewPlan(params.value(), m.id, m.model.crs);
    if (!plan) return problem(res, plan.error(), req.path);
    if (auto s = validateView(st, m, plan.value()); !s) return problem(res, s.error(), req.path);
    const std::string key = cache_key::vector(m, plan.value(), svg, world.value());
    if (auto hit = st.cache->find(key)) return sendEncoded(req, res, *hit);
    auto mp = st.catalog.find(m.id);
    auto result = st.cache->render(
        key,
        [&st, mp, plan = plan.value(), svg, world = world.value(), etag = RenderCache::etagOf(key)](
            workers::WorkerState&, const std::atomic<bool>& cancel) -> Rendered {
            const auto t0 = std::chrono::steady_clock::now();
            auto text = api::renderVector(*mp, plan, svg, world, &cancel);
            if (!text) return text.error();
            st.metrics.render(svg ? "svg" : "geojson",
                              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            return documentEntry(std::move(text.value()), svg ? "image/svg+xml" : "application/geo+json", etag);
        },
        kVectorBytes, false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

}  // namespace geoslice::server
