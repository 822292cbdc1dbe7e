#include "api/sheet.hpp"

#include <chrono>

#include "api/holes.hpp"
#include "api/view.hpp"
#include "model/text_scan.hpp"
#include "print/cairo_output.hpp"
#include "print/map_scale.hpp"
#include "print/section_sheet.hpp"
#include "print/sheet_date.hpp"
#include "print/svg_output.hpp"
#include "section/cut/contours.hpp"
#include "section/cut/polyline.hpp"

namespace geoslice::api {
namespace {

constexpr double kMinDpi = 50.0, kMaxDpi = 600.0;
constexpr std::size_t kMaxSheetTitleBytes = 120;

Error named(std::string_view name, const Error& e) {
    return makeError(e.code, "parameter '" + std::string(name) + "': " + e.message);
}

// The section's definition as asked, for the title block: the canonical geometry and vx.
std::string definition(const SectionDef& def) {
    std::string s = def.canonical();
    const std::size_t amp = s.find('&');
    s = amp == std::string::npos ? s : s.substr(amp + 1);  // drop "model=..."
    const std::size_t bg = s.find("&bg=");
    return bg == std::string::npos ? s : s.substr(0, bg);
}

std::string crsText(const Crs& crs) {
    if (crs.isLocal()) return "local metres (no CRS)";
    const std::string id = crs.epsg() > 0 ? "EPSG:" + std::to_string(crs.epsg()) + " " : "";
    return id + crs.name();
}

}  // namespace

std::string SheetRequest::canonical() const {
    std::string s = plan.canonical() + "&sheet=" +
                    (format == SheetFormat::Pdf   ? "pdf"
                     : format == SheetFormat::Svg ? "svg"
                                                  : "raster");
    s += "&paper=" + paper.name +
         (paper.orientation == print::Orientation::Landscape ? "&orientation=landscape" : "&orientation=portrait");
    if (scale) s += "&scale=" + formatNumber(*scale);
    if (format == SheetFormat::Raster) s += "&dpi=" + formatNumber(dpi);
    s += "&date=" + date;
    if (!title.empty()) s += "&title=" + title;  // last: a title may hold '&'
    return s;
}

std::size_t SheetRequest::memoryBytes() const {
    if (format != SheetFormat::Raster) return 0;
    return std::size_t(print::sheetPixels(paper.widthMm, dpi)) * std::size_t(print::sheetPixels(paper.heightMm, dpi)) *
           12;
}

const std::vector<std::string_view>& sheetParamNames() {
    static const std::vector<std::string_view> names{"paper", "orientation", "scale",    "dpi",
                                                     "date",  "layout",      "decorate", "title"};
    return names;
}

Result<bool> wantsSheet(const Params& params, SheetFormat format) {
    if (format == SheetFormat::Pdf) return true;
    if (const auto layout = param(params, "layout")) {
        if (*layout != "print" && *layout != "plain")
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'layout': '" + std::string(*layout) + "' is not 'print' or 'plain'");
        if (format != SheetFormat::Svg && *layout == "print")
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'layout': layout=print is for section.svg (images take decorate=1)");
        if (*layout == "print") return true;
    }
    if (const auto decorate = param(params, "decorate")) {
        auto d = parseBool("decorate", *decorate);
        if (!d) return d.error();
        if (format != SheetFormat::Raster && d.value())
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'decorate': decorate=1 is for section images (SVG takes layout=print)");
        return d.value();
    }
    return false;
}

Result<SheetRequest> parseSheetRequest(const Params& params, const CatalogModel& model, SheetFormat format,
                                       const std::string& today) {
    SheetRequest r;
    r.format = format;
    for (std::string_view name : {"size", "bg"})
        if (param(params, name))
            return makeError(ErrorCode::InvalidArgument,
                             "parameter '" + std::string(name) + "': " +
                                 (name == "size" ? "a sheet's size comes from 'paper' (and 'dpi' for images)"
                                                 : "a sheet is printed on white"));
    if (format != SheetFormat::Raster && param(params, "dpi"))
        return makeError(
            ErrorCode::InvalidArgument,
            "parameter 'dpi': only decorated images (decorate=1) have a resolution; PDF and SVG are vector");
    auto orientation = print::parseOrientation(param(params, "orientation").value_or("landscape"));
    if (!orientation) return named("orientation", orientation.error());
    auto paper = print::paperSize(param(params, "paper").value_or("A3"), orientation.value());
    if (!paper) return named("paper", paper.error());
    r.paper = paper.value();
    if (const auto s = param(params, "scale")) {
        auto v = parseNumber("scale", *s);
        if (!v) return v.error();
        if (Status c = print::checkScale(v.value()); !c) return named("scale", c.error());
        r.scale = v.value();
    }
    if (const auto d = param(params, "dpi")) {
        auto v = parseNumber("dpi", *d);
        if (!v) return v.error();
        if (v.value() < kMinDpi || v.value() > kMaxDpi)
            return makeError(ErrorCode::OutOfRange,
                             "parameter 'dpi': " + std::string(*d) + " is outside 50..600 dots per inch");
        r.dpi = v.value();
    }
    if (format == SheetFormat::Raster) {
        const int w = print::sheetPixels(r.paper.widthMm, r.dpi), h = print::sheetPixels(r.paper.heightMm, r.dpi);
        if (Status s = checkImageSize(r.paper.name + " at " + formatNumber(r.dpi) + " dpi", w, h); !s)
            return named("dpi", s.error());
    }
    r.date = std::string(param(params, "date").value_or(today));
    if (!print::isCalendarDate(r.date))
        return makeError(ErrorCode::InvalidArgument,
                         "parameter 'date': '" + r.date + "' is not a calendar date YYYY-MM-DD");
    if (const auto title = param(params, "title")) {
        const std::string_view t = text::trim(*title);
        if (t.size() > kMaxSheetTitleBytes)
            return makeError(ErrorCode::InvalidArgument, "parameter 'title': " + std::to_string(t.size()) +
                                                             " bytes (at most " + std::to_string(kMaxSheetTitleBytes) +
                                                             ")");
        for (unsigned char c : t)
            if (c < 0x20 || c == 0x7f)
                return makeError(ErrorCode::InvalidArgument, "parameter 'title': holds a control character");
        r.title = std::string(t);
    }
    auto plan = parseViewPlan(params, model.id, model.model.crs);
    if (!plan) return plan.error();
    if (plan.value().view != ViewKind::Profile)
        return makeError(ErrorCode::InvalidArgument,
                         "parameter 'view': print sheets are sections (view=profile), not perspective views");
    r.plan = std::move(plan.value());
    return r;
}

Result<SheetOutput> renderSheet(const CatalogModel& model, const SheetRequest& request,
                                const std::atomic<bool>* cancel) {
    const auto t0 = std::chrono::steady_clock::now();
    const SectionDef& def = request.plan.section;
    print::SheetOptions o;
    o.paper = request.paper;
    o.scale = request.scale;
    o.exaggeration = def.exaggeration;
    o.frame = request.plan.frame;
    o.rasterGeometry = request.format == SheetFormat::Raster;
    o.dpi = request.dpi;
    o.cancel = cancel;
    o.scaleName = "parameter 'scale'";
    o.labels = request.plan.labels.value_or(true);
    o.patterns = request.plan.patterns.value_or(true);
    auto classes = blockClasses(model, def);
    if (!classes) return classes.error();
    if (classes.value()) o.blocks = print::SheetBlocks{model.model.blocks.get(), *classes.value(), model.blockRecords};
    // The drillholes over the geology (api/holes.hpp), projected as on the view's images.
    auto mapping = profileMapping(model, request.plan);
    if (!mapping) return mapping.error();
    auto holes = viewHoles(model, def, mapping.value());
    if (!holes) return holes.error();
    if (!holes.value().empty())
        o.overlay = [&model, &holes](const print::MapFrame& frame, print::Sheet& sheet) {
            addHolesToSheet(model, holes.value(), frame, sheet);
        };
    print::SheetInfo info;
    info.model = model.id;
    info.version = model.version;
    info.crs = crsText(model.model.crs);
    info.date = request.date;
    info.title = request.title;
    info.definition = definition(def);

    Result<print::Sheet> sheet = makeError(ErrorCode::Internal, "no sheet");
    if (def.geometry == Geometry::Line) {
        auto section = computePolylineSection(*model.index, def.line, besideOtherWork());
        if (!section) return makeError(section.error().code, "parameter 'line': " + section.error().message);
        if (Status c = checkCancel(cancel); !c) return c.error();
        sheet = print::sectionSheet(*model.index, section.value(), o, info);
    } else {
        auto section = computeSection(*model.index, sectionPlane(def), besideOtherWork());
        if (!section) return section.error();
        if (Status c = checkCancel(cancel); !c) return c.error();
        sheet = print::sectionSheet(*model.index, section.value(), o, info);
    }
    if (!sheet) return sheet.error();
    if (Status c = checkCancel(cancel); !c) return c.error();
    SheetOutput out;
    if (request.format == SheetFormat::Pdf) {
        auto pdf = print::renderPdf(sheet.value());
        if (!pdf) return pdf.error();
        out.document = std::move(pdf.value());
    } else if (request.format == SheetFormat::Svg) {
        auto svg = print::renderSvg(sheet.value());
        if (!svg) return svg.error();
        out.document = std::move(svg.value());
    } else {
        auto raster = print::renderRaster(sheet.value(), request.dpi);
        if (!raster) return raster.error();
        out.width = raster.value().width;
        out.height = raster.value().height;
        out.rgba = std::move(raster.value().rgba);
    }
    out.renderMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace geoslice::api
