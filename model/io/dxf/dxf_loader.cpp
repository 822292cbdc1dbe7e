// DXF reader (ASCII DXF): triangulated wireframes from 3DFACE, POLYLINE polyface and
// polygon meshes and MESH entities; LINE, LWPOLYLINE and other POLYLINEs as lines.
//
// Why not a library: Debian's dxflib (libdxflib-dev 3.26) reports a POLYLINE's VERTEX
// records as DL_VertexData {x, y, z, bulge} only: the vertex flags (group 70) and the face
// indices of a polyface mesh's face records (groups 71-74) are dropped, so a polyface
// mesh, the form Surpac, Micromine, 3DMine and DIMINE export solids in, cannot be rebuilt
// from its callbacks; it has no MESH entity either. Using it for 3DFACE alone would mean two
// readers of one file. libassimp's DXF importer was not taken: it flattens layers into
// node names of one scene and OSS-Fuzz has reported many crashes in its importers.
// DXF's group-code grammar is two lines per pair, read here with every count checked
// against the pairs present.
//
// Frame: DXF world coordinates (WCS) are read as world coordinates: x east, y north, z up,
// metres ($INSUNITS is not applied). Entities inside BLOCKS are not read and INSERTs are not
// expanded (both counted in the model note "dxf_skipped").
//
// Parts: one per layer (group 8): every face of a layer (3DFACEs, polyface meshes, polygon
// meshes and MESH entities alike) goes into the layer's part, welded exactly (model/io/weld.hpp),
// so a closed shell becomes a body, an open one a surface. Lines of a layer (LINE,
// LWPOLYLINE, 2D/3D POLYLINE) go into one Polyline named after the layer.
//  - 3DFACE: corners 10-13/20-23/30-33; a triangle when the fourth corner equals the third,
//    otherwise a quad split along its 1-3 diagonal; edge visibility (70) is ignored.
//  - POLYLINE with flag 64 (polyface mesh): VERTEX records with flags 128+64 are the mesh
//    vertices, those with 128 alone are faces whose groups 71-74 give 1-based vertex
//    numbers (negative: the edge that starts there is invisible; the sign is dropped; 0 or
//    absent 74: a triangle).
//  - POLYLINE with flag 16 (M x N polygon mesh, groups 71/72; flags 1 and 32 close it in M
//    and N): each grid cell is a quad, two triangles. Smoothed surfaces (75) use the control
//    grid.
//  - MESH (AcDbSubDMesh): vertices (92 count, then 10/20/30) and the face list (93 size, then
//    groups 90: a corner count followed by 0-based vertex indices). A subdivision level
//    (91) above 0 is not applied: the control cage is read.
// A binary DXF is an Unsupported error naming it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "model/io/loaders.hpp"
#include "model/io/weld.hpp"
#include "model/text_scan.hpp"

namespace geoslice {
namespace {

using namespace geoslice::text;

struct Pair {
    int code = 0;
    std::string_view value;
    std::size_t line = 0;  // line of the group code
};

class DxfReader {
public:
    DxfReader(std::string_view text, const std::string& source) : text_(text), source_(source) {}
    Result<Model> run();

private:
    Error failAt(std::size_t line, const std::string& what) const {
        return makeError(ErrorCode::ParseError, source_ + ": line " + std::to_string(line) + ": " + what);
    }
    Status readPairs();
    // The entity starting at pairs_[i] (its code-0 pair): [i + 1, end) are its groups.
    std::size_t entityEnd(std::size_t i) const {
        std::size_t j = i + 1;
        while (j < pairs_.size() && pairs_[j].code != 0) ++j;
        return j;
    }
    Status number(const Pair& p, double& out) const;
    Status integer(const Pair& p, std::int64_t& out) const;
    WeldedPart& part(std::string_view layer);
    Polyline& lines(std::string_view layer);
    Status face3d(std::size_t b, std::size_t e);
    Status line(std::size_t b, std::size_t e);
    Status lwPolyline(std::size_t b, std::size_t e);
    // Reads a POLYLINE from pairs_[i] with its VERTEX records and SEQEND; returns the index
    // of the pair after them in `next`.
    Status polyline(std::size_t i, std::size_t& next);
    Status mesh(std::size_t b, std::size_t e);
    Status addFace(WeldedPart& part, const std::vector<glm::dvec3>& corners);

