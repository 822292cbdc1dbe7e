#include "print/cairo_output.hpp"

#include <cairo-pdf.h>
#include <cairo.h>

#include <cmath>
#include <numbers>

#include "print/pattern_cairo.hpp"
#include "print/text_metrics.hpp"
#include "view/view_limits.hpp"

namespace geoslice::print {
namespace {

void setColour(cairo_t* cr, Rgba8 c) { cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, c.a / 255.0); }

void drawPath(cairo_t* cr, const PathItem& p) {
    cairo_save(cr);
    if (p.clip) {
        cairo_rectangle(cr, p.clip->x, p.clip->y, p.clip->width, p.clip->height);
        cairo_clip(cr);
    }
    cairo_new_path(cr);
    for (const auto& sub : p.subpaths) {
        if (sub.empty()) continue;
        cairo_move_to(cr, sub[0].x, sub[0].y);
        for (std::size_t i = 1; i < sub.size(); ++i) cairo_line_to(cr, sub[i].x, sub[i].y);
        if (p.closed) cairo_close_path(cr);
    }
    if (p.fill) {
        setColour(cr, *p.fill);
        cairo_set_fill_rule(cr, CAIRO_FILL_RULE_EVEN_ODD);
        cairo_fill_preserve(cr);
    }
    if (cairo_pattern_t* pattern = lithologyPattern(p.pattern, 1.0)) {
        cairo_set_source(cr, pattern);
        cairo_set_fill_rule(cr, CAIRO_FILL_RULE_EVEN_ODD);
        cairo_fill_preserve(cr);
        cairo_pattern_destroy(pattern);
    }
    if (p.stroke) {
        setColour(cr, *p.stroke);
        cairo_set_line_width(cr, p.strokeMm);
        cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
        cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
        if (p.dashMm > 0.0) cairo_set_dash(cr, &p.dashMm, 1, 0.0);
        cairo_stroke(cr);
    }
    cairo_new_path(cr);
    cairo_restore(cr);
}

void drawText(cairo_t* cr, const TextItem& t) {
    if (t.text.empty()) return;
    cairo_save(cr);
    cairo_select_font_face(cr, fontFamilyFor(t.text), CAIRO_FONT_SLANT_NORMAL,
                           t.bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, t.sizePt * kMmPerPoint);
    applyLayoutFontOptions(cr);
    cairo_translate(cr, t.at.x, t.at.y);
    if (t.rotateDeg != 0.0) cairo_rotate(cr, -t.rotateDeg * std::numbers::pi / 180.0);
    cairo_text_extents_t e{};
    cairo_text_extents(cr, t.text.c_str(), &e);
    double x = 0.0;
    if (t.anchor == TextAnchor::Middle) x = -0.5 * e.x_advance;
    if (t.anchor == TextAnchor::End) x = -e.x_advance;
    cairo_move_to(cr, x, baselineShiftMm(t));
    setColour(cr, t.colour);
    cairo_show_text(cr, t.text.c_str());
    cairo_restore(cr);
}

void drawImage(cairo_t* cr, const ImageItem& im) {
    if (im.width <= 0 || im.height <= 0) return;
    cairo_surface_t* img = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, im.width, im.height);
    cairo_surface_flush(img);
    unsigned char* data = cairo_image_surface_get_data(img);
    const int stride = cairo_image_surface_get_stride(img);
    for (int y = 0; y < im.height; ++y) {
        auto* row = reinterpret_cast<std::uint32_t*>(data + std::size_t(y) * std::size_t(stride));
        for (int x = 0; x < im.width; ++x) {
            const std::uint8_t* p = &im.rgba[(std::size_t(y) * std::size_t(im.width) + std::size_t(x)) * 4];
            const std::uint32_t a = p[3];
            auto pre = [a](std::uint32_t c) { return (c * a + 127) / 255; };
            row[x] = (a << 24) | (pre(p[0]) << 16) | (pre(p[1]) << 8) | pre(p[2]);  // premultiplied ARGB
        }
    }
    cairo_surface_mark_dirty(img);
    cairo_save(cr);
    cairo_rectangle(cr, im.box.x, im.box.y, im.box.width, im.box.height);
    cairo_clip(cr);
    cairo_translate(cr, im.box.x, im.box.y);
    cairo_scale(cr, im.box.width / im.width, im.box.height / im.height);
    cairo_set_source_surface(cr, img, 0.0, 0.0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_GOOD);
    cairo_paint(cr);
    cairo_restore(cr);
    cairo_surface_destroy(img);
}

