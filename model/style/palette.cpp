#include "model/style/palette.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "model/model.hpp"

namespace geoslice {
namespace {

// scripts/make_palette.py 16 (min CIEDE2000: normal 9.3, protanopia 8.4, deuteranopia 8.3).
constexpr Rgba8 kFill[kFillPaletteSize] = {
    {0xee, 0x99, 0x33, 0xff}, {0x77, 0x77, 0xee, 0xff}, {0xaa, 0xee, 0xee, 0xff}, {0xaa, 0x77, 0x77, 0xff},
    {0x55, 0xff, 0xbb, 0xff}, {0x66, 0xaa, 0xbb, 0xff}, {0x88, 0xbb, 0xaa, 0xff}, {0xbb, 0x77, 0x44, 0xff},
    {0xee, 0xee, 0x66, 0xff}, {0x99, 0xcc, 0xff, 0xff}, {0x22, 0xcc, 0x88, 0xff}, {0xdd, 0x55, 0x99, 0xff},
    {0x55, 0xaa, 0xff, 0xff}, {0x77, 0x88, 0xbb, 0xff}, {0x66, 0xcc, 0xcc, 0xff}, {0x00, 0x99, 0x99, 0xff},
};

bool isAlnum(unsigned char c) {
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c >= 0x80;
}

std::uint8_t mix(std::uint8_t c, std::uint8_t towards, double t) {
    return static_cast<std::uint8_t>(c + (double(towards) - double(c)) * t + 0.5);
}

bool lineKind(std::string_view kind) {
    return kind == "fault" || kind == "surface" || kind == "horizon" || kind == "terrain" || kind == "boundary" ||
           kind == "unconformity";
}

}  // namespace

const Rgba8* fillPalette() { return kFill; }

std::string normaliseUnitName(std::string_view name) {
    std::string out;
    bool gap = false;
    for (const char ch : name) {
        const auto c = static_cast<unsigned char>(ch);
        if (!isAlnum(c)) {
            gap = !out.empty();
            continue;
        }
        if (gap) out += ' ';
        gap = false;
        out += static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    }
    return out;
}

std::uint32_t unitNameHash(std::string_view name) {
    std::uint32_t h = 2166136261u;
    for (const char c : normaliseUnitName(name)) {
        h ^= static_cast<unsigned char>(c);
        h *= 16777619u;
    }
    return h;
}

Rgba8 fillColourOf(std::size_t slot) {
    Rgba8 c = kFill[slot % kFillPaletteSize];
    const std::size_t round = slot / kFillPaletteSize;
    if (round == 0) return c;
    // Odd rounds darken, even rounds lighten; each pair of rounds a little further.
    const double t = std::min(0.6, 0.22 * double((round + 1) / 2));
    const std::uint8_t to = round % 2 == 1 ? 0 : 255;
    return Rgba8{mix(c.r, to, t), mix(c.g, to, t), mix(c.b, to, t), c.a};
}

bool isFaultRecord(const AttributeRecord& r) {
    if (r.kind == "fault") return true;
    const std::string n = normaliseUnitName(r.name);
    return n.find("fault") != std::string::npos || n.find("faille") != std::string::npos ||
           r.name.find("\xe6\x96\xad\xe5\xb1\x82") != std::string::npos;  // 断层
}

void applyDefaultColours(Model& model) {
    std::set<RecordId> fills, lines;
    for (const Part& p : model.bodies) fills.insert(p.record);
    for (const Part& p : model.surfaces) lines.insert(p.record);
    for (const Polyline& l : model.lines) lines.insert(l.record);
    // Units in order of normalised name (then id): one colour per normalised name.
    std::map<std::string, std::vector<AttributeRecord*>> units;
    for (const auto& [id, rec] : model.attributes.records()) {
        AttributeRecord* r = model.attributes.find(id);
        if (!r->colourSource.empty() && r->colourSource != "palette") continue;
        const bool fill = fills.count(id) > 0 || (lines.count(id) == 0 && !lineKind(r->kind));
        if (!fill) {
            r->colour = isFaultRecord(*r) ? kFaultLineColour : kSurfaceLineColour;
            r->colourSource = "palette";
            continue;
        }
        units[normaliseUnitName(r->name)].push_back(r);
    }
    // Entries already taken by colours the file or a sidecar chose are avoided too.
    std::vector<std::size_t> used(kFillPaletteSize, 0);
    for (const auto& [id, rec] : model.attributes.records()) {
        if (rec.colourSource.empty() || rec.colourSource == "palette") continue;
        for (std::size_t k = 0; k < kFillPaletteSize; ++k)
            if (kFill[k].r == rec.colour.r && kFill[k].g == rec.colour.g && kFill[k].b == rec.colour.b) ++used[k];
    }
    for (auto& [name, records] : units) {
        const std::size_t preferred = unitNameHash(name) % kFillPaletteSize;
        // The least used entry, nearest after the preferred one: all differ up to the size.
        std::size_t best = preferred;
        for (std::size_t step = 0; step < kFillPaletteSize; ++step) {
            const std::size_t k = (preferred + step) % kFillPaletteSize;
            if (used[k] < used[best]) best = k;
        }
        const std::size_t slot = best + kFillPaletteSize * used[best];
        ++used[best];
        for (AttributeRecord* r : records) {
            r->colour = fillColourOf(slot);
            r->colourSource = "palette";
        }
    }
}

}  // namespace geoslice
