#include "section/fill/vector_export.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>

#include "section/fill/labels.hpp"
#include "section/fill/patterns.hpp"

namespace geoslice {
namespace {

using json = nlohmann::ordered_json;

json position(const VectorSource& src, VectorFrame frame, const glm::dvec2& p) {
    if (frame == VectorFrame::Plane) return json::array({p.x, p.y});
    const glm::dvec3 w = src.toWorld(p);
    return json::array({w.x, w.y, w.z});
}

json ringJson(const VectorSource& src, VectorFrame frame, const Ring& ring) {
    json r = json::array();
    for (const auto& p : ring) r.push_back(position(src, frame, p));
    if (!ring.empty()) r.push_back(position(src, frame, ring.front()));  // RFC 7946: closed
    return r;
}

json attributesOf(const Model& m, RecordId id) {
    const AttributeRecord* r = m.attributes.find(id);
    return r ? r->toJson() : json(nullptr);
}

std::string xmlEscape(const std::string& s) {
    std::string o;
    for (char c : s) {
        switch (c) {
            case '&':
                o += "&amp;";
                break;
            case '<':
                o += "&lt;";
                break;
            case '>':
                o += "&gt;";
                break;
            case '"':
                o += "&quot;";
                break;
            case '\'':
                o += "&apos;";
                break;
            default:
                o += c;
        }
    }
    return o;
}

std::string hexColour(Rgba8 c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    return buf;
}

}  // namespace

VectorSource vectorSource(const Section& section) {
    VectorSource s;
    s.bodies = &section.bodies;
    s.traces = &section.traces;
    const SectionFrame frame = section.frame;
    s.toWorld = [frame](const glm::dvec2& uv) { return frame.toWorld(uv); };
    s.axes = "plane u/v metres from the section frame origin (u horizontal, v = u x n)";
    return s;
}

VectorSource vectorSource(const PolylineSection& section) {
    VectorSource s;
    s.bodies = &section.bodies;
    s.traces = &section.traces;
    const SectionLine line = section.line;
    s.toWorld = [line](const glm::dvec2& sz) { return line.worldAt(sz.x, sz.y); };
    s.axes = "u = distance along the section line from its first point (m), v = elevation (m)";
    return s;
}

json toGeoJson(const SectionIndex& index, const VectorSource& src, VectorFrame frame) {
    const Model& m = *index.model;
    json features = json::array();
    for (const BodySection& b : *src.bodies) {
        json polys = json::array();
        for (const SectionPolygon& p : b.polygons) {
            json rings = json::array({ringJson(src, frame, p.outer)});
            for (const Ring& h : p.holes) rings.push_back(ringJson(src, frame, h));
            polys.push_back(std::move(rings));
        }
        features.push_back({{"type", "Feature"},
                            {"geometry", {{"type", "MultiPolygon"}, {"coordinates", std::move(polys)}}},
                            {"properties",
                             {{"kind", "body"},
                              {"part", b.part},
                              {"name", index.parts[b.part].part->name},
                              {"record", b.record},
                              {"area_m2", b.area},
                              {"attributes", attributesOf(m, b.record)}}}});
    }
    for (const SectionTrace& t : *src.traces) {
        json coords = json::array();
        for (const auto& p : t.points) coords.push_back(position(src, frame, p));
        if (t.closed && !t.points.empty()) coords.push_back(position(src, frame, t.points.front()));
        const std::size_t surface = t.part - index.bodyCount;
        features.push_back({{"type", "Feature"},
                            {"geometry", {{"type", "LineString"}, {"coordinates", std::move(coords)}}},
                            {"properties",
                             {{"kind", "trace"},
                              {"part", surface},
                              {"name", index.parts[t.part].part->name},
                              {"record", t.record},
                              {"closed", t.closed},
                              {"attributes", attributesOf(m, t.record)}}}});
    }
    json meta = {{"frame", frame == VectorFrame::Plane ? "plane" : "world"},
                 {"axes", frame == VectorFrame::Plane
                              ? src.axes
                              : std::string("world x easting, y northing, z elevation, metres, in the model's CRS")},
                 {"crs", m.crs.epsg() ? "EPSG:" + std::to_string(m.crs.epsg()) : std::string("local")}};
    json out = {{"type", "FeatureCollection"}};
    if (frame == VectorFrame::World && m.crs.epsg())
        out["crs"] = {{"type", "name"},
                      {"properties", {{"name", "urn:ogc:def:crs:EPSG::" + std::to_string(m.crs.epsg())}}}};
    out["geoslice"] = std::move(meta);
    out["features"] = std::move(features);
    return out;
}

Result<std::string> toSvg(const SectionIndex& index, const VectorSource& src, const FrameRect& rect, int width,
                          int height, const RasterOptions& options, const SvgOverlays& overlays) {
    if (Status s = checkFrame(rect, width, height); !s) return s.error();
    const double sx = width / (rect.u1 - rect.u0), sy = height / (rect.v1 - rect.v0);
    char buf[256];
    auto px = [&](const glm::dvec2& p) {
        std::snprintf(buf, sizeof buf, "%.3f,%.3f", (p.x - rect.u0) * sx, (rect.v1 - p.y) * sy);
        return std::string(buf);
    };
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    std::snprintf(buf, sizeof buf,
                  "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\">\n",
                  width, height, width, height);
    out += buf;
    std::snprintf(buf, sizeof buf, "<!-- frame: u %.6f..%.6f, v %.6f..%.6f (metres); x right, y down -->\n", rect.u0,
                  rect.u1, rect.v0, rect.v1);
    out += buf;
    out += "<!-- " + xmlEscape(src.axes) + " -->\n";
    if (options.background.a > 0) {
        std::snprintf(buf, sizeof buf, "<rect width=\"%d\" height=\"%d\" fill=\"%s\" fill-opacity=\"%.4f\"/>\n", width,
                      height, hexColour(options.background).c_str(), options.background.a / 255.0);
        out += buf;
    }
    // Bodies in nesting order, like the ID buffer: an inner body is drawn over its host's hole.
    std::vector<const BodySection*> order;
    for (const BodySection& b : *src.bodies) order.push_back(&b);
    std::stable_sort(order.begin(), order.end(), [&](const BodySection* a, const BodySection* b) {
        return index.parts[a->part].depth < index.parts[b->part].depth;
    });
    const Model* model = index.model;
    auto lithologyOf = [&](RecordId r) {
        return overlays.patterns && model ? recordLithology(model->attributes.find(r)) : Lithology::None;
    };
    {  // <pattern> definitions of the lithologies shown
        std::map<int, std::string> defs;
        for (const BodySection* b : order)
            if (const Lithology l = lithologyOf(b->record); l != Lithology::None)
                defs.emplace(int(l), svgPattern(l, 96.0 / 25.4));
        if (!defs.empty()) {
            out += "<defs>\n";
            for (const auto& [k, def] : defs) out += def + "\n";
            out += "</defs>\n";
        }
    }
    for (const BodySection* b : order) {
        std::string d;
        auto ring = [&](const Ring& r) {
            for (std::size_t i = 0; i < r.size(); ++i) d += (i == 0 ? "M" : "L") + px(r[i]) + " ";
            d += "Z ";
        };
        for (const SectionPolygon& p : b->polygons) {
            ring(p.outer);
            for (const Ring& h : p.holes) ring(h);
        }
        if (d.empty()) continue;
        const SectionPart& part = index.parts[b->part];
        std::snprintf(buf, sizeof buf,
                      "<path fill=\"%s\" fill-opacity=\"%.4f\" fill-rule=\"evenodd\" data-record=\"%u\" "
                      "data-part=\"%u\" d=\"",
                      hexColour(part.colour).c_str(), part.colour.a / 255.0, b->record, b->part);
        out += buf;
        d.pop_back();
        out += d + "\"><title>" + xmlEscape(part.part->name);
        std::snprintf(buf, sizeof buf, " (record %u): %.3f m2</title></path>\n", b->record, b->area);
        out += buf;
        if (const Lithology l = lithologyOf(b->record); l != Lithology::None) {
            const std::string name(lithologyName(l));
            std::snprintf(buf, sizeof buf, "<path class=\"lith\" data-lithology=\"%s\" data-record=\"%u\" ",
                          name.c_str(), b->record);
            out += buf;
            out += "fill=\"url(#lith-" + name + ")\" fill-rule=\"evenodd\" d=\"" + d + "\"/>\n";
        }
    }
    out += src.svgOverBodies;
    if (overlays.labels) {
        LabelStyle style;
        style.size = overlays.labelPx;
        style.textWidth = overlays.textWidth;
        auto toPx = [&](const glm::dvec2& p) { return glm::dvec2((p.x - rect.u0) * sx, (rect.v1 - p.y) * sy); };
        const LabelBox view{0.0, 0.0, double(width), double(height)};
        for (const PlacedLabel& l :
             sectionLabels(index, *src.bodies, toPx, view, style, options.traces ? src.traces : nullptr)) {
            const SectionPart& part = index.parts[l.part];
            const Rgba8 ink = labelInk(part.colour, lithologyOf(l.record));
            std::snprintf(buf, sizeof buf,
                          "<g class=\"unit-label\" data-record=\"%u\"><rect x=\"%.3f\" y=\"%.3f\" width=\"%.3f\" "
                          "height=\"%.3f\" rx=\"%.2f\" fill=\"%s\"/>",
                          l.record, l.box.x0, l.box.y0, l.box.x1 - l.box.x0, l.box.y1 - l.box.y0, 0.2 * style.size,
                          hexColour(lithologyOf(l.record) == Lithology::Coal
                                        ? patternTile(Lithology::Coal).ink
                                        : Rgba8{part.colour.r, part.colour.g, part.colour.b, 255})
                              .c_str());
            out += buf;
            std::snprintf(buf, sizeof buf,
                          "<text x=\"%.3f\" y=\"%.3f\" font-family=\"DejaVu Sans, WenQuanYi Micro Hei, sans-serif\" "
                          "font-size=\"%.2f\" "
                          "text-anchor=\"middle\" fill=\"%s\">",
                          l.at.x, labelBaseline(l.at.y, style.size), style.size, hexColour(ink).c_str());
            out += buf;
            out += xmlEscape(l.text) + "</text></g>\n";
        }
    }
    if (options.traces) {
        for (const SectionTrace& t : *src.traces) {
            const SectionPart& part = index.parts[t.part];
            std::snprintf(
                buf, sizeof buf, "<%s fill=\"none\" stroke=\"%s\" stroke-width=\"%.2f\" data-record=\"%u\" points=\"",
                t.closed ? "polygon" : "polyline", hexColour(part.colour).c_str(), options.traceWidthPx, t.record);
            out += buf;
            for (std::size_t i = 0; i < t.points.size(); ++i) out += (i ? " " : "") + px(t.points[i]);
            out +=
                "\"><title>" + xmlEscape(part.part->name) + "</title></" + (t.closed ? "polygon" : "polyline") + ">\n";
        }
    }
    out += "</svg>\n";
    return out;
}

}  // namespace geoslice
