#include "model/validate.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <optional>
#include <cmath>
#include <limits>
#include <numeric>
#include <thread>

namespace geoslice {
namespace {

// Unit directions with no simple relation to axis-aligned or grid-aligned geometry.
constexpr std::array<glm::dvec3, 8> kRayDirections = {
    glm::dvec3(0.5316705, 0.2876141, 0.7966510),  glm::dvec3(-0.3120954, 0.8231507, -0.4743921),
    glm::dvec3(0.7071421, -0.6011239, 0.3723344), glm::dvec3(-0.6432120, -0.2213412, 0.7329412),
    glm::dvec3(0.1234567, 0.9183274, 0.3761119),  glm::dvec3(-0.8712301, 0.4022134, -0.2812456),
    glm::dvec3(0.2953311, -0.3187654, -0.9006543), glm::dvec3(0.9112873, 0.1012345, -0.3991234)};

struct UnionFind {
    std::vector<std::uint32_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// Canonical vertex id per vertex: equal positions share the smallest index among them.
std::vector<std::uint32_t> weldByPosition(const std::vector<glm::dvec3>& pos) {
    std::vector<std::uint32_t> order(pos.size());
    std::iota(order.begin(), order.end(), 0u);
    // A strict weak order even with NaN (NaN sorts after every number): std::sort needs one.
    auto key = [](double v) { return std::isnan(v) ? std::numeric_limits<double>::infinity() : v; };
    auto less = [&](std::uint32_t a, std::uint32_t b) {
        const auto &p = pos[a], &q = pos[b];
        for (int k = 0; k < 3; ++k) {
            const bool pn = std::isnan(p[k]), qn = std::isnan(q[k]);
            if (pn != qn) return qn;  // numbers before NaN
            if (key(p[k]) != key(q[k])) return key(p[k]) < key(q[k]);
        }
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<std::uint32_t> canon(pos.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        if (i > 0 && pos[order[i]] == pos[order[i - 1]])
            canon[order[i]] = canon[order[i - 1]];
        else
            canon[order[i]] = order[i];
    }
    return canon;
}

// Ray parity against triangles [first, last) of a triangle list; -1 when the ray grazes.
int rayCrossings(const Mesh& mesh, const std::vector<std::uint32_t>* triangleSubset, const glm::dvec3& p,
                 const glm::dvec3& dir) {
    constexpr double kBaryEps = 1e-9;
    int count = 0;
    auto test = [&](std::size_t tri) -> bool {
        const glm::dvec3 a = mesh.positions[mesh.indices[3 * tri]] - p;
        const glm::dvec3 b = mesh.positions[mesh.indices[3 * tri + 1]] - p;
        const glm::dvec3 c = mesh.positions[mesh.indices[3 * tri + 2]] - p;
        if (!finite(a) || !finite(b) || !finite(c)) return true;
        const glm::dvec3 e1 = b - a, e2 = c - a;
        const glm::dvec3 h = glm::cross(dir, e2);
        const double det = glm::dot(e1, h);
        const double scale = glm::length(e1) * glm::length(e2);
        if (scale == 0.0) return true;  // degenerate triangle: no area, no crossing
        if (std::abs(det) <= 1e-12 * scale) {
            // Ray parallel to the triangle: it matters only if the ray lies in its plane.
            const glm::dvec3 n = glm::cross(e1, e2);
            return std::abs(glm::dot(n, a)) > 1e-9 * scale * glm::length(a + b + c);
        }
        const double inv = 1.0 / det;
        const glm::dvec3 s = -a;
        const double u = glm::dot(s, h) * inv;
        const glm::dvec3 q = glm::cross(s, e1);
        const double v = glm::dot(dir, q) * inv;
        if (u < -kBaryEps || v < -kBaryEps || u + v > 1.0 + kBaryEps) return true;
        const double t = glm::dot(e2, q) * inv;
        const double tEps = 1e-12 * std::sqrt(scale);
        if (t < -tEps) return true;
        if (t <= tEps) return false;  // the point is on the surface
        if (u < kBaryEps || v < kBaryEps || u + v > 1.0 - kBaryEps) return false;  // edge or vertex
        ++count;
        return true;
    };
    if (triangleSubset) {
        for (std::uint32_t t : *triangleSubset)
            if (!test(t)) return -1;
    } else {
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
            if (!test(t)) return -1;
    }
    return count;
}

bool insideParity(const Mesh& mesh, const std::vector<std::uint32_t>* subset, const glm::dvec3& p) {
    int last = 0;
    for (const auto& d : kRayDirections) {
        last = rayCrossings(mesh, subset, p, d);
        if (last >= 0) return last % 2 == 1;
    }
    return false;  // every direction grazed: the point is on the surface; call it outside
}

double volumeOf(const Mesh& mesh, const std::vector<std::uint32_t>* subset, const glm::dvec3& ref) {
    double v = 0.0;
    auto add = [&](std::size_t t) {
        const glm::dvec3 a = mesh.positions[mesh.indices[3 * t]] - ref;
        const glm::dvec3 b = mesh.positions[mesh.indices[3 * t + 1]] - ref;
        const glm::dvec3 c = mesh.positions[mesh.indices[3 * t + 2]] - ref;
        if (finite(a) && finite(b) && finite(c)) v += glm::dot(a, glm::cross(b, c));
    };
    if (subset) {
        for (std::uint32_t t : *subset) add(t);
    } else {
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) add(t);
    }
    return v / 6.0;
}

// A point strictly inside a closed body: a centroid nudged inward from a large triangle.
std::optional<glm::dvec3> interiorPoint(const Mesh& mesh) {
    std::vector<std::pair<double, std::size_t>> byArea;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const auto& a = mesh.positions[mesh.indices[3 * t]];
        const auto& b = mesh.positions[mesh.indices[3 * t + 1]];
        const auto& c = mesh.positions[mesh.indices[3 * t + 2]];
        double area = glm::length(glm::cross(b - a, c - a));
        if (std::isfinite(area) && area > 0.0) byArea.emplace_back(area, t);
    }
    std::size_t keep = std::min<std::size_t>(byArea.size(), 16);
    std::partial_sort(byArea.begin(), byArea.begin() + static_cast<std::ptrdiff_t>(keep), byArea.end(),
                      [](const auto& x, const auto& y) { return x.first > y.first; });
    for (std::size_t k = 0; k < keep; ++k) {
        std::size_t t = byArea[k].second;
        const auto& a = mesh.positions[mesh.indices[3 * t]];
        const auto& b = mesh.positions[mesh.indices[3 * t + 1]];
        const auto& c = mesh.positions[mesh.indices[3 * t + 2]];
        glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
        glm::dvec3 centroid = (a + b + c) / 3.0;
        for (double f : {1e-3, 1e-5}) {
            glm::dvec3 p = centroid - n * (f * std::sqrt(byArea[k].first));
            if (insideParity(mesh, nullptr, p)) return p;
        }
    }
    return std::nullopt;
}

}  // namespace

bool ValidationReport::hasErrors() const {
    return std::any_of(issues.begin(), issues.end(),
                       [](const auto& i) { return i.severity == ValidationIssue::Severity::Error; });
}

bool pointInClosedMesh(const Mesh& mesh, const glm::dvec3& p) { return insideParity(mesh, nullptr, p); }

double signedVolume(const Mesh& mesh) { return volumeOf(mesh, nullptr, mesh.bounds().centre()); }

MeshReport analyseMesh(Mesh& mesh, bool fixOrientation) {
    MeshReport r;
    const std::size_t nt = mesh.triangleCount();
    r.triangles = nt;
    r.vertices = mesh.positions.size();
    for (auto i : mesh.indices) GS_ASSERT(i < mesh.positions.size(), "loader produced an index out of range");
    for (const auto& p : mesh.positions)
        if (!finite(p)) ++r.nonFiniteVertices;
    if (nt == 0) return r;

    const std::vector<std::uint32_t> canon = weldByPosition(mesh.positions);
    auto tri = [&](std::size_t t) {
        return std::array<std::uint32_t, 3>{canon[mesh.indices[3 * t]], canon[mesh.indices[3 * t + 1]],
                                            canon[mesh.indices[3 * t + 2]]};
    };

    // Degenerate and duplicate triangles.
    std::vector<std::array<std::uint32_t, 3>> sorted;
    sorted.reserve(nt);
    std::vector<char> skip(nt, 0);
    for (std::size_t t = 0; t < nt; ++t) {
        auto v = tri(t);
        const auto &a = mesh.positions[v[0]], &b = mesh.positions[v[1]], &c = mesh.positions[v[2]];
        bool repeated = v[0] == v[1] || v[1] == v[2] || v[0] == v[2];
        bool zeroArea = !repeated && glm::length(glm::cross(b - a, c - a)) == 0.0;
        if (repeated || zeroArea) {
            ++r.degenerateTriangles;
            skip[t] = 1;
            continue;
        }
        std::sort(v.begin(), v.end());
        sorted.push_back(v);
    }
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 1; i < sorted.size(); ++i)
        if (sorted[i] == sorted[i - 1]) ++r.duplicateTriangles;

