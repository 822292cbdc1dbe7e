#include "renderer/lod/cluster_selection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace geoslice {

std::vector<std::uint8_t> cullingPlanes(const std::vector<glm::dvec4>& planesLocal, bool convexCut,
                                        const glm::dvec3* eyeLocal) {
    std::vector<std::uint8_t> culls(planesLocal.size(), 1);
    if (convexCut)
        for (std::size_t i = 0; i < planesLocal.size(); ++i) {
            const glm::dvec4& pl = planesLocal[i];
            culls[i] = eyeLocal && glm::dot(glm::dvec3(pl), *eyeLocal) + pl.w < 0.0;
        }
    return culls;
}

std::vector<float> cellBudgets(const std::vector<Aabb>& cells, const ClusterFrame& frame) {
    std::vector<float> allowed(cells.size(), 0.0f);
    const double f = frame.exaggeration;
    const std::vector<glm::dvec4>& planes = frame.planes;
    for (std::size_t c = 0; c < cells.size(); ++c) {
        const Aabb& b = cells[c];
        if (!b.valid()) continue;
        glm::dvec3 corner[8];
        for (int i = 0; i < 8; ++i)
            corner[i] = {i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z};
        // Slack for float32 positions and plane coefficients on the GPU.
        const double tol = 1e-3 + 1e-6 * glm::length(b.size()) + 1e-7 * glm::length(b.max);
        // witness: past a convex cut's exit (a plane that does not cull), where the fragment
        // stage reads which body a ray leaves the kept region in: full detail, like a cut.
        bool removed = frame.unionMode && !planes.empty(), crossing = false, witness = false;
        for (std::size_t i = 0; i < planes.size(); ++i) {
            const glm::dvec4& pl = planes[i];
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (const glm::dvec3& q : corner) {
                const double d = glm::dot(glm::dvec3(pl), q) + pl.w;
                lo = std::min(lo, d);
                hi = std::max(hi, d);
            }
            const bool outside = hi < -tol && frame.culls[i];
            witness = witness || (hi < -tol && !frame.culls[i]);
            removed = frame.unionMode ? (removed && outside) : (removed || outside);
            crossing = crossing || (lo <= tol && hi >= -tol);
        }
        // Outside the view: every corner beyond one clip-space plane.
        bool culled = false;
        for (int axis = 0; axis < 3 && !culled; ++axis)
            for (double side : {-1.0, 1.0}) {
                bool allOut = true;
                for (const glm::dvec3& q : corner) {
                    const glm::dvec4 clip = frame.viewProj * glm::dvec4(q, 1.0);
                    allOut = allOut && side * clip[axis] > clip.w;
                }
                culled = culled || allOut;
            }
        if (removed || culled) {
            allowed[c] = -1.0f;
            continue;
        }
        if (!frame.lod || crossing || witness) continue;  // full detail: the cut stays exact
        double pixelsPerMetre = frame.orthoPixelsPerMetre;
        if (frame.perspective) {
            const glm::dvec3& eye = frame.eyeDisplayLocal;
            const glm::dvec3 lo(b.min.x, b.min.y, f * b.min.z), hi(b.max.x, b.max.y, f * b.max.z);
            const double dist = glm::length(glm::max(glm::max(lo - eye, eye - hi), glm::dvec3(0.0)));
            if (dist <= 0.0) continue;
            pixelsPerMetre = frame.perspPixelsPerMetre / dist;
        }
        // Exaggeration stretches an error along z by up to f.
        allowed[c] = float(frame.lodPixelError / (pixelsPerMetre * std::max(1.0, f)));
    }
    return allowed;
}

void DrawBatch::add(std::size_t first, GLsizei count, GLint baseVertex) {
    if (count == 0) return;
    const void* offset = reinterpret_cast<const void*>(first * sizeof(std::uint32_t));
    // Contiguous with the previous range (full-detail clusters in index order): extend.
    if (!counts.empty() && baseVertices.back() == baseVertex &&
        static_cast<const char*>(offsets.back()) + std::size_t(counts.back()) * sizeof(std::uint32_t) ==
            static_cast<const char*>(offset)) {
        counts.back() += count;
        return;
    }
    counts.push_back(count);
    offsets.push_back(offset);
    baseVertices.push_back(baseVertex);
}

void ClusterSelection::select(const GpuModel::DrawPart& p, const std::vector<float>& allowed, bool allowGroups,
                              double exaggeration) {
    full.clear();
    for (DrawBatch& b : pushed) b.clear();
    anySimplified = false;
    skipped = 0;
    const double shiftScale = std::max(1.0, exaggeration);
    auto addSimplified = [&](std::size_t first, GLsizei count, float error) {
        const double push = 2.0 * error * shiftScale;
        const int k = push <= 0.0 ? 0 : std::clamp(int(std::ceil(std::log2(push))) + 9, 0, kShiftBuckets);
        pushed[std::size_t(k)].add(first, count, p.baseVertex);
        anySimplified = true;
    };
    // A group replaces its members when every one of them may have its error and none is at
    // full detail for a cut (budget 0) or skipped; coarsest first (the model stores them
    // finest first), and a group with a member already drawn by a coarser one stays.
    handled_.assign(p.clusters.size(), 0);
    for (auto it = p.groups.rbegin(); it != p.groups.rend() && allowGroups; ++it) {
        bool ok = true;
        for (std::uint32_t m : it->members) {
            const float budget = allowed[p.clusters[m].cell];
            ok = ok && !handled_[m] && budget > 0.0f && budget >= it->error;
        }
        if (!ok) continue;
        for (std::uint32_t m : it->members) handled_[m] = 1;
        addSimplified(it->first, it->count, it->error);
    }
    for (std::size_t ci = 0; ci < p.clusters.size(); ++ci) {
        if (handled_[ci]) continue;
        const GpuModel::DrawPart::Cluster& c = p.clusters[ci];
        const float budget = allowed[c.cell];
        int level = budget < 0.0f ? -1 : 0;
        while (level >= 0 && level + 1 < c.levels && c.error[level + 1] <= budget) ++level;
        if (level < 0)
            ++skipped;
        else if (level == 0)
            full.add(c.first[0], c.count[0], p.baseVertex);
        else
            addSimplified(c.first[level], c.count[level], c.error[level]);
    }
}

}  // namespace geoslice
