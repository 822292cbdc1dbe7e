// The cluster hierarchy of one part of a GpuModel (renderer/gpu_model.hpp), built on the CPU:
// no GL call, no context (meshoptimizer only), so that it is unit-tested without GL
// (tests/unit/cluster_build_test.cpp). GpuModel::upload builds every part with it, then uploads
// the result; ClusterSelection (renderer/lod/cluster_selection.hpp) picks from it per frame.
//
//   cells     a regular grid over the model's local bounds (makeGrid), about
//             GpuUploadOptions::trianglesPerCell triangles per cell
//   clusters  a part's triangles in one cell: a part is ordered by the cell of its triangles'
//             centroids (a counting sort, so the input order is kept within a cell)
//   levels    up to lodLevels - 1 simplified copies per cluster (Garland & Heckbert quadrics
//             through meshopt_simplify) with the cluster's border locked
//   groups    the clusters of a block of 2, 4 or 8 cells a side merged and simplified again
//             (GpuModel::DrawPart::Group)
// Any thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "renderer/gpu_model.hpp"

namespace geoslice {

// A regular grid over the local bounds with cells about as wide as they are tall.
struct CellGrid {
    glm::dvec3 min{0.0}, cellSize{1.0};
    glm::ivec3 dims{1};
    std::size_t count() const { return std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z); }
    std::uint32_t cellOf(const glm::dvec3& p) const {
        glm::ivec3 c;
        for (int k = 0; k < 3; ++k) c[k] = std::clamp(int(std::floor((p[k] - min[k]) / cellSize[k])), 0, dims[k] - 1);
        return indexOf(c);
    }
    // A cell's number from its grid coordinates (x fastest, then y, then z), and back.
    std::uint32_t indexOf(const glm::ivec3& c) const { return std::uint32_t((c.z * dims.y + c.y) * dims.x + c.x); }
    glm::ivec3 coordsOf(std::uint32_t cell) const {
        return {int(cell % std::uint32_t(dims.x)), int(cell / std::uint32_t(dims.x) % std::uint32_t(dims.y)),
                int(cell / std::uint32_t(dims.x) / std::uint32_t(dims.y))};
    }
};

// About max(1, triangles / perCell) cells (at most min(maxCells, GpuModel::kMaxCells)) over
// `local` (local frame, metres); one cell when the bounds are invalid.
CellGrid makeGrid(const Aabb& local, std::size_t triangles, std::size_t perCell, std::size_t maxCells);

// One part's clusters, levels and groups. `local`: the part's vertices (local frame);
// `partIndices`: its triangles (part-local vertex numbers, each < local.size()). `d.firstIndex`
// must be where the part's full-detail indices will start in the index buffer: cluster level 0
// is the range of `sorted` (the part's indices in cell order, written here) at d.firstIndex.
// Appends to d.clusters and, with `lod`, d.groups; simplified indices are appended to
// `lodIndices` and their offsets in `d` are relative to it. Extends cellBounds[cell] (one per
// grid cell) by each cluster's vertices. `remap` is scratch. Returns the milliseconds spent
// simplifying.
double buildClusters(const CellGrid& grid, const std::vector<glm::vec3>& local,
                     std::span<const std::uint32_t> partIndices, bool lod, int lodLevels, GpuModel::DrawPart& d,
                     std::vector<std::uint32_t>& sorted, std::vector<std::uint32_t>& lodIndices,
                     std::vector<Aabb>& cellBounds, std::vector<std::uint32_t>& remap);

}  // namespace geoslice
