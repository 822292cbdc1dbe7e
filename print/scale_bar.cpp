#include "print/scale_bar.hpp"

#include <cmath>

#include "print/map_scale.hpp"
#include "print/round_numbers.hpp"

namespace geoslice::print {

double scaleBarMetres(double scale, double maxBarMm) { return niceAtMost125(maxBarMm * scale / 1000.0); }

void drawScaleBar(Sheet& sheet, const PageRect& band, const MapFrame& frame, bool vertical, double maxBarMm) {
    const double metres = scaleBarMetres(frame.scale, maxBarMm);
    const double lengthMm = paperMm(metres, frame.scale);
    // 1 x 10^k and 5 x 10^k split in 5 segments, 2 x 10^k in 4: every boundary a round number.
    const double mantissa = metres / std::pow(10.0, std::floor(std::log10(metres) + 1e-9));
    const int segments = std::abs(mantissa - 2.0) < 1e-6 ? 4 : 5;
    const double cx = band.x + 0.5 * band.width;
    const double x0 = cx - 0.5 * lengthMm, y0 = band.y + 9.0, barH = 1.8;

    TextItem title{{cx, band.y + 2.0}, "Scale " + formatScale(frame.scale), 10.0, true};
    title.anchor = TextAnchor::Middle;
    title.baseline = TextBaseline::Hanging;
    sheet.add(std::move(title));
    for (int i = 0; i < segments; ++i) {
        const double a = x0 + lengthMm * i / segments, b = x0 + lengthMm * (i + 1) / segments;
        PathItem seg;
        seg.subpaths = {{{a, y0}, {b, y0}, {b, y0 + barH}, {a, y0 + barH}}};
        seg.fill = i % 2 == 0 ? Rgba8{0, 0, 0, 255} : Rgba8{255, 255, 255, 255};
        seg.stroke = Rgba8{0, 0, 0, 255};
        seg.strokeMm = 0.2;
        sheet.add(std::move(seg));
    }
    const double step = metres / segments;
    const int decimals = decimalsFor(step);
    for (int i = 0; i <= segments; ++i) {
        TextItem label{{x0 + lengthMm * i / segments, y0 + barH + 1.2},
                       formatGrouped(step * i, decimals) + (i == segments ? " m" : ""),
                       7.0};
        label.anchor = TextAnchor::Middle;
        label.baseline = TextBaseline::Hanging;
        sheet.add(std::move(label));
    }
    if (vertical) {
        const std::string k = formatGrouped(frame.exaggeration,
                                            decimalsFor(frame.exaggeration) > 2 ? 2 : decimalsFor(frame.exaggeration));
        std::string text = "Vertical scale " + formatScale(frame.scale / frame.exaggeration) + "  \u2013  ";
        text += frame.exaggeration == 1.0 ? "no vertical exaggeration" : "vertical exaggeration \u00d7" + k;
        TextItem vx{{cx, y0 + barH + 6.5}, text, 7.5};
        vx.anchor = TextAnchor::Middle;
        vx.baseline = TextBaseline::Hanging;
        sheet.add(std::move(vx));
    }
}

}  // namespace geoslice::print
