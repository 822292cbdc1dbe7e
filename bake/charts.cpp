// Charts: region growing under a dihedral-angle threshold (paper section 2.2: 85 degrees),
// bounded in size and normal cone, then cut until every chart is a topological disk.
// Region growing over a triangle adjacency graph follows Levy et al. 2002 ("Least squares
// conformal maps for automatic texture atlas generation", section 5), simplified to
// breadth-first growth from seeds taken in triangle order (deterministic).
#include <algorithm>
#include <cmath>
#include <numeric>

#include "bake/bake.hpp"
#include "model/mesh/union_find.hpp"

namespace geoslice::bake {
namespace {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

// Half-edge (a, b) of a chart with the position of its triangle in the chart list.
struct HalfEdge {
    std::uint32_t a, b, tri;
    bool operator<(const HalfEdge& o) const { return a != o.a ? a < o.a : (b != o.b ? b < o.b : tri < o.tri); }
};

bool sameEdge(const HalfEdge& x, std::uint32_t a, std::uint32_t b) { return x.a == a && x.b == b; }

}  // namespace

std::vector<std::uint32_t> weldVertices(const glm::dvec3* positions, std::size_t vertexCount) {
    std::vector<std::uint32_t> order;
    order.reserve(vertexCount);
    std::vector<std::uint32_t> weld(vertexCount);
    for (std::size_t v = 0; v < vertexCount; ++v) {
        weld[v] = static_cast<std::uint32_t>(v);
        const glm::dvec3& p = positions[v];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
            order.push_back(static_cast<std::uint32_t>(v));
    }
    std::sort(order.begin(), order.end(), [&](std::uint32_t i, std::uint32_t j) {
        const glm::dvec3 &p = positions[i], &q = positions[j];
        if (p.x != q.x) return p.x < q.x;
        if (p.y != q.y) return p.y < q.y;
        if (p.z != q.z) return p.z < q.z;
        return i < j;
    });
    for (std::size_t k = 1; k < order.size(); ++k)
        if (positions[order[k]] == positions[order[k - 1]]) weld[order[k]] = weld[order[k - 1]];
    return weld;
}

bool isTopologicalDisk(const std::uint32_t* indices, const std::uint32_t* triangles, std::size_t count) {
    if (count == 0) return false;
    std::vector<HalfEdge> he;
    he.reserve(count * 3);
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t* t = indices + 3 * std::size_t(triangles[k]);
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return false;  // repeated index: not a simplex
        for (int e = 0; e < 3; ++e) he.push_back({t[e], t[(e + 1) % 3], static_cast<std::uint32_t>(k)});
    }
    std::sort(he.begin(), he.end());
    auto findEdge = [&](std::uint32_t a, std::uint32_t b) -> const HalfEdge* {
        auto it = std::lower_bound(he.begin(), he.end(), HalfEdge{a, b, 0});
        return it != he.end() && sameEdge(*it, a, b) ? &*it : nullptr;
    };
    UnionFind uf(count);
    std::size_t interior = 0, border = 0;
    std::vector<std::uint32_t> verts;
    verts.reserve(he.size());
    for (std::size_t i = 0; i < he.size(); ++i) {
        if (i + 1 < he.size() && sameEdge(he[i + 1], he[i].a, he[i].b)) return false;  // edge used twice one way
        verts.push_back(he[i].a);
        if (const HalfEdge* twin = findEdge(he[i].b, he[i].a)) {
            ++interior;
            uf.unite(he[i].tri, twin->tri);
        } else {
            ++border;
        }
    }
    for (std::size_t k = 1; k < count; ++k)
        if (uf.find(static_cast<std::uint32_t>(k)) != 0) return false;
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    const long long euler = static_cast<long long>(verts.size()) - static_cast<long long>(interior / 2 + border) +
                            static_cast<long long>(count);
    if (euler != 1 || border < 3) return false;
    // Border half-edges: at most one leaving each vertex, and they form a single loop.
    std::vector<HalfEdge> loop;
    for (const HalfEdge& h : he)
        if (!findEdge(h.b, h.a)) loop.push_back(h);
    for (std::size_t i = 1; i < loop.size(); ++i)
        if (loop[i].a == loop[i - 1].a) return false;  // pinched vertex
    auto next = [&](std::uint32_t v) -> const HalfEdge* {
        auto it = std::lower_bound(loop.begin(), loop.end(), HalfEdge{v, 0, 0});
        return it != loop.end() && it->a == v ? &*it : nullptr;
    };
    std::size_t steps = 0;
    std::uint32_t v = loop[0].b;
    while (v != loop[0].a) {
        const HalfEdge* h = next(v);
        if (!h || ++steps > loop.size()) return false;
        v = h->b;
    }
    return steps + 1 == loop.size();
}

