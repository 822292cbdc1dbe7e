#include "print/legend.hpp"

#include <algorithm>
#include <set>

#include "print/text_metrics.hpp"

namespace geoslice::print {
namespace {

LegendEntry entryOf(const SectionIndex& index, std::uint32_t part, bool line) {
    const SectionPart& p = index.parts[part];
    LegendEntry e;
    e.record = p.record;
    e.colour = p.colour;
    e.line = line;
    e.name = p.part ? p.part->name : "";
    if (index.model) {
        if (const AttributeRecord* r = index.model->attributes.find(p.record)) {
            if (!r->name.empty()) e.name = r->name;
            e.lithology = lithologyText(*r);
            if (!line) e.pattern = recordLithology(r);
            e.age = r->age;
        }
    }
    if (e.name.empty()) e.name = "record " + std::to_string(p.record);
    return e;
}

}  // namespace

std::vector<LegendEntry> sectionLegend(const SectionIndex& index, const VectorSource& source) {
    std::vector<LegendEntry> out;
    std::set<std::pair<RecordId, bool>> seen;
    std::set<std::uint32_t> bodyParts, surfaceParts;
    if (source.bodies)
        for (const BodySection& b : *source.bodies) bodyParts.insert(b.part);
    if (source.traces)
        for (const SectionTrace& t : *source.traces) surfaceParts.insert(t.part);
    for (std::uint32_t part : bodyParts)
        if (seen.insert({index.parts[part].record, false}).second) out.push_back(entryOf(index, part, false));
    for (std::uint32_t part : surfaceParts)
        if (seen.insert({index.parts[part].record, true}).second) out.push_back(entryOf(index, part, true));
    return out;
}

LegendRamp legendRamp(const BlockModel& blocks, const PropertyClasses& classes) {
    LegendRamp r;
    const BlockProperty& p = blocks.properties[std::size_t(classes.property)];
    r.title = p.name + (p.unit.empty() ? "" : " (" + p.unit + ")") + ", " + classes.ramp + " classes";
    for (std::size_t k = 0; k < classes.colours.size(); ++k)
        r.classes.emplace_back(classes.colours[k], classes.label(k));
    return r;
}

std::size_t legendRows(const std::vector<LegendEntry>& entries, const LegendRamp* ramp) {
    return entries.size() + (ramp ? 1 + ramp->classes.size() : 0);
}

double drawLegend(Sheet& sheet, const PageRect& area, const std::vector<LegendEntry>& entries, const LegendRamp* ramp) {
    constexpr double kHeadingMm = 8.0, kRowMm = 7.6, kSwatchW = 10.0, kSwatchH = 5.6, kGap = 2.5;
    constexpr double kNamePt = 7.2, kDetailPt = 6.0, kRampRowMm = 5.6;
    TextItem head{{area.x, area.y + 5.0}, "Legend", 10.0, true};
    sheet.add(std::move(head));
    const double rampMm = ramp ? kRowMm + kRampRowMm * double(ramp->classes.size()) : 0.0;
    const double unitsMm = std::max(0.0, area.height - rampMm);
    const std::size_t fit = unitsMm <= kHeadingMm ? 0 : std::size_t((unitsMm - kHeadingMm) / kRowMm);
    const std::size_t shown = entries.size() <= fit ? entries.size() : (fit == 0 ? 0 : fit - 1);
    const double textX = area.x + kSwatchW + kGap, textW = area.right() - textX;
    for (std::size_t i = 0; i < shown; ++i) {
        const LegendEntry& e = entries[i];
        const double y = area.y + kHeadingMm + kRowMm * double(i);
        PathItem swatch;
        if (e.line) {
            swatch.subpaths = {{{area.x, y + 0.5 * kSwatchH}, {area.x + kSwatchW, y + 0.5 * kSwatchH}}};
            swatch.closed = false;
            swatch.stroke = Rgba8{e.colour.r, e.colour.g, e.colour.b, 255};
            swatch.strokeMm = 0.6;
        } else {
            swatch.subpaths = {
                {{area.x, y}, {area.x + kSwatchW, y}, {area.x + kSwatchW, y + kSwatchH}, {area.x, y + kSwatchH}}};
            swatch.fill = e.colour;
            swatch.pattern = e.pattern;
            swatch.stroke = Rgba8{40, 40, 40, 255};
            swatch.strokeMm = 0.15;
        }
        swatch.title = e.name;
        sheet.add(std::move(swatch));
        TextItem name{{textX, y}, fitText(e.name, textW, kNamePt, true), kNamePt, true};
        name.baseline = TextBaseline::Hanging;
        sheet.add(std::move(name));
        std::string detail = e.lithology;
        if (!e.age.empty()) detail += (detail.empty() ? "" : ", ") + e.age;
        if (e.line && detail.empty()) detail = "trace of a surface";
        if (!detail.empty()) {
            TextItem d{{textX, y + 3.4}, fitText(detail, textW, kDetailPt), kDetailPt};
            d.baseline = TextBaseline::Hanging;
            d.colour = Rgba8{70, 70, 70, 255};
            sheet.add(std::move(d));
        }
    }
    double used = kHeadingMm + kRowMm * double(shown);
    if (shown < entries.size()) {
        TextItem more{{area.x, area.y + used + 1.0},
                      "\u2026 and " + std::to_string(entries.size() - shown) + " more units (see the model's legend)",
                      kDetailPt};
        more.baseline = TextBaseline::Hanging;
        sheet.add(std::move(more));
        used += kRowMm;
    }
    if (!ramp) return used;
    TextItem title{{area.x, area.y + used + 2.0}, fitText(ramp->title, area.width, kNamePt, true), kNamePt, true};
    title.baseline = TextBaseline::Hanging;
    sheet.add(std::move(title));
    used += kRowMm;
    for (const auto& [colour, label] : ramp->classes) {
        PathItem swatch;
        const double y = area.y + used;
        swatch.subpaths = {{{area.x, y},
                            {area.x + kSwatchW, y},
                            {area.x + kSwatchW, y + kRampRowMm - 1.0},
                            {area.x, y + kRampRowMm - 1.0}}};
        swatch.fill = colour;
        swatch.stroke = Rgba8{40, 40, 40, 255};
        swatch.strokeMm = 0.15;
        swatch.title = label;
        sheet.add(std::move(swatch));
        TextItem t{{textX, y + 0.5 * (kRampRowMm - 1.0)}, fitText(label, area.right() - textX, kNamePt), kNamePt};
        t.baseline = TextBaseline::Middle;
        sheet.add(std::move(t));
        used += kRampRowMm;
    }
    return used;
}

}  // namespace geoslice::print
