// Drillholes on profile views (api/holes.hpp).
#include "api/holes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <tuple>

#include <cairo.h>

#include "api/view.hpp"
#include "print/sheet.hpp"

namespace geoslice::api {
namespace {

// Tableau 10: a qualitative palette for categories that name no unit of the model.
constexpr Rgba8 kPalette[] = {{78, 121, 167, 255}, {242, 142, 43, 255}, {225, 87, 89, 255},   {118, 183, 178, 255},
                              {89, 161, 79, 255},  {237, 201, 72, 255}, {176, 122, 161, 255}, {255, 157, 167, 255},
                              {156, 117, 95, 255}, {186, 176, 172, 255}};
constexpr Rgba8 kNoInterval{150, 150, 150, 255};
constexpr Rgba8 kTrace{20, 20, 20, 255};

std::string hexOf(Rgba8 c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    return buf;
}

std::string xmlText(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '<')
            o += "&lt;";
        else if (c == '>')
            o += "&gt;";
        else if (c == '&')
            o += "&amp;";
        else if (c == '"')
            o += "&quot;";
        else
            o += c;
    }
    return o;
}

// The rows of `t` that belong to hole h: [first, last).
std::pair<std::size_t, std::size_t> rowsOf(const IntervalTable& t, std::uint32_t h) {
    const auto r = std::equal_range(t.hole.begin(), t.hole.end(), h);
    return {std::size_t(r.first - t.hole.begin()), std::size_t(r.second - t.hole.begin())};
}

// The interval of hole h at depth d in t (the last one starting at or above d that reaches
// below it), or npos.
std::size_t intervalAt(const IntervalTable& t, std::uint32_t h, double d) {
    const auto [first, last] = rowsOf(t, h);
    std::size_t found = std::string::npos;
    for (std::size_t i = first; i < last && t.from[i] <= d; ++i)
        if (t.to[i] > d || (t.to[i] == d && i + 1 == last)) found = i;
    return found;
}

// A piece cut at the intervals of `table` (one span without a table).
struct Span {
    const HoleTracePiece* piece = nullptr;
    double from = 0.0, to = 0.0;
    glm::dvec2 a{0.0}, b{0.0};
    std::size_t interval = std::string::npos;
};

std::vector<Span> spansOf(const ViewHoles& holes, const IntervalTable* table) {
    std::vector<Span> out;
    for (const HoleTracePiece& p : holes.section.pieces) {
        auto at = [&](double d) { return p.a + (d - p.from) / (p.to - p.from) * (p.b - p.a); };
        if (!table) {
            out.push_back({&p, p.from, p.to, p.a, p.b, std::string::npos});
            continue;
        }
        const auto [first, last] = rowsOf(*table, p.hole);
        double d = p.from;
        for (std::size_t i = first; i < last && d < p.to; ++i) {
            if (table->to[i] <= d) continue;
            if (table->from[i] >= p.to) break;
            if (table->from[i] > d) {
                out.push_back({&p, d, table->from[i], at(d), at(table->from[i]), std::string::npos});
                d = table->from[i];
            }
            const double e = std::min(table->to[i], p.to);
            out.push_back({&p, d, e, at(d), at(e), i});
            d = e;
        }
        if (d < p.to) out.push_back({&p, d, p.to, at(d), p.b, std::string::npos});
    }
    return out;
}

glm::dvec2 toPixel(const PixelMapping& m, const glm::dvec2& s) {
    return {(s.x - m.rect.u0) / ((m.rect.u1 - m.rect.u0) / m.width),
            (m.rect.v1 - s.y) / ((m.rect.v1 - m.rect.v0) / m.height)};
}

Rgba8 spanColour(const HoleStyle& style, const Span& s) {
    if (!style.table) return kTrace;
    if (s.interval == std::string::npos) return kNoInterval;
    return style.colourOf(s.interval).value_or(kNoInterval);
}

const IntervalTable* propertiesTable(const CatalogModel& model, const HoleStyle& style) {
    if (style.table) return style.table;
    return model.drillholes && !model.drillholes->intervals.empty() ? &model.drillholes->intervals.front() : nullptr;
}

}  // namespace