void splitTriangles(const glm::dvec3* positions, const std::uint32_t* indices, const std::uint32_t* triangles,
                    std::size_t count, std::vector<std::vector<std::uint32_t>>& out) {
    if (count <= 1) {
        if (count == 1) out.push_back({triangles[0]});
        return;
    }
    std::vector<glm::dvec3> centroid(count);
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t* t = indices + 3 * std::size_t(triangles[k]);
        centroid[k] = (positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0;
        if (!std::isfinite(centroid[k].x + centroid[k].y + centroid[k].z)) centroid[k] = glm::dvec3(0.0);
        lo = glm::min(lo, centroid[k]);
        hi = glm::max(hi, centroid[k]);
    }
    const glm::dvec3 ext = hi - lo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    std::vector<std::uint32_t> order(count);
    std::iota(order.begin(), order.end(), 0u);
    const std::size_t half = count / 2;
    std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(half), order.end(),
                     [&](std::uint32_t i, std::uint32_t j) {
                         return centroid[i][axis] != centroid[j][axis] ? centroid[i][axis] < centroid[j][axis]
                                                                       : triangles[i] < triangles[j];
                     });
    for (int side = 0; side < 2; ++side) {
        std::vector<std::uint32_t> part;
        for (std::size_t k = side ? half : 0; k < (side ? count : half); ++k) part.push_back(triangles[order[k]]);
        std::sort(part.begin(), part.end());
        // Edge-connected components of this half (edges by their two vertices, either way).
        struct Edge {
            std::uint64_t key;
            std::uint32_t tri;
            bool operator<(const Edge& o) const { return key != o.key ? key < o.key : tri < o.tri; }
        };
        std::vector<Edge> edges;
        edges.reserve(part.size() * 3);
        for (std::size_t k = 0; k < part.size(); ++k) {
            const std::uint32_t* t = indices + 3 * std::size_t(part[k]);
            for (int e = 0; e < 3; ++e) {
                std::uint64_t a = t[e], b = t[(e + 1) % 3];
                edges.push_back({std::min(a, b) << 32 | std::max(a, b), static_cast<std::uint32_t>(k)});
            }
        }
        std::sort(edges.begin(), edges.end());
        UnionFind uf(part.size());
        for (std::size_t i = 1; i < edges.size(); ++i)
            if (edges[i].key == edges[i - 1].key) uf.unite(edges[i].tri, edges[i - 1].tri);
        std::vector<std::uint32_t> slot(part.size(), kNone);
        const std::size_t first = out.size();
        for (std::size_t k = 0; k < part.size(); ++k) {
            const std::uint32_t root = uf.find(static_cast<std::uint32_t>(k));
            if (slot[root] == kNone) {
                slot[root] = static_cast<std::uint32_t>(out.size() - first);
                out.emplace_back();
            }
            out[first + slot[root]].push_back(part[k]);
        }
    }
}