    // Edges: key = (lo << 32 | hi), forward when the triangle walks lo -> hi.
    struct Edge {
        std::uint64_t key;
        std::uint32_t forward;
    };
    std::vector<Edge> edges;
    edges.reserve(3 * nt);
    UnionFind uf(mesh.positions.size());
    for (std::size_t t = 0; t < nt; ++t) {
        if (skip[t]) continue;
        auto v = tri(t);
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = v[static_cast<std::size_t>(k)], b = v[static_cast<std::size_t>((k + 1) % 3)];
            std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
            edges.push_back({(std::uint64_t(lo) << 32) | hi, a < b ? 1u : 0u});
            uf.unite(a, b);
        }
    }
    std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.key < y.key; });
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        std::uint32_t fwd = 0;
        while (j < edges.size() && edges[j].key == edges[i].key) fwd += edges[j++].forward;
        std::size_t uses = j - i;
        if (uses == 1) ++r.boundaryEdges;
        else if (uses > 2) ++r.nonManifoldEdges;
        else if (fwd != 1) ++r.inconsistentEdges;
        i = j;
    }
    // A mesh whose triangles are all degenerate has no edges: it encloses nothing.
    r.closed = !edges.empty() && r.boundaryEdges == 0 && r.nonManifoldEdges == 0;
    r.consistentlyOriented = r.inconsistentEdges == 0 && r.nonManifoldEdges == 0;

    // Components: triangles grouped by the union-find root of their first vertex.
    std::vector<std::vector<std::uint32_t>> comps;
    {
        std::vector<std::int64_t> compOfRoot(mesh.positions.size(), -1);
        for (std::size_t t = 0; t < nt; ++t) {
            if (skip[t]) continue;
            std::uint32_t root = uf.find(tri(t)[0]);
            if (compOfRoot[root] < 0) {
                compOfRoot[root] = static_cast<std::int64_t>(comps.size());
                comps.emplace_back();
            }
            comps[static_cast<std::size_t>(compOfRoot[root])].push_back(static_cast<std::uint32_t>(t));
        }
    }
    r.components = comps.size();
    if (!r.closed || !r.consistentlyOriented || r.nonFiniteVertices > 0) return r;

    // Outward orientation, per shell: a shell inside an odd number of the other shells is a
    // cavity and must face inward (negative volume); all others outward.
    const glm::dvec3 ref = mesh.bounds().centre();
    std::vector<double> vols(comps.size());
    for (std::size_t c = 0; c < comps.size(); ++c) vols[c] = volumeOf(mesh, &comps[c], ref);
    bool anyFlip = false;
    for (std::size_t c = 0; c < comps.size(); ++c) {
        int containers = 0;
        if (comps.size() > 1) {
            const glm::dvec3 probe = mesh.positions[mesh.indices[3 * comps[c][0]]];
            for (std::size_t d = 0; d < comps.size(); ++d)
                if (d != c && insideParity(mesh, &comps[d], probe)) ++containers;
        }
        bool wantPositive = containers % 2 == 0;
        if ((vols[c] > 0.0) != wantPositive) {
            anyFlip = true;
            if (fixOrientation) {
                for (std::uint32_t t : comps[c]) std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
                vols[c] = -vols[c];
            }
        }
    }
    r.flipped = anyFlip && fixOrientation;
    r.signedVolume = std::accumulate(vols.begin(), vols.end(), 0.0);
    return r;
}

