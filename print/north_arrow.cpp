#include "print/north_arrow.hpp"

#include <cmath>
#include <cstdio>

namespace geoslice::print {

void drawNorthArrow(Sheet& sheet, PagePoint c, double h, std::optional<double> trueNorthDeg) {
    const double half = 0.5 * h, w = 0.28 * h;
    const PagePoint tip{c.x, c.y - half}, left{c.x - w, c.y + half}, right{c.x + w, c.y + half};
    PathItem dark;  // the classic half-filled arrowhead: left half black, right half white
    dark.subpaths = {{tip, left, {c.x, c.y + 0.25 * h}}};
    dark.fill = Rgba8{0, 0, 0, 255};
    dark.stroke = Rgba8{0, 0, 0, 255};
    dark.strokeMm = 0.25;
    PathItem light;
    light.subpaths = {{tip, {c.x, c.y + 0.25 * h}, right}};
    light.fill = Rgba8{255, 255, 255, 255};
    light.stroke = Rgba8{0, 0, 0, 255};
    light.strokeMm = 0.25;
    sheet.add(std::move(dark));
    sheet.add(std::move(light));
    TextItem n{{c.x, tip.y - 1.5}, "N", 12.0, true};
    n.anchor = TextAnchor::Middle;
    sheet.add(std::move(n));
    TextItem grid{{c.x, c.y + half + 1.5}, "grid north", 6.5};
    grid.anchor = TextAnchor::Middle;
    grid.baseline = TextBaseline::Hanging;
    sheet.add(std::move(grid));
    if (trueNorthDeg) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "true north %.2f\u00b0 %s", std::abs(*trueNorthDeg),
                      *trueNorthDeg < 0.0 ? "W" : "E");
        TextItem tn{{c.x, c.y + half + 4.6}, buf, 6.0};
        tn.anchor = TextAnchor::Middle;
        tn.baseline = TextBaseline::Hanging;
        tn.colour = Rgba8{70, 70, 70, 255};
        sheet.add(std::move(tn));
    }
}

}  // namespace geoslice::print