std::optional<Rgba8> HoleStyle::colourOf(std::size_t interval) const {
    if (!table || column < 0) return std::nullopt;
    const IntervalColumn& c = table->columns[std::size_t(column)];
    if (numeric) {
        const double v = c.numbers[interval];
        if (!std::isfinite(v) || !classes) return std::nullopt;
        return classes->colourOf(v);
    }
    const std::string& t = c.texts[interval];
    if (t.empty()) return std::nullopt;
    const auto it = std::lower_bound(categories.begin(), categories.end(), t);
    if (it == categories.end() || *it != t) return std::nullopt;
    return categoryColours[std::size_t(it - categories.begin())];
}

Result<HoleStyle> holeStyle(const CatalogModel& model, const HoleDrawing& drawing) {
    HoleStyle style;
    if (drawing.column.empty()) return style;
    if (!model.drillholes)
        return makeError(ErrorCode::InvalidArgument, "parameter 'holecolour': model '" + model.id +
                                                         "' has no drillhole database (attach one with a "
                                                         "<stem>.drillholes.json sidecar)");
    const DrillholeDatabase& db = *model.drillholes;
    std::string tableName, columnName = drawing.column;
    if (const auto dot = drawing.column.find('.'); dot != std::string::npos) {
        tableName = drawing.column.substr(0, dot);
        columnName = drawing.column.substr(dot + 1);
    }
    std::string known;
    for (const IntervalTable& t : db.intervals) {
        for (std::size_t c = 0; c < t.columns.size(); ++c) {
            known += (known.empty() ? "" : ", ") + t.name + "." + t.columns[c].name;
            if (style.table || (!tableName.empty() && t.name != tableName) || t.columns[c].name != columnName) continue;
            style.table = &t;
            style.column = int(c);
        }
    }
    if (!style.table)
        return makeError(ErrorCode::InvalidArgument, "parameter 'holecolour': no interval column '" + drawing.column +
                                                         "'; the columns are " + (known.empty() ? "none" : known));
    const IntervalColumn& col = style.table->columns[std::size_t(style.column)];
    style.numeric = col.numeric;
    if (col.numeric) {
        std::vector<double> breaks;
        if (drawing.breaks) {
            breaks = *drawing.breaks;
        } else {
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (double v : col.numbers)
                if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
            if (hi > lo)
                for (int k = 1; k < 5; ++k) breaks.push_back(lo + (hi - lo) * k / 5.0);
        }
        auto classes = makePropertyClasses(-1, drawing.ramp, std::move(breaks));
        if (!classes)
            return makeError(classes.error().code,
                             std::string(drawing.breaks ? "parameter 'holebreaks': " : "parameter 'holecolour': ") +
                                 classes.error().message);
        style.classes = std::move(classes.value());
        return style;
    }
    style.categories = col.texts;
    std::sort(style.categories.begin(), style.categories.end());
    style.categories.erase(std::unique(style.categories.begin(), style.categories.end()), style.categories.end());
    style.categories.erase(std::remove(style.categories.begin(), style.categories.end(), std::string()),
                           style.categories.end());
    std::size_t next = 0;
    for (const std::string& cat : style.categories) {
        std::optional<Rgba8> c;
        for (const auto& [id, r] : model.model.attributes.records()) {
            if (r.name == cat || r.lithology == cat || r.age.find("(" + cat + ")") != std::string::npos) {
                c = r.colour;
                c->a = 255;
                break;
            }
        }
        style.categoryColours.push_back(c ? *c : kPalette[next++ % std::size(kPalette)]);
    }
    return style;
}

