#include "print/text_metrics.hpp"

#include <cairo.h>

#include <algorithm>
#include <string>
#include <vector>

#include "model/result.hpp"
#include "print/sheet.hpp"

namespace geoslice::print {

void applyLayoutFontOptions(cairo_t* cr) {
    cairo_font_options_t* fo = cairo_font_options_create();
    cairo_font_options_set_hint_metrics(fo, CAIRO_HINT_METRICS_OFF);
    cairo_font_options_set_hint_style(fo, CAIRO_HINT_STYLE_NONE);
    cairo_set_font_options(cr, fo);
    cairo_font_options_destroy(fo);
}

double textWidthMm(std::string_view text, double sizePt, bool bold) {
    cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_A8, 1, 1);
    cairo_t* cr = cairo_create(surface);
    cairo_select_font_face(cr, fontFamilyFor(text), CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, sizePt * kMmPerPoint);  // user units = mm
    applyLayoutFontOptions(cr);
    cairo_text_extents_t e{};
    const std::string s(text);
    cairo_text_extents(cr, s.c_str(), &e);
    GS_ASSERT(cairo_status(cr) == CAIRO_STATUS_SUCCESS, "cairo could not measure text");
    cairo_destroy(cr);
    cairo_surface_destroy(surface);
    return e.x_advance;
}

std::string fitText(const std::string& text, double maxWidthMm, double sizePt, bool bold) {
    if (textWidthMm(text, sizePt, bold) <= maxWidthMm) return text;
    static const std::string kEllipsis = "\u2026";
    // Byte offsets of code point starts (UTF-8 lead bytes): prefix k = text[0, cuts[k]).
    std::vector<std::size_t> cuts;
    for (std::size_t i = 0; i < text.size(); ++i)
        if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) cuts.push_back(i);
    // The longest prefix that fits with the ellipsis (width grows with k): bisection.
    std::size_t lo = 0, hi = cuts.empty() ? 0 : cuts.size() - 1;
    while (lo < hi) {
        const std::size_t mid = (lo + hi + 1) / 2;
        if (textWidthMm(text.substr(0, cuts[mid]) + kEllipsis, sizePt, bold) <= maxWidthMm)
            lo = mid;
        else
            hi = mid - 1;
    }
    return text.substr(0, cuts.empty() ? 0 : cuts[lo]) + kEllipsis;
}

std::vector<std::string> wrapText(const std::string& text, double maxWidthMm, double sizePt, std::size_t maxLines,
                                  bool bold) {
    std::vector<std::string> lines;
    std::size_t pos = 0;
    while (pos < text.size() && lines.size() + 1 < maxLines) {
        // The longest run of whole words from `pos` that fits (words end at spaces, which
        // are dropped); failing that, of a long word cut after a comma (kept), so lists of
        // coordinates wrap too.
        auto longest = [&](const char* breaks, bool keepBreak) {
            std::size_t end = pos, next = pos;
            while (next < text.size()) {
                const std::size_t brk = text.find_first_of(breaks, next);
                const std::size_t stop = brk == std::string::npos ? text.size() : brk + (keepBreak ? 1 : 0);
                if (textWidthMm(text.substr(pos, stop - pos), sizePt, bold) > maxWidthMm) break;
                end = stop;
                next = brk == std::string::npos ? text.size() : brk + 1;
            }
            return end;
        };
        std::size_t end = longest(" ", false);
        if (end == pos) end = longest(",", true);
        if (end == pos) break;  // not even a piece fits: cut below
        lines.push_back(text.substr(pos, end - pos));
        pos = end < text.size() && text[end] == ' ' ? end + 1 : end;
    }
    if (pos < text.size()) lines.push_back(fitText(text.substr(pos), maxWidthMm, sizePt, bold));
    if (lines.empty()) lines.push_back("");
    return lines;
}

}  // namespace geoslice::print
