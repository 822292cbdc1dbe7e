#include "renderer/lod/cluster_build.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace geoslice {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

CellGrid makeGrid(const Aabb& local, std::size_t triangles, std::size_t perCell, std::size_t maxCells) {
    CellGrid g;
    if (!local.valid()) return g;
    const double target = double(std::clamp<std::size_t>(triangles / std::max<std::size_t>(perCell, 1), 1,
                                                         std::clamp<std::size_t>(maxCells, 1, GpuModel::kMaxCells)));
    const glm::dvec3 extent = glm::max(local.size(), glm::dvec3(1e-3));
    const double k = std::cbrt(target / (extent.x * extent.y * extent.z));
    for (int a = 0; a < 3; ++a) g.dims[a] = std::max(1, int(std::floor(extent[a] * k)));
    g.min = local.min;
    g.cellSize = extent / glm::dvec3(g.dims);
    return g;
}

double buildClusters(const CellGrid& grid, const std::vector<glm::vec3>& local,
                     std::span<const std::uint32_t> partIndices, bool lod, int lodLevels, GpuModel::DrawPart& d,
                     std::vector<std::uint32_t>& sorted, std::vector<std::uint32_t>& lodIndices,
                     std::vector<Aabb>& cellBounds, std::vector<std::uint32_t>& remap) {
    double ms = 0.0;
    // Triangles by the cell of their centroid (counting sort keeps the input order
    // within a cell, so the output is deterministic).
    const std::size_t triCount = partIndices.size() / 3;
    std::vector<std::uint32_t> cellOf(triCount);
    std::vector<std::uint32_t> start(grid.count() + 1, 0);
    for (std::size_t t = 0; t < triCount; ++t) {
        const glm::dvec3 c = (glm::dvec3(local[partIndices[3 * t]]) + glm::dvec3(local[partIndices[3 * t + 1]]) +
                              glm::dvec3(local[partIndices[3 * t + 2]])) /
                             3.0;
        cellOf[t] = grid.cellOf(c);
        ++start[cellOf[t] + 1];
    }
    for (std::size_t c = 0; c < grid.count(); ++c) start[c + 1] += start[c];
    sorted.assign(partIndices.size(), 0);
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t t = 0; t < triCount; ++t) {
            const std::uint32_t at = fill[cellOf[t]]++;
            for (int k = 0; k < 3; ++k)
                sorted[3 * std::size_t(at) + std::size_t(k)] = partIndices[3 * t + std::size_t(k)];
        }
    }
    remap.assign(local.size(), std::numeric_limits<std::uint32_t>::max());
    std::vector<glm::vec3> compactPos;
    std::vector<std::uint32_t> compactIdx, back, prev, out;
    for (std::uint32_t cell = 0; cell < grid.count(); ++cell) {
        if (start[cell] == start[cell + 1]) continue;
        GpuModel::DrawPart::Cluster cl;
        cl.cell = cell;
        cl.first[0] = d.firstIndex + 3 * std::size_t(start[cell]);
        cl.count[0] = GLsizei(3 * std::size_t(start[cell + 1] - start[cell]));
        const std::uint32_t* tri = sorted.data() + 3 * std::size_t(start[cell]);
        for (GLsizei i = 0; i < cl.count[0]; ++i) cellBounds[cell].extend(glm::dvec3(local[tri[i]]));
        // Tiny clusters are not worth a draw call per level.
        if (lod && cl.count[0] >= 3 * 64) {
            const auto t0 = std::chrono::steady_clock::now();
            compactPos.clear();
            compactIdx.clear();
            back.clear();
            for (GLsizei i = 0; i < cl.count[0]; ++i) {
                std::uint32_t& r = remap[tri[i]];
                if (r == std::numeric_limits<std::uint32_t>::max()) {
                    r = std::uint32_t(compactPos.size());
                    compactPos.push_back(local[tri[i]]);
                    back.push_back(tri[i]);
                }
                compactIdx.push_back(r);
            }
            for (std::uint32_t v : back) remap[v] = std::numeric_limits<std::uint32_t>::max();
            const float scale = meshopt_simplifyScale(&compactPos[0].x, compactPos.size(), sizeof(glm::vec3));
            prev = compactIdx;
            float cumulative = 0.0f;
            while (cl.levels < lodLevels) {
                const std::size_t target = std::max<std::size_t>(prev.size() / 4 / 3 * 3, 3);
                out.resize(prev.size());
                float err = 0.0f;
                const std::size_t n =
                    meshopt_simplify(out.data(), prev.data(), prev.size(), &compactPos[0].x, compactPos.size(),
                                     sizeof(glm::vec3), target, 1.0f, meshopt_SimplifyLockBorder, &err);
                if (n == 0 || n * 10 > prev.size() * 8) break;  // locked borders: no real progress
                cumulative += err * scale;
                const int l = cl.levels++;
                cl.first[l] = lodIndices.size();
                cl.count[l] = GLsizei(n);
                cl.error[l] = cumulative;
                for (std::size_t i = 0; i < n; ++i) lodIndices.push_back(back[out[i]]);
                prev.assign(out.begin(), out.begin() + std::ptrdiff_t(n));
            }
            ms += msSince(t0);
        }
        d.clusters.push_back(cl);
    }
    if (lod) {
        const auto t0 = std::chrono::steady_clock::now();
        // Blocks of 2, 4 and 8 cells a side, each merging the groups of the level below
        // (or its clusters' coarsest levels where there is none).
        std::vector<std::int32_t> cover(d.clusters.size(), -1);  // finest group so far
        for (std::uint32_t side = 2; side <= 8; side *= 2) {
            auto blockOf = [&](std::uint32_t cell) {
                const glm::uvec3 c(grid.coordsOf(cell));
                const std::uint32_t bx = (std::uint32_t(grid.dims.x) + side - 1) / side,
                                    by = (std::uint32_t(grid.dims.y) + side - 1) / side;
                return ((c.z / side) * by + c.y / side) * bx + c.x / side;
            };
            std::vector<std::pair<std::uint32_t, std::uint32_t>> byBlock;
            for (std::uint32_t i = 0; i < d.clusters.size(); ++i) byBlock.emplace_back(blockOf(d.clusters[i].cell), i);
            std::sort(byBlock.begin(), byBlock.end());
            std::vector<std::int32_t> nextCover = cover;
            for (std::size_t b0 = 0; b0 < byBlock.size();) {
                std::size_t b1 = b0;
                while (b1 < byBlock.size() && byBlock[b1].first == byBlock[b0].first) ++b1;
                GpuModel::DrawPart::Group grp;
                std::vector<std::uint32_t> merged;
                std::vector<std::int32_t> usedGroups;
                float memberError = 0.0f;
                std::size_t sources = 0;
                for (std::size_t k = b0; k < b1; ++k) {
                    const std::uint32_t ci = byBlock[k].second;
                    grp.members.push_back(ci);
                    if (cover[ci] >= 0) {
                        if (std::find(usedGroups.begin(), usedGroups.end(), cover[ci]) != usedGroups.end()) continue;
                        usedGroups.push_back(cover[ci]);
                        const GpuModel::DrawPart::Group& sub = d.groups[std::size_t(cover[ci])];
                        merged.insert(merged.end(), lodIndices.begin() + std::ptrdiff_t(sub.first),
                                      lodIndices.begin() + std::ptrdiff_t(sub.first) + sub.count);
                        memberError = std::max(memberError, sub.error);
                    } else {
                        const GpuModel::DrawPart::Cluster& c = d.clusters[ci];
                        const int l = c.levels - 1;
                        const std::uint32_t* src =
                            l == 0 ? sorted.data() + (c.first[0] - d.firstIndex) : lodIndices.data() + c.first[l];
                        merged.insert(merged.end(), src, src + c.count[l]);
                        memberError = std::max(memberError, c.error[l]);
                    }
                    ++sources;
                }
                b0 = b1;
                if (sources < 2 || merged.size() < 3 * 128) continue;
                compactPos.clear();
                compactIdx.clear();
                back.clear();
                for (std::uint32_t v : merged) {
                    std::uint32_t& r = remap[v];
                    if (r == std::numeric_limits<std::uint32_t>::max()) {
                        r = std::uint32_t(compactPos.size());
                        compactPos.push_back(local[v]);
                        back.push_back(v);
                    }
                    compactIdx.push_back(r);
                }
                for (std::uint32_t v : back) remap[v] = std::numeric_limits<std::uint32_t>::max();
                const float scale = meshopt_simplifyScale(&compactPos[0].x, compactPos.size(), sizeof(glm::vec3));
                prev = compactIdx;
                float cumulative = 0.0f;
                // Up to three levels per group, each about half the one before; every one
                // is a group entry of its own (finer first).
                for (int round = 0; round < 3; ++round) {
                    out.resize(prev.size());
                    float err = 0.0f;
                    const std::size_t n = meshopt_simplify(
                        out.data(), prev.data(), prev.size(), &compactPos[0].x, compactPos.size(), sizeof(glm::vec3),
                        std::max<std::size_t>(prev.size() / 2 / 3 * 3, 3), 1.0f, meshopt_SimplifyLockBorder, &err);
                    if (n == 0 || n * 10 > prev.size() * 8) break;
                    cumulative += err * scale;
                    prev.assign(out.begin(), out.begin() + std::ptrdiff_t(n));
                    GpuModel::DrawPart::Group level = grp;
                    level.first = lodIndices.size();
                    level.count = GLsizei(prev.size());
                    level.error = memberError + cumulative;
                    for (std::uint32_t i : prev) lodIndices.push_back(back[i]);
                    for (std::uint32_t m : grp.members) nextCover[m] = std::int32_t(d.groups.size());
                    d.groups.push_back(std::move(level));
                }
            }
            cover = std::move(nextCover);
        }
        ms += msSince(t0);
    }
    return ms;
}

}  // namespace geoslice
