// GOCAD Voxet (.vo): a regular grid. Header: AXIS_O (origin), AXIS_U/V/W (axis vectors),
// AXIS_MIN/AXIS_MAX (the sampled range along each axis, in axis-vector units; default 0
// and 1), AXIS_N (samples per axis), and per property PROPERTY / PROP_FILE / PROP_ESIZE /
// PROP_ETYPE / PROP_FORMAT / PROP_OFFSET / PROP_NO_DATA_VALUE: one binary file per
// property, big-endian (RAW), i fastest. Sample (i,j,k) is at
//   O + (MIN_u + i (MAX_u - MIN_u)/(N_u - 1)) U + (same for v, w),
// which becomes Grid::origin + i step[0] + j step[1] + k step[2] in world metres.
//
// Also the GridHeader shared with SGrid (gocad_sgrid.cpp).
#include <cmath>
#include <limits>

#include "model/io/gocad/gocad_reader.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

namespace {

constexpr std::size_t kMaxGridProperties = 256;
// Samples per grid: 2^32 floats is 16 GiB per property, well past what a model server holds.
constexpr std::uint64_t kMaxSamples = std::uint64_t(1) << 32;

Status readVector(const Lines& lines, Tokens& tokens, std::string_view keyword, glm::dvec3& out) {
    for (int a = 0; a < 3; ++a) {
        std::string_view tok;
        std::optional<double> v;
        if (!tokens.next(tok) || !(v = parseDouble(tok)) || !std::isfinite(*v))
            return lines.fail(std::string(keyword) + " needs three finite numbers");
        out[a] = *v;
    }
    return {};
}

}  // namespace

Status GridHeader::readKeyword(Context& cx, std::string_view keyword, Tokens& tokens, bool& handled) {
    const Lines& lines = cx.lines;
    handled = true;
    if (keyword == "AXIS_N") {
        dimsLine = lines.lineNo();
        std::uint64_t total = 1;
        for (int a = 0; a < 3; ++a) {
            std::uint64_t n = 0;
            if (Status s = readId(lines, tokens, "AXIS_N count", n); !s) return s;
            if (n == 0) return lines.fail("AXIS_N counts must be at least 1");
            if (n > kMaxSamples || total * n > kMaxSamples)
                return lines.fail("AXIS_N gives more than " + std::to_string(kMaxSamples) + " samples");
            total *= n;
            dims[a] = static_cast<std::size_t>(n);
        }
        return {};
    }
    if (keyword == "PROP_ALIGNMENT") {
        // "PROP_ALIGNMENT CELLS" for the whole grid, or "PROP_ALIGNMENT n CELLS" for property n
        // (as Gocad/SKUA write SGrids); one grid holds properties of one alignment.
        std::string v = lower(tokens.rest());
        std::string which = "PROP_ALIGNMENT";
        if (const std::size_t sp = v.find_first_of(" \t");
            sp != std::string::npos && text::parseDouble(v.substr(0, sp))) {
            which += " " + v.substr(0, sp);
            v = std::string(text::trimSpace(v.substr(sp)));
        }
        bool cells = false;
        if (v == "cells")
            cells = true;
        else if (v != "points")
            return lines.fail(which + " must be POINTS or CELLS, found " + quoteToken(tokens.rest()));
        if (alignmentLine != 0 && cells != cellCentred)
            return lines.fail(which + " " + (cells ? "CELLS" : "POINTS") + " differs from the alignment on line " +
                              std::to_string(alignmentLine) +
                              ": properties on points and on cells in one grid are not read");
        cellCentred = cells;
        alignmentLine = lines.lineNo();
        return {};
    }
    static constexpr std::string_view kPropKeys[] = {"PROPERTY",    "PROP_FILE",   "PROP_ESIZE",         "PROP_ETYPE",
                                                     "PROP_FORMAT", "PROP_OFFSET", "PROP_NO_DATA_VALUE", "PROP_UNIT"};
    bool isProp = false;
    for (auto k : kPropKeys) isProp = isProp || keyword == k;
    if (!isProp) {
        handled = false;
        return {};
    }
    const std::string kw(keyword);
    std::uint64_t n = 0;
    if (Status s = readId(lines, tokens, kw + " number", n); !s) return s;
    if (props.find(n) == props.end() && props.size() >= kMaxGridProperties)
        return lines.fail("more than " + std::to_string(kMaxGridProperties) + " properties");
    Prop& p = props[n];
    std::string_view rest = tokens.rest();
    if (keyword == "PROPERTY") {
        p.name = toUtf8(unquote(rest));
        p.line = lines.lineNo();
    } else if (keyword == "PROP_FILE") {
        p.file = std::string(rest);
        p.fileLine = lines.lineNo();
    } else if (keyword == "PROP_UNIT") {
        p.unit = toUtf8(unquote(rest));
    } else if (keyword == "PROP_ESIZE") {
        std::uint64_t e = 0;
        if (Status s = readId(lines, tokens, "PROP_ESIZE", e); !s) return s;
        if (e != 1 && e != 2 && e != 4 && e != 8) return lines.fail("PROP_ESIZE must be 1, 2, 4 or 8 bytes");
        p.format.esize = static_cast<std::size_t>(e);
    } else if (keyword == "PROP_ETYPE") {
        std::string v = std::string(unquote(rest));
        for (char& c : v) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        if (v == "FLOAT") v = "IEEE";
        if (v != "IEEE" && v != "SIGNED_INT" && v != "UNSIGNED_INT")
            return lines.failAt(lines.lineNo(),
                                "PROP_ETYPE " + quoteToken(rest) + " is not supported (IEEE, SIGNED_INT, UNSIGNED_INT)",
                                ErrorCode::Unsupported);
        p.format.etype = v;
    } else if (keyword == "PROP_FORMAT") {
        std::string v = std::string(unquote(rest));
        for (char& c : v) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        if (v != "RAW")
            return lines.failAt(lines.lineNo(), "PROP_FORMAT " + quoteToken(rest) + " is not supported (RAW)",
                                ErrorCode::Unsupported);
        p.formatName = v;
    } else if (keyword == "PROP_OFFSET") {
        if (Status s = readId(lines, tokens, "PROP_OFFSET", p.format.offset); !s) return s;
    } else if (keyword == "PROP_NO_DATA_VALUE") {
        std::optional<double> v = parseDouble(rest);
        if (!v) return lines.fail("PROP_NO_DATA_VALUE " + quoteToken(rest) + " is not a number");
        p.noData = *v;
    }
    return {};
}

