// libFuzzer target for whole requests (issue 11 item 1): the bytes are a query string as
// the HTTP layer hands it over; parameters -> plan -> render on a tiny generated model
// (profile views with the exact engine, the section's tile grid and one tile, a vector
// export and a pixel query; a print sheet). GL is skipped (perspective plans: two ray queries). Any input
// gives an image or an error naming the parameter: never a crash, a hang or a sanitizer
// report. Renders are capped at 256 x 256 pixels here (the limits themselves are checked
// by the parser, which runs on every input).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "api/catalog.hpp"
#include "api/params.hpp"
#include "api/pixel_query.hpp"
#include "api/plan.hpp"
#include "api/sheet.hpp"
#include "api/tile_grid.hpp"
#include "api/view.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace geoslice;
    static const auto model = api::makeDemoModel(2000).value();
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    api::Params params;
    std::string_view rest = text;
    while (!rest.empty()) {
        const std::size_t amp = rest.find('&');
        const std::string_view item = rest.substr(0, amp);
        const std::size_t eq = item.find('=');
        if (eq != std::string_view::npos) params[std::string(item.substr(0, eq))] = std::string(item.substr(eq + 1));
        if (amp == std::string_view::npos) break;
        rest.remove_prefix(amp + 1);
    }
    // Print sheets (api/sheet.hpp): the parser on every input, the PDF or SVG when it parses
    // (images only at <= 60 dpi to keep a run short).
    // The format: `sheet=pdf|svg|image` (a name only this target reads), else from the size.
    api::SheetFormat sheetFormat = api::SheetFormat(size % 3);
    if (auto f = api::param(params, "sheet"))
        sheetFormat = *f == "pdf"   ? api::SheetFormat::Pdf
                      : *f == "svg" ? api::SheetFormat::Svg
                                    : api::SheetFormat::Raster;
    if (auto sheet = api::parseSheetRequest(params, *model, sheetFormat, "2026-01-01")) {
        if (sheetFormat != api::SheetFormat::Raster || sheet.value().dpi <= 60.0) {
            auto out = api::renderSheet(*model, sheet.value());
            if (out && sheetFormat == api::SheetFormat::Pdf && out.value().document.rfind("%PDF-", 0) != 0)
                __builtin_trap();
        }
    }
    auto plan = api::parseViewPlan(params, model->id, model->model.crs);
    if (!plan) return 0;
    const api::ViewPlan& p = plan.value();
    if (p.view != api::ViewKind::Profile) {
        // No GL here; the ray queries of a perspective view (cut-outs: api/cut.hpp) run on the CPU.
        (void)api::queryPixel(*model, p, p.width / 2, p.height / 2, nullptr);
        (void)api::queryPixel(*model, p, 0, p.height - 1, nullptr);
        return 0;
    }
    if (std::size_t(p.width) * std::size_t(p.height) > 256 * 256) return 0;
    if (auto image = api::renderProfile(*model, p)) {
        if (image.value().ids.size() != std::size_t(p.width) * std::size_t(p.height)) __builtin_trap();
        (void)api::queryPixel(*model, p, p.width / 2, p.height / 2, &image.value());
    }
    (void)api::queryPixel(*model, p, 0, 0, nullptr);
    (void)api::renderVector(*model, p, api::VectorFormat::Svg, VectorFrame::Plane);
    if (auto grid = api::tileGrid(*model, p.section)) {
        const int z = int(size % std::size_t(grid.value().maxZoom + 1));
        (void)api::renderSectionTile(*model, p.section, grid.value(), z, 0, 0);
    }
    return 0;
}
