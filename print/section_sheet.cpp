#include "print/section_sheet.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "print/axes.hpp"
#include "print/grid_convergence.hpp"
#include "print/legend.hpp"
#include "print/map_scale.hpp"
#include "print/north_arrow.hpp"
#include "print/pattern_cairo.hpp"
#include "print/round_numbers.hpp"
#include "print/scale_bar.hpp"
#include "print/section_ends.hpp"
#include "print/text_metrics.hpp"
#include "print/title_block.hpp"
#include "section/fill/labels.hpp"
#include "section/fill/vector_export.hpp"
#include "view/exaggeration.hpp"

namespace geoslice::print {
namespace {

constexpr Rgba8 kInk{0, 0, 0, 255};
constexpr Rgba8 kContact{35, 35, 35, 255};

// What differs between a plane, a slice and a polyline: filled in by the two entry points.
struct Shape {
    enum Kind { Vertical, Inclined, Horizontal, Polyline } kind = Vertical;
    VectorSource source;
    FrameRect extent;  // section coordinates to show
    AxesSpec axes;
    std::string title;
    struct End {
        double u = 0.0;  // section coordinate of the end or bend
        std::string label;
        bool bend = false;
    };
    std::vector<End> ends;
    std::vector<TitleRow> rows;       // shape-specific title block rows (section, ends, azimuth...)
    std::optional<double> trueNorth;  // horizontal slices in a projected CRS: from grid north, degrees
    // Inclined planes: the unit normal, whose v axis the exaggeration stretches by
    // VerticalExaggeration::vStretch (as images and tiles do), not by the raw factor.
    glm::dvec3 normal{0.0, 0.0, 1.0};
    // The engine's raster of a section rectangle, for rasterGeometry (with ids when asked).
    std::function<Result<SectionImage>(const FrameRect&, int, int, const RasterOptions&)> raster;
    // Section coordinates (u, v) -> world, for colouring a raster by block cells.
    std::function<glm::dvec3(double, double)> toWorld;
    // The block pieces of the section (SheetOptions::blocks), for vector geometry.
    std::function<Result<std::vector<BlockPiece>>()> pieces;
};

std::string metres(double v) { return formatGrouped(v, std::abs(v) < 100.0 ? 1 : 0); }
std::string mapPoint(const glm::dvec2& p) { return formatGrouped(p.x, 0) + " E, " + formatGrouped(p.y, 0) + " N"; }
std::string degrees(double a) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%03.0f\u00b0", std::fmod(std::round(a), 360.0));
    return buf;
}

// Vertical extent of the contents with a 3 % margin (at least 1 m), or `fallback` when empty.
void verticalExtent(FrameRect& r, const glm::dvec2& lo, const glm::dvec2& hi, bool empty, double fallbackLo,
                    double fallbackHi) {
    double a = empty ? fallbackLo : lo.y, b = empty ? fallbackHi : hi.y;
    const double m = std::max(0.03 * (b - a), 1.0);
    r.v0 = a - m;
    r.v1 = b + m;
}

// The page's regions (mm): where the map frame may go, the title band above it, the scale
// band below it, and the side (landscape) or bottom (portrait) panel with the legend and
// the title block (portrait: as tall as `legendRows` need, up to 45 % of the sheet).
struct SheetLayout {
    PageRect neat;  // the sheet's border
    PageRect titleBand, mapArea, scaleBand, panel;
};

SheetLayout layoutFor(const Paper& paper, std::size_t legendRows) {
    SheetLayout l;
    const double margin = 10.0;
    l.neat = {margin, margin, paper.widthMm - 2 * margin, paper.heightMm - 2 * margin};
    PageRect main = l.neat;
    if (paper.orientation == Orientation::Landscape) {
        const double w = std::clamp(0.23 * l.neat.width, 68.0, 95.0);
        l.panel = {l.neat.right() - w, l.neat.y, w, l.neat.height};
        main.width -= w;
    } else {
        // Tall enough for the legend's rows (print/legend.cpp: 8 mm heading, 7.6 mm a row) and
        // a title block, up to 45 % of the sheet.
        const double legend = 8.0 + 7.6 * double(legendRows) + 8.0;
        const double h = std::min(std::max({0.30 * l.neat.height, legend, 95.0}), 0.45 * l.neat.height);
        l.panel = {l.neat.x, l.neat.bottom() - h, l.neat.width, h};
        main.height -= h;
    }
    l.titleBand = {main.x, main.y, main.width, 17.0};
    l.scaleBand = {main.x, main.bottom() - 24.0, main.width, 24.0};
    // Room for tick labels and axis titles: left 24 mm, right 16, top 12 (end names), bottom 14.
    l.mapArea = {main.x + 24.0, l.titleBand.bottom() + 12.0, main.width - 40.0,
                 l.scaleBand.y - 14.0 - (l.titleBand.bottom() + 12.0)};
    return l;
}

PathItem rect(const PageRect& r, std::optional<Rgba8> stroke, double widthMm) {
    PathItem p;
    p.subpaths = {{{r.x, r.y}, {r.right(), r.y}, {r.right(), r.bottom()}, {r.x, r.bottom()}}};
    p.stroke = stroke;
    p.strokeMm = widthMm;
    return p;
}

// The section's polygons and traces as page paths clipped to the map box.
Lithology lithologyOfRecord(const SectionIndex& index, RecordId r) {
    return index.model ? recordLithology(index.model->attributes.find(r)) : Lithology::None;
}

void vectorGeometry(Sheet& sheet, const SectionIndex& index, const VectorSource& src, const MapFrame& f,
                    const std::vector<BlockPiece>* blockPieces, const SheetBlocks* blocks, bool patterns) {
    std::vector<const BodySection*> order;
    for (const BodySection& b : *src.bodies) order.push_back(&b);
    std::stable_sort(order.begin(), order.end(), [&](const BodySection* a, const BodySection* b) {
        return index.parts[a->part].depth < index.parts[b->part].depth;  // inner bodies over their hosts' holes
    });
    for (const BodySection* b : order) {
        PathItem p;
        for (const SectionPolygon& poly : b->polygons) {
            auto ring = [&](const Ring& r) {
                std::vector<PagePoint> sub;
                sub.reserve(r.size());
                for (const glm::dvec2& q : r) sub.push_back(f.toPage(q));
                p.subpaths.push_back(std::move(sub));
            };
            ring(poly.outer);
            for (const Ring& h : poly.holes) ring(h);
        }
        const SectionPart& part = index.parts[b->part];
        p.fill = part.colour;
        p.stroke = kContact;
        p.strokeMm = 0.12;
        p.clip = f.box;
        p.title = part.part ? part.part->name : "";
        if (patterns) p.pattern = lithologyOfRecord(index, b->record);
        sheet.add(std::move(p));
    }
    if (blockPieces && blocks) {
        const BlockProperty& prop = blocks->blocks->properties[std::size_t(blocks->classes.property)];
        for (const BlockPiece& piece : *blockPieces) {
            const double value = prop.values[piece.cell];
            if (blocks->classes.classOf(value) < 0) continue;  // no value: the body's fill shows
            PathItem p;
            for (const Ring& r : piece.rings) {
                std::vector<PagePoint> sub;
                sub.reserve(r.size());
                for (const glm::dvec2& q : r) sub.push_back(f.toPage(q));
                p.subpaths.push_back(std::move(sub));
            }
            const Rgba8 c = blocks->classes.colourOf(value);
            p.fill = c;
            p.stroke = c;  // hides the hairline seams anti-aliasing leaves between neighbours
            p.strokeMm = 0.05;
            p.clip = f.box;
            p.title = prop.name + " " + blocks->classes.label(std::size_t(blocks->classes.classOf(value)));
            sheet.add(std::move(p));
        }
        // The clipping bodies' contacts again, over their cells.
        for (const BodySection* b : order) {
            if (!blocks->blocks->clips(b->part)) continue;
            PathItem p;
            for (const SectionPolygon& poly : b->polygons) {
                auto ring = [&](const Ring& r) {
                    std::vector<PagePoint> sub;
                    for (const glm::dvec2& q : r) sub.push_back(f.toPage(q));
                    p.subpaths.push_back(std::move(sub));
                };
                ring(poly.outer);
                for (const Ring& h : poly.holes) ring(h);
            }
            p.stroke = kContact;
            p.strokeMm = 0.12;
            p.clip = f.box;
            sheet.add(std::move(p));
        }
    }
    for (const SectionTrace& t : *src.traces) {
        PathItem p;
        std::vector<PagePoint> sub;
        for (const glm::dvec2& q : t.points) sub.push_back(f.toPage(q));
        p.subpaths.push_back(std::move(sub));
        p.closed = t.closed;
        const Rgba8 c = index.parts[t.part].colour;
        p.stroke = Rgba8{c.r, c.g, c.b, 255};
        p.strokeMm = 0.45;
        p.clip = f.box;
        p.title = index.parts[t.part].part ? index.parts[t.part].part->name : "";
        sheet.add(std::move(p));
    }
}

// The engine's raster of the map box: pixels aligned with the sheet's pixels at `dpi`, so
// the composite is not resampled.
Status rasterGeometry(Sheet& sheet, const Shape& shape, const MapFrame& f, const SheetOptions& o) {
    const double ppmm = o.dpi / 25.4;
    const double x0 = std::floor(f.box.x * ppmm) / ppmm, y0 = std::floor(f.box.y * ppmm) / ppmm;
    const double x1 = std::ceil(f.box.right() * ppmm) / ppmm, y1 = std::ceil(f.box.bottom() * ppmm) / ppmm;
    ImageItem im;
    im.box = {x0, y0, x1 - x0, y1 - y0};
    im.width = std::max(1, int(std::lround((x1 - x0) * ppmm)));
    im.height = std::max(1, int(std::lround((y1 - y0) * ppmm)));
    FrameRect r;  // the section rectangle under the pixel-aligned box
    r.u0 = f.shown.u0 + (x0 - f.box.x) / f.mmPerMetreX();
    r.u1 = f.shown.u0 + (x1 - f.box.x) / f.mmPerMetreX();
    r.v1 = f.shown.v1 - (y0 - f.box.y) / f.mmPerMetreY();
    r.v0 = f.shown.v1 - (y1 - f.box.y) / f.mmPerMetreY();
    RasterOptions ro;
    ro.background = Rgba8{0, 0, 0, 0};
    ro.ids = o.blocks.has_value();
    ro.cancel = o.cancel;
    auto image = shape.raster(r, im.width, im.height, ro);
    if (!image) return image.error();
    im.rgba = std::move(image.value().rgba);
    if (o.blocks) {
        const double pu = (r.u1 - r.u0) / im.width, pv = (r.v1 - r.v0) / im.height;
        colourPixelsByBlocks(
            *o.blocks->blocks, o.blocks->classes, o.blocks->clipRecords,
            [&](int i, int j) { return shape.toWorld(r.u0 + (i + 0.5) * pu, r.v1 - (j + 0.5) * pv); }, im.width,
            im.height, image.value().ids.data(), im.rgba.data(), nullptr);
    }
    sheet.add(std::move(im));
    return {};
}

// The patterns of a raster sheet: pattern-only paths of the bodies' polygons over the image.
void rasterPatterns(Sheet& sheet, const SectionIndex& index, const VectorSource& src, const MapFrame& f) {
    for (const BodySection& b : *src.bodies) {
        const Lithology l = lithologyOfRecord(index, b.record);
        if (l == Lithology::None) continue;
        PathItem p;
        for (const SectionPolygon& poly : b.polygons) {
            auto ring = [&](const Ring& r) {
                std::vector<PagePoint> sub;
                for (const glm::dvec2& q : r) sub.push_back(f.toPage(q));
                p.subpaths.push_back(std::move(sub));
            };
            ring(poly.outer);
            for (const Ring& h : poly.holes) ring(h);
        }
        p.pattern = l;
        p.clip = f.box;
        sheet.add(std::move(p));
    }
}

// Unit codes inside the polygons (section/fill/labels.hpp), each on a box of its unit's
// colour that hides the pattern under the text.
void unitLabels(Sheet& sheet, const SectionIndex& index, const VectorSource& src, const MapFrame& f, double sizePt) {
    LabelStyle style;
    style.size = sizePt * kMmPerPoint;
    style.textWidth = [](const std::string& text, double sizeMm) { return textWidthMm(text, sizeMm / kMmPerPoint); };
    const LabelBox view{f.box.x, f.box.y, f.box.right(), f.box.bottom()};
    auto toPage = [&](const glm::dvec2& q) {
        const PagePoint p = f.toPage(q);
        return glm::dvec2(p.x, p.y);
    };
    for (const PlacedLabel& l : sectionLabels(index, *src.bodies, toPage, view, style, src.traces)) {
        const Lithology lith = lithologyOfRecord(index, l.record);
        const Rgba8 c = index.parts[l.part].colour;
        PathItem box;
        box.subpaths = {{{l.box.x0, l.box.y0}, {l.box.x1, l.box.y0}, {l.box.x1, l.box.y1}, {l.box.x0, l.box.y1}}};
        box.fill = lith == Lithology::Coal ? patternTile(Lithology::Coal).ink : Rgba8{c.r, c.g, c.b, 255};
        sheet.add(std::move(box));
        TextItem t{{l.at.x, labelBaseline(l.at.y, style.size)}, l.text, sizePt};
        t.anchor = TextAnchor::Middle;
        t.colour = labelInk(c, lith);
        sheet.add(std::move(t));
    }
}

void drawEnds(Sheet& sheet, const Shape& shape, const MapFrame& f) {
    for (const Shape::End& e : shape.ends) {
        const double x = f.toPage({e.u, f.shown.v1}).x;
        if (x < f.box.x - 1e-6 || x > f.box.right() + 1e-6) continue;
        if (e.bend) {
            PathItem line;
            line.subpaths = {{{x, f.box.y - 2.0}, {x, f.box.bottom()}}};
            line.closed = false;
            line.stroke = Rgba8{20, 20, 20, 255};
            line.strokeMm = 0.3;
            line.dashMm = 1.5;
            sheet.add(std::move(line));
        }
        TextItem t{{x, f.box.y - 3.2}, e.label, e.bend ? 11.0 : 13.0, true};
        t.anchor = TextAnchor::Middle;
        sheet.add(std::move(t));
    }
}

Result<Sheet> layoutSheet(const SectionIndex& index, Shape shape, const SheetOptions& o, const SheetInfo& info) {
    std::vector<LegendEntry> legend = sectionLegend(index, shape.source);
    if (!o.patterns)
        for (LegendEntry& e : legend) e.pattern = Lithology::None;
    std::optional<LegendRamp> ramp;
    if (o.blocks) ramp = legendRamp(*o.blocks->blocks, o.blocks->classes);
    const SheetLayout l = layoutFor(o.paper, legendRows(legend, ramp ? &*ramp : nullptr));
    if (o.frame) shape.extent = *o.frame;
    FitRequest fit;
    fit.extent = shape.extent;
    fit.area = l.mapArea;
    fit.scale = o.scale;
    // The stretch of the sheet's v axis is the one every picture of this plane uses
    // (view/exaggeration.hpp): the factor on vertical planes and polylines, 1 on horizontal
    // slices, vStretch(n) on inclined planes, whose v axis is only partly vertical.
    fit.exaggeration = shape.kind == Shape::Horizontal ? 1.0
                       : shape.kind == Shape::Inclined
                           ? VerticalExaggeration{o.exaggeration, 0.0}.vStretch(shape.normal)
                           : o.exaggeration;
    fit.snapU = shape.kind == Shape::Horizontal && !o.frame;
    fit.snapV = !o.frame;
    fit.scaleName = o.scaleName;
    fit.areaName = o.paper.name + (o.paper.orientation == Orientation::Landscape ? " landscape" : " portrait");
    auto frame = fitMapFrame(fit);
    if (!frame) return frame.error();
    const MapFrame& f = frame.value();

    Sheet sheet;
    sheet.widthMm = o.paper.widthMm;
    sheet.heightMm = o.paper.heightMm;
    // A named section ("Line 12") leads its heading: "Line 12: Geological section A–B".
    const std::string heading = (info.title.empty() ? "" : info.title + ": ") + shape.title;
    sheet.title = heading + " \u2013 " + info.model;
    sheet.subject = info.definition;
    sheet.date = info.date;

    // Geometry first, the surrounds over it.
    if (o.rasterGeometry) {
        if (Status s = rasterGeometry(sheet, shape, f, o); !s) return s.error();
    } else {
        std::optional<std::vector<BlockPiece>> pieces;
        if (o.blocks) {
            auto p = shape.pieces();
            if (!p) return p.error();
            pieces = std::move(p.value());
        }
        vectorGeometry(sheet, index, shape.source, f, pieces ? &*pieces : nullptr, o.blocks ? &*o.blocks : nullptr,
                       o.patterns);
    }
    if (o.rasterGeometry && o.patterns) rasterPatterns(sheet, index, shape.source, f);
    if (o.overlay) o.overlay(f, sheet);
    drawAxes(sheet, f, shape.axes);
    drawEnds(sheet, shape, f);
    if (o.labels) unitLabels(sheet, index, shape.source, f, o.labelPt);  // over the grid lines

    sheet.add(rect(l.neat, kInk, 0.5));
    PathItem rules;
    rules.closed = false;
    rules.stroke = kInk;
    rules.strokeMm = 0.3;
    rules.subpaths.push_back({{l.titleBand.x, l.titleBand.bottom()}, {l.titleBand.right(), l.titleBand.bottom()}});
    if (o.paper.orientation == Orientation::Landscape)
        rules.subpaths.push_back({{l.panel.x, l.panel.y}, {l.panel.x, l.panel.bottom()}});
    else
        rules.subpaths.push_back({{l.panel.x, l.panel.y}, {l.panel.right(), l.panel.y}});
    sheet.add(std::move(rules));

    TextItem title{
        {l.titleBand.x + 5.0, l.titleBand.y + 7.0}, fitText(heading, l.titleBand.width - 10.0, 15.0, true), 15.0, true};
    title.baseline = TextBaseline::Middle;
    sheet.add(std::move(title));
    TextItem sub{{l.titleBand.x + 5.0, l.titleBand.y + 13.2},
                 fitText("Model " + info.model + "  \u00b7  " + info.crs, l.titleBand.width - 10.0, 8.0),
                 8.0};
    sub.baseline = TextBaseline::Middle;
    sub.colour = Rgba8{60, 60, 60, 255};
    sheet.add(std::move(sub));

    // The scale statement just under the axis title when the frame leaves room below it.
    const double scaleY = std::min(l.scaleBand.y, f.box.bottom() + 16.0);
    drawScaleBar(sheet, {f.box.x, scaleY, f.box.width, l.scaleBand.height}, f, shape.kind != Shape::Horizontal,
                 std::min(100.0, 0.5 * std::max(f.box.width, 0.5 * l.mapArea.width)));

    // The panel: (north arrow), legend from the top, title block at the bottom.
    std::vector<TitleRow> rows;
    rows.push_back({"Model", info.model + (info.version.empty() ? "" : "  (version " + info.version + ")")});
    rows.push_back({"CRS", info.crs});
    for (const TitleRow& r : shape.rows) rows.push_back(r);
    std::string scaleText = formatScale(f.scale);
    if (shape.kind == Shape::Inclined)
        scaleText += " along strike, " + formatScale(f.scale / f.exaggeration) + " down dip (VE \u00d7" +
                     formatGrouped(o.exaggeration, std::min(decimalsFor(o.exaggeration), 2)) + ": down-dip \u00d7" +
                     formatGrouped(f.exaggeration, std::min(decimalsFor(f.exaggeration), 3)) + ")";
    else if (shape.kind != Shape::Horizontal)
        scaleText += " horizontal, " + formatScale(f.scale / f.exaggeration) + " vertical (VE \u00d7" +
                     formatGrouped(f.exaggeration, std::min(decimalsFor(f.exaggeration), 2)) + ")";
    rows.push_back({"Scale", scaleText});
    rows.push_back({"Paper", o.paper.describe()});
    rows.push_back({"Geometry", o.rasterGeometry ? "exact section engine, raster at " + formatGrouped(o.dpi, 0) + " dpi"
                                                 : "exact section engine, vector polygons"});
    if (o.blocks) {
        const BlockProperty& p = o.blocks->blocks->properties[std::size_t(o.blocks->classes.property)];
        rows.push_back({"Colour", "block property " + p.name + (p.unit.empty() ? "" : " [" + p.unit + "]") + " of " +
                                      o.blocks->blocks->source + ", " + o.blocks->classes.ramp + " classes" +
                                      (o.rasterGeometry ? " (cell under each pixel centre)" : " (exact cell pieces)")});
    }
    rows.push_back({"Date", info.date});
    const double pad = 4.0;
    const PageRect inner{l.panel.x + pad, l.panel.y + pad, l.panel.width - 2 * pad, l.panel.height - 2 * pad};
    PageRect legendArea = inner, blockArea = inner;
    if (o.paper.orientation == Orientation::Portrait) {
        legendArea.width = 0.5 * inner.width - pad;
        blockArea.x = inner.x + 0.5 * inner.width;
        blockArea.width = 0.5 * inner.width;
    }
    const double blockHeight = drawTitleBlock(sheet, blockArea, "geoslice  \u00b7  section sheet", rows);
    if (shape.kind == Shape::Horizontal) {
        drawNorthArrow(sheet, {legendArea.right() - 12.0, legendArea.y + 12.0}, 16.0, shape.trueNorth);
    }
    if (o.paper.orientation == Orientation::Landscape) legendArea.height -= blockHeight + pad;
    drawLegend(sheet, legendArea, legend, ramp ? &*ramp : nullptr);
    return sheet;
}

}  // namespace

