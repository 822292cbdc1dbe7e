// Spatially varying attributes (issue 4, section 5): a block model of grades, its classes and
// their attribute records (one per part record and class, named, tinted low -> high), a
// uniform-grid index (cell = median block size) that finds the block holding a point, and the
// barycentric interpolation of a per-vertex property (TSurf PVRTX).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <unordered_map>

#include "bake/bake.hpp"
#include "bake/field.hpp"
#include "model/blocks/block_model.hpp"

namespace geoslice::bake {
Result<BlockModel> parseBlockCsv(std::string_view text, const std::string& source) {
    auto rows = readBlockRows(text, source);
    if (!rows) return rows.error();
    if (rows->names.size() != 1)
        return makeError(ErrorCode::ParseError, source + ": more than one value column (\"" + rows->names[0] +
                                                    "\", \"" + rows->names[1] + "\"): a field bake takes one");
    if (rows->centres.empty()) return makeError(ErrorCode::ParseError, source + ": no blocks");
    BlockModel b;
    b.name = rows->names[0];
    b.centres = std::move(rows->centres);
    b.sizes = std::move(rows->sizes);
    b.values = std::move(rows->values[0]);
    for (std::size_t r = 0; r < b.values.size(); ++r)
        if (std::isnan(b.values[r]))
            return makeError(ErrorCode::ParseError,
                             source + ":" + std::to_string(rows->lines[r]) + ": the value is empty");
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

std::vector<AttributeRecord> fieldClassRecords(const AttributeTable& table, const FieldIds& field) {
    std::vector<AttributeRecord> records;
    const auto& br = field.options->breaks;
    for (std::size_t r = 0; r < field.partRecords.size(); ++r)
        for (std::size_t k = 0; k <= br.size(); ++k) {
            const AttributeRecord* parent = table.find(field.partRecords[r]);
            AttributeRecord rec = parent ? *parent : AttributeRecord{};
            rec.id = field.base + RecordId(r * (br.size() + 1) + k);
            const double lo = k ? br[k - 1] : -std::numeric_limits<double>::infinity();
            const double hi = k < br.size() ? br[k] : std::numeric_limits<double>::infinity();
            char range[96];
            if (k == 0 && br.empty())
                std::snprintf(range, sizeof range, "all");
            else if (k == 0)
                std::snprintf(range, sizeof range, "< %g", hi);
            else if (k == br.size())
                std::snprintf(range, sizeof range, ">= %g", lo);
            else
                std::snprintf(range, sizeof range, "%g - %g", lo, hi);
            const std::string fieldName =
                field.options->blocks ? field.options->blocks->name : field.options->vertexProperty;
            rec.name = (parent ? parent->name : "record " + std::to_string(field.partRecords[r])) + ", " + fieldName +
                       " " + range;
            rec.grade = std::isfinite(lo) && std::isfinite(hi) ? 0.5 * (lo + hi) : (std::isfinite(lo) ? lo : hi);
            if (br.empty()) rec.grade.reset();
            if (!field.options->unit.empty()) rec.gradeUnit = field.options->unit;
            rec.extra["field"] = fieldName;
            rec.extra["class"] = k;
            if (std::isfinite(lo)) rec.extra["min"] = lo;
            if (std::isfinite(hi)) rec.extra["max"] = hi;
            rec.extra["parent"] = field.partRecords[r];
            // Classes must look different, not only carry different ids: blend the parent's
            // colour from dark (lowest class) to a bright warm tint (highest), so a
            // grade map reads low -> high like a heat scale over the stratum's own hue.
            if (br.size() > 0) {
                const double t = double(k) / double(br.size());
                const double dark = 0.55, tint[3] = {255.0, 210.0, 60.0};
                auto mix = [&](std::uint8_t c, double warm) {
                    const double base = double(c) * (dark + (1.0 - dark) * (1.0 - t));
                    return std::uint8_t(std::lround(std::clamp(base + t * 0.6 * warm, 0.0, 255.0)));
                };
                rec.colour.r = mix(rec.colour.r, tint[0]);
                rec.colour.g = mix(rec.colour.g, tint[1]);
                rec.colour.b = mix(rec.colour.b, tint[2]);
            }
            records.push_back(std::move(rec));
        }
    return records;
}

}  // namespace geoslice::bake
