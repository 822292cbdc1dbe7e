#include "api/legend.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "print/pattern_cairo.hpp"
#include "section/fill/patterns.hpp"
#include "stb_easy_font.h"

namespace geoslice::api {
namespace {

struct Canvas {
    int width, height;
    std::vector<std::uint8_t>& rgba;
    void fill(int x0, int y0, int x1, int y1, Rgba8 c) {
        x0 = std::max(x0, 0);
        y0 = std::max(y0, 0);
        x1 = std::min(x1, width);
        y1 = std::min(y1, height);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                std::uint8_t* p = &rgba[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4];
                p[0] = c.r;
                p[1] = c.g;
                p[2] = c.b;
                p[3] = c.a;
            }
    }
};

// stb_easy_font only knows printable ASCII; anything else becomes '?'.
std::string ascii(const std::string& s) {
    std::string out;
    for (unsigned char c : s) {
        if (c >= 0x80 && (c & 0xc0) == 0x80) continue;  // UTF-8 continuation bytes
        out += (c >= 32 && c < 127) ? char(c) : '?';
    }
    return out;
}

struct Quad {
    float x, y, z;
    unsigned char colour[4];
};

void drawText(Canvas& canvas, int x, int y, const std::string& text, int scale, Rgba8 colour) {
    std::string t = ascii(text);
    std::vector<Quad> buffer(t.size() * 64 + 64);  // ~ at most 36 quads per glyph x 4 vertices
    const int quads =
        stb_easy_font_print(0.0f, 0.0f, t.data(), nullptr, buffer.data(), int(buffer.size() * sizeof(Quad)));
    for (int q = 0; q < quads; ++q) {
        const Quad* v = &buffer[std::size_t(q) * 4];
        const float qx0 = std::min(v[0].x, v[2].x), qx1 = std::max(v[0].x, v[2].x);
        const float qy0 = std::min(v[0].y, v[2].y), qy1 = std::max(v[0].y, v[2].y);
        canvas.fill(x + int(std::lround(qx0 * float(scale))), y + int(std::lround(qy0 * float(scale))),
                    x + int(std::lround(qx1 * float(scale))), y + int(std::lround(qy1 * float(scale))), colour);
    }
}

}  // namespace

nlohmann::ordered_json blockLegendJson(const BlockModel& blocks, const PropertyClasses& classes) {
    const BlockProperty& p = blocks.properties[std::size_t(classes.property)];
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < classes.colours.size(); ++k)
        rows.push_back(
            {{"class", k},
             {"from", k == 0 ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(classes.breaks[k - 1])},
             {"to",
              k == classes.breaks.size() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(classes.breaks[k])},
             {"colour", formatColour(classes.colours[k])},
             {"label", classes.label(k)}});
    return {{"property", p.name},
            {"unit", p.unit},
            {"ramp", classes.ramp},
            {"breaks", classes.breaks},
            {"classes", std::move(rows)}};
}

LegendImage renderLegend(const CatalogModel& model, int scale, const PropertyClasses* classes) {
    struct Row {
        Rgba8 colour;
        std::string label;
        bool line;
        RecordId record = kNoRecord;  // bodies: the swatch shows the record's lithology pattern
    };
    std::vector<Row> rows;
    std::vector<RecordId> seen;  // fault blocks of one stratum share a record: one row each
    auto add = [&](const Part& p, bool line) {
        if (p.record != kNoRecord) {
            if (std::find(seen.begin(), seen.end(), p.record) != seen.end()) return;
            seen.push_back(p.record);
        }
        Row r{Rgba8{}, p.name, line, line ? kNoRecord : p.record};
        if (const AttributeRecord* rec = model.model.attributes.find(p.record)) {
            r.colour = rec->colour;
            if (!rec->name.empty()) r.label = rec->name;
            if (const std::string lith = lithologyText(*rec); !lith.empty()) r.label += " - " + lith;
        }
        rows.push_back(std::move(r));
    };
    for (const Part& p : model.model.bodies) add(p, false);
    for (const Part& p : model.model.surfaces) add(p, true);
    if (classes && model.model.blocks) {
        const BlockProperty& p = model.model.blocks->properties[std::size_t(classes->property)];
        rows.push_back({Rgba8{255, 255, 255, 0},
                        p.name + (p.unit.empty() ? "" : " (" + p.unit + ")") + ", " + classes->ramp + ":", false});
        for (std::size_t k = 0; k < classes->colours.size(); ++k)
            rows.push_back({classes->colours[k], "  " + classes->label(k), false});
    }

    const int pad = 4 * scale, rowH = 12 * scale, swatch = 10 * scale;
    int textW = 0;
    for (const Row& r : rows) {
        std::string t = ascii(r.label);
        textW = std::max(textW, stb_easy_font_width(t.data()) * scale);
    }
    LegendImage img;
    img.width = std::min(4096, pad * 3 + swatch + textW);
    img.height = std::min(4096, pad * 2 + rowH * std::max<int>(1, int(rows.size())));
    img.rgba.assign(std::size_t(img.width) * std::size_t(img.height) * 4, 255);
    Canvas canvas{img.width, img.height, img.rgba};
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const int y = pad + int(i) * rowH;
        Rgba8 c = rows[i].colour;
        c.a = 255;
        if (rows[i].line)
            canvas.fill(pad, y + swatch / 2 - scale, pad + swatch, y + swatch / 2 + scale, c);
        else {
            canvas.fill(pad, y, pad + swatch, y + swatch, Rgba8{60, 60, 60, 255});
            canvas.fill(pad + 1, y + 1, pad + swatch - 1, y + swatch - 1, c);
        }
        drawText(canvas, pad * 2 + swatch, y + scale, rows[i].label, scale, Rgba8{20, 20, 20, 255});
    }
    // Lithology patterns (section/fill/patterns.hpp) inside the bodies' swatches, tiles
    // scaled with the legend (1.9 px a millimetre per unit of scale).
    std::vector<std::uint32_t> ids(std::size_t(img.width) * std::size_t(img.height), kNoRecord);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        if (rows[i].line || rows[i].record == kNoRecord) continue;
        const int y = pad + int(i) * rowH;
        for (int j = std::max(0, y + 1); j < std::min(img.height, y + swatch - 1); ++j)
            for (int x = pad + 1; x < std::min(img.width, pad + swatch - 1); ++x)
                ids[std::size_t(j) * std::size_t(img.width) + std::size_t(x)] = rows[i].record;
    }
    print::drawPatternsOnImage(
        img.rgba.data(), ids.data(), img.width, img.height,
        [&](RecordId r) { return recordLithology(model.model.attributes.find(r)); }, 1.9 * scale);
    return img;
}

}  // namespace geoslice::api