nlohmann::ordered_json holeLegendJson(const HoleStyle& style) {
    if (!style.table) return nullptr;
    const IntervalColumn& col = style.table->columns[std::size_t(style.column)];
    nlohmann::ordered_json j;
    j["table"] = style.table->name;
    j["column"] = col.name;
    j["unit"] = col.unit;
    j["kind"] = style.numeric ? "classes" : "categories";
    j["entries"] = nlohmann::ordered_json::array();
    if (style.numeric && style.classes) {
        for (std::size_t k = 0; k < style.classes->colours.size(); ++k)
            j["entries"].push_back({{"label", style.classes->label(k)}, {"colour", hexOf(style.classes->colours[k])}});
    } else {
        for (std::size_t k = 0; k < style.categories.size(); ++k)
            j["entries"].push_back({{"label", style.categories[k]}, {"colour", hexOf(style.categoryColours[k])}});
    }
    j["entries"].push_back({{"label", "no interval"}, {"colour", hexOf(kNoInterval)}});
    return j;
}

Result<ViewHoles> viewHoles(const CatalogModel& model, const SectionDef& def, const PixelMapping& mapping) {
    ViewHoles out;
    auto style = holeStyle(model, def.holes);
    if (!style) return style.error();
    out.style = std::move(style.value());
    if (!model.holeIndex || def.holes.window <= 0.0) return out;
    out.section = mapping.geometry == Geometry::Line
                      ? holesOnLine(*model.holeIndex, mapping.line, def.holes.window)
                      : holesOnPlane(*model.holeIndex, mapping.planar.section, def.holes.window);
    return out;
}

