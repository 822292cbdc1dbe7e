#include "section/fill/patterns.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace geoslice {
namespace {

struct Keyword {
    std::string_view text;  // lower case (ASCII) or Chinese
    Lithology lithology;
    bool token = false;  // a code: matches only as a whole word (SST, LS)
};

// Names and codes. Codes follow common borehole-log abbreviations.
constexpr std::array kKeywords = {
    Keyword{"sandstone", Lithology::Sandstone},
    Keyword{"arenite", Lithology::Sandstone},
    Keyword{"greywacke", Lithology::Sandstone},
    Keyword{"graywacke", Lithology::Sandstone},
    Keyword{"sst", Lithology::Sandstone, true},
    Keyword{"ss", Lithology::Sandstone, true},
    Keyword{"砂岩", Lithology::Sandstone},
    Keyword{"siltstone", Lithology::Siltstone},
    Keyword{"slst", Lithology::Siltstone, true},
    Keyword{"sltst", Lithology::Siltstone, true},
    Keyword{"粉砂岩", Lithology::Siltstone},
    Keyword{"mudstone", Lithology::Mudstone},
    Keyword{"mdst", Lithology::Mudstone, true},
    Keyword{"ms", Lithology::Mudstone, true},
    Keyword{"泥岩", Lithology::Mudstone},
    Keyword{"shale", Lithology::Shale},
    Keyword{"sh", Lithology::Shale, true},
    Keyword{"页岩", Lithology::Shale},
    Keyword{"clay", Lithology::Clay},
    Keyword{"claystone", Lithology::Clay},
    Keyword{"黏土", Lithology::Clay},
    Keyword{"粘土", Lithology::Clay},
    Keyword{"黏土岩", Lithology::Clay},
    Keyword{"粘土岩", Lithology::Clay},
    Keyword{"limestone", Lithology::Limestone},
    Keyword{"lst", Lithology::Limestone, true},
    Keyword{"ls", Lithology::Limestone, true},
    Keyword{"灰岩", Lithology::Limestone},
    Keyword{"石灰岩", Lithology::Limestone},
    Keyword{"dolomite", Lithology::Dolomite},
    Keyword{"dolostone", Lithology::Dolomite},
    Keyword{"dol", Lithology::Dolomite, true},
    Keyword{"白云岩", Lithology::Dolomite},
    Keyword{"conglomerate", Lithology::Conglomerate},
    Keyword{"cgl", Lithology::Conglomerate, true},
    Keyword{"砾岩", Lithology::Conglomerate},
    Keyword{"breccia", Lithology::Breccia},
    Keyword{"bx", Lithology::Breccia, true},
    Keyword{"角砾岩", Lithology::Breccia},
    Keyword{"coal", Lithology::Coal},
    Keyword{"煤", Lithology::Coal},
    Keyword{"煤层", Lithology::Coal},
    Keyword{"granite", Lithology::Granite},
    Keyword{"granodiorite", Lithology::Granite},
    Keyword{"gr", Lithology::Granite, true},
    Keyword{"花岗岩", Lithology::Granite},
    Keyword{"花岗闪长岩", Lithology::Granite},
    Keyword{"diorite", Lithology::Diorite},
    Keyword{"gabbro", Lithology::Diorite},
    Keyword{"闪长岩", Lithology::Diorite},
    Keyword{"辉长岩", Lithology::Diorite},
    Keyword{"basalt", Lithology::Basalt},
    Keyword{"andesite", Lithology::Basalt},
    Keyword{"volcanic", Lithology::Basalt},
    Keyword{"volcanics", Lithology::Basalt},
    Keyword{"玄武岩", Lithology::Basalt},
    Keyword{"安山岩", Lithology::Basalt},
    Keyword{"火山岩", Lithology::Basalt},
    Keyword{"tuff", Lithology::Tuff},
    Keyword{"凝灰岩", Lithology::Tuff},
    Keyword{"schist", Lithology::Schist},
    Keyword{"phyllite", Lithology::Schist},
    Keyword{"片岩", Lithology::Schist},
    Keyword{"千枚岩", Lithology::Schist},
};

std::string lowerAscii(std::string_view s) {
    std::string o(s);
    for (char& c : o)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return o;
}

bool isWordChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; }

