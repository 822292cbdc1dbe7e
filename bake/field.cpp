// Spatially varying attributes (issue 4, section 5): a block model of grades, its classes,
// a uniform-grid index (cell = median block size) that finds the block holding a point, and
// the barycentric interpolation of a per-vertex property (TSurf PVRTX).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "bake/bake.hpp"
#include "bake/field.hpp"

namespace geoslice::bake {
namespace {

std::vector<std::string_view> splitRow(std::string_view line, char sep) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= line.size(); ++i)
        if (i == line.size() || line[i] == sep) {
            std::string_view f = line.substr(start, i - start);
            while (!f.empty() && (f.front() == ' ' || f.front() == '\t' || f.front() == '"')) f.remove_prefix(1);
            while (!f.empty() && (f.back() == ' ' || f.back() == '\t' || f.back() == '\r' || f.back() == '"'))
                f.remove_suffix(1);
            out.push_back(f);
            start = i + 1;
        }
    return out;
}

}  // namespace

Result<BlockModel> parseBlockCsv(std::string_view text, const std::string& source) {
    BlockModel b;
    std::size_t pos = 0, lineNo = 0;
    int col[7] = {-1, -1, -1, -1, -1, -1, -1};  // x y z dx dy dz value
    std::size_t columns = 0;
    char sep = ',';
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++lineNo;
        if (line.find_first_not_of(" \t\r") == std::string_view::npos) continue;
        if (columns == 0) {
            sep = line.find(';') != std::string_view::npos && line.find(',') == std::string_view::npos ? ';' : ',';
            const auto names = splitRow(line, sep);
            columns = names.size();
            static const char* known[6] = {"x", "y", "z", "dx", "dy", "dz"};
            for (std::size_t i = 0; i < names.size(); ++i) {
                std::string n(names[i]);
                std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return char(std::tolower(c)); });
                int k = -1;
                for (int j = 0; j < 6; ++j)
                    if (n == known[j]) k = j;
                if (k < 0) {
                    if (col[6] >= 0)
                        return makeError(ErrorCode::ParseError, source + ":" + std::to_string(lineNo) +
                                                                    ": more than one value column (\"" + b.name +
                                                                    "\", \"" + std::string(names[i]) + "\")");
                    col[6] = int(i);
                    b.name = std::string(names[i]);
                } else {
                    col[k] = int(i);
                }
            }
            for (int j = 0; j < 7; ++j)
                if (col[j] < 0)
                    return makeError(ErrorCode::ParseError,
                                     source + ":" + std::to_string(lineNo) +
                                         ": the header needs columns x,y,z,dx,dy,dz and one value column");
            continue;
        }
        const auto f = splitRow(line, sep);
        if (f.size() != columns)
            return makeError(ErrorCode::ParseError, source + ":" + std::to_string(lineNo) + ": " +
                                                        std::to_string(f.size()) + " fields, the header has " +
                                                        std::to_string(columns));
        double v[7];
        for (int j = 0; j < 7; ++j) {
            const std::string_view s = f[std::size_t(col[j])];
            auto [next, ec] = std::from_chars(s.data(), s.data() + s.size(), v[j]);
            if (ec != std::errc() || next != s.data() + s.size() || !std::isfinite(v[j]))
                return makeError(ErrorCode::ParseError, source + ":" + std::to_string(lineNo) + ": \"" +
                                                            std::string(s.substr(0, 40)) + "\" is not a finite number");
            if (j >= 3 && j < 6 && !(v[j] > 0.0))
                return makeError(ErrorCode::ParseError,
                                 source + ":" + std::to_string(lineNo) + ": block size must be > 0");
        }
        b.centres.push_back({v[0], v[1], v[2]});
        b.sizes.push_back({v[3], v[4], v[5]});
        b.values.push_back(v[6]);
    }
    if (columns == 0) return makeError(ErrorCode::ParseError, source + ": empty block model (no header)");
    if (b.values.empty()) return makeError(ErrorCode::ParseError, source + ": no blocks");
    return b;
}

BlockIndex::BlockIndex(const BlockModel& blocks) : blocks_(blocks) {
    std::vector<double> s;
    for (const auto& d : blocks.sizes) s.push_back(std::min({d.x, d.y, d.z}));
    std::nth_element(s.begin(), s.begin() + std::ptrdiff_t(s.size() / 2), s.end());
    // The median block size, but at least 1/32 of the largest block's side, so that no block
    // spans more than 33 cells per axis.
    double largest = 0.0;
    for (const auto& d : blocks.sizes) largest = std::max({largest, d.x, d.y, d.z});
    cell_ = std::max(s[s.size() / 2], largest / 32.0);
    // Smallest block first, so that the first block found holding a point is the smallest.
    std::vector<std::uint32_t> order(blocks.values.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        const auto& sa = blocks.sizes[a];
        const auto& sb = blocks.sizes[b];
        return sa.x * sa.y * sa.z < sb.x * sb.y * sb.z;
    });
    for (std::uint32_t i : order) {
        const glm::dvec3 lo = blocks.centres[i] - 0.5 * blocks.sizes[i], hi = blocks.centres[i] + 0.5 * blocks.sizes[i];
        const glm::dvec3 a = glm::floor(lo / cell_), b = glm::floor(hi / cell_);
        for (double z = a.z; z <= b.z; ++z)
            for (double y = a.y; y <= b.y; ++y)
                for (double x = a.x; x <= b.x; ++x) grid_[key(x, y, z)].push_back(i);
    }
}

std::uint64_t BlockIndex::key(double x, double y, double z) {
    auto u = [](double v) { return std::uint64_t(std::int64_t(v) & 0x1FFFFF); };
    return u(x) | u(y) << 21 | u(z) << 42;
}

int BlockIndex::find(const glm::dvec3& p) const {
    const glm::dvec3 c = glm::floor(p / cell_);
    auto it = grid_.find(key(c.x, c.y, c.z));
    if (it == grid_.end()) return -1;
    for (std::uint32_t i : it->second) {
        const glm::dvec3 d = glm::abs(p - blocks_.centres[i]);
        const glm::dvec3 h = 0.5 * blocks_.sizes[i];
        if (d.x <= h.x && d.y <= h.y && d.z <= h.z) return int(i);
    }
    return -1;
}

int fieldClass(const std::vector<double>& breaks, double value) {
    return int(std::upper_bound(breaks.begin(), breaks.end(), value) - breaks.begin());
}

int propertyColumn(const Mesh& mesh, const std::string& name) {
    for (std::size_t k = 0; k < mesh.propertyNames.size(); ++k)
        if (mesh.propertyNames[k] == name) return int(k);
    return -1;
}

double interpolateProperty(const Mesh& mesh, int column, std::size_t triangle, const glm::dvec3& bary) {
    const std::size_t columns = mesh.propertyNames.size();
    double sum = 0.0;
    for (int e = 0; e < 3; ++e) {
        const std::size_t v = mesh.indices[3 * triangle + std::size_t(e)];
        const double value = mesh.propertyValues[v * columns + std::size_t(column)];
        if (std::isnan(value)) return std::numeric_limits<double>::quiet_NaN();
        sum += bary[e] * value;
    }
    return sum;
}

}  // namespace geoslice::bake
