// GET /v1/models/{id}/section.{format}: a section image (jpg, png, webp), profile (CPU,
// exact) or perspective (GL, on a render worker's context). The same path also serves the
// vector section (geojson, svg, dxf: vectors.cpp) and print sheets (pdf, ?layout=print,
// ?decorate=1: print.cpp). A rendered view keeps its ID buffer for pixel queries.
#include "api/request.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {
namespace {

// Print sheets (api/sheet.hpp, print/): section.pdf, section.svg?layout=print and
// section.{png,jpg,webp}?decorate=1. nullopt: not a sheet request.
Result<std::optional<api::SheetFormat>> sheetFormat(const HttpRequest& req, const std::string& ext) {
    const api::SheetFormat format = ext == "pdf"   ? api::SheetFormat::Pdf
                                    : ext == "svg" ? api::SheetFormat::Svg
                                                   : api::SheetFormat::Raster;
    if (ext == "geojson" || ext == "dxf") return std::optional<api::SheetFormat>();
    auto params = queryParams(req);
    if (!params) return params.error();
    auto wants = api::wantsSheet(params.value(), format);
    if (!wants) return wants.error();
    return wants.value() ? std::optional<api::SheetFormat>(format) : std::nullopt;
}

void sectionImage(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    const std::string ext = req.matches[2];
    if (auto sheet = sheetFormat(req, ext); !sheet) {
        return problem(res, sheet.error(), req.path);
    } else if (sheet.value()) {
        return sectionSheet(st, req, res, *m, *sheet.value(), ext);
    }
    if (ext == "geojson" || ext == "svg" || ext == "dxf") return sectionVector(st, req, res, *m, ext);
    auto format = imageFormatFromName(ext);
    if (!format)
        return problem(
            res, 404,
            "unknown image format '" + std::string(req.matches[2]) + "': use section.jpg, section.png or section.webp",
            req.path, "not_found");
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    // decorate=0 / layout=plain (validated by sheetFormat) ask for the plain image.
    if (auto s =
            api::checkKnownParams(params.value(), withNames(api::viewParamNames(), {"quality", "decorate", "layout"}));
        !s)
        return problem(res, s.error(), req.path);
    auto plan = api::parseViewPlan(params.value(), m->id, m->model.crs);
    if (!plan) return problem(res, plan.error(), req.path);
    auto quality = api::parseQuality(params.value());
    if (!quality) return problem(res, quality.error(), req.path);
    // The whole view is validated (plane against the model, frame, pixel size) before any
    // cache or ETag is consulted: If-None-Match never answers a bad request.
    if (auto s = validateView(st, *m, plan.value()); !s) return problem(res, s.error(), req.path);
    const std::string viewKey = cache_key::view(*m, plan.value());
    const std::string key = cache_key::image(viewKey, extension(format.value()), quality.value());
    const std::string etag = RenderCache::etagOf(key);
    if (answerNotModified(req, res, etag)) {
        st.metrics.count("geoslice_cache_total", "cache=\"etag\",result=\"hit\"");
        return;
    }
    if (auto hit = st.cache->find(key, "image")) return sendEncoded(req, res, *hit);
    const bool perspective = plan.value().view == api::ViewKind::Perspective;
    auto result = st.cache->render(
        key,
        [&st, m, plan = plan.value(), format = format.value(), q = quality.value(), etag, viewKey](
            workers::WorkerState& w, const std::atomic<bool>& cancel) -> Rendered {
            auto view = plan.view == api::ViewKind::Perspective ? w.renderPerspective(*m, plan, &cancel)
                                                                : api::renderProfile(*m, plan, &cancel);
            if (!view) return view.error();
            if (auto c = checkCancel(&cancel); !c) return c.error();
            st.metrics.render(plan.view == api::ViewKind::Perspective ? "gl" : "section", view.value().renderMs / 1e3);
            auto e = encodeEntry(view.value(), format, q, etag, &cancel);
            if (e) st.cache->keepIds(viewKey, std::move(view.value()));
            return e;
        },
        renderBytes(plan.value().width, plan.value().height, perspective), perspective, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

}  // namespace

void addSectionRoutes(Router& router, ServerState& st) {
    router.add("GET", "/v1/models/{id}/section.{format}", "/v1/models/([^/]+)/section\\.([A-Za-z0-9]+)",
               [&st](const HttpRequest& req, HttpResponse& res) { sectionImage(st, req, res); });
}

}  // namespace geoslice::server