void drawHoles(const CatalogModel& model, const ViewHoles& holes, const PixelMapping& mapping, ViewImage& image) {
    if (holes.empty() || !model.drillholes) return;
    const int w = image.width, h = image.height;
    if (image.rgba.size() != std::size_t(w) * std::size_t(h) * 4) return;
    const bool coloured = holes.style.table != nullptr;
    // Runs: consecutive spans of one hole, side and colour that join end to end, as pixel
    // polylines; each group of runs of one side and colour is one path, stroked once (a stroke
    // per chord cost ten times the section itself). Dashes restart with each run.
    struct Run {
        bool front = false;
        Rgba8 colour;
        std::vector<glm::dvec2> points;
    };
    std::vector<Run> runs;
    const HoleTracePiece* last = nullptr;
    double lastTo = 0.0;
    for (const Span& s : spansOf(holes, holes.style.table)) {
        const Rgba8 c = spanColour(holes.style, s);
        const glm::dvec2 a = toPixel(mapping, s.a), b = toPixel(mapping, s.b);
        const bool joins = last && !runs.empty() && last->hole == s.piece->hole && last->front == s.piece->front &&
                           last->leg == s.piece->leg && lastTo == s.from && runs.back().colour == c;
        if (!joins) runs.push_back({s.piece->front, c, {a}});
        runs.back().points.push_back(b);
        last = s.piece;
        lastTo = s.to;
    }
    // The overlay is drawn with cairo into a buffer kept per thread and composited over the
    // image, both only in the 16-pixel tiles that something is drawn in (a fresh full-size
    // surface cost more in page faults and blending than the drawing; bench/drillholes.cpp).
    constexpr int kTile = 16;
    const int tx = (w + kTile - 1) / kTile, ty = (h + kTile - 1) / kTile;
    std::vector<unsigned char> dirty(std::size_t(tx) * std::size_t(ty), 0);
    auto mark = [&](double x0, double y0, double x1, double y1) {
        const int i0 = std::max(0, int(std::floor(x0)) / kTile), i1 = std::min(tx - 1, int(std::floor(x1)) / kTile);
        const int j0 = std::max(0, int(std::floor(y0)) / kTile), j1 = std::min(ty - 1, int(std::floor(y1)) / kTile);
        if (x1 < 0.0 || y1 < 0.0 || x0 >= w || y0 >= h) return;
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) dirty[std::size_t(j) * std::size_t(tx) + std::size_t(i)] = 1;
    };
    constexpr double kLineReach = 6.0;  // half the widest stroke (casing) plus antialiasing, px
    for (const Run& r : runs)
        for (std::size_t k = 1; k < r.points.size(); ++k) {
            const glm::dvec2 a = r.points[k - 1], b = r.points[k];
            const int steps = std::max(1, int(std::ceil(glm::length(b - a) / 8.0)));
            for (int s = 0; s <= steps; ++s) {
                const glm::dvec2 p = a + (b - a) * (double(s) / steps);
                mark(p.x - kLineReach - 8.0, p.y - kLineReach - 8.0, p.x + kLineReach + 8.0, p.y + kLineReach + 8.0);
            }
        }
    for (const HolePierce& p : holes.section.pierces) {
        const glm::dvec2 q = toPixel(mapping, p.at);
        mark(q.x - 7.0, q.y - 7.0, q.x + 7.0, q.y + 7.0);
    }
    thread_local std::vector<unsigned char> buffer;
    const int stride = cairo_format_stride_for_width(CAIRO_FORMAT_ARGB32, w);
    const std::size_t bytes = std::size_t(stride) * std::size_t(h);
    if (buffer.size() < bytes) buffer.resize(bytes);
    cairo_surface_t* surface = cairo_image_surface_create_for_data(buffer.data(), CAIRO_FORMAT_ARGB32, w, h, stride);
    cairo_t* cr = cairo_create(surface);
    cairo_select_font_face(cr, print::kFontFamily, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_font_size(cr, 11.0);
    for (const HoleLabel& l : holes.section.labels) {
        const glm::dvec2 q = toPixel(mapping, l.at);
        cairo_text_extents_t e;
        cairo_text_extents(cr, model.drillholes->holes[l.hole].id.c_str(), &e);
        mark(q.x - 8.0, q.y - 10.0 + e.y_bearing - 4.0, q.x + 6.0 + e.x_advance + 4.0, q.y + 2.0);
    }
    auto forDirtyRows = [&](const std::function<void(int y, int x0, int x1)>& f) {
        for (int j = 0; j < ty; ++j)
            for (int i = 0; i < tx;) {
                if (!dirty[std::size_t(j) * std::size_t(tx) + std::size_t(i)]) {
                    ++i;
                    continue;
                }
                int e = i;
                while (e < tx && dirty[std::size_t(j) * std::size_t(tx) + std::size_t(e)]) ++e;
                const int x0 = i * kTile, x1 = std::min(w, e * kTile);
                for (int y = j * kTile; y < std::min(h, (j + 1) * kTile); ++y) f(y, x0, x1);
                i = e;
            }
    };
    forDirtyRows([&](int y, int x0, int x1) {
        std::memset(buffer.data() + std::size_t(y) * std::size_t(stride) + std::size_t(x0) * 4, 0,
                    std::size_t(x1 - x0) * 4);
    });
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    std::vector<std::size_t> order(runs.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    auto key = [&](const Run& r) { return std::tuple(r.front, r.colour.r, r.colour.g, r.colour.b); };
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t x, std::size_t y) { return key(runs[x]) < key(runs[y]); });
    const double dash[2] = {7.0, 5.0};
    auto strokeGroups = [&](bool casing) {
        for (std::size_t i = 0; i < order.size();) {
            const Run& first = runs[order[i]];
            std::size_t j = i;
            for (;
                 j < order.size() && (casing ? runs[order[j]].front == first.front : key(runs[order[j]]) == key(first));
                 ++j) {
                const Run& r = runs[order[j]];
                cairo_move_to(cr, r.points[0].x, r.points[0].y);
                for (std::size_t k = 1; k < r.points.size(); ++k) cairo_line_to(cr, r.points[k].x, r.points[k].y);
            }
            const bool front = first.front;
            const double width = front ? 4.0 : 2.5;
            cairo_set_dash(cr, front ? nullptr : dash, front ? 0 : 2, 0.0);
            if (casing) {
                if (coloured)
                    cairo_set_source_rgba(cr, 0.08, 0.08, 0.08, front ? 0.9 : 0.55);
                else
                    cairo_set_source_rgba(cr, 1.0, 1.0, 1.0, front ? 0.85 : 0.6);
                cairo_set_line_width(cr, width + 2.5);
            } else {
                const Rgba8 c = first.colour;
                cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, front ? 1.0 : 0.7);
                cairo_set_line_width(cr, width);
            }
            cairo_stroke(cr);
            i = j;
        }
    };
    strokeGroups(true);
    strokeGroups(false);
    cairo_set_dash(cr, nullptr, 0, 0.0);
    for (const HolePierce& p : holes.section.pierces) {
        const glm::dvec2 q = toPixel(mapping, p.at);
        cairo_arc(cr, q.x, q.y, 4.5, 0.0, 6.283185307179586);
        cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
        cairo_set_line_width(cr, 1.5);
        cairo_stroke(cr);
    }
    for (const HoleLabel& l : holes.section.labels) {
        const glm::dvec2 q = toPixel(mapping, l.at);
        if (l.collar) {
            cairo_move_to(cr, q.x, q.y);
            cairo_line_to(cr, q.x - 5.0, q.y - 8.0);
            cairo_line_to(cr, q.x + 5.0, q.y - 8.0);
            cairo_close_path(cr);
            cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
            cairo_fill(cr);
        }
        // The halo is the text shown at eight offsets: cached glyphs, where a stroked text path
        // cost half the overlay.
        const char* id = model.drillholes->holes[l.hole].id.c_str();
        cairo_set_source_rgba(cr, 1.0, 1.0, 1.0, 0.9);
        for (const auto& [ox, oy] :
             {std::pair{-1.5, 0.0}, std::pair{1.5, 0.0}, std::pair{0.0, -1.5}, std::pair{0.0, 1.5},
              std::pair{-1.0, -1.0}, std::pair{1.0, 1.0}, std::pair{-1.0, 1.0}, std::pair{1.0, -1.0}}) {
            cairo_move_to(cr, q.x + 6.0 + ox, q.y - 10.0 + oy);
            cairo_show_text(cr, id);
        }
        cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
        cairo_move_to(cr, q.x + 6.0, q.y - 10.0);
        cairo_show_text(cr, id);
    }
    cairo_destroy(cr);
    cairo_surface_flush(surface);
    // Over: the overlay (premultiplied BGRA in native order) onto the straight-alpha image.
    forDirtyRows([&](int y, int x0, int x1) {
        const std::uint32_t* row =
            reinterpret_cast<const std::uint32_t*>(buffer.data() + std::size_t(y) * std::size_t(stride));
        std::uint8_t* dst = image.rgba.data() + (std::size_t(y) * std::size_t(w) + std::size_t(x0)) * 4;
        for (int x = x0; x < x1; ++x, dst += 4) {
            const std::uint32_t p = row[x];
            const double sa = double(p >> 24) / 255.0;
            if (sa == 0.0) continue;
            const double sr = double((p >> 16) & 255) / 255.0, sg = double((p >> 8) & 255) / 255.0,
                         sb = double(p & 255) / 255.0;
            const double da = dst[3] / 255.0, k = da * (1.0 - sa), oa = sa + k;
            auto mix = [&](double s, std::uint8_t d) {
                return std::uint8_t(std::lround(255.0 * (s + d / 255.0 * k) / oa));
            };
            dst[0] = mix(sr, dst[0]);
            dst[1] = mix(sg, dst[1]);
            dst[2] = mix(sb, dst[2]);
            dst[3] = std::uint8_t(std::lround(255.0 * oa));
        }
    });
    cairo_surface_destroy(surface);
}