Charts buildCharts(const glm::dvec3* positions, std::size_t vertexCount, const std::uint32_t* indices,
                   std::size_t triangleCount, const ChartOptions& options) {
    Charts charts;
    if (triangleCount == 0) return charts;
    // Unit normals; zero for degenerate or non-finite triangles (they never join a chart).
    std::vector<glm::dvec3> normal(triangleCount);
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const std::uint32_t* v = indices + 3 * t;
        glm::dvec3 n = glm::cross(positions[v[1]] - positions[v[0]], positions[v[2]] - positions[v[0]]);
        const double len = glm::length(n);
        normal[t] = len > 0.0 && std::isfinite(len) ? n / len : glm::dvec3(0.0);
    }
    // Vertex -> triangles (CSR), then the neighbour across each edge: the one triangle that
    // has the reversed half-edge, when no other triangle repeats either direction.
    std::vector<std::uint32_t> start(vertexCount + 1, 0), vt(triangleCount * 3);
    for (std::size_t i = 0; i < triangleCount * 3; ++i) ++start[indices[i] + 1];
    for (std::size_t v = 0; v < vertexCount; ++v) start[v + 1] += start[v];
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < triangleCount * 3; ++i) vt[fill[indices[i]]++] = static_cast<std::uint32_t>(i / 3);
    }
    auto countHalfEdge = [&](std::uint32_t a, std::uint32_t b, std::uint32_t& which) {
        int n = 0;
        for (std::uint32_t k = start[a]; k < start[a + 1]; ++k) {
            const std::uint32_t t = vt[k];
            const std::uint32_t* v = indices + 3 * std::size_t(t);
            for (int e = 0; e < 3; ++e)
                if (v[e] == a && v[(e + 1) % 3] == b) {
                    ++n;
                    which = t;
                }
        }
        return n;
    };
    std::vector<std::uint32_t> neighbour(triangleCount * 3, kNone);
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const std::uint32_t* v = indices + 3 * t;
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = v[e], b = v[(e + 1) % 3];
            if (a == b) continue;
            std::uint32_t other = kNone, self = kNone;
            if (countHalfEdge(b, a, other) == 1 && countHalfEdge(a, b, self) == 1 && other != t)
                neighbour[3 * t + e] = other;
        }
    }

    const double cosDihedral = std::cos(glm::radians(options.maxDihedralDegrees));
    const double cosCone = std::cos(glm::radians(options.maxConeDegrees));
    const std::uint32_t maxTriangles = std::max<std::uint32_t>(1, options.maxTriangles);
    std::vector<std::uint32_t> chartOf(triangleCount, kNone);
    std::vector<std::uint32_t> queue;
    std::vector<std::vector<std::uint32_t>> pieces;
    std::vector<std::vector<std::uint32_t>> work;
    std::vector<std::vector<std::uint32_t>> result;
    std::uint32_t grown = 0;
    for (std::size_t seed = 0; seed < triangleCount; ++seed) {
        if (chartOf[seed] != kNone) continue;
        const glm::dvec3 seedNormal = normal[seed];
        queue.assign(1, static_cast<std::uint32_t>(seed));
        chartOf[seed] = grown;
        const bool joinable = seedNormal != glm::dvec3(0.0);
        for (std::size_t head = 0; head < queue.size() && joinable; ++head) {
            const std::uint32_t t = queue[head];
            for (int e = 0; e < 3 && queue.size() < maxTriangles; ++e) {
                const std::uint32_t n = neighbour[3 * std::size_t(t) + e];
                if (n == kNone || chartOf[n] != kNone) continue;
                if (glm::dot(normal[t], normal[n]) < cosDihedral || glm::dot(seedNormal, normal[n]) < cosCone) continue;
                chartOf[n] = grown;
                queue.push_back(n);
            }
        }
        ++grown;
        std::sort(queue.begin(), queue.end());
        // Cut until every piece is a disk (a single triangle always is).
        work.assign(1, queue);
        while (!work.empty()) {
            std::vector<std::uint32_t> piece = std::move(work.back());
            work.pop_back();
            if (piece.size() == 1 || isTopologicalDisk(indices, piece.data(), piece.size())) {
                result.push_back(std::move(piece));
                continue;
            }
            pieces.clear();
            splitTriangles(positions, indices, piece.data(), piece.size(), pieces);
            for (auto& p : pieces) work.push_back(std::move(p));
        }
    }
    std::sort(result.begin(), result.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
    for (const auto& c : result) {
        charts.triangles.insert(charts.triangles.end(), c.begin(), c.end());
        charts.offsets.push_back(static_cast<std::uint32_t>(charts.triangles.size()));
    }
    return charts;
}

}  // namespace geoslice::bake
