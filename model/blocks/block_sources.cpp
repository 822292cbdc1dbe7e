// Block models from their sources: CSV rows (x,y,z,dx,dy,dz,properties...) and GOCAD grids
// (a Voxet's boxes, an SGrid's curvilinear cells with every tetrahedron checked positive).
#include "model/blocks/block_model.hpp"
#include "model/blocks/block_model_internal.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "model/blocks/cell_locator.hpp"
#include "model/limits.hpp"
#include "model/model.hpp"
#include "model/text_scan.hpp"

namespace geoslice {
namespace {

std::string where(const std::string& source, std::size_t line) { return source + ":" + std::to_string(line); }

// "grade [g/t Au]" -> {"grade", "g/t Au"}.
std::pair<std::string, std::string> splitUnit(std::string_view header) {
    header = text::trim(header);
    const std::size_t open = header.find('[');
    if (open != std::string_view::npos && !header.empty() && header.back() == ']')
        return {std::string(text::trim(header.substr(0, open))),
                std::string(text::trim(header.substr(open + 1, header.size() - open - 2)))};
    return {std::string(header), ""};
}

}  // namespace

Result<BlockRows> readBlockRows(std::string_view text, const std::string& source) {
    std::size_t pos = 0, line = 1;
    if (text.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;  // UTF-8 byte order mark
    // Skip blank lines before the header.
    while (pos < text.size()) {
        const std::size_t end = std::min(text.find('\n', pos), text.size());
        if (!text::trim(text.substr(pos, end - pos)).empty()) break;
        pos = end + 1;
        ++line;
    }
    if (pos >= text.size()) return makeError(ErrorCode::ParseError, source + ": empty block model (no header)");
    const std::string_view first = text.substr(pos, std::min(text.find('\n', pos), text.size()) - pos);
    const char sep = first.find(';') != std::string_view::npos && first.find(',') == std::string_view::npos ? ';' : ',';
    bool badQuote = false;
    const std::size_t headerLine = line;
    std::vector<std::string> header = text::csvRecord(text, pos, badQuote, sep);
    if (badQuote) return makeError(ErrorCode::ParseError, where(source, headerLine) + ": unterminated quote");
    line += 1;
    int col[6] = {-1, -1, -1, -1, -1, -1};
    static const char* kKnown[6] = {"x", "y", "z", "dx", "dy", "dz"};
    BlockRows rows;
    std::vector<std::size_t> propCol;
    std::map<std::string, int> seen;
    for (std::size_t c = 0; c < header.size(); ++c) {
        auto [name, unit] = splitUnit(header[c]);
        const std::string low = text::lower(name);
        if (name.empty())
            return makeError(ErrorCode::ParseError,
                             where(source, headerLine) + ": column " + std::to_string(c + 1) + " has no name");
        if (!seen.emplace(low, int(c)).second)
            return makeError(ErrorCode::ParseError,
                             where(source, headerLine) + ": column \"" + text::toUtf8(name) + "\" appears twice");
        int k = -1;
        for (int j = 0; j < 6; ++j)
            if (low == kKnown[j]) k = j;
        if (k >= 0) {
            col[k] = int(c);
        } else {
            rows.names.push_back(text::toUtf8(name));
            rows.units.push_back(text::toUtf8(unit));
            propCol.push_back(c);
        }
    }
    for (int j = 0; j < 6; ++j)
        if (col[j] < 0)
            return makeError(ErrorCode::ParseError, where(source, headerLine) +
                                                        ": the header needs columns x,y,z,dx,dy,dz and at least one "
                                                        "value column (no \"" +
                                                        kKnown[j] + "\")");
    if (propCol.empty())
        return makeError(ErrorCode::ParseError,
                         where(source, headerLine) + ": the header needs at least one value column after x..dz");
    rows.values.resize(propCol.size());
    while (pos < text.size()) {
        const std::size_t rowLine = line;
        const std::size_t before = pos;
        std::vector<std::string> f = text::csvRecord(text, pos, badQuote, sep);
        line +=
            std::size_t(std::count(text.begin() + std::ptrdiff_t(before), text.begin() + std::ptrdiff_t(pos), '\n'));
        if (badQuote) return makeError(ErrorCode::ParseError, where(source, rowLine) + ": unterminated quote");
        if (f.size() == 1 && text::trim(f[0]).empty()) continue;
        if (f.size() != header.size())
            return makeError(ErrorCode::ParseError, where(source, rowLine) + ": " + std::to_string(f.size()) +
                                                        " fields, the header has " + std::to_string(header.size()));
        double v[6];
        for (int j = 0; j < 6; ++j) {
            const std::string_view s = text::trim(f[std::size_t(col[j])]);
            const auto d = text::parseDouble(s);
            if (!d || !std::isfinite(*d))
                return makeError(ErrorCode::ParseError, where(source, rowLine) + ": " + kKnown[j] + " " +
                                                            text::quoteToken(s) + " is not a finite number");
            if (j >= 3 && !(*d > 0.0))
                return makeError(ErrorCode::ParseError, where(source, rowLine) + ": " + kKnown[j] + " " +
                                                            text::quoteToken(s) + ": block size must be > 0");
            v[j] = *d;
        }
        for (std::size_t p = 0; p < propCol.size(); ++p) {
            const std::string_view s = text::trim(f[propCol[p]]);
            double d = std::numeric_limits<double>::quiet_NaN();
            if (!s.empty()) {
                const auto parsed = text::parseDouble(s);
                if (!parsed || !std::isfinite(*parsed))
                    return makeError(ErrorCode::ParseError, where(source, rowLine) + ": " + rows.names[p] + " " +
                                                                text::quoteToken(s) +
                                                                " is not a finite number (leave it empty for none)");
                d = *parsed;
            }
            rows.values[p].push_back(d);
        }
        rows.centres.push_back({v[0], v[1], v[2]});
        rows.sizes.push_back({v[3], v[4], v[5]});
        rows.lines.push_back(rowLine);
    }
    return rows;
}

Result<BlockModel> blockModelFromCsv(std::string_view text, const std::string& source) {
    auto parsed = readBlockRows(text, source);
    if (!parsed) return parsed.error();
    const BlockRows& rows = parsed.value();
    if (rows.centres.empty()) return makeError(ErrorCode::ParseError, source + ": no blocks (a header and no rows)");
    BlockModel b;
    b.source = source;
    const glm::dvec3 size = rows.sizes[0];
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (std::size_t r = 0; r < rows.centres.size(); ++r) {
        const glm::dvec3 d = glm::abs(rows.sizes[r] - size);
        if (d.x > 1e-9 * size.x || d.y > 1e-9 * size.y || d.z > 1e-9 * size.z)
            return makeError(ErrorCode::ParseError,
                             where(source, rows.lines[r]) +
                                 ": block size differs from the first row's: a block model is one regular grid "
                                 "(sub-blocks are not supported)");
        lo = glm::min(lo, rows.centres[r]);
        hi = glm::max(hi, rows.centres[r]);
        for (int a = 0; a < 3; ++a)
            if (!(std::abs(rows.centres[r][a]) <= kMaxCoordinateMetres) || !(rows.sizes[r][a] <= kMaxCoordinateMetres))
                return makeError(ErrorCode::OutOfRange, where(source, rows.lines[r]) + ": a centre or size beyond " +
                                                            std::to_string(kMaxCoordinateMetres) + " m");
    }
    // Cells must be far larger than a double's step at these coordinates (1e6 steps), or a
    // point could not be placed in its cell.
    for (int a = 0; a < 3; ++a) {
        const double reach = std::max({1.0, std::abs(lo[a]), std::abs(hi[a])});
        if (!(size[a] >= 1e-9 * reach))
            return makeError(ErrorCode::OutOfRange,
                             where(source, rows.lines[0]) + ": a cell size of " + std::to_string(size[a]) +
                                 " m is below the resolution of coordinates near " + std::to_string(reach) + " m");
    }
    b.origin = lo - 0.5 * size;
    b.size = {size.x, size.y, size.z};
    double cells = 1.0;
    for (int a = 0; a < 3; ++a) {
        const double n = std::round((hi[a] - lo[a]) / size[a]) + 1.0;
        cells *= n;
        b.dims[std::size_t(a)] = std::size_t(std::min(n, 1e12));
    }
    if (cells > double(kMaxBlockCells))
        return makeError(ErrorCode::OutOfRange, source + ": the rows span a grid of " + std::to_string(b.dims[0]) +
                                                    " x " + std::to_string(b.dims[1]) + " x " +
                                                    std::to_string(b.dims[2]) + " cells, over the limit of " +
                                                    std::to_string(kMaxBlockCells));
    const std::size_t n = b.cellCount();
    for (std::size_t p = 0; p < rows.names.size(); ++p)
        b.properties.push_back(
            {rows.names[p], rows.units[p], std::vector<double>(n, std::numeric_limits<double>::quiet_NaN())});
    std::vector<std::uint8_t> taken(n, 0);
    for (std::size_t r = 0; r < rows.centres.size(); ++r) {
        std::size_t idx[3];
        for (int a = 0; a < 3; ++a) {
            const double t = (rows.centres[r][a] - lo[a]) / size[a];
            const double k = std::round(t);
            // Centres within a millionth of a cell of the lattice (text rounding of the centres).
            if (std::abs(t - k) > 1e-6)
                return makeError(ErrorCode::ParseError, where(source, rows.lines[r]) + ": the centre is " +
                                                            std::to_string(std::abs(t - k)) + " cells off the grid " +
                                                            "of the other rows (a block model is one regular grid)");
            idx[a] = std::size_t(k);
        }
        const std::size_t c = b.linear(idx[0], idx[1], idx[2]);
        if (taken[c]++)
            return makeError(ErrorCode::ParseError, where(source, rows.lines[r]) + ": a second row for cell (" +
                                                        std::to_string(idx[0]) + ", " + std::to_string(idx[1]) + ", " +
                                                        std::to_string(idx[2]) + ")");
        for (std::size_t p = 0; p < rows.names.size(); ++p) b.properties[p].values[c] = rows.values[p][r];
    }
    return b;
}

namespace {

std::string cellName(const std::array<std::size_t, 3>& ijk) {
    return "cell (" + std::to_string(ijk[0]) + ", " + std::to_string(ijk[1]) + ", " + std::to_string(ijk[2]) + ")";
}

// The grid's cell properties, one value per cell.
Status addGridProperties(const Grid& grid, const std::string& name, BlockModel& b) {
    for (const GridProperty& p : grid.properties) {
        if (p.values.size() != b.cellCount())
            return makeError(ErrorCode::Unsupported, name + " property '" + p.name +
                                                         "': " + std::to_string(p.values.size()) + " values for " +
                                                         std::to_string(b.cellCount()) + " cells");
        b.properties.push_back({p.name, p.unit, std::vector<double>(p.values.begin(), p.values.end())});
    }
    return {};
}

// An SGrid's cells (see the header): corners = its points, every tetrahedron of the split
// positive in the grid's orientation.
Result<BlockModel> curvilinearBlockModel(const Grid& grid, const std::string& name) {
    BlockModel b;
    b.source = name;
    b.shape = CellShape::Hexahedron;
    double cells = 1.0;
    for (int a = 0; a < 3; ++a) {
        if (grid.dims[a] < 2)
            return makeError(ErrorCode::InvalidArgument, name + ": " + std::to_string(grid.dims[a]) +
                                                             " point(s) along axis " + std::to_string(a) +
                                                             ": a block model needs at least one cell (2 points)");
        b.dims[std::size_t(a)] = grid.dims[a] - 1;
        cells *= double(b.dims[std::size_t(a)]);
    }
    if (cells > double(kMaxBlockCells))
        return makeError(ErrorCode::OutOfRange, name + ": " + std::to_string(std::size_t(cells)) +
                                                    " cells, over the limit of " + std::to_string(kMaxBlockCells));
    if (grid.points.size() != grid.sampleCount())
        return makeError(ErrorCode::InvalidArgument, name + ": " + std::to_string(grid.points.size()) +
                                                         " points for AXIS_N's " + std::to_string(grid.sampleCount()));
    if (!grid.cellCentred)
        return makeError(ErrorCode::Unsupported,
                         name +
                             ": its properties are on points (PROP_ALIGNMENT POINTS); a curvilinear block model "
                             "needs properties on cells (PROP_ALIGNMENT CELLS), one value per hexahedron between "
                             "the points");
    for (std::size_t p = 0; p < grid.points.size(); ++p)
        if (!std::isfinite(grid.points[p].x) || !std::isfinite(grid.points[p].y) || !std::isfinite(grid.points[p].z)) {
            const std::size_t i = p % grid.dims[0], j = (p / grid.dims[0]) % grid.dims[1],
                              k = p / (grid.dims[0] * grid.dims[1]);
            return makeError(
                ErrorCode::InvalidArgument,
                name + ": point (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                    ") is not finite (a corner of " +
                    cellName({std::min(i, b.dims[0] - 1), std::min(j, b.dims[1] - 1), std::min(k, b.dims[2] - 1)}) +
                    ")");
        }
    b.corners = grid.points;
    b.origin = grid.points.front();
    // The grid's orientation: the sign of its total volume.
    double total = 0.0;
    for (std::size_t c = 0; c < b.cellCount(); ++c) {
        const auto k = b.cellCorners(c);
        for (const auto& t : kCellTets) total += tetVolume6(k[t[0]], k[t[1]], k[t[2]], k[t[3]]);
    }
    const double handed = total < 0.0 ? -1.0 : 1.0;
    std::vector<Aabb> bounds(b.cellCount());
    for (std::size_t c = 0; c < b.cellCount(); ++c) {
        const auto k = b.cellCorners(c);
        for (const glm::dvec3& p : k) bounds[c].extend(p);
        const glm::dvec3 e = bounds[c].size();
        const double scale = std::max({e.x, e.y, e.z});
        for (std::size_t t = 0; t < kCellTets.size(); ++t) {
            const auto& tet = kCellTets[t];
            const double v = handed * tetVolume6(k[tet[0]], k[tet[1]], k[tet[2]], k[tet[3]]);
            if (!(v > 1e-12 * scale * scale * scale)) {
                char buf[64];
                std::snprintf(buf, sizeof buf, "%.6g", v / 6.0);
                return makeError(ErrorCode::InvalidArgument,
                                 name + ": " + cellName(b.ijk(c)) + " is " + (v < 0.0 ? "inverted" : "flat") +
                                     ": its tetrahedron of corners " + std::to_string(tet[0]) + "," +
                                     std::to_string(tet[1]) + "," + std::to_string(tet[2]) + "," +
                                     std::to_string(tet[3]) + " has volume " + buf +
                                     " m³ in the grid's orientation (a block model's cells need positive volume; "
                                     "corners numbered bit 0 = +i, bit 1 = +j, bit 2 = +k)");
            }
        }
    }
    b.locator = std::make_shared<const CellLocator>(bounds);
    return b;
}

}  // namespace

Result<BlockModel> blockModelFromGrid(const Grid& grid) {
    const std::string name = grid.type + " '" + grid.name + "'";
    if (grid.properties.empty()) return makeError(ErrorCode::Unsupported, name + ": the grid has no properties");
    if (grid.type == "SGrid" || !grid.points.empty()) {
        auto b = curvilinearBlockModel(grid, name);
        if (!b) return b.error();
        if (Status st = addGridProperties(grid, name, *b); !st) return st.error();
        return b;
    }
    BlockModel b;
    b.source = name;
    for (int a = 0; a < 3; ++a) {
        const double len = glm::length(grid.step[a]);
        if (!(len > 0.0) || !std::isfinite(len))
            return makeError(ErrorCode::Unsupported,
                             name + ": axis " + std::to_string(a) + " has a zero step (one sample along it)");
        b.axis[std::size_t(a)] = grid.step[a] / len;
        b.size[std::size_t(a)] = len;
    }
    for (int a = 0; a < 3; ++a)
        for (int c = a + 1; c < 3; ++c)
            if (std::abs(glm::dot(b.axis[std::size_t(a)], b.axis[std::size_t(c)])) > 1e-9)
                return makeError(ErrorCode::Unsupported,
                                 name + ": the grid's axes are not orthogonal (its cells are not boxes)");
    if (grid.cellCentred) {
        b.origin = grid.origin;
        for (int a = 0; a < 3; ++a) b.dims[std::size_t(a)] = grid.dims[a] > 1 ? grid.dims[a] - 1 : 1;
    } else {
        b.origin = grid.origin - 0.5 * (grid.step[0] + grid.step[1] + grid.step[2]);
        for (int a = 0; a < 3; ++a) b.dims[std::size_t(a)] = grid.dims[a];
    }
    if (Status st = addGridProperties(grid, name, b); !st) return st.error();
    return b;
}

}  // namespace geoslice