void addHolesToSheet(const CatalogModel& model, const ViewHoles& holes, const print::MapFrame& frame,
                     print::Sheet& sheet) {
    if (holes.empty() || !model.drillholes) return;
    const bool coloured = holes.style.table != nullptr;
    auto page = [&](const glm::dvec2& uv) { return frame.toPage(uv); };
    const std::vector<Span> spans = spansOf(holes, holes.style.table);
    for (const bool casing : {true, false})
        for (const Span& s : spans) {
            const bool front = s.piece->front;
            print::PathItem p;
            p.closed = false;
            p.subpaths.push_back({page(s.a), page(s.b)});
            const double width = front ? 0.5 : 0.3;
            p.strokeMm = casing ? width + 0.3 : width;
            p.dashMm = front ? 0.0 : 1.5;
            p.clip = frame.box;
            if (casing) {
                p.stroke = coloured ? Rgba8{20, 20, 20, std::uint8_t(front ? 230 : 140)}
                                    : Rgba8{255, 255, 255, std::uint8_t(front ? 217 : 153)};
            } else {
                Rgba8 c = spanColour(holes.style, s);
                c.a = front ? 255 : 180;
                p.stroke = c;
                p.title = model.drillholes->holes[s.piece->hole].id;
            }
            sheet.add(std::move(p));
        }
    for (const HolePierce& q : holes.section.pierces) {
        print::PathItem disc;
        const print::PagePoint c = page(q.at);
        std::vector<print::PagePoint> ring;
        for (int k = 0; k < 16; ++k)
            ring.push_back(
                {c.x + 0.5 * std::cos(k * 0.39269908169872414), c.y + 0.5 * std::sin(k * 0.39269908169872414)});
        disc.subpaths.push_back(std::move(ring));
        disc.fill = Rgba8{255, 255, 255, 255};
        disc.stroke = Rgba8{0, 0, 0, 255};
        disc.strokeMm = 0.2;
        disc.clip = frame.box;
        sheet.add(std::move(disc));
    }
    for (const HoleLabel& l : holes.section.labels) {
        const print::PagePoint c = page(l.at);
        if (c.x < frame.box.x || c.x > frame.box.right() || c.y < frame.box.y || c.y > frame.box.bottom()) continue;
        if (l.collar) {
            print::PathItem tri;
            tri.subpaths.push_back({{c.x, c.y}, {c.x - 0.7, c.y - 1.1}, {c.x + 0.7, c.y - 1.1}});
            tri.fill = Rgba8{0, 0, 0, 255};
            tri.stroke.reset();
            sheet.add(std::move(tri));
        }
        print::TextItem t;
        t.at = {c.x + 0.8, c.y - 1.3};
        t.text = model.drillholes->holes[l.hole].id;
        t.sizePt = 6.0;
        t.bold = true;
        sheet.add(std::move(t));
    }
}

