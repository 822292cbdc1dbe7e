// GOCAD SGrid (.sg): a curvilinear grid. Header: AXIS_N, the point geometry in
// POINTS_FILE (binary big-endian float32 x y z per point, i fastest, from POINTS_OFFSET)
// or in ASCII_DATA_FILE (one line per point: x y z then one value per property, in
// PROPERTY order; '*' lines are comments), PROP_ALIGNMENT POINTS|CELLS, and properties
// as in a Voxet (PROPERTY / PROP_FILE / PROP_ESIZE / ...; gocad_voxet.cpp).
//
// Limits: FLAGS_FILE (dead cells, region flags) and split-node files are not read (a
// warning says so); properties from ASCII_DATA_FILE are per point.
#include <cmath>
#include <fstream>
#include <limits>

#include "model/io/gocad/gocad_reader.hpp"
#include "model/io/loaders.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

namespace {

// Reads the ASCII_DATA_FILE: x y z v1..vn per line, `points` lines.
Status readAsciiData(Context& cx, const std::string& path, std::size_t fileLine, Grid& grid,
                     const std::vector<std::string>& names, std::size_t points) {
    const std::string what = cx.lines.source() + ": SGrid " + quoteToken(grid.name) + " ASCII_DATA_FILE " + path;
    auto bytes = readFile(path);
    if (!bytes)
        return makeError(bytes.error().code,
                         what + " (line " + std::to_string(fileLine) + "): " + bytes.error().message);
    const std::string& text = bytes.value();
    // At least 6 bytes ("0 0 0\n") per point: check before allocating.
    if (text.size() / 6 < points)
        return makeError(ErrorCode::ParseError, what + ": " + std::to_string(text.size()) + " bytes cannot hold " +
                                                    std::to_string(points) + " points (AXIS_N): truncated file?");
    grid.points.reserve(points);
    std::vector<GridProperty> props(names.size());
    for (std::size_t k = 0; k < names.size(); ++k) {
        props[k].name = names[k];
        props[k].values.reserve(points);
    }
    Lines lines(text, path);
    std::string_view line;
    while (lines.next(line)) {
        std::string_view t = trim(line);
        if (t.empty() || t.front() == '*' || t.front() == '#') continue;
        if (grid.points.size() == points)
            return lines.fail("more than the " + std::to_string(points) + " points of AXIS_N");
        Tokens tokens(t);
        glm::dvec3 p(0.0);
        std::string_view tok;
        for (int a = 0; a < 3; ++a) {
            std::optional<double> v;
            if (!tokens.next(tok) || !(v = parseDouble(tok)) || !std::isfinite(*v))
                return lines.fail("a point needs three finite numbers x y z");
            p[a] = *v;
        }
        grid.points.push_back(p);
        for (auto& gp : props) {
            std::optional<double> v;
            if (!tokens.next(tok) || !(v = parseDouble(tok)))
                return lines.fail("property " + quoteToken(gp.name) + " needs a value on every point line");
            const bool ok = std::isfinite(*v) && std::fabs(*v) <= std::numeric_limits<float>::max();
            gp.values.push_back(ok ? static_cast<float>(*v) : std::numeric_limits<float>::quiet_NaN());
        }
    }
    if (grid.points.size() != points)
        return makeError(ErrorCode::ParseError, what + ": " + std::to_string(grid.points.size()) +
                                                    " points, AXIS_N needs " + std::to_string(points) +
                                                    " (truncated file?)");
    for (auto& gp : props) grid.properties.push_back(std::move(gp));
    return {};
}

}  // namespace

Status readSgrid(Context& cx, std::size_t startLine) {
    Lines& lines = cx.lines;
    ObjectInfo info;
    info.crs = cx.fileCrs;
    GridHeader header;
    std::string pointsFile, asciiFile;
    std::size_t pointsLine = 0, asciiLine = 0;
    SampleFormat pointsFormat;
    auto own = [&](Lines::Statement& st, bool& handled) -> Status {
        const std::string_view keyword = st.keyword;
        Tokens& tokens = st.tokens;
        if (keyword == "POINTS_FILE") {
            pointsFile = std::string(tokens.rest());
            pointsLine = lines.lineNo();
        } else if (keyword == "POINTS_OFFSET") {
            return readId(lines, tokens, "POINTS_OFFSET", pointsFormat.offset);
        } else if (keyword == "ASCII_DATA_FILE") {
            asciiFile = std::string(tokens.rest());
            asciiLine = lines.lineNo();
        } else if (keyword == "FLAGS_FILE" || keyword == "REGION_FLAGS_FILE" || keyword == "SPLIT_FILE") {
            cx.warn(lines.lineNo(), std::string(keyword) + " is not read (dead cells and regions are ignored)",
                    "sgrid " + std::string(keyword));
        } else {
            handled = false;
        }
        return {};
    };
    if (Status s = readObjectBody(cx, info, "SGrid object", startLine, own, header.keywords(cx)); !s) return s;
    Grid grid;
    if (Status s = header.startGrid(cx, "SGrid", startLine, info, grid); !s) return s;
    const std::size_t n = grid.sampleCount();
    if (!asciiFile.empty()) {
        auto path = dataFilePath(cx, asciiFile, asciiLine);
        if (!path) return path.error();
        std::vector<std::string> names;
        for (const auto& [number, p] : header.props)
            if (p.file.empty()) names.push_back(p.name.empty() ? "property_" + std::to_string(number) : p.name);
        if (Status s = readAsciiData(cx, path.value(), asciiLine, grid, names, n); !s) return s;
        GridHeader binary = header;  // properties with their own files are read as in a Voxet
        for (auto it = binary.props.begin(); it != binary.props.end();)
            it = it->second.file.empty() ? binary.props.erase(it) : std::next(it);
        if (Status s = binary.readProperties(cx, startLine, grid); !s) return s;
    } else if (!pointsFile.empty()) {
        auto path = dataFilePath(cx, pointsFile, pointsLine);
        if (!path) return path.error();
        if (n > std::numeric_limits<std::size_t>::max() / 3)
            return lines.failAt(header.dimsLine, "AXIS_N gives too many points");
        auto xyz = readSampleFile(path.value(), pointsFormat, 3 * n, std::nullopt,
                                  cx.lines.source() + ": SGrid " + quoteToken(grid.name) + " POINTS_FILE (line " +
                                      std::to_string(pointsLine) + ")");
        if (!xyz) return xyz.error();
        grid.points.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const float* v = xyz.value().data() + 3 * i;
            if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
                return makeError(ErrorCode::ParseError, cx.lines.source() + ": SGrid " + quoteToken(grid.name) +
                                                            " point " + std::to_string(i) +
                                                            " in POINTS_FILE is not finite");
            grid.points[i] = glm::dvec3(v[0], v[1], v[2]);
        }
        if (Status s = header.readProperties(cx, startLine, grid); !s) return s;
    } else {
        return lines.failAt(startLine, "the SGrid object has neither POINTS_FILE nor ASCII_DATA_FILE");
    }
    for (glm::dvec3& p : grid.points) p = info.crs.toWorld(p);
    cx.model.grids.push_back(std::move(grid));
    return {};
}

}  // namespace geoslice::gocad
