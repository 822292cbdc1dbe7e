#include "print/svg_output.hpp"

#include <pugixml.hpp>

#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

namespace geoslice::print {
namespace {

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", v);
    std::string s = buf;  // trim trailing zeros: "12.500" -> "12.5", "3.000" -> "3"
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    return s == "-0" ? "0" : s;
}

std::string hex(Rgba8 c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    return buf;
}

}  // namespace

Result<std::string> renderSvg(const Sheet& sheet) {
    pugi::xml_document doc;
    auto decl = doc.append_child(pugi::node_declaration);
    decl.append_attribute("version") = "1.0";
    decl.append_attribute("encoding") = "UTF-8";
    pugi::xml_node svg = doc.append_child("svg");
    svg.append_attribute("xmlns") = "http://www.w3.org/2000/svg";
    svg.append_attribute("version") = "1.1";
    svg.append_attribute("width") = (num(sheet.widthMm) + "mm").c_str();
    svg.append_attribute("height") = (num(sheet.heightMm) + "mm").c_str();
    svg.append_attribute("viewBox") = ("0 0 " + num(sheet.widthMm) + " " + num(sheet.heightMm)).c_str();
    svg.append_child("title").text() = sheet.title.c_str();
    if (!sheet.subject.empty()) svg.append_child("desc").text() = sheet.subject.c_str();
    pugi::xml_node defs = svg.append_child("defs");
    pugi::xml_node page = svg.append_child("rect");
    page.append_attribute("width") = num(sheet.widthMm).c_str();
    page.append_attribute("height") = num(sheet.heightMm).c_str();
    page.append_attribute("fill") = "#ffffff";

    std::map<std::tuple<double, double, double, double>, std::string> clips;
    std::set<std::string> patterns;
    auto clipId = [&](const PageRect& r) {
        const auto key = std::make_tuple(r.x, r.y, r.width, r.height);
        auto it = clips.find(key);
        if (it != clips.end()) return it->second;
        const std::string id = "clip" + std::to_string(clips.size());
        pugi::xml_node cp = defs.append_child("clipPath");
        cp.append_attribute("id") = id.c_str();
        pugi::xml_node rect = cp.append_child("rect");
        rect.append_attribute("x") = num(r.x).c_str();
        rect.append_attribute("y") = num(r.y).c_str();
        rect.append_attribute("width") = num(r.width).c_str();
        rect.append_attribute("height") = num(r.height).c_str();
        clips.emplace(key, id);
        return id;
    };

    for (const SheetItem& item : sheet.items) {
        if (std::holds_alternative<ImageItem>(item))
            return makeError(ErrorCode::Unsupported, "an SVG sheet holds vector items only (no raster)");
        if (const auto* p = std::get_if<PathItem>(&item)) {
            std::string d;
            for (const auto& sub : p->subpaths) {
                for (std::size_t i = 0; i < sub.size(); ++i)
                    d += (i == 0 ? "M" : "L") + num(sub[i].x) + " " + num(sub[i].y) + " ";
                if (!sub.empty() && p->closed) d += "Z ";
            }
            if (d.empty()) continue;
            d.pop_back();
            pugi::xml_node path = svg.append_child("path");
            path.append_attribute("d") = d.c_str();
            if (p->fill) {
                path.append_attribute("fill") = hex(*p->fill).c_str();
                if (p->fill->a != 255) path.append_attribute("fill-opacity") = num(p->fill->a / 255.0).c_str();
                path.append_attribute("fill-rule") = "evenodd";
            } else {
                path.append_attribute("fill") = "none";
            }
            if (p->stroke) {
                path.append_attribute("stroke") = hex(*p->stroke).c_str();
                if (p->stroke->a != 255) path.append_attribute("stroke-opacity") = num(p->stroke->a / 255.0).c_str();
                path.append_attribute("stroke-width") = num(p->strokeMm).c_str();
                path.append_attribute("stroke-linejoin") = "round";
                if (p->dashMm > 0.0) path.append_attribute("stroke-dasharray") = num(p->dashMm).c_str();
            }
            if (p->clip) path.append_attribute("clip-path") = ("url(#" + clipId(*p->clip) + ")").c_str();
            if (!p->title.empty()) path.append_child("title").text() = p->title.c_str();
            if (p->pattern != Lithology::None) {  // the pattern over the fill
                const std::string name(lithologyName(p->pattern));
                if (patterns.insert(name).second) {
                    pugi::xml_document tile;
                    tile.load_string(svgPattern(p->pattern, 1.0).c_str());
                    defs.append_copy(tile.first_child());
                }
                pugi::xml_node over = svg.append_child("path");
                over.append_attribute("d") = d.c_str();
                over.append_attribute("class") = "lith";
                over.append_attribute("data-lithology") = name.c_str();
                over.append_attribute("fill") = ("url(#lith-" + name + ")").c_str();
                over.append_attribute("fill-rule") = "evenodd";
                if (p->clip) over.append_attribute("clip-path") = ("url(#" + clipId(*p->clip) + ")").c_str();
            }
        }
        if (const auto* t = std::get_if<TextItem>(&item)) {
            if (t->text.empty()) continue;
            pugi::xml_node text = svg.append_child("text");
            // The anchor's baseline is placed here (not with dominant-baseline, which
            // renderers treat differently), the same shift cairo_output applies.
            text.append_attribute("x") = num(t->at.x).c_str();
            text.append_attribute("y") = num(t->at.y + baselineShiftMm(*t)).c_str();
            text.append_attribute("font-family") = (std::string(fontFamilyFor(t->text)) + ", sans-serif").c_str();
            text.append_attribute("font-size") = num(t->sizePt * kMmPerPoint).c_str();
            if (t->bold) text.append_attribute("font-weight") = "bold";
            if (t->anchor != TextAnchor::Start)
                text.append_attribute("text-anchor") = t->anchor == TextAnchor::Middle ? "middle" : "end";
            text.append_attribute("fill") = hex(t->colour).c_str();
            if (t->rotateDeg != 0.0)
                text.append_attribute("transform") =
                    ("rotate(" + num(-t->rotateDeg) + " " + num(t->at.x) + " " + num(t->at.y) + ")").c_str();
            text.text() = t->text.c_str();
        }
    }
    std::ostringstream out;
    doc.save(out, "  ", pugi::format_default, pugi::encoding_utf8);
    return out.str();
}

}  // namespace geoslice::print