std::string holesSvg(const CatalogModel& model, const ViewHoles& holes, const PixelMapping& mapping) {
    if (holes.empty() || !model.drillholes) return "";
    std::string out = "<g class=\"drillholes\" fill=\"none\" stroke-linecap=\"butt\">\n";
    char buf[512];
    const bool coloured = holes.style.table != nullptr;
    const std::vector<Span> spans = spansOf(holes, holes.style.table);
    // The casing under the traces, as on the images.
    for (const Span& s : spans) {
        const glm::dvec2 a = toPixel(mapping, s.a), b = toPixel(mapping, s.b);
        const bool front = s.piece->front;
        std::snprintf(buf, sizeof buf,
                      "<line class=\"casing\" x1=\"%.3f\" y1=\"%.3f\" x2=\"%.3f\" y2=\"%.3f\" stroke=\"%s\" "
                      "stroke-width=\"%.1f\" stroke-opacity=\"%.2f\"%s/>\n",
                      a.x, a.y, b.x, b.y, coloured ? "#141414" : "#ffffff", front ? 6.5 : 5.0,
                      coloured ? (front ? 0.9 : 0.55) : (front ? 0.85 : 0.6), front ? "" : " stroke-dasharray=\"7 5\"");
        out += buf;
    }
    for (const Span& s : spans) {
        const glm::dvec2 a = toPixel(mapping, s.a), b = toPixel(mapping, s.b);
        const bool front = s.piece->front;
        const Rgba8 c = spanColour(holes.style, s);
        const std::string& id = model.drillholes->holes[s.piece->hole].id;
        std::snprintf(buf, sizeof buf,
                      "<line x1=\"%.3f\" y1=\"%.3f\" x2=\"%.3f\" y2=\"%.3f\" stroke=\"%s\" stroke-width=\"%.1f\" "
                      "stroke-opacity=\"%.2f\"%s data-hole=\"%s\" data-from=\"%.3f\" data-to=\"%.3f\" "
                      "data-side=\"%s\"><title>",
                      a.x, a.y, b.x, b.y, hexOf(c).c_str(), front ? 4.0 : 2.5, front ? 1.0 : 0.7,
                      front ? "" : " stroke-dasharray=\"7 5\"", xmlText(id).c_str(), s.from, s.to,
                      front ? "front" : "behind");
        out += buf;
        std::snprintf(buf, sizeof buf, " %.2f-%.2f m (%s)</title></line>\n", s.from, s.to,
                      front ? "in front of the section" : "behind the section");
        out += xmlText(id) + buf;
    }
    for (const HolePierce& p : holes.section.pierces) {
        const glm::dvec2 q = toPixel(mapping, p.at);
        std::snprintf(buf, sizeof buf,
                      "<circle class=\"pierce\" cx=\"%.3f\" cy=\"%.3f\" r=\"4.5\" fill=\"#ffffff\" stroke=\"#000000\" "
                      "stroke-width=\"1.5\" data-depth=\"%.3f\"><title>",
                      q.x, q.y, p.depth);
        out += buf;
        std::snprintf(buf, sizeof buf, " pierces the section at %.2f m</title></circle>\n", p.depth);
        out += xmlText(model.drillholes->holes[p.hole].id) + buf;
    }
    for (const HoleLabel& l : holes.section.labels) {
        const glm::dvec2 q = toPixel(mapping, l.at);
        if (l.collar) {
            std::snprintf(buf, sizeof buf, "<path class=\"collar\" d=\"M%.3f %.3fl-5 -8h10z\" fill=\"#000000\"/>\n",
                          q.x, q.y);
            out += buf;
        }
        std::snprintf(buf, sizeof buf,
                      "<text x=\"%.3f\" y=\"%.3f\" font-family=\"DejaVu Sans, sans-serif\" font-size=\"11\" "
                      "font-weight=\"bold\" fill=\"#000000\" stroke=\"#ffffff\" stroke-width=\"3\" "
                      "paint-order=\"stroke\">",
                      q.x + 6.0, q.y - 10.0);
        out += buf + xmlText(model.drillholes->holes[l.hole].id) + "</text>\n";
    }
    out += "</g>\n";
    return out;
}

