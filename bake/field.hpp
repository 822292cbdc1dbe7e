// Internal to bake/: the block index, the per-vertex property lookups used while rasterizing a
// field, and the field's class record ids and attribute records. Not part of the API.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "bake/bake.hpp"

namespace geoslice::bake {

// Finds the block holding a world point; immutable after construction (any thread may call
// find()). Uniform grid hash with the median block size as its cell.
class BlockIndex {
public:
    explicit BlockIndex(const BlockModel& blocks);
    int find(const glm::dvec3& world) const;  // block index or -1

private:
    static std::uint64_t key(double x, double y, double z);
    const BlockModel& blocks_;
    double cell_ = 1.0;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid_;
};

// The class of a value: the number of breaks <= value.
int fieldClass(const std::vector<double>& breaks, double value);

// Column of the per-vertex property `name` in a mesh (exact name, as Mesh::propertyNames
// holds it), or -1 when the mesh does not have it.
int propertyColumn(const Mesh& mesh, const std::string& name);

// The property in column `column` at barycentric weights `bary` of triangle `triangle` of
// `mesh`: sum of weight x value over the triangle's three source vertices (mesh.indices).
// NaN when any of the three values is NaN (no data). Preconditions (checked by the caller):
// column < propertyNames.size(), propertyValues holds vertexCount() x propertyNames.size()
// values, indices are in range.
double interpolateProperty(const Mesh& mesh, int column, std::size_t triangle, const glm::dvec3& bary);

// Record ids of a field bake: one per (part record, class), from `base` up.
struct FieldIds {
    const BlockIndex* index = nullptr;  // block field only
    const FieldOptions* options = nullptr;
    std::vector<RecordId> partRecords;  // sorted, unique, no 0
    RecordId base = 0;
    // The record of a part record's class of `value`; the part record itself for NaN values
    // and records without classes.
    RecordId classRecord(RecordId partRecord, double value) const {
        if (partRecord == kNoRecord || std::isnan(value)) return partRecord;
        const auto it = std::lower_bound(partRecords.begin(), partRecords.end(), partRecord);
        if (it == partRecords.end() || *it != partRecord) return partRecord;
        const int k = fieldClass(options->breaks, value);
        return base + RecordId(it - partRecords.begin()) * RecordId(options->breaks.size() + 1) + RecordId(k);
    }
    // Block field: the record at a world point.
    RecordId at(RecordId partRecord, const glm::dvec3& world) const {
        if (partRecord == kNoRecord) return partRecord;
        const int b = index->find(world);
        if (b < 0) return partRecord;
        return classRecord(partRecord, options->blocks->values[std::size_t(b)]);
    }
};

// The attribute records of a field bake's classes (BakedModel::fieldRecords): for each of
// field.partRecords (r) and each class k of field.options->breaks, id field.base + r x
// (breaks + 1) + k, a copy of the part record's row in `table` (or an empty row) named
// "<record name>, <field name> <range>", its grade the class's midpoint (its one finite end for
// the first and last class; none without breaks), gradeUnit the field's unit, extra {field,
// class, min, max, parent}, and its colour blended from dark (lowest class) to a warm tint
// (highest) over the record's own hue.
std::vector<AttributeRecord> fieldClassRecords(const AttributeTable& table, const FieldIds& field);

}  // namespace geoslice::bake
