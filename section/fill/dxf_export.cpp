#include "section/fill/dxf_export.hpp"

#include <dxflib/dl_dxf.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "section/fill/labels.hpp"

namespace geoslice {
namespace {

// A UTF-8 string as DXF R2000 text: ASCII as is, every other code point as \U+XXXX (code
// points past U+FFFF and malformed bytes become '?').
std::string dxfText(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size();) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        if (c < 0x80) {
            out += (c < 0x20) ? ' ' : char(c);
            ++i;
            continue;
        }
        const int n = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : c >= 0xC0 ? 2 : 1;
        unsigned cp = n == 2 ? (c & 0x1Fu) : n == 3 ? (c & 0x0Fu) : (c & 0x07u);
        bool ok = n > 1 && i + std::size_t(n) <= s.size();
        for (int k = 1; ok && k < n; ++k) {
            const unsigned char d = static_cast<unsigned char>(s[i + std::size_t(k)]);
            ok = (d & 0xC0u) == 0x80u;
            cp = (cp << 6) | (d & 0x3Fu);
        }
        if (ok && cp <= 0xFFFF) {
            char buf[16];
            std::snprintf(buf, sizeof buf, "\\U+%04X", cp);
            out += buf;
        } else {
            out += '?';
        }
        i += ok ? std::size_t(n) : 1;
    }
    return out;
}

int trueColour(Rgba8 c) { return (int(c.r) << 16) | (int(c.g) << 8) | int(c.b); }

// The temporary file dxflib writes to, removed when this goes out of scope.
struct TempPath {
    std::string path;
    ~TempPath() {
        if (!path.empty()) ::unlink(path.c_str());
    }
};

}  // namespace

std::string dxfLayerName(const std::string& name) {
    std::string out;
    for (char c : name) out += std::string_view("<>/\\\":;?*|=`,").find(c) != std::string_view::npos ? '_' : c;
    while (!out.empty() && out.back() == ' ') out.pop_back();
    while (!out.empty() && out.front() == ' ') out.erase(out.begin());
    return out.empty() ? "unnamed" : dxfText(out);
}

