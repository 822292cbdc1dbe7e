// GOCAD TSurf objects (GOCAD "ASCII File Formats", TSurf).
//
// Choices, and why:
//  - One Part per `GOCAD TSurf ... END` object, holding every TFACE of that object. A
//    geologist sees a TSurf as one surface (one fault, one horizon); TFACEs are patches of
//    it that GOCAD stitches with ATOMs, and a closed shell is often made of several. The
//    TFACE boundaries are kept (TsurfData::tfaceStart) for Model3d, whose regions name them.
//  - ATOM / PATOM ids are aliases of the vertex they reference (same mesh index), so the
//    patches they stitch share vertices and a shell split into TFACEs can still be closed.
//  - Vertices no triangle uses are dropped: they would only widen the bounds and origin.
//  - Lenient, with a warning: GOCAD's CNXYZ constraint flag on VRTX/PVRTX lines; a missing
//    final END when the input ends after complete lines (parseGocad); AXIS_UNIT km and feet
//    (converted to metres).
//  - Robustness: every line must be text (no control bytes); lines with unknown keywords
//    are skipped only when they are also well-formed UTF-8. Nothing is sized from a count
//    in the file; PVRTX columns are capped (gocad_vertices.cpp).
#include <algorithm>
#include <limits>

#include "model/io/gocad/gocad_reader.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

namespace {

constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();

struct Triangle {
    std::uint64_t ids[3] = {0, 0, 0};
    std::size_t line = 0;
};

Status readTriangle(const Lines& lines, Tokens& tokens, Triangle& t) {
    t.line = lines.lineNo();
    std::size_t n = 0;
    std::string_view tok;
    while (tokens.next(tok)) {
        if (n == 3) return lines.fail("TRGL has more than 3 vertex ids");
        switch (parseId(tok, t.ids[n])) {
            case IdStatus::Ok:
                break;
            case IdStatus::NotInteger:
                return lines.fail("TRGL vertex id " + quoteToken(tok) + " is not a non-negative integer");
            case IdStatus::TooLarge:
                return lines.fail("TRGL vertex id " + quoteToken(tok) + " is out of range");
        }
        ++n;
    }
    if (n < 3) return lines.fail("TRGL needs 3 vertex ids, found " + std::to_string(n));
    return {};
}

}  // namespace

Status readTsurfData(Context& cx, std::size_t startLine, TsurfData& out) {
    Lines& lines = cx.lines;
    out = TsurfData{};
    out.startLine = startLine;
    out.info.crs = cx.fileCrs;
    out.info.crs.declared = false;
    PropertySchema schema;
    VertexIds ids;
    std::vector<glm::dvec3> positions;
    std::vector<Triangle> triangles;
    std::vector<std::size_t> tfaceStart;

    auto own = [&](Lines::Statement& st, bool& handled) -> Status {
        const std::string_view keyword = st.keyword;
        Tokens& tokens = st.tokens;
        if (keyword == "TRGL") {
            Triangle tri;
            if (Status s = readTriangle(lines, tokens, tri); !s) return s;
            triangles.push_back(tri);
            return {};
        }
        if (keyword == "TFACE") {
            tfaceStart.push_back(triangles.size());
            return {};
        }
        // Topology and display records we do not need: borders, stones, lines.
        static constexpr std::string_view kIgnored[] = {"BSTONE", "BORDER", "SEG", "ILINE", "PLINE", "VRTX_END"};
        handled = std::find(std::begin(kIgnored), std::end(kIgnored), keyword) != std::end(kIgnored);
        return {};
    };
    const KeywordReader vertices = vertexKeywords(cx, "TSurf", schema, ids, positions);
    bool ended = false;
    if (Status s = readObjectBody(cx, out.info, "TSurf object", startLine, own, vertices, &ended); !s) return s;
    if (!ended) {
        // Lenient: complete lines with triangles and no END. A line cut in the middle is still
        // an error (it has no newline, so it may be a number cut short).
        const bool cutLine = !lines.text().empty() && lines.text().back() != '\n';
        if (cutLine || triangles.empty()) return missingEnd(lines, "TSurf object", startLine);
        cx.warn(lines.lastLine(), "the TSurf object that starts on line " + std::to_string(startLine) +
                                      " has no final END; its " + std::to_string(triangles.size()) +
                                      " complete triangles are kept");
    }

    if (Status s = ids.resolve(lines); !s) return s;
    if (triangles.empty()) return {};  // a TSurf without triangles adds nothing

    std::vector<std::uint32_t> indices;
    indices.reserve(triangles.size() * 3);
    for (const Triangle& t : triangles) {
        for (std::uint64_t id : t.ids) {
            const VertexIds::Key* k = ids.find(id);
            if (!k)
                return lines.failAt(t.line, "TRGL refers to vertex id " + std::to_string(id) +
                                                ", which is not defined in the TSurf object that starts on line " +
                                                std::to_string(startLine));
            indices.push_back(k->index);
        }
    }
    // Keep the vertices that triangles use, in file order.
    std::vector<std::uint32_t> remap(positions.size(), kUnused);
    for (std::uint32_t i : indices) remap[i] = 0;
    Mesh& mesh = out.mesh;
    const std::size_t columns = schema.columnNames.size();
    const CoordinateSystem& cs = out.info.crs;
    for (std::size_t v = 0; v < positions.size(); ++v) {
        if (remap[v] == kUnused) continue;
        remap[v] = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.push_back(cs.toWorld(positions[v]));
        if (columns > 0)
            mesh.propertyValues.insert(mesh.propertyValues.end(),
                                       schema.values.begin() + static_cast<std::ptrdiff_t>(v * columns),
                                       schema.values.begin() + static_cast<std::ptrdiff_t>((v + 1) * columns));
    }
    for (std::uint32_t& i : indices) i = remap[i];
    mesh.indices = std::move(indices);
    mesh.propertyNames = schema.columnNames;
    if (tfaceStart.empty() || tfaceStart.front() != 0) tfaceStart.insert(tfaceStart.begin(), 0);
    // A TFACE line with no triangle after it is an empty patch; keep it (Model3d counts them).
    out.tfaceStart = std::move(tfaceStart);
    return {};
}

void addTsurfPart(Context& cx, TsurfData&& data) {
    if (data.mesh.indices.empty()) return;
    Part part;
    part.name = data.info.name;
    part.mesh = std::move(data.mesh);
    part.kind = PartKind::Surface;
    part.record = cx.model.attributes.add(data.info.record());
    if (part.name.empty()) cx.unnamedSurfaces.push_back(cx.model.surfaces.size());
    cx.model.surfaces.push_back(std::move(part));
}

Status readTsurf(Context& cx, std::size_t startLine) {
    TsurfData data;
    if (Status s = readTsurfData(cx, startLine, data); !s) return s;
    addTsurfPart(cx, std::move(data));
    return {};
}

}  // namespace geoslice::gocad
