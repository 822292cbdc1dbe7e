// section.geojson, section.svg and section.dxf (from section.cpp): the exact section as polygons, in
// WGS 84 lon/lat (space=world, RFC 7946), the model's CRS (space=projected) or plane u/v metres
// (space=plane). Computed on a render worker
// (model-sized work), cached by model version + canonical plan + form.
#include <chrono>

#include "api/request.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {

void sectionVector(ServerState& st, const HttpRequest& req, HttpResponse& res, const api::CatalogModel& m,
                   const std::string& ext) {
    const api::VectorFormat format = ext == "svg"   ? api::VectorFormat::Svg
                                     : ext == "dxf" ? api::VectorFormat::Dxf
                                                    : api::VectorFormat::GeoJson;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    // SVG: decorate=0 / layout=plain (validated by section.cpp's sheetFormat) ask for the plain SVG.
    const auto known = format == api::VectorFormat::Svg
                           ? withNames(api::viewParamNames(), {"space", "decorate", "layout"})
                           : withNames(api::viewParamNames(), {"space"});
    if (auto s = api::checkKnownParams(params.value(), known); !s) return problem(res, s.error(), req.path);
    auto frame = format == api::VectorFormat::Dxf ? api::parseDxfSpace(params.value())
                                                  : api::parseVectorSpace(params.value(), !m.model.crs.isLocal());
    if (!frame) return problem(res, frame.error(), req.path);
    auto plan = api::parseViewPlan(params.value(), m.id, m.model.crs);
    if (!plan) return problem(res, plan.error(), req.path);
    if (auto s = validateView(st, m, plan.value()); !s) return problem(res, s.error(), req.path);
    static constexpr const char* kFrames[] = {"plane", "projected", "world"};
    const std::string form =
        format == api::VectorFormat::Svg ? std::string("svg") : ext + "-" + kFrames[int(frame.value())];
    const std::string key = cache_key::vector(m, plan.value(), form);
    if (auto hit = st.cache->find(key)) return sendEncoded(req, res, *hit);
    auto mp = st.catalog.find(m.id);
    auto result = st.cache->render(
        key,
        [&st, mp, plan = plan.value(), format, ext, frame = frame.value(), etag = RenderCache::etagOf(key)](
            workers::WorkerState&, const std::atomic<bool>& cancel) -> Rendered {
            const auto t0 = std::chrono::steady_clock::now();
            auto text = api::renderVector(*mp, plan, format, frame, &cancel);
            if (!text) return text.error();
            st.metrics.render(ext, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            const char* type = format == api::VectorFormat::Svg   ? "image/svg+xml"
                               : format == api::VectorFormat::Dxf ? "image/vnd.dxf"
                                                                  : "application/geo+json";
            return documentEntry(std::move(text.value()), type, etag);
        },
        kVectorBytes, false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

}  // namespace geoslice::server
