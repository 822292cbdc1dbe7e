// Per-mesh validation (analyseMesh, model/mesh/validate.hpp): vertices welded by exact position,
// degenerate and duplicate triangles, edge topology with pinch-out edges paired by angle,
// outward orientation per shell (cavities inward), and the split 2-manifold written back
// into the mesh.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include "model/mesh/closed_mesh.hpp"
#include "model/mesh/union_find.hpp"
#include "model/mesh/validate.hpp"

namespace geoslice {
namespace {

using closed_mesh::finite;
using closed_mesh::insideParity;
using closed_mesh::volumeOf;

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

// One use of an edge by a triangle: the undirected key of its welded end points (lo << 32 |
// hi) and the corners (3 t + slot) it runs from and to, in the triangle's winding.
struct EdgeUse {
    std::uint64_t key;
    std::uint32_t from, to;
};

// Face connectivity of a triangle soup on welded vertex ids: which triangles meet across
// each edge, and which corners are the same vertex of the resulting 2-manifold.
struct Topology {
    UnionFind corners{0};  // over corners 3 t + slot: one class = one vertex of the manifold
    UnionFind faces{0};    // over triangles: one class = one shell
    std::size_t boundaryEdges = 0, nonManifoldEdges = 0, inconsistentEdges = 0, splitEdges = 0, edges = 0;
    std::vector<std::uint32_t> splitFaces;  // triangles on an edge resolved by angular pairing
    std::vector<glm::dvec3> problemEdges;   // midpoints of a few open / unresolved edges
};

constexpr std::size_t kProblemSamples = 5;

// Builds the topology of `mesh` as its triangles are wound now. Around an edge used by more
// than two triangles (a body touching itself along the edge: a pinch-out), the triangles are
// sorted by their angle about the edge and each one that runs lo -> hi is paired with the
// nearest unpaired one at smaller angle (wrapping round) that runs hi -> lo: brackets
// matched on a circle, hi -> lo opening and lo -> hi closing. For outward shells the solid
// lies on the side of decreasing angle of a lo -> hi triangle (its normal d x w points to
// increasing angle, d = hi - lo), so an outward shell's two triangles at the edge are an
// adjacent pair, hi -> lo then lo -> hi, that the matching joins, and every shell stays a
// closed, consistently oriented 2-manifold. Where the directions alternate round the edge
// this is each lo -> hi triangle with its angular predecessor. A shell wound inward is a
// closing then an opening bracket: alone among outward shells it still pairs with itself
// (across the wrap); inward shells next to each other pair with each other, and the shell
// they make has a negative volume and is flipped, after which the pairing is redone (see
// analyseMesh). Edges with unequal numbers of triangles each way, or two at one angle
// (collinear, or overlapping faces), stay non-manifold.
Topology buildTopology(const Mesh& mesh, const std::vector<std::uint32_t>& canon, const std::vector<char>& skip) {
    const std::size_t nt = mesh.triangleCount();
    Topology topo;
    topo.corners = UnionFind(3 * nt);
    topo.faces = UnionFind(nt);
    auto vertexOf = [&](std::uint32_t corner) { return canon[mesh.indices[corner]]; };
    std::vector<EdgeUse> edges;
    edges.reserve(3 * nt);
    for (std::size_t t = 0; t < nt; ++t) {
        if (skip[t]) continue;
        for (std::uint32_t k = 0; k < 3; ++k) {
            const auto from = static_cast<std::uint32_t>(3 * t + k),
                       to = static_cast<std::uint32_t>(3 * t + (k + 1) % 3);
            const std::uint32_t a = vertexOf(from), b = vertexOf(to);
            edges.push_back({(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), from, to});
        }
    }
    std::sort(edges.begin(), edges.end(),
              [](const EdgeUse& x, const EdgeUse& y) { return x.key != y.key ? x.key < y.key : x.from < y.from; });
    topo.edges = edges.size();
    auto sample = [&](const EdgeUse& e) {
        if (topo.problemEdges.size() < kProblemSamples)
            topo.problemEdges.push_back(0.5 *
                                        (mesh.positions[mesh.indices[e.from]] + mesh.positions[mesh.indices[e.to]]));
    };
    // Joins two uses of one edge: the corners at each end point become one vertex.
    auto join = [&](const EdgeUse& x, const EdgeUse& y) {
        if (vertexOf(x.from) == vertexOf(y.from)) {
            topo.corners.unite(x.from, y.from);
            topo.corners.unite(x.to, y.to);
        } else {
            topo.corners.unite(x.from, y.to);
            topo.corners.unite(x.to, y.from);
        }
        topo.faces.unite(x.from / 3, y.from / 3);
    };
    struct Around {
        double angle;
        std::size_t use;
        bool forward;
    };
    std::vector<Around> around;
    std::vector<std::size_t> opened;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        const std::size_t uses = j - i;
        if (uses == 1) {
            ++topo.boundaryEdges;
            sample(edges[i]);
        } else if (uses == 2) {
            if (vertexOf(edges[i].from) == vertexOf(edges[i + 1].from)) ++topo.inconsistentEdges;
            join(edges[i], edges[i + 1]);
        } else {
            const auto lo = static_cast<std::uint32_t>(edges[i].key >> 32);
            const auto hi = static_cast<std::uint32_t>(edges[i].key & 0xFFFFFFFFu);
            const glm::dvec3 p0 = mesh.positions[lo];
            const glm::dvec3 d = mesh.positions[hi] - p0;
            const double dd = glm::dot(d, d);
            around.clear();
            glm::dvec3 e1(0.0), e2(0.0);
            bool ok = uses % 2 == 0 && dd > 0.0 && std::isfinite(dd);
            for (std::size_t u = i; ok && u < j; ++u) {
                const EdgeUse& e = edges[u];
                const std::uint32_t third = 3 * (e.from / 3) + (3 - e.from % 3 - e.to % 3);
                const glm::dvec3 w = mesh.positions[mesh.indices[third]] - p0;
                const glm::dvec3 perp = w - d * (glm::dot(w, d) / dd);
                if (u == i) {
                    const double len = glm::length(perp);
                    if (!(len > 0.0)) ok = false;
                    e1 = perp / len;
                    e2 = glm::normalize(glm::cross(d, e1));
                }
                const double angle = std::atan2(glm::dot(perp, e2), glm::dot(perp, e1));
                if (glm::dot(perp, perp) == 0.0 || !std::isfinite(angle)) ok = false;
                around.push_back({angle, u, vertexOf(e.from) == lo});
            }
            std::size_t start = 0;  // where the bracket matching starts: after the lowest balance
            if (ok) {
                std::sort(around.begin(), around.end(), [](const Around& x, const Around& y) {
                    return x.angle != y.angle ? x.angle < y.angle : x.use < y.use;
                });
                std::ptrdiff_t balance = 0, lowest = 0;
                for (std::size_t k = 0; k < uses; ++k) {
                    if (around[k].angle == around[(k + 1) % uses].angle) ok = false;
                    balance += around[k].forward ? -1 : 1;
                    if (balance < lowest) {
                        lowest = balance;
                        start = k + 1;
                    }
                }
                if (balance != 0) ok = false;
            }
            if (ok) {
                // From `start` no prefix closes more than it opened (the cycle lemma): a stack
                // matches every lo -> hi triangle with the nearest open hi -> lo one before it.
                opened.clear();
                for (std::size_t step = 0; step < uses; ++step) {
                    const std::size_t k = (start + step) % uses;
                    if (!around[k].forward) {
                        opened.push_back(k);
                        continue;
                    }
                    join(edges[around[k].use], edges[around[opened.back()].use]);
                    opened.pop_back();
                }
                ++topo.splitEdges;
                for (std::size_t u = i; u < j; ++u) topo.splitFaces.push_back(edges[u].from / 3);
            } else {
                ++topo.nonManifoldEdges;
                sample(edges[i]);
                for (std::size_t u = i + 1; u < j; ++u) join(edges[i], edges[u]);
            }
        }
        i = j;
    }
    return topo;
}

// Writes the manifold's vertices back into the mesh: one vertex per corner class (positions
// and per-vertex properties copied), so that index topology (what the section engine's edge
// keys, the BVH and the bake follow) is the split 2-manifold. Returns the number of welded
// vertices that were split into several (pinch-out vertices); the mesh is left as it is
// when every class is already one vertex of its own.
std::size_t writeManifold(Mesh& mesh, Topology& topo, const std::vector<std::uint32_t>& canon,
                          const std::vector<char>& skip) {
    constexpr std::uint32_t kUnset = std::numeric_limits<std::uint32_t>::max();
    const std::size_t nt = mesh.triangleCount(), nv = mesh.positions.size();
    std::vector<std::uint32_t> classOfCanon(nv, kUnset), firstOrig(3 * nt, kUnset), classOfOrig(nv, kUnset);
    std::vector<std::uint32_t> rootOf(3 * nt);
    bool rewrite = false;
    std::size_t split = 0;
    for (std::size_t c = 0; c < 3 * nt; ++c) {
        if (skip[c / 3]) continue;
        const std::uint32_t root = topo.corners.find(static_cast<std::uint32_t>(c));
        rootOf[c] = root;
        const std::uint32_t orig = mesh.indices[c], w = canon[orig];
        if (firstOrig[root] == kUnset) {
            firstOrig[root] = orig;
            if (classOfCanon[w] == kUnset)
                classOfCanon[w] = root;
            else
                ++split;  // a second class of the same welded vertex
        } else if (firstOrig[root] != orig) {
            rewrite = true;  // one manifold vertex held by several mesh vertices: weld
        }
        if (classOfOrig[orig] == kUnset)
            classOfOrig[orig] = root;
        else if (classOfOrig[orig] != root)
            rewrite = true;  // one mesh vertex is several manifold vertices: split
    }
    if (!rewrite) return split;
    // Degenerate triangles have no edges of their own: their corners join a class of the
    // same welded vertex (or get one when none has).
    for (std::size_t c = 0; c < 3 * nt; ++c) {
        if (!skip[c / 3]) continue;
        const std::uint32_t w = canon[mesh.indices[c]];
        if (classOfCanon[w] == kUnset) {
            classOfCanon[w] = static_cast<std::uint32_t>(c);
            firstOrig[c] = mesh.indices[c];
        }
        rootOf[c] = classOfCanon[w];
    }
    const std::size_t nProps = mesh.propertyNames.size();
    const bool props = nProps > 0 && mesh.propertyValues.size() == nv * nProps;
    std::vector<std::uint32_t> newId(3 * nt, kUnset);
    std::vector<glm::dvec3> positions;
    std::vector<float> values;
    for (std::size_t c = 0; c < 3 * nt; ++c) {
        const std::uint32_t root = rootOf[c];
        if (newId[root] == kUnset) {
            newId[root] = static_cast<std::uint32_t>(positions.size());
            const std::uint32_t orig = firstOrig[root];
            positions.push_back(mesh.positions[orig]);
            if (props)
                values.insert(values.end(), mesh.propertyValues.begin() + static_cast<std::ptrdiff_t>(orig * nProps),
                              mesh.propertyValues.begin() + static_cast<std::ptrdiff_t>((orig + 1) * nProps));
        }
        mesh.indices[c] = newId[root];
    }
    mesh.positions = std::move(positions);
    if (props) mesh.propertyValues = std::move(values);
    return split;
}

}  // namespace

