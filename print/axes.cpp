#include "print/axes.hpp"

#include <algorithm>

#include "print/text_metrics.hpp"

namespace geoslice::print {
namespace {

constexpr double kTickMm = 1.5;
constexpr double kLabelGapMm = 1.2;
constexpr Rgba8 kInk{0, 0, 0, 255};
constexpr Rgba8 kGrid{40, 40, 40, 110};

std::vector<PlacedTick> place(double lo, double hi, double step, double pageAtLo, double mmPerMetre, bool down) {
    std::vector<PlacedTick> out;
    for (const Tick& t : axisTicks(lo, hi, step))
        out.push_back({t, down ? pageAtLo - (t.value - lo) * mmPerMetre : pageAtLo + (t.value - lo) * mmPerMetre});
    return out;
}

}  // namespace

std::vector<PlacedTick> horizontalTicks(const MapFrame& f, const AxisSpec& axis) {
    const double lo = f.shown.u0 - axis.origin, hi = f.shown.u1 - axis.origin;
    double spacing = kMinTickSpacingMm;
    for (int attempt = 0; attempt < 8; ++attempt) {
        const double step = tickStep(1.0 / f.mmPerMetreX(), spacing);
        auto ticks = place(lo, hi, step, f.box.x, f.mmPerMetreX(), false);
        double widest = 0.0;
        for (const PlacedTick& t : ticks) widest = std::max(widest, textWidthMm(t.tick.label, kTickLabelPt));
        if (widest + 3.0 <= step * f.mmPerMetreX()) return ticks;
        spacing = widest + 3.0;
    }
    return place(lo, hi, tickStep(1.0 / f.mmPerMetreX(), f.box.width), f.box.x, f.mmPerMetreX(), false);
}

std::vector<PlacedTick> verticalTicks(const MapFrame& f, const AxisSpec& axis) {
    const double lo = f.shown.v0 - axis.origin, hi = f.shown.v1 - axis.origin;
    const double step = tickStep(1.0 / f.mmPerMetreY(), kMinTickSpacingMm);
    return place(lo, hi, step, f.box.bottom(), f.mmPerMetreY(), true);
}

void drawAxes(Sheet& sheet, const MapFrame& f, const AxesSpec& spec) {
    const auto hx = horizontalTicks(f, spec.horizontal);
    const auto vy = verticalTicks(f, spec.vertical);
    const PageRect& b = f.box;
    if (spec.grid) {
        PathItem grid;
        grid.closed = false;
        grid.stroke = kGrid;
        grid.strokeMm = 0.1;
        for (const PlacedTick& t : hx) grid.subpaths.push_back({{t.pageMm, b.y}, {t.pageMm, b.bottom()}});
        for (const PlacedTick& t : vy) grid.subpaths.push_back({{b.x, t.pageMm}, {b.right(), t.pageMm}});
        sheet.add(std::move(grid));
    }
    PathItem outline;
    outline.subpaths = {{{b.x, b.y}, {b.right(), b.y}, {b.right(), b.bottom()}, {b.x, b.bottom()}}};
    outline.stroke = kInk;
    outline.strokeMm = 0.35;
    sheet.add(std::move(outline));

    PathItem ticks;
    ticks.closed = false;
    ticks.stroke = kInk;
    ticks.strokeMm = 0.25;
    for (const PlacedTick& t : hx) {
        ticks.subpaths.push_back({{t.pageMm, b.bottom()}, {t.pageMm, b.bottom() + kTickMm}});
        ticks.subpaths.push_back({{t.pageMm, b.y}, {t.pageMm, b.y - kTickMm}});
    }
    for (const PlacedTick& t : vy) {
        ticks.subpaths.push_back({{b.x, t.pageMm}, {b.x - kTickMm, t.pageMm}});
        ticks.subpaths.push_back({{b.right(), t.pageMm}, {b.right() + kTickMm, t.pageMm}});
    }
    sheet.add(std::move(ticks));

    double widestV = 0.0;
    for (const PlacedTick& t : hx) {
        TextItem label{{t.pageMm, b.bottom() + kTickMm + kLabelGapMm}, t.tick.label, kTickLabelPt};
        label.anchor = TextAnchor::Middle;
        label.baseline = TextBaseline::Hanging;
        sheet.add(std::move(label));
    }
    for (const PlacedTick& t : vy) {
        widestV = std::max(widestV, textWidthMm(t.tick.label, kTickLabelPt));
        TextItem left{{b.x - kTickMm - kLabelGapMm, t.pageMm}, t.tick.label, kTickLabelPt};
        left.anchor = TextAnchor::End;
        left.baseline = TextBaseline::Middle;
        TextItem right = left;
        right.at.x = b.right() + kTickMm + kLabelGapMm;
        right.anchor = TextAnchor::Start;
        sheet.add(std::move(left));
        sheet.add(std::move(right));
    }
    TextItem xTitle{{b.x + 0.5 * b.width, b.bottom() + kTickMm + kLabelGapMm + 6.0}, spec.horizontal.title, 8.0};
    xTitle.anchor = TextAnchor::Middle;
    xTitle.baseline = TextBaseline::Hanging;
    sheet.add(std::move(xTitle));
    TextItem yTitle{{b.x - kTickMm - kLabelGapMm - widestV - 3.0, b.y + 0.5 * b.height}, spec.vertical.title, 8.0};
    yTitle.anchor = TextAnchor::Middle;
    yTitle.rotateDeg = 90.0;
    sheet.add(std::move(yTitle));
}

}  // namespace geoslice::print
