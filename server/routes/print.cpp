// Print sheets (from section.cpp; api/sheet.hpp, print/): section.pdf, section.svg?layout=print
// and section.{png,jpg,webp}?decorate=1. Rendered on a render worker, cached and answered
// with an ETag (If-None-Match: 304 without rendering) like section images.
#include "api/request.hpp"
#include "print/sheet_date.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {

void sectionSheet(ServerState& st, const HttpRequest& req, HttpResponse& res, const api::CatalogModel& m,
                  api::SheetFormat format, const std::string& ext) {
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    auto imageFormat = imageFormatFromName(ext);
    if (format == api::SheetFormat::Raster && !imageFormat) return problem(res, imageFormat.error(), req.path);
    auto known = withNames(api::viewParamNames(), {"quality"});
    known.insert(known.end(), api::sheetParamNames().begin(), api::sheetParamNames().end());
    if (auto s = api::checkKnownParams(params.value(), known); !s) return problem(res, s.error(), req.path);
    auto quality = api::parseQuality(params.value());
    if (!quality) return problem(res, quality.error(), req.path);
    auto sheet = api::parseSheetRequest(params.value(), m, format, print::todayUtc());
    if (!sheet) return problem(res, sheet.error(), req.path);
    if (auto s = validateView(st, m, sheet.value().plan); !s) return problem(res, s.error(), req.path);
    const std::string key = cache_key::sheet(m, sheet.value().canonical(), ext, quality.value());
    const std::string etag = RenderCache::etagOf(key);
    if (answerNotModified(req, res, etag)) return;
    if (auto hit = st.cache->find(key)) return sendEncoded(req, res, *hit);
    auto mp = st.catalog.find(m.id);
    auto result = st.cache->render(
        key,
        [&st, mp, r = sheet.value(), etag, q = quality.value(),
         imageFormat = imageFormat.ok() ? imageFormat.value() : ImageFormat::Png](
            workers::WorkerState&, const std::atomic<bool>& cancel) -> Rendered {
            auto out = api::renderSheet(*mp, r, &cancel);
            if (!out) return out.error();
            st.metrics.render("sheet", out.value().renderMs / 1e3);
            if (r.format == api::SheetFormat::Raster) {
                api::ViewImage v;
                v.width = out.value().width;
                v.height = out.value().height;
                v.rgba = std::move(out.value().rgba);
                return encodeEntry(v, imageFormat, q, etag, &cancel);
            }
            return documentEntry(std::move(out.value().document),
                                 r.format == api::SheetFormat::Pdf ? "application/pdf" : "image/svg+xml", etag);
        },
        std::max(kVectorBytes, sheet.value().memoryBytes()), false, *req.cancelled);
    if (!result) return problem(res, result.error(), req.path);
    sendEncoded(req, res, *result.value());
}

}  // namespace geoslice::server