// Draws every item; `cr` maps millimetres to the surface.
void drawSheet(cairo_t* cr, const Sheet& sheet) {
    for (const SheetItem& item : sheet.items) {
        if (const auto* p = std::get_if<PathItem>(&item)) drawPath(cr, *p);
        if (const auto* t = std::get_if<TextItem>(&item)) drawText(cr, *t);
        if (const auto* im = std::get_if<ImageItem>(&item)) drawImage(cr, *im);
    }
}

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

Error cairoError(const char* what, cairo_status_t status) {
    return makeError(ErrorCode::Internal, std::string(what) + ": cairo: " + cairo_status_to_string(status));
}

}  // namespace

Result<std::string> renderPdf(const Sheet& sheet) {
    std::string out;
    constexpr double kPointsPerMm = 72.0 / 25.4;
    cairo_surface_t* surface = cairo_pdf_surface_create_for_stream(appendToString, &out, sheet.widthMm * kPointsPerMm,
                                                                   sheet.heightMm * kPointsPerMm);
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE, sheet.title.c_str());
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_SUBJECT, sheet.subject.c_str());
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, "geoslice");
    if (!sheet.date.empty()) {
        const std::string iso = sheet.date + "T00:00:00Z";
        cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATE_DATE, iso.c_str());
    }
    cairo_t* cr = cairo_create(surface);
    cairo_scale(cr, kPointsPerMm, kPointsPerMm);
    drawSheet(cr, sheet);
    cairo_show_page(cr);
    const cairo_status_t drawn = cairo_status(cr);
    cairo_destroy(cr);
    cairo_surface_finish(surface);
    const cairo_status_t finished = cairo_surface_status(surface);
    cairo_surface_destroy(surface);
    if (drawn != CAIRO_STATUS_SUCCESS) return cairoError("drawing the PDF page", drawn);
    if (finished != CAIRO_STATUS_SUCCESS) return cairoError("writing the PDF", finished);
    return out;
}

int sheetPixels(double mm, double dpi) { return int(std::lround(mm * dpi / 25.4)); }

Result<SheetRaster> renderRaster(const Sheet& sheet, double dpi) {
    const int w = sheetPixels(sheet.widthMm, dpi), h = sheetPixels(sheet.heightMm, dpi);
    if (Status s = checkImageSize("the sheet at " + limitNumber(dpi) + " dpi", w, h); !s) return s.error();
    cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h);
    cairo_t* cr = cairo_create(surface);
    cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
    cairo_paint(cr);
    cairo_scale(cr, double(w) / sheet.widthMm, double(h) / sheet.heightMm);
    drawSheet(cr, sheet);
    const cairo_status_t drawn = cairo_status(cr);
    cairo_destroy(cr);
    cairo_surface_flush(surface);
    if (drawn != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(surface);
        return cairoError("drawing the sheet", drawn);
    }
    SheetRaster out;
    out.width = w;
    out.height = h;
    out.rgba.resize(std::size_t(w) * std::size_t(h) * 4);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    for (int y = 0; y < h; ++y) {
        const auto* row = reinterpret_cast<const std::uint32_t*>(data + std::size_t(y) * std::size_t(stride));
        for (int x = 0; x < w; ++x) {
            const std::uint32_t p = row[x];  // opaque (white page below everything): no un-premultiply
            std::uint8_t* o = &out.rgba[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4];
            o[0] = std::uint8_t(p >> 16);
            o[1] = std::uint8_t(p >> 8);
            o[2] = std::uint8_t(p);
            o[3] = 255;
        }
    }
    cairo_surface_destroy(surface);
    return out;
}

}  // namespace geoslice::print
