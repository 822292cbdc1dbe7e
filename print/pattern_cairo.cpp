#include "print/pattern_cairo.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "print/sheet.hpp"
#include "print/text_metrics.hpp"

namespace geoslice::print {
namespace {

void setColour(cairo_t* cr, Rgba8 c) { cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, c.a / 255.0); }

// Straight-alpha RGBA8 -> a premultiplied ARGB32 surface, and back.
cairo_surface_t* toSurface(const std::uint8_t* rgba, int w, int h) {
    cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h);
    cairo_surface_flush(s);
    unsigned char* data = cairo_image_surface_get_data(s);
    const int stride = cairo_image_surface_get_stride(s);
    for (int y = 0; y < h; ++y) {
        auto* row = reinterpret_cast<std::uint32_t*>(data + std::size_t(y) * std::size_t(stride));
        for (int x = 0; x < w; ++x) {
            const std::uint8_t* p = &rgba[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4];
            const std::uint32_t a = p[3];
            auto pre = [a](std::uint32_t c) { return (c * a + 127) / 255; };
            row[x] = (a << 24) | (pre(p[0]) << 16) | (pre(p[1]) << 8) | pre(p[2]);
        }
    }
    cairo_surface_mark_dirty(s);
    return s;
}

// Back to straight alpha, only inside [x0, x1) x [y0, y1): the premultiplied round trip is
// lossy for partly transparent pixels, so pixels nothing was drawn on are left untouched.
void fromSurface(cairo_surface_t* s, std::uint8_t* rgba, int w, int x0, int y0, int x1, int y1) {
    cairo_surface_flush(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    const int stride = cairo_image_surface_get_stride(s);
    for (int y = y0; y < y1; ++y) {
        const auto* row = reinterpret_cast<const std::uint32_t*>(data + std::size_t(y) * std::size_t(stride));
        for (int x = x0; x < x1; ++x) {
            const std::uint32_t v = row[x], a = v >> 24;
            std::uint8_t* p = &rgba[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4];
            auto un = [a](std::uint32_t c) {
                return std::uint8_t(a ? std::min<std::uint32_t>(255, (c * 255 + a / 2) / a) : 0);
            };
            p[0] = un((v >> 16) & 255);
            p[1] = un((v >> 8) & 255);
            p[2] = un(v & 255);
            p[3] = std::uint8_t(a);
        }
    }
}

}  // namespace

cairo_pattern_t* lithologyPattern(Lithology l, double s) {
    if (l == Lithology::None) return nullptr;
    const PatternTile& t = patternTile(l);
    if (t.solid)  // a plain colour: no tile seams at scales that are not whole pixels
        return cairo_pattern_create_rgba(t.ink.r / 255.0, t.ink.g / 255.0, t.ink.b / 255.0, t.ink.a / 255.0);
    cairo_rectangle_t extents{0.0, 0.0, t.width * s, t.height * s};
    cairo_surface_t* tile = cairo_recording_surface_create(CAIRO_CONTENT_COLOR_ALPHA, &extents);
    cairo_t* cr = cairo_create(tile);
    cairo_scale(cr, s, s);
    setColour(cr, t.ink);
    cairo_set_line_width(cr, t.strokeMm);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    for (const auto& line : t.polylines) {
        for (std::size_t i = 0; i < line.size(); ++i) (i ? cairo_line_to : cairo_move_to)(cr, line[i].x, line[i].y);
        cairo_stroke(cr);
    }
    for (const glm::dvec3& c : t.circles) {
        cairo_new_sub_path(cr);
        cairo_arc(cr, c.x, c.y, c.z, 0.0, 2.0 * 3.14159265358979323846);
        cairo_stroke(cr);
    }
    for (const glm::dvec3& c : t.dots) {
        cairo_new_sub_path(cr);
        cairo_arc(cr, c.x, c.y, c.z, 0.0, 2.0 * 3.14159265358979323846);
        cairo_fill(cr);
    }
    cairo_destroy(cr);
    cairo_pattern_t* p = cairo_pattern_create_for_surface(tile);
    cairo_surface_destroy(tile);
    cairo_pattern_set_extend(p, CAIRO_EXTEND_REPEAT);
    return p;
}

