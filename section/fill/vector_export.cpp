#include "section/fill/vector_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "section/fill/labels.hpp"
#include "section/fill/patterns.hpp"

namespace geoslice {
namespace {

using json = nlohmann::ordered_json;

json position(const GeoJsonSpace& space, const glm::dvec2& p) {
    const glm::dvec3 w = space.position(p);
    if (!space.threeD()) return json::array({w.x, w.y});
    return json::array({w.x, w.y, w.z});
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

Status GeoJsonSpace::checkPositions() const {
    const std::size_t n = failures->load();
    if (n == 0) return {};
    return makeError(ErrorCode::Unsupported, "PROJ could not convert " + std::to_string(n) +
                                                 " point(s) of the section to WGS 84; ask for space=projected");
}

Result<GeoJsonSpace> geoJsonSpace(const VectorSource& src, VectorFrame frame, const Crs& crs,
                                  const CrsTransform* toLonLat, const std::string& lonLatNote) {
    GeoJsonSpace space;
    space.frame = frame;
    const std::string crsId = crs.isLocal() ? std::string("local") : crs.id();
    if (frame == VectorFrame::Plane) {
        space.position = [](const glm::dvec2& p) { return glm::dvec3(p, 0.0); };
        // An engineering CRS: GDAL/QGIS read [u, v] as metres on a local plane, not degrees.
        space.crsMember = {{"type", "name"},
                           {"properties",
                            {{"name",
                              "ENGCRS[\"geoslice section plane\",EDATUM[\"section plane\"],CS[Cartesian,2],"
                              "AXIS[\"u\",east,ORDER[1],LENGTHUNIT[\"metre\",1]],"
                              "AXIS[\"v\",north,ORDER[2],LENGTHUNIT[\"metre\",1]]]"}}}};
        space.meta = {{"frame", "plane"}, {"axes", src.axes}, {"modelCrs", crsId}};
        return space;
    }
    const auto toWorld = src.toWorld;
    if (frame == VectorFrame::Projected) {
        space.position = toWorld;
        // GDAL reads the URN and WKT alike; a model without CRS gets a local engineering CRS.
        const std::string name = crs.isLocal()
                                     ? std::string(
                                           "ENGCRS[\"geoslice model coordinates\",EDATUM[\"model origin\"],"
                                           "CS[Cartesian,3],AXIS[\"x\",east,ORDER[1],LENGTHUNIT[\"metre\",1]],"
                                           "AXIS[\"y\",north,ORDER[2],LENGTHUNIT[\"metre\",1]],"
                                           "AXIS[\"z\",up,ORDER[3],LENGTHUNIT[\"metre\",1]]]")
                                 : crs.epsg() ? "urn:ogc:def:crs:EPSG::" + std::to_string(crs.epsg())
                                              : crs.id();
        space.crsMember = {{"type", "name"}, {"properties", {{"name", name}}}};
        space.meta = {{"frame", "projected"},
                      {"axes", "easting, northing, elevation (metres) in the model's CRS"},
                      {"modelCrs", crsId}};
        return space;
    }
    if (crs.isLocal())
        return makeError(ErrorCode::InvalidArgument,
                         "parameter 'space': the model has no CRS, so there are no lon/lat coordinates; use "
                         "space=projected (the model's own x, y, z) or space=plane");
    if (!toLonLat)
        return makeError(ErrorCode::Unsupported,
                         "parameter 'space': " + lonLatNote + "; ask for space=projected (the model's CRS)");
    const CrsTransform t = *toLonLat;
    auto failures = space.failures;
    space.position = [toWorld, t, failures](const glm::dvec2& p) {
        Result<glm::dvec3> g = t.apply(toWorld(p));
        if (g && std::isfinite(g.value().x) && std::isfinite(g.value().y)) return g.value();
        failures->fetch_add(1);
        return glm::dvec3(NAN);
    };
    space.meta = {{"frame", "world"},
                  {"axes", "longitude, latitude (degrees, WGS 84, RFC 7946), elevation (metres, the model's)"},
                  {"modelCrs", crsId},
                  {"operation", t.operationName()}};
    if (t.accuracyM() >= 0.0) space.meta["accuracyM"] = t.accuracyM();
    if (!lonLatNote.empty()) space.meta["note"] = lonLatNote;
    return space;
}

json geoJsonRing(const std::vector<glm::dvec2>& ring, bool exterior, const GeoJsonSpace& space) {
    std::vector<glm::dvec3> pts;
    pts.reserve(ring.size() + 1);
    for (const auto& p : ring) pts.push_back(space.position(p));
    double twiceArea = 0.0;  // shoelace in the written x/y: > 0 counter-clockwise
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const glm::dvec3& a = pts[i];
        const glm::dvec3& b = pts[(i + 1) % pts.size()];
        twiceArea += (a.x - b.x) * (a.y + b.y);
    }
    if ((twiceArea < 0.0) == exterior) std::reverse(pts.begin(), pts.end());
    json r = json::array();
    auto put = [&](const glm::dvec3& w) {
        r.push_back(space.threeD() ? json::array({w.x, w.y, w.z}) : json::array({w.x, w.y}));
    };
    for (const auto& w : pts) put(w);
    if (!pts.empty()) put(pts.front());  // closed
    return r;
}

Result<json> toGeoJson(const SectionIndex& index, const VectorSource& src, const GeoJsonSpace& space) {
    const Model& m = *index.model;
    json features = json::array();
    for (const BodySection& b : *src.bodies) {
        json polys = json::array();
        for (const SectionPolygon& p : b.polygons) {
            json rings = json::array({geoJsonRing(p.outer, true, space)});
            for (const Ring& h : p.holes) rings.push_back(geoJsonRing(h, false, space));
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
        for (const auto& p : t.points) coords.push_back(position(space, p));
        if (t.closed && !t.points.empty()) coords.push_back(position(space, t.points.front()));
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
    if (Status s = space.checkPositions(); !s) return s.error();
    json out = {{"type", "FeatureCollection"}};
    if (!space.crsMember.is_null()) out["crs"] = space.crsMember;
    out["geoslice"] = space.meta;
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