Result<Sheet> sectionSheet(const SectionIndex& index, const Section& section, const SheetOptions& o,
                           const SheetInfo& info) {
    Shape s;
    s.source = vectorSource(section);
    const SectionFrame& fr = section.frame;
    const glm::dvec3 n = section.plane.normal;
    const bool empty = section.empty();
    s.raster = [&index, &section](const FrameRect& r, int w, int h, const RasterOptions& ro) {
        return rasterizeSection(index, section, r, w, h, ro);
    };
    s.toWorld = [&section](double u, double v) { return section.frame.toWorld({u, v}); };
    s.pieces = [&section, &o] { return blockPieces(*o.blocks->blocks, section); };
    // Projected model bounds, the extent of an empty section.
    glm::dvec2 blo{INFINITY}, bhi{-INFINITY};
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 w{(c & 1) ? index.bounds.max.x : index.bounds.min.x,
                           (c & 2) ? index.bounds.max.y : index.bounds.min.y,
                           (c & 4) ? index.bounds.max.z : index.bounds.min.z};
        const glm::dvec2 uv = fr.toPlane(w - fr.modelOrigin);
        blo = glm::min(blo, uv);
        bhi = glm::max(bhi, uv);
    }
    const glm::dvec2 lo = empty ? blo : section.lo, hi = empty ? bhi : section.hi;
    if (std::abs(n.z) > 1.0 - 1e-12) {
        if (n.z > 0.0)
            return makeError(ErrorCode::Unsupported,
                             "a horizontal plane that keeps what lies above it is seen from below (a mirrored map): "
                             "print the slice with elevation=z (normal 0,0,-1)");
        s.kind = Shape::Horizontal;
        const double z = fr.originWorld().z;
        s.title = "Horizontal slice at elevation " + metres(z) + " m";
        const double m = 0.03 * std::max(hi.x - lo.x, hi.y - lo.y) + 1.0;
        s.extent = {lo.x - m, lo.y - m, hi.x + m, hi.y + m};
        s.axes.horizontal = {"Easting (m)", 0.0};
        s.axes.vertical = {"Northing (m)", 0.0};
        s.axes.grid = true;
        s.rows.push_back({"Section", info.definition});
        s.rows.push_back({"Elevation", metres(z) + " m, seen from above"});
        if (index.model) s.trueNorth = trueNorthDeg(index.model->crs, 0.5 * (lo + hi));
    } else {
        const bool vertical = std::abs(n.z) < 1e-9;
        s.kind = vertical ? Shape::Vertical : Shape::Inclined;
        s.normal = n;
        s.extent.u0 = lo.x;
        s.extent.u1 = hi.x;
        verticalExtent(s.extent, lo, hi, false, lo.y, hi.y);
        const double azRight = azimuthDeg({fr.u.x, fr.u.y});
        const std::string left = compassPoint(azRight + 180.0), right = compassPoint(azRight);
        const std::string leftLabel = left == right ? left + "'" : left;
        // Distances count from the frame's left edge (the left end), as pixel queries do.
        const double u0 = o.frame ? o.frame->u0 : s.extent.u0;
        const double u1 = o.frame ? o.frame->u1 : s.extent.u1;
        s.ends = {{u0, leftLabel, false}, {u1, right, false}};
        s.title = std::string(vertical ? "Geological section " : "Inclined section ") + leftLabel + "\u2013" + right;
        s.axes.horizontal = {"Distance from " + leftLabel + " (m)", u0};
        s.axes.vertical = {vertical ? "Elevation (m)" : "Distance up the plane (m)", 0.0};
        s.axes.grid = true;
        s.rows.push_back({"Section", info.definition});
        const double vMid = 0.5 * (s.extent.v0 + s.extent.v1);
        const glm::dvec3 a = fr.toWorld({u0, vMid}), b = fr.toWorld({u1, vMid});
        s.rows.push_back(
            {"Ends", leftLabel + " " + mapPoint({a.x, a.y}) + "  \u2192  " + right + " " + mapPoint({b.x, b.y})});
        const double dip = std::acos(std::min(1.0, std::abs(n.z))) * 180.0 / std::numbers::pi;
        s.rows.push_back(
            {"Azimuth", degrees(azRight) + " (" + leftLabel + " to " + right + ")" +
                            (vertical ? ", vertical plane"
                                      : ", plane dipping " + formatGrouped(90.0 - dip, 1) + "\u00b0 from horizontal")});
    }
    return layoutSheet(index, std::move(s), o, info);
}

