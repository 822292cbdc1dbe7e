// A printed sheet as a display list: paths, text and images in page millimetres, in
// drawing order. Layout code (print/section_sheet.hpp) builds one; the outputs draw it:
// PDF and raster through cairo (print/cairo_output.hpp), SVG as XML text that keeps every
// label as a <text> element (print/svg_output.hpp). One list, so the three outputs show
// the same sheet.
//
// Frame: page millimetres, origin at the top-left corner of the page, x right, y down.
// Text sizes are in points (1 pt = 25.4 / 72 mm), as printers and cairo count them.
// Plain data, any thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "model/attributes.hpp"
#include "section/fill/patterns.hpp"

namespace geoslice::print {

constexpr double kMmPerPoint = 25.4 / 72.0;

struct PagePoint {
    double x = 0.0, y = 0.0;  // mm from the page's top-left corner, y down
};

struct PageRect {
    double x = 0.0, y = 0.0, width = 0.0, height = 0.0;  // mm; (x, y) = top-left corner
    double right() const { return x + width; }
    double bottom() const { return y + height; }
};

// A filled and/or stroked path of one or more subpaths. Filled paths use the even-odd
// rule (holes of section polygons are subpaths). `clip`: drawn only inside that rectangle.
struct PathItem {
    std::vector<std::vector<PagePoint>> subpaths;
    bool closed = true;
    std::optional<Rgba8> fill;
    std::optional<Rgba8> stroke;
    double strokeMm = 0.25;
    double dashMm = 0.0;  // > 0: dashes and gaps of this length
    std::optional<PageRect> clip;
    std::string title;  // SVG: a <title> (e.g. the unit's name); ignored by cairo
    // A lithology pattern (section/fill/patterns.hpp) filled over `fill` (even-odd), tiles
    // aligned with the page's origin: a PDF tiling pattern, an SVG <pattern>.
    Lithology pattern = Lithology::None;
};

enum class TextAnchor { Start, Middle, End };
// Vertical placement of the anchor point: the text's baseline, or the middle / top of its
// capital letters (cap height 0.73 em for DejaVu Sans, which both outputs name).
enum class TextBaseline { Alphabetic, Middle, Hanging };

struct TextItem {
    PagePoint at;
    std::string text;  // UTF-8
    double sizePt = 8.0;
    bool bold = false;
    TextAnchor anchor = TextAnchor::Start;
    TextBaseline baseline = TextBaseline::Alphabetic;
    double rotateDeg = 0.0;  // counter-clockwise on the page, about `at`
    Rgba8 colour{0, 0, 0, 255};
};

// A raster drawn into `box` (stretched to it): straight-alpha RGBA8, rows top first.
struct ImageItem {
    PageRect box;
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;
};

// Millimetres from `at` down to the baseline for the item's TextBaseline (0 for Alphabetic).
inline double baselineShiftMm(const TextItem& t) {
    constexpr double kCapHeightEm = 0.729;  // DejaVu Sans
    const double cap = kCapHeightEm * t.sizePt * kMmPerPoint;
    switch (t.baseline) {
        case TextBaseline::Middle:
            return 0.5 * cap;
        case TextBaseline::Hanging:
            return cap;
        case TextBaseline::Alphabetic:
            break;
    }
    return 0.0;
}

using SheetItem = std::variant<PathItem, TextItem, ImageItem>;

struct Sheet {
    double widthMm = 420.0, heightMm = 297.0;
    std::string title;    // document title (PDF metadata, SVG <title>)
    std::string subject;  // document subject (PDF metadata)
    std::string date;     // YYYY-MM-DD, the sheet's date (PDF creation date)
    std::vector<SheetItem> items;

    void add(SheetItem item) { items.push_back(std::move(item)); }
};

// Font families both outputs use: their metrics decide the layout. DejaVu Sans
// (fonts-dejavu-core) has no CJK glyphs, so text with any CJK character (Chinese unit
// names from Geo3DML models, "地层C") is set whole in WenQuanYi Micro Hei
// (fonts-wqy-microhei), which has Latin glyphs too; cairo's simple text API picks one font
// per string and does no fallback of its own.
constexpr const char* kFontFamily = "DejaVu Sans";
constexpr const char* kCjkFontFamily = "WenQuanYi Micro Hei";

// kCjkFontFamily when `text` (UTF-8) holds a character of the CJK, kana, hangul or
// full-width blocks, else kFontFamily.
const char* fontFamilyFor(std::string_view text);

}  // namespace geoslice::print
