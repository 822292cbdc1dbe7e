// GOCAD PLine (.pl): lines (well paths, traces, contours) as ILINE parts of VRTX/PVRTX/ATOM
// vertices joined by SEG id id. One Polyline per PLine object (all its ILINEs), kept by
// the Model and described by `info`; sections do not use lines yet.
#include <algorithm>
#include <limits>

#include "model/io/gocad/gocad_reader.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

Status readPline(Context& cx, std::size_t startLine) {
    Lines& lines = cx.lines;
    ObjectInfo info;
    info.crs = cx.fileCrs;
    PropertySchema schema;
    VertexIds ids;
    std::vector<glm::dvec3> positions;
    struct Seg {
        std::uint64_t a = 0, b = 0;
        std::size_t line = 0;
    };
    std::vector<Seg> segs;
    auto own = [&](Lines::Statement& st, bool& handled) -> Status {
        const std::string_view keyword = st.keyword;
        Tokens& tokens = st.tokens;
        if (keyword == "SEG") {
            Seg s;
            s.line = lines.lineNo();
            if (Status e = readId(lines, tokens, "SEG vertex id", s.a); !e) return e;
            if (Status e = readId(lines, tokens, "SEG vertex id", s.b); !e) return e;
            segs.push_back(s);
            return {};
        }
        handled = keyword == "ILINE";  // a new part of the same line object
        return {};
    };
    const KeywordReader vertices = vertexKeywords(cx, "PLine", schema, ids, positions);
    if (Status s = readObjectBody(cx, info, "PLine object", startLine, own, vertices); !s) return s;
    if (Status s = ids.resolve(lines); !s) return s;
    if (segs.empty()) {
        cx.warn(startLine, "the PLine object has no SEG: no line");
        return {};
    }
    Polyline pl;
    pl.name = info.name.empty() ? cx.model.name + "#line" + std::to_string(cx.model.lines.size() + 1) : info.name;
    constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> remap(positions.size(), kUnused);
    const std::size_t columns = schema.columnNames.size();
    for (const Seg& s : segs) {
        for (std::uint64_t id : {s.a, s.b}) {
            const VertexIds::Key* k = ids.find(id);
            if (!k)
                return lines.failAt(s.line, "SEG refers to vertex id " + std::to_string(id) +
                                                ", which is not defined in the PLine object that starts on line " +
                                                std::to_string(startLine));
            std::uint32_t& r = remap[k->index];
            if (r == kUnused) {
                r = static_cast<std::uint32_t>(pl.points.size());
                pl.points.push_back(info.crs.toWorld(positions[k->index]));
                if (columns > 0)
                    pl.propertyValues.insert(
                        pl.propertyValues.end(),
                        schema.values.begin() + static_cast<std::ptrdiff_t>(k->index * columns),
                        schema.values.begin() + static_cast<std::ptrdiff_t>((k->index + 1) * columns));
            }
            pl.segments.push_back(r);
        }
    }
    pl.propertyNames = schema.columnNames;
    AttributeRecord rec = info.record();
    rec.name = pl.name;
    if (rec.kind.empty()) rec.kind = "line";
    pl.record = cx.model.attributes.add(std::move(rec));
    cx.model.lines.push_back(std::move(pl));
    return {};
}

}  // namespace geoslice::gocad