std::vector<nlohmann::ordered_json> holesGeoJson(const CatalogModel& model, const ViewHoles& holes,
                                                 const std::function<glm::dvec3(const glm::dvec2&)>* toWorld) {
    std::vector<nlohmann::ordered_json> out;
    if (!model.drillholes) return out;
    const DrillholeDatabase& db = *model.drillholes;
    auto coord = [&](const glm::dvec2& p) {
        if (!toWorld) return nlohmann::ordered_json::array({p.x, p.y});
        const glm::dvec3 w = (*toWorld)(p);
        return nlohmann::ordered_json::array({w.x, w.y, w.z});
    };
    const IntervalTable* table = propertiesTable(model, holes.style);
    for (const Span& s : spansOf(holes, table)) {
        nlohmann::ordered_json f;
        f["type"] = "Feature";
        f["geometry"] = {{"type", "LineString"}, {"coordinates", {coord(s.a), coord(s.b)}}};
        nlohmann::ordered_json p;
        p["kind"] = "drillhole";
        p["hole"] = db.holes[s.piece->hole].id;
        p["from"] = s.from;
        p["to"] = s.to;
        p["side"] = s.piece->front ? "front" : "behind";
        const double t0 = (s.from - s.piece->from) / (s.piece->to - s.piece->from),
                     t1 = (s.to - s.piece->from) / (s.piece->to - s.piece->from);
        p["offsetFrom"] = s.piece->offsetA + t0 * (s.piece->offsetB - s.piece->offsetA);
        p["offsetTo"] = s.piece->offsetA + t1 * (s.piece->offsetB - s.piece->offsetA);
        if (holes.style.table) {
            const Rgba8 c = spanColour(holes.style, s);
            p["colour"] = hexOf(c);
        }
        if (table && s.interval != std::string::npos) {
            p["table"] = table->name;
            p["intervalFrom"] = table->from[s.interval];
            p["intervalTo"] = table->to[s.interval];
            for (const IntervalColumn& c : table->columns) {
                if (c.numeric)
                    p[c.name] = std::isfinite(c.numbers[s.interval]) ? nlohmann::ordered_json(c.numbers[s.interval])
                                                                     : nlohmann::ordered_json(nullptr);
                else
                    p[c.name] = c.texts[s.interval];
            }
        }
        f["properties"] = std::move(p);
        out.push_back(std::move(f));
    }
    for (const HolePierce& q : holes.section.pierces) {
        out.push_back(
            {{"type", "Feature"},
             {"geometry", {{"type", "Point"}, {"coordinates", coord(q.at)}}},
             {"properties", {{"kind", "drillhole-pierce"}, {"hole", db.holes[q.hole].id}, {"depth", q.depth}}}});
    }
    for (const HoleLabel& l : holes.section.labels) {
        out.push_back({{"type", "Feature"},
                       {"geometry", {{"type", "Point"}, {"coordinates", coord(l.at)}}},
                       {"properties",
                        {{"kind", l.collar ? "drillhole-collar" : "drillhole-entry"},
                         {"hole", db.holes[l.hole].id},
                         {"depth", l.depth}}}});
    }
    return out;
}