    std::string_view text_;
    const std::string& source_;
    std::vector<Pair> pairs_;
    std::vector<WeldedPart> parts_;
    std::map<std::string, std::size_t> partByLayer_;
    std::vector<Polyline> lines_;
    std::map<std::string, std::size_t> linesByLayer_;
    std::map<std::string, std::size_t> skipped_;
    std::size_t subdividedMeshes_ = 0;
};

Status DxfReader::readPairs() {
    std::size_t pos = 0, lineNo = 0;
    std::string_view codeLine, valueLine;
    while (text::nextLine(text_, pos, codeLine)) {
        ++lineNo;
        const std::string_view c = trim(codeLine);
        if (c.empty() && pos >= text_.size()) break;  // a final blank line
        std::int64_t code = 0;
        if (parseInt(c, code) != IntStatus::Ok || code < 0 || code > 1071)
            return failAt(lineNo, "group code " + quoteToken(c) + " is not a DXF group code (0..1071)");
        if (!text::nextLine(text_, pos, valueLine))
            return failAt(lineNo, "the file ends after group code " + std::to_string(code) + " (no value line)");
        ++lineNo;
        pairs_.push_back(Pair{static_cast<int>(code), trim(valueLine), lineNo - 1});
    }
    return {};
}

Status DxfReader::number(const Pair& p, double& out) const {
    auto v = parseDouble(p.value);
    if (!v)
        return failAt(p.line + 1, "group " + std::to_string(p.code) + ": " + quoteToken(p.value) + " is not a number");
    if (!std::isfinite(*v))
        return failAt(p.line + 1, "group " + std::to_string(p.code) + ": " + quoteToken(p.value) + " is not finite");
    out = *v;
    return {};
}

Status DxfReader::integer(const Pair& p, std::int64_t& out) const {
    if (parseInt(p.value, out) != IntStatus::Ok)
        return failAt(p.line + 1,
                      "group " + std::to_string(p.code) + ": " + quoteToken(p.value) + " is not an integer");
    return {};
}

WeldedPart& DxfReader::part(std::string_view layer) {
    std::string name = layer.empty() ? std::string("0") : toUtf8(layer);
    auto [it, inserted] = partByLayer_.try_emplace(name, parts_.size());
    if (inserted) {
        parts_.emplace_back();
        parts_.back().name = name;
    }
    return parts_[it->second];
}

Polyline& DxfReader::lines(std::string_view layer) {
    std::string name = layer.empty() ? std::string("0") : toUtf8(layer);
    auto [it, inserted] = linesByLayer_.try_emplace(name, lines_.size());
    if (inserted) {
        lines_.emplace_back();
        lines_.back().name = name;
    }
    return lines_[it->second];
}

Status DxfReader::addFace(WeldedPart& p, const std::vector<glm::dvec3>& c) {
    for (std::size_t k = 1; k + 1 < c.size(); ++k) p.addTriangle(c[0], c[k], c[k + 1]);
    if (p.indices.size() > std::size_t(std::numeric_limits<std::uint32_t>::max()) - 8)
        return makeError(ErrorCode::OutOfRange, source_ + ": layer '" + p.name + "' has too many triangles");
    return {};
}

Status DxfReader::face3d(std::size_t b, std::size_t e) {
    glm::dvec3 c[4] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
    std::string_view layer;
    int seen = 0;
    for (std::size_t i = b; i < e; ++i) {
        const Pair& p = pairs_[i];
        if (p.code == 8) layer = p.value;
        const int axis = p.code >= 10 && p.code <= 13   ? 0
                         : p.code >= 20 && p.code <= 23 ? 1
                         : p.code >= 30 && p.code <= 33 ? 2
                                                        : -1;
        if (axis < 0) continue;
        const int corner = p.code % 10;
        if (Status s = number(p, c[corner][axis]); !s) return s;
        seen |= 1 << (corner * 3 + axis);
    }
    if ((seen & 0777) != 0777)
        return failAt(pairs_[b - 1].line, "3DFACE without its first three corners (groups 10-12, 20-22, 30-32)");
    if ((seen & 07000) != 07000) c[3] = c[2];  // a fourth corner left out: a triangle
    std::vector<glm::dvec3> corners = {c[0], c[1], c[2]};
    if (c[3] != c[2]) corners.push_back(c[3]);
    return addFace(part(layer), corners);
}

Status DxfReader::line(std::size_t b, std::size_t e) {
    glm::dvec3 a(0.0), z(0.0);
    std::string_view layer;
    for (std::size_t i = b; i < e; ++i) {
        const Pair& p = pairs_[i];
        if (p.code == 8) layer = p.value;
        double* slot = p.code == 10   ? &a.x
                       : p.code == 20 ? &a.y
                       : p.code == 30 ? &a.z
                       : p.code == 11 ? &z.x
                       : p.code == 21 ? &z.y
                       : p.code == 31 ? &z.z
                                      : nullptr;
        if (slot)
            if (Status s = number(p, *slot); !s) return s;
    }
    Polyline& l = lines(layer);
    const auto n = static_cast<std::uint32_t>(l.points.size());
    l.points.push_back(a);
    l.points.push_back(z);
    l.segments.push_back(n);
    l.segments.push_back(n + 1);
    return {};
}

Status DxfReader::lwPolyline(std::size_t b, std::size_t e) {
    std::string_view layer;
    double elevation = 0.0;
    std::int64_t flags = 0;
    std::vector<glm::dvec3> pts;
    for (std::size_t i = b; i < e; ++i) {
        const Pair& p = pairs_[i];
        if (p.code == 8)
            layer = p.value;
        else if (p.code == 38) {
            if (Status s = number(p, elevation); !s) return s;
        } else if (p.code == 70) {
            if (Status s = integer(p, flags); !s) return s;
        } else if (p.code == 10) {
            pts.emplace_back(0.0);
            if (Status s = number(p, pts.back().x); !s) return s;
        } else if (p.code == 20) {
            if (pts.empty()) return failAt(p.line, "LWPOLYLINE: group 20 before any group 10");
            if (Status s = number(p, pts.back().y); !s) return s;
        }
    }
    if (pts.size() < 2) return {};
    Polyline& l = lines(layer);
    const auto base = static_cast<std::uint32_t>(l.points.size());
    for (auto& q : pts) l.points.push_back({q.x, q.y, elevation});
    const auto n = static_cast<std::uint32_t>(pts.size());
    for (std::uint32_t k = 0; k + 1 < n; ++k) {
        l.segments.push_back(base + k);
        l.segments.push_back(base + k + 1);
    }
    if (flags & 1) {
        l.segments.push_back(base + n - 1);
        l.segments.push_back(base);
    }
    return {};
}

Status DxfReader::polyline(std::size_t i, std::size_t& next) {
    const std::size_t headLine = pairs_[i].line;
    const std::size_t he = entityEnd(i);
    std::string_view layer;
    std::int64_t flags = 0, m = 0, n = 0;
    double elevation = 0.0;
    for (std::size_t k = i + 1; k < he; ++k) {
        const Pair& p = pairs_[k];
        if (p.code == 8)
            layer = p.value;
        else if (p.code == 70) {
            if (Status s = integer(p, flags); !s) return s;
        } else if (p.code == 71) {
            if (Status s = integer(p, m); !s) return s;
        } else if (p.code == 72) {
            if (Status s = integer(p, n); !s) return s;
        } else if (p.code == 30) {
            if (Status s = number(p, elevation); !s) return s;
        }
    }
    struct Vertex {
        glm::dvec3 p{0.0};
        std::int64_t flags = 0;
        std::int64_t idx[4] = {0, 0, 0, 0};
        std::size_t line = 0;
    };
    std::vector<Vertex> verts;
    std::size_t k = he;
    for (;;) {
        if (k >= pairs_.size())
            return failAt(headLine, "POLYLINE without SEQEND (the file ends in its VERTEX records)");
        const std::string_view type = pairs_[k].value;
        const std::size_t ve = entityEnd(k);
        if (type == "SEQEND") {
            next = ve;
            break;
        }
        if (type != "VERTEX")
            return failAt(pairs_[k].line, "POLYLINE of line " + std::to_string(headLine) +
                                              ": expected VERTEX or SEQEND, found " + quoteToken(type));
        Vertex v;
        v.line = pairs_[k].line;
        for (std::size_t g = k + 1; g < ve; ++g) {
            const Pair& p = pairs_[g];
            if (p.code == 10 || p.code == 20 || p.code == 30) {
                if (Status s = number(p, v.p[p.code / 10 - 1]); !s) return s;
            } else if (p.code == 70) {
                if (Status s = integer(p, v.flags); !s) return s;
            } else if (p.code >= 71 && p.code <= 74) {
                if (Status s = integer(p, v.idx[p.code - 71]); !s) return s;
            }
        }
        verts.push_back(v);
        k = ve;
    }
    const std::string where = "POLYLINE of line " + std::to_string(headLine);
    if (flags & 64) {  // polyface mesh
        std::vector<glm::dvec3> positions;
        for (const Vertex& v : verts)
            if ((v.flags & 128) && (v.flags & 64)) positions.push_back(v.p);
        WeldedPart& p = part(layer);
        std::vector<glm::dvec3> corners;
        for (const Vertex& v : verts) {
            if (!(v.flags & 128) || (v.flags & 64)) continue;
            corners.clear();
            for (std::int64_t raw : v.idx) {
                if (raw == 0) continue;
                const std::int64_t a = raw < 0 ? -raw : raw;
                if (a > static_cast<std::int64_t>(positions.size()))
                    return failAt(v.line, where + ": face record refers to vertex " + std::to_string(a) + " of " +
                                              std::to_string(positions.size()));
                corners.push_back(positions[static_cast<std::size_t>(a - 1)]);
            }
            if (corners.size() < 3)
                return failAt(v.line, where + ": face record with " + std::to_string(corners.size()) +
                                          " vertex numbers (groups 71-74; 3 at least)");
            if (Status s = addFace(p, corners); !s) return s;
        }
        return {};
    }
    if (flags & 16) {  // M x N polygon mesh
        // m and n at most the vertex count first: their product cannot then wrap around.
        const auto size = static_cast<std::int64_t>(verts.size());
        if (m < 2 || n < 2 || m > size || n > size ||
            static_cast<std::uint64_t>(m) * static_cast<std::uint64_t>(n) != verts.size())
            return failAt(headLine, where + ": polygon mesh of " + std::to_string(m) + " x " + std::to_string(n) +
                                        " vertices (groups 71, 72) has " + std::to_string(verts.size()) +
                                        " VERTEX records");
        WeldedPart& p = part(layer);
        const bool closedM = flags & 1, closedN = flags & 32;
        auto at = [&](std::int64_t a, std::int64_t b) {
            return verts[static_cast<std::size_t>((a % m) * n + (b % n))].p;
        };
        for (std::int64_t a = 0; a < (closedM ? m : m - 1); ++a)
            for (std::int64_t b = 0; b < (closedN ? n : n - 1); ++b)
                if (Status s = addFace(p, {at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)}); !s) return s;
        return {};
    }
    // A 2D or 3D polyline: a line object.
    if (verts.size() < 2) return {};
    Polyline& l = lines(layer);
    const auto base = static_cast<std::uint32_t>(l.points.size());
    for (const Vertex& v : verts) l.points.push_back(flags & 8 ? v.p : glm::dvec3(v.p.x, v.p.y, elevation));
    const auto cnt = static_cast<std::uint32_t>(verts.size());
    for (std::uint32_t j = 0; j + 1 < cnt; ++j) {
        l.segments.push_back(base + j);
        l.segments.push_back(base + j + 1);
    }
    if (flags & 1) {
        l.segments.push_back(base + cnt - 1);
        l.segments.push_back(base);
    }
    return {};
}

Status DxfReader::mesh(std::size_t b, std::size_t e) {
    std::string_view layer;
    std::vector<glm::dvec3> positions;
    std::int64_t vertexCount = -1, faceListSize = -1, level = 0;
    std::vector<std::int64_t> faceList;
    std::size_t faceListLine = 0;
    enum { None, Vertices, Faces, Other } state = None;
    int axisNext = 0;
    for (std::size_t i = b; i < e; ++i) {
        const Pair& p = pairs_[i];
        if (p.code == 8) {
            layer = p.value;
        } else if (p.code == 91) {
            if (Status s = integer(p, level); !s) return s;
        } else if (p.code == 92) {
            if (Status s = integer(p, vertexCount); !s) return s;
            // Each vertex takes three pairs: a count past them is checked before reserving.
            if (vertexCount < 0 || static_cast<std::uint64_t>(vertexCount) > (e - i) / 3)
                return failAt(p.line, "MESH: vertex count " + std::to_string(vertexCount) + " is more than the " +
                                          std::to_string((e - i) / 3) + " vertices the entity has room for");
            positions.reserve(static_cast<std::size_t>(vertexCount));
            state = Vertices;
        } else if (p.code == 93) {
            if (Status s = integer(p, faceListSize); !s) return s;
            if (faceListSize < 0 || static_cast<std::uint64_t>(faceListSize) > e - i)
                return failAt(p.line, "MESH: face list size " + std::to_string(faceListSize) + " is more than the " +
                                          std::to_string(e - i) + " groups left in the entity");
            faceList.reserve(static_cast<std::size_t>(faceListSize));
            faceListLine = p.line;
            state = Faces;
        } else if (p.code == 94 || p.code == 95) {
            state = Other;
        } else if (state == Vertices && (p.code == 10 || p.code == 20 || p.code == 30)) {
            const int axis = p.code / 10 - 1;
            if (axis != axisNext) return failAt(p.line, "MESH: vertex coordinates out of order (10, 20, 30 expected)");
            if (axis == 0) {
                if (positions.size() >= static_cast<std::size_t>(vertexCount))
                    return failAt(p.line,
                                  "MESH: more vertices than the count (group 92) of " + std::to_string(vertexCount));
                positions.emplace_back(0.0);
            }
            if (Status s = number(p, positions.back()[axis]); !s) return s;
            axisNext = (axis + 1) % 3;
        } else if (state == Faces && p.code == 90 && faceList.size() < static_cast<std::size_t>(faceListSize)) {
            std::int64_t v = 0;
            if (Status s = integer(p, v); !s) return s;
            faceList.push_back(v);
        }
    }
    const std::size_t meshLine = pairs_[b - 1].line;
    if (vertexCount < 0 || faceListSize < 0)
        return failAt(meshLine, "MESH without a vertex count (92) or a face list (93)");
    if (positions.size() != static_cast<std::size_t>(vertexCount) || axisNext != 0)
        return failAt(meshLine, "MESH: " + std::to_string(positions.size()) + " vertices of the " +
                                    std::to_string(vertexCount) + " declared (group 92)");
    if (faceList.size() != static_cast<std::size_t>(faceListSize))
        return failAt(faceListLine, "MESH: face list of " + std::to_string(faceList.size()) + " values, " +
                                        std::to_string(faceListSize) + " declared (group 93)");
    if (level > 0) ++subdividedMeshes_;
    WeldedPart& part = this->part(layer);
    std::vector<glm::dvec3> corners;
    for (std::size_t i = 0; i < faceList.size();) {
        const std::int64_t count = faceList[i++];
        if (count < 3 || static_cast<std::uint64_t>(count) > faceList.size() - i)
            return failAt(faceListLine, "MESH: a face of " + std::to_string(count) + " corners at face-list value " +
                                            std::to_string(i) + " (3 or more, within the list)");
        corners.clear();
        for (std::int64_t k = 0; k < count; ++k) {
            const std::int64_t v = faceList[i++];
            if (v < 0 || v >= vertexCount)
                return failAt(faceListLine, "MESH: vertex index " + std::to_string(v) + " out of range (" +
                                                std::to_string(vertexCount) + " vertices)");
            corners.push_back(positions[static_cast<std::size_t>(v)]);
        }
        if (Status s = addFace(part, corners); !s) return s;
    }
    return {};
}

Result<Model> DxfReader::run() {
    if (text_.substr(0, 18) == "AutoCAD Binary DXF")
        return makeError(ErrorCode::Unsupported,
                         source_ + ": a binary DXF, which geoslice does not read: save it as ASCII DXF");
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
    if (Status s = readPairs(); !s) return s.error();
    std::string section;
    for (std::size_t i = 0; i < pairs_.size();) {
        const Pair& p = pairs_[i];
        if (p.code != 0) {
            ++i;
            continue;
        }
        const std::size_t e = entityEnd(i);
        if (p.value == "SECTION") {
            section = e > i + 1 && pairs_[i + 1].code == 2 ? std::string(pairs_[i + 1].value) : std::string();
            i = e;
            continue;
        }
        if (p.value == "ENDSEC") {
            section.clear();
            i = e;
            continue;
        }
        if (p.value == "EOF") break;
        if (section != "ENTITIES") {
            if (section == "BLOCKS" && p.value != "BLOCK" && p.value != "ENDBLK") ++skipped_["entities in BLOCKS"];
            i = e;
            continue;
        }
        Status s;
        std::size_t next = e;
        if (p.value == "3DFACE")
            s = face3d(i + 1, e);
        else if (p.value == "POLYLINE")
            s = polyline(i, next);
        else if (p.value == "MESH")
            s = mesh(i + 1, e);
        else if (p.value == "LINE")
            s = line(i + 1, e);
        else if (p.value == "LWPOLYLINE")
            s = lwPolyline(i + 1, e);
        else
            ++skipped_[std::string(toUtf8(p.value))];
        if (!s) return s.error();
        i = next;
    }
    Model model;
    model.source = source_;
    addWeldedParts(model, parts_);
    for (Polyline& l : lines_)
        if (!l.segments.empty()) model.lines.push_back(std::move(l));
    if (model.bodies.empty() && model.lines.empty())
        return makeError(
            ErrorCode::ParseError,
            source_ +
                (pairs_.empty() ? ": empty input"
                                : ": no 3DFACE, POLYLINE, MESH, LINE or LWPOLYLINE entities in the ENTITIES section") +
                ": nothing to load");
    std::string skipped;
    for (const auto& [type, count] : skipped_)
        skipped += (skipped.empty() ? "" : ", ") + type + " " + std::to_string(count);
    if (!skipped.empty()) model.notes["dxf_skipped"] = skipped;
    if (subdividedMeshes_ > 0)
        model.notes["dxf_mesh_subdivision"] =
            std::to_string(subdividedMeshes_) + " MESH entities ask for subdivision; their control cages were read";
    // Line objects get records too (finishLoadedModel() gives parts theirs).
    for (Polyline& l : model.lines) {
        AttributeRecord rec;
        rec.name = l.name;
        rec.kind = "line";
        l.record = model.attributes.add(std::move(rec));
    }
    finishLoadedModel(model, /*classifyByClosure=*/true);
    setRecordKinds(model);
    return model;
}

}  // namespace

Result<Model> parseDxf(std::string_view text, const std::string& source) { return DxfReader(text, source).run(); }

}  // namespace geoslice
