// Internal to bake/: the block index used while rasterizing a field. Not part of the API.
#pragma once

#include <cstdint>
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

}  // namespace geoslice::bake