PatternTile makeTile(Lithology l) {
    PatternTile t;
    using P = glm::dvec2;
    switch (l) {
        case Lithology::None:
            break;
        case Lithology::Sandstone:  // dots on a staggered grid
            t.width = t.height = 3.0;
            t.dots = {{0.75, 0.75, 0.24}, {2.25, 2.25, 0.24}};
            break;
        case Lithology::Siltstone:  // dashes and dots, staggered rows
            t.width = 6.0;
            t.height = 3.0;
            t.polylines = {{P{0.4, 0.75}, P{2.6, 0.75}}, {P{3.4, 2.25}, P{5.6, 2.25}}};
            t.dots = {{3.9, 0.75, 0.2}, {5.1, 0.75, 0.2}, {0.9, 2.25, 0.2}, {2.1, 2.25, 0.2}};
            break;
        case Lithology::Mudstone:  // short dashes, staggered rows
            t.width = 6.0;
            t.height = 3.0;
            t.polylines = {{P{0.5, 0.75}, P{2.5, 0.75}}, {P{3.5, 2.25}, P{5.5, 2.25}}};
            break;
        case Lithology::Shale:  // long dashes in close rows, staggered
            t.width = 6.0;
            t.height = 2.0;
            t.polylines = {{P{0.3, 0.5}, P{4.7, 0.5}}, {P{3.3, 1.5}, P{6.0, 1.5}}, {P{0.0, 1.5}, P{1.7, 1.5}}};
            break;
        case Lithology::Clay:  // unbroken lines
            t.width = 6.0;
            t.height = 1.5;
            t.polylines = {{P{0.0, 0.75}, P{6.0, 0.75}}};
            break;
        case Lithology::Limestone:  // bricks: courses and staggered joints
            t.width = 6.0;
            t.height = 3.0;
            t.polylines = {{P{0.0, 0.75}, P{6.0, 0.75}},
                           {P{0.0, 2.25}, P{6.0, 2.25}},
                           {P{1.5, 0.75}, P{1.5, 2.25}},
                           {P{4.5, 2.25}, P{4.5, 3.0}},
                           {P{4.5, 0.0}, P{4.5, 0.75}}};
            break;
        case Lithology::Dolomite:  // bricks with slanted joints
            t.width = 6.0;
            t.height = 3.0;
            t.polylines = {{P{0.0, 0.75}, P{6.0, 0.75}},
                           {P{0.0, 2.25}, P{6.0, 2.25}},
                           {P{1.9, 0.75}, P{1.1, 2.25}},
                           {P{4.9, 2.25}, P{4.5, 3.0}},
                           {P{4.5, 0.0}, P{4.1, 0.75}}};
            break;
        case Lithology::Conglomerate:  // pebbles
            t.width = 8.0;
            t.height = 6.0;
            t.circles = {{2.0, 1.5, 0.9}, {6.0, 4.5, 0.9}, {6.2, 1.3, 0.45}, {1.8, 4.7, 0.45}};
            break;
        case Lithology::Breccia: {  // angular fragments
            t.width = 8.0;
            t.height = 6.0;
            for (const P c : {P{2.0, 1.6}, P{6.0, 4.6}})
                t.polylines.push_back({c + P{-0.9, 0.6}, c + P{0.9, 0.6}, c + P{0.0, -0.9}, c + P{-0.9, 0.6}});
            break;
        }
        case Lithology::Coal:
            t.width = t.height = 2.0;
            t.solid = true;
            t.ink = Rgba8{10, 10, 10, 255};
            break;
        case Lithology::Granite:  // "+"
        case Lithology::Diorite:  // "x"
            t.width = t.height = 5.0;
            for (const P c : {P{1.25, 1.25}, P{3.75, 3.75}}) {
                if (l == Lithology::Granite) {
                    t.polylines.push_back({c + P{-0.6, 0.0}, c + P{0.6, 0.0}});
                    t.polylines.push_back({c + P{0.0, -0.6}, c + P{0.0, 0.6}});
                } else {
                    t.polylines.push_back({c + P{-0.45, -0.45}, c + P{0.45, 0.45}});
                    t.polylines.push_back({c + P{-0.45, 0.45}, c + P{0.45, -0.45}});
                }
            }
            break;
        case Lithology::Basalt:  // "v"
        case Lithology::Tuff:    // "v" and dots
            t.width = 5.0;
            t.height = 4.0;
            for (const P c : {P{1.25, 1.0}, P{3.75, 3.0}})
                t.polylines.push_back({c + P{-0.55, -0.45}, c + P{0.0, 0.45}, c + P{0.55, -0.45}});
            if (l == Lithology::Tuff) t.dots = {{3.75, 1.0, 0.18}, {1.25, 3.0, 0.18}};
            break;
        case Lithology::Schist: {  // wavy lines, one period per tile
            t.width = 6.0;
            t.height = 2.0;
            std::vector<P> w;
            for (int k = 0; k <= 24; ++k) {
                const double x = 0.25 * k;
                w.push_back({x, 1.0 + 0.35 * std::sin(2.0 * 3.14159265358979323846 * x / 6.0)});
            }
            t.polylines.push_back(std::move(w));
            break;
        }
    }
    return t;
}

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", v);
    std::string s = buf;
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    return s;
}

std::string hex(Rgba8 c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    return buf;
}

}  // namespace