MeshReport analyseMesh(Mesh& mesh, bool fix) {
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
    std::vector<std::array<std::uint32_t, 3>>().swap(sorted);

    // Topology, then outward orientation per shell. The topology's corner classes name
    // corner slots (3 t + k) of the mesh as it was wound when they were built, and the
    // pairing around split edges depends on the orientation: after any flip both are stale,
    // so the topology is built again from the flipped mesh before anything reads it. A
    // second pass never flips a shell the first one oriented, unless flipping changed the
    // pairing around a pinch-out edge; the loop ends on the pass that flips nothing (at most
    // kPasses; a mesh still flipping then keeps its last topology, rebuilt after the flip).
    Topology topo;
    std::vector<std::vector<std::uint32_t>> comps;
    std::vector<double> vols;
    bool anyFlip = false;
    constexpr int kPasses = 4;
    bool topologyStale = false;
    for (int pass = 0; pass < kPasses; ++pass) {
        topologyStale = false;
        topo = buildTopology(mesh, canon, skip);
        r.boundaryEdges = topo.boundaryEdges;
        r.nonManifoldEdges = topo.nonManifoldEdges;
        r.inconsistentEdges = topo.inconsistentEdges;
        r.splitEdges = topo.splitEdges;
        r.problemEdges = topo.problemEdges;
        // A mesh whose triangles are all degenerate has no edges: it encloses nothing.
        r.closed = topo.edges > 0 && r.boundaryEdges == 0 && r.nonManifoldEdges == 0;
        r.consistentlyOriented = r.inconsistentEdges == 0 && r.nonManifoldEdges == 0;

        comps.clear();
        std::vector<std::int64_t> compOfRoot(nt, -1);
        for (std::size_t t = 0; t < nt; ++t) {
            if (skip[t]) continue;
            const std::uint32_t root = topo.faces.find(static_cast<std::uint32_t>(t));
            if (compOfRoot[root] < 0) {
                compOfRoot[root] = static_cast<std::int64_t>(comps.size());
                comps.emplace_back();
            }
            comps[static_cast<std::size_t>(compOfRoot[root])].push_back(static_cast<std::uint32_t>(t));
        }
        r.components = comps.size();
        if (!r.closed || !r.consistentlyOriented || r.nonFiniteVertices > 0) return r;

        // Outward orientation, per shell: a shell inside an odd number of the other shells
        // is a cavity and must face inward (negative volume); all others outward. The probe
        // is a triangle centroid, not a vertex: shells split at a pinch-out share vertices.
        const glm::dvec3 ref = mesh.bounds().centre();
        vols.assign(comps.size(), 0.0);
        std::vector<Aabb> boxes(comps.size());
        for (std::size_t c = 0; c < comps.size(); ++c) {
            vols[c] = volumeOf(mesh, &comps[c], ref);
            for (std::uint32_t t : comps[c])
                for (int k = 0; k < 3; ++k)
                    boxes[c].extend(mesh.positions[mesh.indices[3 * t + static_cast<std::uint32_t>(k)]]);
        }
        bool flipNow = false;
        for (std::size_t c = 0; c < comps.size(); ++c) {
            int containers = 0;
            if (comps.size() > 1) {
                const std::uint32_t t0 = comps[c][0];
                const glm::dvec3 probe =
                    (mesh.positions[mesh.indices[3 * t0]] + mesh.positions[mesh.indices[3 * t0 + 1]] +
                     mesh.positions[mesh.indices[3 * t0 + 2]]) /
                    3.0;
                for (std::size_t d = 0; d < comps.size(); ++d) {
                    if (d == c || !boxes[d].contains(boxes[c])) continue;
                    if (insideParity(mesh, &comps[d], probe)) ++containers;
                }
            }
            const bool wantPositive = containers % 2 == 0;
            if ((vols[c] > 0.0) != wantPositive) {
                anyFlip = true;
                if (fix) {
                    for (std::uint32_t t : comps[c]) std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
                    vols[c] = -vols[c];
                    flipNow = true;
                }
            }
        }
        if (!flipNow) break;
        topologyStale = true;
    }
    if (topologyStale) topo = buildTopology(mesh, canon, skip);
    r.flipped = anyFlip && fix;
    r.signedVolume = std::accumulate(vols.begin(), vols.end(), 0.0);
    if (fix) {
        r.splitVertices = writeManifold(mesh, topo, canon, skip);
        r.vertices = mesh.positions.size();
    }
    return r;
}

}  // namespace geoslice