Result<Sheet> sectionSheet(const SectionIndex& index, const PolylineSection& section, const SheetOptions& o,
                           const SheetInfo& info) {
    Shape s;
    s.kind = Shape::Polyline;
    s.source = vectorSource(section);
    s.raster = [&index, &section](const FrameRect& r, int w, int h, const RasterOptions& ro) -> Result<SectionImage> {
        auto img = rasterizePolylineSection(index, section, r, w, h, ro);
        if (!img) return img.error();
        SectionImage out;
        out.rgba = std::move(img.value().rgba);
        out.ids = std::move(img.value().ids);
        return out;
    };
    s.toWorld = [&section](double u, double v) { return section.line.worldAt(u, v); };
    s.pieces = [&index, &section, &o] { return blockPieces(*o.blocks->blocks, section, index.origin); };
    const SectionLine& line = section.line;
    s.extent.u0 = 0.0;
    s.extent.u1 = std::max(line.length(), 1e-3);
    verticalExtent(s.extent, section.lo, section.hi, section.empty(), index.bounds.min.z, index.bounds.max.z);
    std::string names;
    for (std::size_t i = 0; i < line.points.size(); ++i) {
        const std::string letter = vertexLetter(i);
        s.ends.push_back({line.chainage[i], letter, i > 0 && i + 1 < line.points.size()});
        names += (i ? "\u2013" : "") + letter;
    }
    s.title = "Geological section " + names;
    s.axes.horizontal = {"Distance along the section from A (m)", 0.0};
    s.axes.vertical = {"Elevation (m)", 0.0};
    s.axes.grid = true;
    s.rows.push_back({"Section", info.definition});
    std::string vertices;
    for (std::size_t i = 0; i < line.points.size(); ++i)
        vertices += (i ? "; " : "") + vertexLetter(i) + " " + mapPoint(line.points[i]);
    s.rows.push_back({"Vertices", vertices});
    s.rows.push_back({"Length", metres(line.length()) + " m along " + std::to_string(line.points.size() - 1) +
                                    (line.points.size() == 2 ? " leg" : " legs") + ", bends marked"});
    return layoutSheet(index, std::move(s), o, info);
}

}  // namespace geoslice::print