std::string_view lithologyName(Lithology l) {
    switch (l) {
        case Lithology::None:
            return "";
        case Lithology::Sandstone:
            return "sandstone";
        case Lithology::Siltstone:
            return "siltstone";
        case Lithology::Mudstone:
            return "mudstone";
        case Lithology::Shale:
            return "shale";
        case Lithology::Clay:
            return "clay";
        case Lithology::Limestone:
            return "limestone";
        case Lithology::Dolomite:
            return "dolomite";
        case Lithology::Conglomerate:
            return "conglomerate";
        case Lithology::Breccia:
            return "breccia";
        case Lithology::Coal:
            return "coal";
        case Lithology::Granite:
            return "granite";
        case Lithology::Diorite:
            return "diorite";
        case Lithology::Basalt:
            return "basalt";
        case Lithology::Tuff:
            return "tuff";
        case Lithology::Schist:
            return "schist";
    }
    return "";
}

const std::vector<Lithology>& allLithologies() {
    static const std::vector<Lithology> all = [] {
        std::vector<Lithology> v;
        for (int k = int(Lithology::Sandstone); k <= int(Lithology::Schist); ++k) v.push_back(Lithology(k));
        return v;
    }();
    return all;
}

Lithology matchLithology(std::string_view text) {
    const std::string s = lowerAscii(text);
    Lithology best = Lithology::None;
    std::size_t bestEnd = 0, bestLen = 0;
    for (const Keyword& k : kKeywords) {
        for (std::size_t at = s.find(k.text); at != std::string::npos; at = s.find(k.text, at + 1)) {
            const std::size_t end = at + k.text.size();
            if (k.token && ((at > 0 && isWordChar(s[at - 1])) || (end < s.size() && isWordChar(s[end])))) continue;
            if (end > bestEnd || (end == bestEnd && k.text.size() > bestLen)) {
                best = k.lithology;
                bestEnd = end;
                bestLen = k.text.size();
            }
        }
    }
    return best;
}

std::string lithologyText(const AttributeRecord& record) {
    if (!record.lithology.empty()) return record.lithology;
    for (const auto& [key, value] : record.extra.items()) {
        const std::string k = lowerAscii(key);
        if ((k == "lith" || k == "rock" || k == "rock_type" || k == "岩性") && value.is_string())
            return value.get<std::string>();
    }
    return "";
}

Lithology recordLithology(const AttributeRecord* record) {
    return record ? matchLithology(lithologyText(*record)) : Lithology::None;
}

const PatternTile& patternTile(Lithology l) {
    static const std::vector<PatternTile> tiles = [] {
        std::vector<PatternTile> v;
        for (int k = 0; k <= int(Lithology::Schist); ++k) v.push_back(makeTile(Lithology(k)));
        return v;
    }();
    return tiles[std::size_t(l)];
}

std::string svgPattern(Lithology l, double s) {
    const PatternTile& t = patternTile(l);
    if (l == Lithology::None) return "";
    std::string o = "<pattern id=\"lith-" + std::string(lithologyName(l)) +
                    "\" patternUnits=\"userSpaceOnUse\" width=\"" + num(t.width * s) + "\" height=\"" +
                    num(t.height * s) + "\">";
    const std::string ink = hex(t.ink);
    if (t.solid)
        o += "<rect width=\"" + num(t.width * s) + "\" height=\"" + num(t.height * s) + "\" fill=\"" + ink + "\"/>";
    const std::string stroke = "fill=\"none\" stroke=\"" + ink + "\" stroke-width=\"" + num(t.strokeMm * s) + "\"";
    for (const auto& line : t.polylines) {
        o += "<polyline " + stroke + " points=\"";
        for (std::size_t i = 0; i < line.size(); ++i)
            o += (i ? " " : "") + num(line[i].x * s) + "," + num(line[i].y * s);
        o += "\"/>";
    }
    for (const glm::dvec3& c : t.circles)
        o += "<circle " + stroke + " cx=\"" + num(c.x * s) + "\" cy=\"" + num(c.y * s) + "\" r=\"" + num(c.z * s) +
             "\"/>";
    for (const glm::dvec3& c : t.dots)
        o += "<circle fill=\"" + ink + "\" cx=\"" + num(c.x * s) + "\" cy=\"" + num(c.y * s) + "\" r=\"" +
             num(c.z * s) + "\"/>";
    o += "</pattern>";
    return o;
}

Rgba8 labelInk(Rgba8 fill, Lithology l) {
    if (l == Lithology::Coal) return Rgba8{255, 255, 255, 255};
    const double y = 0.2126 * fill.r + 0.7152 * fill.g + 0.0722 * fill.b;  // Rec. 709 luma, 0..255
    return y < 110.0 ? Rgba8{255, 255, 255, 255} : Rgba8{0, 0, 0, 255};
}

}  // namespace geoslice