Result<std::string> toDxf(const SectionIndex& index, const VectorSource& src, const DxfOptions& options) {
    const bool plane = options.frame == DxfFrame::Plane;
    // Layers in first-seen order: bodies, then surfaces.
    std::map<std::string, Rgba8> layerColour;
    std::vector<std::string> layers;
    auto layerOf = [&](std::uint32_t part) {
        const std::string name = dxfLayerName(index.parts[part].part->name);
        if (layerColour.emplace(name, index.parts[part].colour).second) layers.push_back(name);
        return name;
    };
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const BodySection& b : *src.bodies) {
        layerOf(b.part);
        for (const SectionPolygon& p : b.polygons)
            for (const auto& q : p.outer) lo = glm::min(lo, q), hi = glm::max(hi, q);
    }
    for (const SectionTrace& t : *src.traces) layerOf(t.part);
    const double extent = hi.x > lo.x ? std::max(hi.x - lo.x, hi.y - lo.y) : 1.0;
    const double textHeight = options.labelHeightM > 0.0 ? options.labelHeightM : extent / 100.0;

    TempPath tmp;
    {
        std::string templ = (std::filesystem::temp_directory_path() / "geoslice-dxf-XXXXXX").string();
        const int fd = ::mkstemp(templ.data());
        if (fd < 0) return makeError(ErrorCode::IoError, "DXF: cannot create a temporary file in " + templ);
        ::close(fd);
        tmp.path = templ;
    }
    DL_Dxf dxf;
    const DL_Codes::version version = plane ? DL_Codes::AC1015 : DL_Codes::AC1009;  // R12: 3D POLYLINE
    std::unique_ptr<DL_WriterA> dw(dxf.out(tmp.path.c_str(), version));
    if (!dw) return makeError(ErrorCode::IoError, "DXF: cannot write the temporary file " + tmp.path);

    dxf.writeHeader(*dw);
    dw->sectionEnd();
    dw->sectionTables();
    dxf.writeVPort(*dw);
    dw->tableLinetypes(3);
    dxf.writeLinetype(*dw, DL_LinetypeData("BYBLOCK", "", 0, 0, 0.0));
    dxf.writeLinetype(*dw, DL_LinetypeData("BYLAYER", "", 0, 0, 0.0));
    dxf.writeLinetype(*dw, DL_LinetypeData("CONTINUOUS", "Solid line", 0, 0, 0.0));
    dw->tableEnd();
    dw->tableLayers(int(layers.size()) + 1);
    dxf.writeLayer(*dw, DL_LayerData("0", 0), DL_Attributes("", 7, -1, 0, "CONTINUOUS"));
    for (const std::string& name : layers)
        dxf.writeLayer(*dw, DL_LayerData(name, 0),
                       DL_Attributes("", 7, plane ? trueColour(layerColour[name]) : -1, 0, "CONTINUOUS"));
    dw->tableEnd();
    dw->tableStyle(1);
    DL_StyleData style("Standard", 0, 0.0, 1.0, 0.0, 0, textHeight, "txt", "");
    style.bold = false;
    style.italic = false;
    dxf.writeStyle(*dw, style);
    dw->tableEnd();
    dxf.writeView(*dw);
    dxf.writeUcs(*dw);
    dw->tableAppid(1);
    dxf.writeAppid(*dw, "ACAD");
    dw->tableEnd();
    dxf.writeDimStyle(*dw, 1.0, 1.0, 1.0, 1.0, 1.0);
    if (plane) {
        dxf.writeBlockRecord(*dw);
        dw->tableEnd();
    }
    dw->sectionEnd();
    dw->sectionBlocks();
    dxf.writeBlock(*dw, DL_BlockData("*Model_Space", 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(*dw, "*Model_Space");
    dxf.writeBlock(*dw, DL_BlockData("*Paper_Space", 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(*dw, "*Paper_Space");
    dw->sectionEnd();

    dw->sectionEntities();
    auto attributes = [&](const std::string& layer) {
        // Colour by layer (256); in R2000 also the unit's true colour on the entity.
        return DL_Attributes(layer, 256, plane ? trueColour(layerColour[layer]) : -1, -1, "BYLAYER");
    };
    auto polyline = [&](const std::vector<glm::dvec2>& pts, bool closed, const DL_Attributes& attrib) {
        if (plane) {
            dxf.writePolyline(*dw, DL_PolylineData(int(pts.size()), 0, 0, closed ? 1 : 0), attrib);
            for (const auto& p : pts) dxf.writeVertex(*dw, DL_VertexData(p.x, p.y, 0.0, 0.0));
        } else {
            dxf.writePolyline(*dw, DL_PolylineData(int(pts.size()), 0, 0, 8 | (closed ? 1 : 0)), attrib);
            for (const auto& p : pts) {
                const glm::dvec3 w = src.toWorld(p);
                dxf.writeVertex(*dw, DL_VertexData(w.x, w.y, w.z, 0.0));
            }
        }
        dxf.writePolylineEnd(*dw);
    };
    for (const BodySection& b : *src.bodies) {
        const std::string layer = layerOf(b.part);
        const DL_Attributes attrib = attributes(layer);
        for (const SectionPolygon& p : b.polygons) {
            if (p.outer.size() < 3) continue;
            polyline(p.outer, true, attrib);
            for (const Ring& h : p.holes) polyline(h, true, attrib);
            if (!plane) continue;
            std::vector<const Ring*> loops{&p.outer};
            for (const Ring& h : p.holes)
                if (h.size() >= 3) loops.push_back(&h);
            const DL_HatchData hatch(int(loops.size()), true, 1.0, 0.0, "SOLID");
            dxf.writeHatch1(*dw, hatch, attrib);
            for (const Ring* r : loops) {
                const DL_HatchLoopData loop(int(r->size()));
                dxf.writeHatchLoop1(*dw, loop);
                for (std::size_t i = 0; i < r->size(); ++i) {
                    const glm::dvec2& a = (*r)[i];
                    const glm::dvec2& c = (*r)[(i + 1) % r->size()];
                    dxf.writeHatchEdge(*dw, DL_HatchEdgeData(a.x, a.y, c.x, c.y));
                }
                dxf.writeHatchLoop2(*dw, loop);
            }
            dxf.writeHatch2(*dw, hatch, attrib);
            if (!options.labels) continue;
            std::vector<Ring> rings{p.outer};
            rings.insert(rings.end(), p.holes.begin(), p.holes.end());
            double room = 0.0;
            const glm::dvec2 at = poleOfInaccessibility(rings, textHeight / 10.0, &room);
            // The label's box (width about 0.67 x height per character) inside the largest
            // circle the polygon holds: shrunk to fit, left out when under a quarter size.
            const std::string& name = index.parts[b.part].part->name;
            const double chars = double(std::max<std::size_t>(1, name.size()));
            const double h = std::min(textHeight, 2.0 * room / std::sqrt(0.45 * chars * chars + 1.0));
            if (h < 0.25 * textHeight) continue;
            // Ink in colour 7 (black on a white background, white on black), over the fill.
            const DL_Attributes ink(layer, 7, -1, -1, "BYLAYER");
            dxf.writeText(
                *dw, DL_TextData(at.x, at.y, 0.0, at.x, at.y, 0.0, h, 1.0, 0, 1, 2, dxfText(name), "Standard", 0.0),
                ink);
        }
    }
    for (const SectionTrace& t : *src.traces)
        if (t.points.size() >= 2) polyline(t.points, t.closed, attributes(layerOf(t.part)));
    dw->sectionEnd();
    if (plane) {
        dxf.writeObjects(*dw);
        dxf.writeObjectsEnd(*dw);
    }
    dw->dxfEOF();
    dw->close();
    dw.reset();

    std::ifstream in(tmp.path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    std::string out = text.str();
    // dxflib reports no write errors: a DXF that does not end in EOF was cut short (a full disk).
    std::string tail = out.substr(out.size() > 16 ? out.size() - 16 : 0);
    while (!tail.empty() && (tail.back() == '\n' || tail.back() == '\r' || tail.back() == ' ')) tail.pop_back();
    if (!in || tail.size() < 3 || tail.compare(tail.size() - 3, 3, "EOF") != 0)
        return makeError(ErrorCode::IoError,
                         "DXF: the temporary file " + tmp.path + " was not written to the end (is the disk full?)");
    return out;
}

}  // namespace geoslice
