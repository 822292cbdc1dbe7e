// A part's charts, flattened: welded and grouped into charts (charts.cpp), each flattened by
// LSCM (lscm.cpp) and cut again while a triangle flips or collapses or the chart outgrows a
// page; then, once packed, emitted into the output mesh (local float positions with their
// residuals, UVs on the page).
#include <algorithm>
#include <limits>

#include "bake/bake_internal.hpp"

namespace geoslice::bake::bake_detail {
namespace {

// What float32 lost of a local position: local - hi, in double, rounded to float. The
// volatile is needed: GCC 12 at -O3 vectorised (SLP) the x and y of local - double(hi) and
// folded double(float(x)) back to x, so the residual came out 0 (seen in the assembly).
glm::vec3 residual(const glm::dvec3& local) {
    glm::vec3 r;
    for (int k = 0; k < 3; ++k) {
        volatile float hi = static_cast<float>(local[k]);
        r[k] = static_cast<float>(local[k] - static_cast<double>(hi));
    }
    return r;
}

}  // namespace

void chartPart(PartWork& w, const ChartOptions& options) {
    const Mesh& m = w.part->mesh;
    const std::vector<std::uint32_t> weld = weldVertices(m.positions.data(), m.positions.size());
    w.indices.resize(m.indices.size());
    for (std::size_t i = 0; i < m.indices.size(); ++i) w.indices[i] = weld[m.indices[i]];
    w.charts = buildCharts(m.positions.data(), m.positions.size(), w.indices.data(), m.triangleCount(), options);
}

double maxExtentAt(double density, const PackOptions& o) {
    return (double(std::min(o.width, o.height)) - 2.0 * o.margin - 2.0) / density;
}

void flattenChart(const PartWork& w, std::uint32_t partIndex, std::size_t chart, double maxExtent,
                  std::vector<Flattened>& out) {
    const glm::dvec3* pos = w.part->mesh.positions.data();
    const std::uint32_t* idx = w.indices.data();
    std::vector<std::pair<std::vector<std::uint32_t>, bool>> stack;
    const std::uint32_t b = w.charts.offsets[chart], e = w.charts.offsets[chart + 1];
    stack.push_back(
        {std::vector<std::uint32_t>(w.charts.triangles.begin() + b, w.charts.triangles.begin() + e), false});
    std::vector<std::vector<std::uint32_t>> pieces;
    while (!stack.empty()) {
        auto [tris, split] = std::move(stack.back());
        stack.pop_back();
        ChartUv uv = lscmChart(pos, idx, tris.data(), tris.size());
        glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (const auto& q : uv.uv) {
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        const bool tooLarge = hi.x - lo.x > maxExtent || hi.y - lo.y > maxExtent;
        if ((uv.badTriangles || tooLarge) && tris.size() > 1) {
            pieces.clear();
            splitTriangles(pos, idx, tris.data(), tris.size(), pieces);
            // Pieces that are not disks are cut further before they are flattened.
            for (auto it = pieces.rbegin(); it != pieces.rend(); ++it) {
                if (it->size() > 1 && !isTopologicalDisk(idx, it->data(), it->size())) {
                    std::vector<std::vector<std::uint32_t>> sub;
                    splitTriangles(pos, idx, it->data(), it->size(), sub);
                    for (auto s = sub.rbegin(); s != sub.rend(); ++s) stack.push_back({std::move(*s), true});
                } else {
                    stack.push_back({std::move(*it), true});
                }
            }
            continue;
        }
        for (auto& q : uv.uv) q -= lo;
        Flattened f;
        f.part = partIndex;
        f.distortion = measureDistortion(pos, idx, tris.data(), tris.size(), uv);
        f.extent = uv.uv.empty() ? glm::dvec2(0.0) : hi - lo;
        f.triangles = std::move(tris);
        f.uv = std::move(uv);
        f.split = split;
        out.push_back(std::move(f));
    }
}

void emitChart(const Flattened& f, const Placement& pl, const Mesh& mesh, const glm::dvec3& origin, double density,
               std::uint32_t width, std::uint32_t height, BakedPart& bp) {
    const auto base = static_cast<std::uint32_t>(bp.positions.size());
    for (std::size_t v = 0; v < f.uv.vertices.size(); ++v) {
        const glm::dvec3 local = mesh.positions[f.uv.vertices[v]] - origin;
        const glm::vec3 hi(local);
        bp.positions.push_back(hi);
        bp.positionsLo.push_back(residual(local));
        const glm::dvec2 q = f.uv.uv[v];
        bp.uvs.emplace_back(static_cast<float>(double(pl.page) + (pl.x + 0.5 + q.x * density) / width),
                            static_cast<float>((pl.y + 0.5 + q.y * density) / height));
    }
    for (std::size_t k = 0; k < f.triangles.size(); ++k)
        for (int e = 0; e < 3; ++e) bp.indices[3 * std::size_t(f.triangles[k]) + e] = base + f.uv.corners[3 * k + e];
}

}  // namespace geoslice::bake::bake_detail
