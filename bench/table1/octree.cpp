#include "bench/table1/octree.hpp"

#include <algorithm>
#include <cmath>

namespace geoslice::bench {
namespace {

// Morton code of finest-cell coordinates: bit 3k is x's bit k, 3k+1 y's, 3k+2 z's, so the
// child of a node at `shift` is (code >> shift) & 7 = x | y << 1 | z << 2.
std::uint32_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    std::uint32_t c = 0;
    for (int b = 0; b < 10; ++b)
        c |= (((x >> b) & 1u) << (3 * b)) | (((y >> b) & 1u) << (3 * b + 1)) | (((z >> b) & 1u) << (3 * b + 2));
    return c;
}

struct Builder {
    std::vector<std::uint32_t>& nodes;
    const std::vector<std::uint32_t>& codes;
    int depth;
    std::vector<std::uint32_t> leafNode;  // node index of each leaf
    std::vector<glm::dvec3> leafCentre;   // finest-cell units
    std::size_t boundary = 0;

    void build(std::uint32_t node, int level, std::size_t b, std::size_t e, std::uint32_t cx, std::uint32_t cy,
               std::uint32_t cz) {
        const std::uint32_t size = 1u << (depth - level);
        if (b == e || level == depth) {
            if (b != e) ++boundary;
            nodes[node] = VoxelOctree::kLeaf;
            leafNode.push_back(node);
            leafCentre.emplace_back(cx + 0.5 * size, cy + 0.5 * size, cz + 0.5 * size);
            return;
        }
        const auto first = static_cast<std::uint32_t>(nodes.size());
        nodes.resize(nodes.size() + 8, 0);
        nodes[node] = first;
        const int shift = 3 * (depth - 1 - level);
        const std::uint32_t half = size / 2;
        std::size_t lo = b;
        for (std::uint32_t c = 0; c < 8; ++c) {
            const std::size_t hi = static_cast<std::size_t>(
                std::partition_point(codes.begin() + static_cast<std::ptrdiff_t>(lo),
                                     codes.begin() + static_cast<std::ptrdiff_t>(e),
                                     [&](std::uint32_t code) { return ((code >> shift) & 7u) <= c; }) -
                codes.begin());
            build(first + c, level + 1, lo, hi, cx + (c & 1u) * half, cy + ((c >> 1) & 1u) * half,
                  cz + ((c >> 2) & 1u) * half);
            lo = hi;
        }
    }
};

}  // namespace

VoxelOctree VoxelOctree::build(const Model& model, const Classifier& oracle, int depth, unsigned threads) {
    VoxelOctree o;
    o.depth_ = std::clamp(depth, 1, 10);
    const Aabb b = model.bounds();
    const glm::dvec3 ext = b.max - b.min;
    const double side = std::max({ext.x, ext.y, ext.z}) * (1.0 + 1e-9) + 1e-6;
    o.lo_ = b.min;
    o.cells_ = double(1u << o.depth_);
    o.scale_ = o.cells_ / side;
    const auto maxCell = static_cast<std::int64_t>(o.cells_) - 1;

    // Finest voxels that may touch a body surface (triangle bounding box overlap).
    std::vector<std::uint32_t> codes;
    for (const Part& part : model.bodies) {
        const Mesh& m = part.mesh;
        for (std::size_t t = 0; t < m.triangleCount(); ++t) {
            glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3 p = (m.positions[m.indices[3 * t + std::size_t(k)]] - o.lo_) * o.scale_;
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
            if (!std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z)) continue;
            std::int64_t a[3], z[3];
            for (int k = 0; k < 3; ++k) {
                a[k] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(lo[k])), 0, maxCell);
                z[k] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(hi[k])), 0, maxCell);
            }
            for (std::int64_t x = a[0]; x <= z[0]; ++x)
                for (std::int64_t y = a[1]; y <= z[1]; ++y)
                    for (std::int64_t w = a[2]; w <= z[2]; ++w)
                        codes.push_back(morton(std::uint32_t(x), std::uint32_t(y), std::uint32_t(w)));
        }
        // Keep the working set small: dedupe as we go.
        std::sort(codes.begin(), codes.end());
        codes.erase(std::unique(codes.begin(), codes.end()), codes.end());
    }

    o.nodes_.assign(1, kLeaf);
    Builder bld{o.nodes_, codes, o.depth_, {}, {}, 0};
    bld.build(0, 0, 0, codes.size(), 0, 0, 0);
    o.nodes_.shrink_to_fit();
    o.leaves_ = bld.leafNode.size();
    o.boundary_ = bld.boundary;

    // Every leaf's record: its centre's.
    std::vector<glm::dvec3> centres(bld.leafCentre.size());
    for (std::size_t i = 0; i < centres.size(); ++i) centres[i] = o.lo_ + bld.leafCentre[i] / o.scale_;
    std::vector<RecordId> records(centres.size());
    oracle.classifyBatch(centres.data(), centres.size(), records.data(), threads);
    for (std::size_t i = 0; i < records.size(); ++i) o.nodes_[bld.leafNode[i]] = kLeaf | records[i];
    return o;
}

}  // namespace geoslice::bench