Status GridHeader::startGrid(const Context& cx, std::string_view type, std::size_t startLine, const ObjectInfo& info,
                             Grid& grid) const {
    if (dimsLine == 0) return cx.lines.failAt(startLine, "the " + std::string(type) + " object has no AXIS_N");
    grid.type = std::string(type);
    grid.name = info.name.empty() ? cx.model.name : info.name;
    for (int a = 0; a < 3; ++a) grid.dims[a] = dims[a];
    grid.cellCentred = cellCentred;
    return {};
}

Status GridHeader::readProperties(Context& cx, std::size_t startLine, Grid& grid) const {
    std::size_t count = grid.sampleCount();
    if (cellCentred) {
        count = 1;
        for (std::size_t n : grid.dims) count *= n > 1 ? n - 1 : 1;
    }
    for (const auto& [number, p] : props) {
        const std::string what = cx.lines.source() + ": " + grid.type + " " + quoteToken(grid.name) + " property " +
                                 std::to_string(number) + " " + quoteToken(p.name);
        if (p.file.empty())
            return cx.lines.failAt(p.line ? p.line : startLine, "property " + std::to_string(number) + " " +
                                                                    quoteToken(p.name) + " has no PROP_FILE");
        auto path = dataFilePath(cx, p.file, p.fileLine);
        if (!path) return path.error();
        auto values = readSampleFile(path.value(), p.format, count, p.noData,
                                     what + " (PROP_FILE on line " + std::to_string(p.fileLine) + ")");
        if (!values) return values.error();
        GridProperty gp;
        gp.name = p.name.empty() ? "property_" + std::to_string(number) : p.name;
        gp.unit = p.unit;
        gp.noDataValue = p.noData;
        gp.values = std::move(values.value());
        grid.properties.push_back(std::move(gp));
    }
    return {};
}

Status readVoxet(Context& cx, std::size_t startLine) {
    Lines& lines = cx.lines;
    ObjectInfo info;
    info.crs = cx.fileCrs;
    GridHeader header;
    glm::dvec3 o(0.0), axis[3] = {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)};
    glm::dvec3 mn(0.0), mx(1.0);
    auto own = [&](Lines::Statement& st, bool& handled) -> Status {
        const std::string_view keyword = st.keyword;
        if (keyword == "AXIS_O") return readVector(lines, st.tokens, keyword, o);
        if (keyword == "AXIS_U") return readVector(lines, st.tokens, keyword, axis[0]);
        if (keyword == "AXIS_V") return readVector(lines, st.tokens, keyword, axis[1]);
        if (keyword == "AXIS_W") return readVector(lines, st.tokens, keyword, axis[2]);
        if (keyword == "AXIS_MIN") return readVector(lines, st.tokens, keyword, mn);
        if (keyword == "AXIS_MAX") return readVector(lines, st.tokens, keyword, mx);
        handled = false;
        return {};
    };
    if (Status s = readObjectBody(cx, info, "Voxet object", startLine, own, header.keywords(cx)); !s) return s;
    Grid grid;
    if (Status s = header.startGrid(cx, "Voxet", startLine, info, grid); !s) return s;
    glm::dvec3 origin = o;
    for (int a = 0; a < 3; ++a) {
        origin += mn[a] * axis[a];
        const double n = static_cast<double>(header.dims[a]);
        grid.step[a] = info.crs.vectorToWorld(n > 1 ? (mx[a] - mn[a]) / (n - 1.0) * axis[a] : glm::dvec3(0.0));
    }
    grid.origin = info.crs.toWorld(origin);
    if (Status s = header.readProperties(cx, startLine, grid); !s) return s;
    cx.model.grids.push_back(std::move(grid));
    return {};
}

}  // namespace geoslice::gocad