ValidationReport validate(Model& model) {
    ValidationReport report;
    using Sev = ValidationIssue::Severity;

    // Bodies in parallel: each analysis touches only its own part.
    std::vector<Part*> parts;
    for (auto& p : model.bodies) parts.push_back(&p);
    for (auto& p : model.surfaces) parts.push_back(&p);
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (std::size_t i = next++; i < parts.size(); i = next++)
            parts[i]->report = analyseMesh(parts[i]->mesh, parts[i]->kind == PartKind::Body);
    };
    unsigned nThreads = std::max(1u, std::min<unsigned>(std::thread::hardware_concurrency(), 8));
    std::vector<std::thread> pool;
    for (unsigned i = 1; i < nThreads; ++i) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();

    for (const Part* p : parts) {
        const MeshReport& r = p->report;
        auto add = [&](Sev s, std::string msg) { report.issues.push_back({s, p->name, std::move(msg)}); };
        if (r.triangles == 0) add(Sev::Error, "has no triangles");
        if (r.nonFiniteVertices) add(Sev::Error, std::to_string(r.nonFiniteVertices) + " vertices are NaN or Inf");
        if (r.degenerateTriangles) add(Sev::Warning, std::to_string(r.degenerateTriangles) + " degenerate triangles");
        if (r.duplicateTriangles) add(Sev::Warning, std::to_string(r.duplicateTriangles) + " duplicate triangles");
        if (p->kind == PartKind::Body) {
            if (!r.closed)
                add(Sev::Error, "body is not a closed 2-manifold: " + std::to_string(r.boundaryEdges) +
                                    " boundary edges, " + std::to_string(r.nonManifoldEdges) + " non-manifold edges");
            else if (!r.consistentlyOriented)
                add(Sev::Error, std::to_string(r.inconsistentEdges) + " edges with inconsistent orientation");
            if (r.flipped) add(Sev::Note, "normals pointed inward; flipped to outward");
        } else if (r.nonManifoldEdges) {
            add(Sev::Warning, std::to_string(r.nonManifoldEdges) + " non-manifold edges");
        }
    }

    // Nesting of closed bodies: B is inside A when a point strictly inside B is inside A.
    const std::size_t nb = model.bodies.size();
    std::vector<Aabb> boxes(nb);
    for (std::size_t i = 0; i < nb; ++i) boxes[i] = model.bodies[i].mesh.bounds();
    for (std::size_t b = 0; b < nb; ++b) {
        Part& inner = model.bodies[b];
        inner.report.nestingDepth = 0;
        inner.report.parent = -1;
        if (!inner.report.closed || !inner.report.consistentlyOriented) continue;
        std::optional<glm::dvec3> probe;
        double parentVolume = std::numeric_limits<double>::infinity();
        for (std::size_t a = 0; a < nb; ++a) {
            const Part& outer = model.bodies[a];
            if (a == b || !outer.report.closed || !outer.report.consistentlyOriented || !boxes[a].contains(boxes[b]))
                continue;
            if (!probe) probe = interiorPoint(inner.mesh);
            if (!probe) break;
            if (pointInClosedMesh(outer.mesh, *probe)) {
                ++inner.report.nestingDepth;
                if (std::abs(outer.report.signedVolume) < parentVolume) {
                    parentVolume = std::abs(outer.report.signedVolume);
                    inner.report.parent = static_cast<int>(a);
                }
            }
        }
        if (inner.report.parent >= 0)
            report.issues.push_back({Sev::Note, inner.name,
                                     "nested inside \"" + model.bodies[static_cast<std::size_t>(inner.report.parent)].name +
                                         "\" (depth " + std::to_string(inner.report.nestingDepth) + ")"});
    }
    model.validation = report;
    return report;
}

}  // namespace geoslice