std::optional<HoleHit> holeNearPixel(const CatalogModel& model, const ViewHoles& holes, const PixelMapping& mapping,
                                     double x, double y, double radiusPx) {
    if (!model.drillholes) return std::nullopt;
    std::optional<HoleHit> best;
    const glm::dvec2 q(x, y);
    for (const HoleTracePiece& p : holes.section.pieces) {
        const glm::dvec2 a = toPixel(mapping, p.a), b = toPixel(mapping, p.b);
        const glm::dvec2 ab = b - a;
        const double len2 = glm::dot(ab, ab);
        const double t = len2 > 0.0 ? std::clamp(glm::dot(q - a, ab) / len2, 0.0, 1.0) : 0.0;
        const double dist = glm::length(a + t * ab - q);
        if (dist > radiusPx || (best && dist >= best->distancePx)) continue;
        HoleHit hit;
        hit.hole = p.hole;
        hit.depth = p.from + t * (p.to - p.from);
        hit.distancePx = dist;
        hit.offset = p.offsetA + t * (p.offsetB - p.offsetA);
        hit.world = model.drillholes->holes[p.hole].path.at(hit.depth);
        best = hit;
    }
    return best;
}

void writeHoleHit(JsonWriter& w, const CatalogModel& model, const HoleHit& hit) {
    const DrillholeDatabase& db = *model.drillholes;
    w.key("drillhole").beginObject();
    w.key("id").value(db.holes[hit.hole].id);
    w.key("depth").value(hit.depth);
    w.key("distancePx").value(hit.distancePx);
    w.key("offset").value(hit.offset);
    w.key("side").value(hit.offset < 0.0 ? "front" : "behind");
    w.key("world").beginArray().value(hit.world.x).value(hit.world.y).value(hit.world.z).endArray();
    w.key("intervals").beginArray();
    for (const IntervalTable& t : db.intervals) {
        const std::size_t i = intervalAt(t, hit.hole, hit.depth);
        if (i == std::string::npos) continue;
        w.beginObject().key("table").value(t.name).key("from").value(t.from[i]).key("to").value(t.to[i]);
        w.key("columns").beginObject();
        for (const IntervalColumn& c : t.columns) {
            if (c.numeric)
                w.key(c.name).value(c.numbers[i]);
            else
                w.key(c.name).value(c.texts[i]);
        }
        w.endObject().endObject();
    }
    w.endArray();
    w.key("note").value(
        "depth: metres along the hole at the traced point nearest the pixel; offset: metres from the section, "
        "negative in front (toward the viewer)");
    w.endObject();
}

}  // namespace geoslice::api
