// The "octree voxel method" of the paper's Table 1, as a benchmark baseline (never part of
// the product). The paper names the method and measures it (init, slice, memory, query,
// 86-91 % attribute accuracy from "geometric approximation errors introduced by
// voxelization at stratigraphic boundaries") but gives no construction; this is the usual
// adaptive one that its description implies:
//
// - a cube over the model bounds, subdivided down to `depth` levels wherever a cell may
//   touch a body's surface (conservative: the triangle's bounding box overlaps the cell),
//   so boundaries get the finest voxels and homogeneous space stays coarse;
// - every leaf holds one attribute record: that of the cell's centre point, from the
//   point classifier (section/rays/classify.hpp). A leaf that touches no surface is homogeneous,
//   so its record is exact; a boundary voxel holds its centre's record and is wrong for
//   the part of it that lies across the boundary, which is the error the paper reports;
// - a section is the voxels sampled at the image's pixel centres, and an attribute query is
//   one point lookup (root to leaf).
//
// Nodes are 4 bytes: a leaf holds kLeaf | record, an internal node the index of the first
// of its 8 consecutive children. Thread-safety: build once; lookups from any thread.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "section/rays/classify.hpp"

namespace geoslice::bench {

class VoxelOctree {
public:
    static constexpr std::uint32_t kLeaf = 0x80000000u;

    // depth 1..10 (finest voxel = cube side / 2^depth). Bodies only (surfaces carry no
    // volume record). `threads` for the classification of leaf centres.
    static VoxelOctree build(const Model& model, const Classifier& oracle, int depth, unsigned threads = 2);

    RecordId lookup(const glm::dvec3& world) const {
        const glm::dvec3 q = (world - lo_) * scale_;
        if (!(q.x >= 0.0 && q.y >= 0.0 && q.z >= 0.0 && q.x < cells_ && q.y < cells_ && q.z < cells_)) return kNoRecord;
        const auto ix = static_cast<std::uint32_t>(q.x), iy = static_cast<std::uint32_t>(q.y),
                   iz = static_cast<std::uint32_t>(q.z);
        std::uint32_t node = nodes_[0];
        for (int level = depth_ - 1; !(node & kLeaf); --level) {
            const std::uint32_t child =
                ((ix >> level) & 1u) | (((iy >> level) & 1u) << 1) | (((iz >> level) & 1u) << 2);
            node = nodes_[node + child];
        }
        return node & ~kLeaf;
    }

    std::size_t nodeCount() const { return nodes_.size(); }
    std::size_t leafCount() const { return leaves_; }
    std::size_t boundaryVoxels() const { return boundary_; }
    std::size_t memoryBytes() const { return nodes_.capacity() * sizeof(std::uint32_t); }
    double voxelMetres() const { return 1.0 / scale_; }
    int depth() const { return depth_; }

private:
    std::vector<std::uint32_t> nodes_;  // nodes_[0] is the root
    glm::dvec3 lo_{0.0};
    double scale_ = 1.0;  // finest cells per metre
    double cells_ = 1.0;  // 2^depth
    int depth_ = 1;
    std::size_t leaves_ = 0, boundary_ = 0;
};

}  // namespace geoslice::bench