void drawPatternsOnImage(std::uint8_t* rgba, const std::uint32_t* ids, int w, int h,
                         const std::function<Lithology(RecordId)>& lithologyOf, double pxPerMm) {
    if (w <= 0 || h <= 0 || !ids) return;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    std::map<RecordId, Lithology> cache;
    std::map<int, bool> used;
    std::vector<std::uint8_t> lith(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (ids[i] == kNoRecord) continue;
        auto it = cache.find(ids[i]);
        if (it == cache.end()) it = cache.emplace(ids[i], lithologyOf(ids[i])).first;
        lith[i] = std::uint8_t(it->second);
        if (it->second != Lithology::None) used[int(it->second)] = true;
    }
    for (const auto& [k, _] : used) {
        // The pattern alone on a transparent layer, then composited where the pixel is this lithology.
        cairo_surface_t* layer = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h);
        cairo_t* cr = cairo_create(layer);
        cairo_pattern_t* p = lithologyPattern(Lithology(k), pxPerMm);
        cairo_set_source(cr, p);
        cairo_paint(cr);
        cairo_pattern_destroy(p);
        cairo_destroy(cr);
        cairo_surface_flush(layer);
        const unsigned char* data = cairo_image_surface_get_data(layer);
        const int stride = cairo_image_surface_get_stride(layer);
        for (int y = 0; y < h; ++y) {
            const auto* row = reinterpret_cast<const std::uint32_t*>(data + std::size_t(y) * std::size_t(stride));
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
                if (lith[i] != k) continue;
                const std::uint32_t v = row[x], a = v >> 24;
                if (a == 0) continue;
                std::uint8_t* q = &rgba[4 * i];
                // source-over of a premultiplied source on a straight-alpha destination
                const double sa = a / 255.0, da = q[3] / 255.0, oa = sa + da * (1.0 - sa);
                const std::uint32_t src[3] = {(v >> 16) & 255, (v >> 8) & 255, v & 255};
                for (int c = 0; c < 3; ++c) {
                    const double o = (src[c] / 255.0 + q[c] / 255.0 * da * (1.0 - sa)) / oa;
                    q[c] = std::uint8_t(std::clamp(o * 255.0 + 0.5, 0.0, 255.0));
                }
                q[3] = std::uint8_t(std::clamp(oa * 255.0 + 0.5, 0.0, 255.0));
            }
        }
        cairo_surface_destroy(layer);
    }
}

double labelTextWidth(const std::string& text, double sizePx) { return textWidthMm(text, sizePx / kMmPerPoint); }

void drawLabelsOnImage(std::uint8_t* rgba, int w, int h, const std::vector<ImageLabel>& labels, double sizePx) {
    if (labels.empty() || w <= 0 || h <= 0) return;
    cairo_surface_t* s = toSurface(rgba, w, h);
    cairo_t* cr = cairo_create(s);
    applyLayoutFontOptions(cr);
    for (const ImageLabel& l : labels) {
        const LabelBox& b = l.label.box;
        setColour(cr, l.box);
        cairo_rectangle(cr, b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0);
        cairo_fill(cr);
        cairo_select_font_face(cr, fontFamilyFor(l.label.text), CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
        cairo_set_font_size(cr, sizePx);
        cairo_text_extents_t e{};
        cairo_text_extents(cr, l.label.text.c_str(), &e);
        cairo_move_to(cr, l.label.at.x - 0.5 * e.x_advance, labelBaseline(l.label.at.y, sizePx));
        setColour(cr, l.ink);
        cairo_show_text(cr, l.label.text.c_str());
    }
    cairo_destroy(cr);
    for (const ImageLabel& l : labels) {  // the boxes' pixels, where all drawing happened
        const LabelBox& b = l.label.box;
        fromSurface(s, rgba, w, std::clamp(int(std::floor(b.x0)), 0, w), std::clamp(int(std::floor(b.y0)), 0, h),
                    std::clamp(int(std::ceil(b.x1)), 0, w), std::clamp(int(std::ceil(b.y1)), 0, h));
    }
    cairo_surface_destroy(s);
}

}  // namespace geoslice::print

namespace geoslice::print {

void decorateSectionImage(const SectionIndex& index, const std::vector<BodySection>& bodies, const FrameRect& rect,
                          int width, int height, std::uint8_t* rgba, const std::uint32_t* ids,
                          const ImageDecorations& o, const std::vector<SectionTrace>* traces) {
    const Model* m = index.model;
    auto lithologyOf = [m](RecordId r) { return m ? recordLithology(m->attributes.find(r)) : Lithology::None; };
    if (o.patterns && ids) drawPatternsOnImage(rgba, ids, width, height, lithologyOf, o.pxPerMm);
    if (!o.labels) return;
    const double sx = width / (rect.u1 - rect.u0), sy = height / (rect.v1 - rect.v0);
    LabelStyle style;
    style.size = o.labelPx;
    style.textWidth = labelTextWidth;
    std::vector<ImageLabel> labels;
    for (const PlacedLabel& l : sectionLabels(
             index, bodies, [&](const glm::dvec2& p) { return glm::dvec2((p.x - rect.u0) * sx, (rect.v1 - p.y) * sy); },
             LabelBox{0.0, 0.0, double(width), double(height)}, style, traces)) {
        const Rgba8 c = index.parts[l.part].colour;
        const Lithology lith = o.patterns ? lithologyOf(l.record) : Lithology::None;
        labels.push_back(
            {l, lith == Lithology::Coal ? patternTile(lith).ink : Rgba8{c.r, c.g, c.b, 255}, labelInk(c, lith)});
    }
    drawLabelsOnImage(rgba, width, height, labels, o.labelPx);
}

}  // namespace geoslice::print
