// Internal to bake/: the block index and the per-vertex property lookups used while
// rasterizing a field. Not part of the API.
#pragma once

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

}  // namespace geoslice::bake
