// Tetrahedron ∩ body volumes from the body's triangles near the tetrahedron (the method is in
// section/blocks/block_reserves.hpp, "Hexahedral cells").
#include "section/blocks/block_tet_volumes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <unordered_map>

#include "model/blocks/cell_locator.hpp"
#include "section/cut/edge_crossing.hpp"
#include "section/index/bvh.hpp"

namespace geoslice {
namespace {

double orient(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    return glm::dot(b - a, glm::cross(c - a, d - a));
}

// One tetrahedron, positively oriented (orient(v0, v1, v2, v3) > 0), in the body's local
// frame. Face i is the face opposite v[i]; side(i, p) >= 0 on v[i]'s side of it. The roles:
// v0 the apex of the 3D sum, face 0 its lid, v1 the apex of the lid's 2D sum, v2 -> v3 the
// lid's edge opposite v1 (faces 0 and 1 meet there; face 3 bounds it at v2, face 2 at v3).
struct Tetra {
    glm::dvec3 v[4];
    glm::dvec3 n[4];
    double d[4] = {0, 0, 0, 0};
    double volume = 0.0;                  // m³
    glm::dvec3 u{0.0};                    // unit, v2 -> v3
    double length = 0.0;                  // |v3 - v2|
    Aabb box;                             // bounds, widened by the margin
    std::size_t point[4] = {0, 0, 0, 0};  // the corners' lattice indices

    Tetra(const std::array<glm::dvec3, 4>& corners, const std::array<std::size_t, 4>& points, double margin) {
        for (int m = 0; m < 4; ++m) {
            v[m] = corners[std::size_t(m)];
            point[m] = points[std::size_t(m)];
        }
        if (orient(v[0], v[1], v[2], v[3]) < 0.0) {
            std::swap(v[2], v[3]);
            std::swap(point[2], point[3]);
        }
        volume = orient(v[0], v[1], v[2], v[3]) / 6.0;
        for (int m = 0; m < 4; ++m) {
            const glm::dvec3 &a = v[(m + 1) % 4], &b = v[(m + 2) % 4], &c = v[(m + 3) % 4];
            n[m] = glm::cross(b - a, c - a);
            if (glm::dot(n[m], v[m] - a) < 0.0) n[m] = -n[m];
            d[m] = -glm::dot(n[m], a);
            box.extend(v[m]);
        }
        length = glm::length(v[3] - v[2]);
        u = (v[3] - v[2]) / length;
        box.min -= glm::dvec3(margin);
        box.max += glm::dvec3(margin);
    }
    double side(int i, const glm::dvec3& p) const { return glm::dot(n[i], p) + d[i]; }
};

struct Vertex {
    glm::dvec3 p;
    bool on0;  // on face 0: made by the face-0 cut, or by a later cut of an edge on face 0
};

// A convex polygon: a triangle clipped by up to 4 planes has at most 7 vertices.
struct Poly {
    std::array<Vertex, 8> v;
    int n = 0;
};

// Keeps the part of `in` where side(face, p) >= 0 (Sutherland-Hodgman; the cut points from
// edge_crossing.hpp, so the same edge gives the same point wherever it is cut).
void clip(const Poly& in, const Tetra& t, int face, Poly& out) {
    out.n = 0;
    double s[8];
    for (int k = 0; k < in.n; ++k) s[k] = t.side(face, in.v[std::size_t(k)].p);
    for (int k = 0; k < in.n; ++k) {
        const int k1 = k + 1 == in.n ? 0 : k + 1;
        const Vertex &a = in.v[std::size_t(k)], &b = in.v[std::size_t(k1)];
        if (s[k] >= 0.0) out.v[std::size_t(out.n++)] = a;
        if ((s[k] >= 0.0) != (s[k1] >= 0.0))
            out.v[std::size_t(out.n++)] = {edgeCrossing(a.p, s[k], b.p, s[k1]), face == 0 || (a.on0 && b.on0)};
    }
    if (out.n < 3) out.n = 0;
}

// The triangle clipped to face 0's side; `x -> e` its edge on face 0 (the triangle's section
// by the face's plane, in the triangle's order) when it has one.
bool sectionEdge(const Poly& tri, const Tetra& t, Poly& kept, glm::dvec3& x, glm::dvec3& e) {
    clip(tri, t, 0, kept);
    for (int k = 0; k < kept.n; ++k) {
        const int k1 = k + 1 == kept.n ? 0 : k + 1;
        if (kept.v[std::size_t(k)].on0 && kept.v[std::size_t(k1)].on0) {
            x = kept.v[std::size_t(k)].p;
            e = kept.v[std::size_t(k1)].p;
            return true;
        }
    }
    return false;
}

// Where the section edge x -> e crosses face 1 (the line of edge v2 v3 in face 0's plane):
// the crossing point and +1 when it goes from side1 < 0 to side1 >= 0, -1 the other way, 0
// when it does not cross.
int crossing(const Tetra& t, const glm::dvec3& x, const glm::dvec3& e, glm::dvec3& c) {
    const double sx = t.side(1, x), se = t.side(1, e);
    if ((sx >= 0.0) == (se >= 0.0)) return 0;
    c = edgeCrossing(x, sx, e, se);
    return se >= 0.0 ? 1 : -1;
}

// A segment p0 + s d, s in [s0, s1], meeting boxes widened by `margin`.
struct Segment {
    glm::dvec3 p0{0.0}, d{0.0};
    double s0 = 0.0, s1 = 0.0, margin = 0.0;
    bool meets(const Aabb& b) const {
        double lo = s0, hi = s1;
        for (int a = 0; a < 3; ++a) {
            const double bl = b.min[a] - margin, bh = b.max[a] + margin;
            if (d[a] == 0.0) {
                if (p0[a] < bl || p0[a] > bh) return false;
                continue;
            }
            double ta = (bl - p0[a]) / d[a], tb = (bh - p0[a]) / d[a];
            if (ta > tb) std::swap(ta, tb);
            lo = std::max(lo, ta);
            hi = std::min(hi, tb);
            if (lo > hi) return false;
        }
        return true;
    }
};

// A body triangle near a cell: its vertices (local frame) and bounds.
struct NearTriangle {
    Poly tri;
    Aabb box;
};

class TetVolumes {
public:
    TetVolumes(const Mesh& body, const glm::dvec3& origin, double margin)
        : body_(body), origin_(origin), margin_(margin) {
        local_.resize(body.positions.size());
        for (std::size_t k = 0; k < local_.size(); ++k) {
            local_[k] = body.positions[k] - origin;
            bounds_.extend(local_[k]);
        }
        bounds_.min -= glm::dvec3(margin);
        bounds_.max += glm::dvec3(margin);
        triBounds_.resize(body.triangleCount());
        for (std::size_t t = 0; t < triBounds_.size(); ++t)
            for (int k = 0; k < 3; ++k) triBounds_[t].extend(local_[body.indices[3 * t + std::size_t(k)]]);
        const BvhMesh mesh{body.positions.data(), body.positions.size(), body.indices.data(), body.triangleCount()};
        // One thread: the caller may run several bodies at once, and the tree is the same.
        auto bvh = buildBvh(&mesh, 1, origin, BvhOptions{8, 1});
        // A closed body has fewer than 2^32 - 2 triangles (its indices are 32-bit).
        if (bvh) bvh_ = std::move(bvh.value());
    }

    const glm::dvec3& origin() const { return origin_; }

    // The triangles whose bounds meet `box` (local, already widened), copied out (a cell's six
    // tetrahedra read them in turn).
    void near(const Aabb& box, std::vector<NearTriangle>& out) const {
        out.clear();
        visit([&](const Aabb& b) { return b.meets(box); },
              [&](std::uint32_t t) {
                  if (!triBounds_[t].meets(box)) return;
                  NearTriangle n;
                  n.tri.n = 3;
                  for (int k = 0; k < 3; ++k)
                      n.tri.v[std::size_t(k)] = {local_[body_.indices[3 * std::size_t(t) + std::size_t(k)]], false};
                  n.box = triBounds_[t];
                  out.push_back(n);
              });
    }

    // vol(T ∩ body) from `candidates`, a superset of the triangles meeting T's box.
    double volume(const Tetra& t, const std::vector<NearTriangle>& candidates) {
        double sum6 = 0.0;      // 6 x the 3D and 2D sums
        double lengthIn = 0.0;  // the 1D sum without the inside state at v2
        Poly a, b;
        glm::dvec3 x, e, c;
        bool clear = true;  // no triangle's bounds come within the margin of v2
        const glm::dvec3 lo = t.v[2] - glm::dvec3(margin_), hi = t.v[2] + glm::dvec3(margin_);
        for (const NearTriangle& n : candidates) {
            clear = clear &&
                    !(glm::all(glm::lessThanEqual(n.box.min, hi)) && glm::all(glm::greaterThanEqual(n.box.max, lo)));
            if (!n.box.meets(t.box)) continue;
            const Poly& tri = n.tri;
            if (missed(t, tri)) continue;
            const bool cut = sectionEdge(tri, t, a, x, e);
            if (a.n == 0) continue;
            if (cut) {
                if (const int o = crossing(t, x, e, c); o != 0 && t.side(2, c) >= 0.0 && t.side(3, c) >= 0.0)
                    lengthIn += o * (t.length - std::clamp(glm::dot(c - t.v[2], t.u), 0.0, t.length));
            }
            clip(a, t, 1, b);
            clip(b, t, 2, a);
            clip(a, t, 3, b);
            for (int k = 1; k + 1 < b.n; ++k)
                sum6 += orient(t.v[0], b.v[0].p, b.v[std::size_t(k)].p, b.v[std::size_t(k + 1)].p);
            for (int k = 0; k < b.n; ++k) {
                const Vertex &p = b.v[std::size_t(k)], &q = b.v[std::size_t(k + 1 == b.n ? 0 : k + 1)];
                if (p.on0 && q.on0) sum6 += orient(t.v[1], p.p, q.p, t.v[0]);
            }
        }
        // Off the surface by more than the margin, v2's winding number is the body's, whatever
        // plane the ray's crossings are taken in: one ray per such lattice point. On it (within
        // rounding), only this tetrahedron's own ray agrees with its other decisions.
        int inside = 0;
        if (!clear) {
            inside = insideAtV2(t);
        } else if (const auto it = insideAt_.find(t.point[2]); it != insideAt_.end()) {
            inside = it->second;
        } else {
            inside = insideAtV2(t);
            insideAt_.emplace(t.point[2], inside);
        }
        return sum6 / 6.0 + t.volume * (double(inside) * t.length + lengthIn) / t.length;
    }

    // The winding number of the body's section by face 0's plane at v2 (1 inside, 0 outside):
    // the signed crossings of its edges with the line v2 v3 beyond v2 (side3 < 0), decided
    // by the same clips and tests as volume(), so the inside state, the crossings along the
    // edge and the pieces agree in every tie.
    int insideAtV2(const Tetra& t) {
        Segment ray;
        ray.p0 = t.v[2];
        ray.d = -t.u;
        ray.margin = margin_;
        // The ray's part inside the body's bounds.
        double lo = 0.0, hi = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
            if (ray.d[k] == 0.0) {
                if (ray.p0[k] < bounds_.min[k] || ray.p0[k] > bounds_.max[k]) return 0;
                continue;
            }
            double ta = (bounds_.min[k] - ray.p0[k]) / ray.d[k], tb = (bounds_.max[k] - ray.p0[k]) / ray.d[k];
            if (ta > tb) std::swap(ta, tb);
            lo = std::max(lo, ta);
            hi = std::min(hi, tb);
        }
        if (lo > hi) return 0;
        ray.s0 = lo - margin_;
        ray.s1 = hi + margin_;
        rayHits_.clear();
        visit([&](const Aabb& b) { return ray.meets(b); }, [&](std::uint32_t id) { rayHits_.push_back(id); });
        int winding = 0;
        Poly tri, a;
        glm::dvec3 x, e, c;
        for (std::uint32_t id : rayHits_) {
            loadTriangle(id, tri);
            const double s0 = t.side(0, tri.v[0].p), s1 = t.side(0, tri.v[1].p), s2 = t.side(0, tri.v[2].p);
            if ((s0 >= 0.0) == (s1 >= 0.0) && (s1 >= 0.0) == (s2 >= 0.0)) continue;
            if (!sectionEdge(tri, t, a, x, e)) continue;
            if (const int o = crossing(t, x, e, c); o != 0 && t.side(3, c) < 0.0) winding += o;
        }
        return winding;
    }

private:
    // Calls hit(triangle) for the triangles in the BVH's leaves whose boxes satisfy `meets`
    // (node boxes: float32, rounded outward, so they hold their triangles).
    template <class Meets, class Hit>
    void visit(const Meets& meets, const Hit& hit) const {
        if (bvh_.nodes.empty()) return;
        std::uint32_t stack[128];  // median splits: depth <= log2(triangles) + 1
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const BvhNode& nd = bvh_.nodes[stack[--top]];
            Aabb box;
            box.min = {nd.lo[0], nd.lo[1], nd.lo[2]};
            box.max = {nd.hi[0], nd.hi[1], nd.hi[2]};
            if (!meets(box)) continue;
            if (nd.count) {
                for (std::uint32_t k = nd.first; k < nd.first + nd.count; ++k) hit(bvh_.triangles[k]);
                continue;
            }
            stack[top++] = nd.first + 1;
            stack[top++] = nd.first;
        }
    }

    // Whether the triangle is beyond face 0 (every vertex at side < 0: no clip keeps anything
    // and it has no section edge), or beyond another face by more than the margin, so that
    // no point the clips make from it (convex combinations up to rounding far below the
    // margin) can be on that face's side: leaving it out decides as the clips would.
    bool missed(const Tetra& t, const Poly& tri) const {
        for (int f = 0; f < 4; ++f) {
            const double tol = f == 0 ? 0.0 : margin_ * glm::length(t.n[f]);
            if (t.side(f, tri.v[0].p) < -tol && t.side(f, tri.v[1].p) < -tol && t.side(f, tri.v[2].p) < -tol)
                return true;
        }
        return false;
    }

    void loadTriangle(std::uint32_t id, Poly& tri) const {
        tri.n = 3;
        for (int k = 0; k < 3; ++k)
            tri.v[std::size_t(k)] = {local_[body_.indices[3 * std::size_t(id) + std::size_t(k)]], false};
    }

    const Mesh& body_;
    glm::dvec3 origin_;
    double margin_;
    std::vector<glm::dvec3> local_;
    Aabb bounds_;
    std::vector<Aabb> triBounds_;
    Bvh bvh_;
    std::vector<std::uint32_t> rayHits_;
    std::unordered_map<std::size_t, int> insideAt_;  // lattice point -> winding number
};

}  // namespace

std::vector<CellVolume> tetCellBodyVolumes(const BlockModel& blocks, const Mesh& body) {
    std::vector<CellVolume> out;
    const Aabb bb = body.bounds();
    if (!bb.valid() || !blocks.locator) return out;
    // Boxes are widened by far more than the rounding of any test below (1e-9 of the
    // coordinates' scale), so no triangle that a clip could keep is left out of a query.
    const glm::dvec3 extent = glm::max(bb.size(), blocks.bounds().size());
    const double margin = 1e-9 * (1.0 + std::max(extent.x, std::max(extent.y, extent.z)));
    TetVolumes tv(body, bb.centre(), margin);
    Aabb wide = bb;
    wide.min -= glm::dvec3(margin);
    wide.max += glm::dvec3(margin);
    std::vector<std::size_t> cells;
    blocks.locator->cellsMeeting([&](const Aabb& b) { return b.meets(wide); },
                                 [&](std::size_t cell) { cells.push_back(cell); });
    if (cells.empty()) return out;
    // The cells' (i, j, k) range, for the flood fill of the cells the surface misses.
    std::array<std::size_t, 3> lo{blocks.dims}, hi{0, 0, 0};
    for (std::size_t cell : cells) {
        const auto ijk = blocks.ijk(cell);
        for (int a = 0; a < 3; ++a) {
            lo[std::size_t(a)] = std::min(lo[std::size_t(a)], ijk[std::size_t(a)]);
            hi[std::size_t(a)] = std::max(hi[std::size_t(a)], ijk[std::size_t(a)]);
        }
    }
    const std::size_t ni = hi[0] - lo[0] + 1, nj = hi[1] - lo[1] + 1, nk = hi[2] - lo[2] + 1;
    auto local = [&](const std::array<std::size_t, 3>& c) {
        return (c[0] - lo[0]) + ni * ((c[1] - lo[1]) + nj * (c[2] - lo[2]));
    };
    enum : std::uint8_t { kAway = 0, kMissed = 1, kDone = 2 };
    std::vector<std::uint8_t> state(ni * nj * nk, kAway);
    std::vector<NearTriangle> near;
    auto tetraOf = [&](std::size_t cell, const std::array<glm::dvec3, 8>& k, const std::array<int, 4>& tet) {
        std::array<glm::dvec3, 4> v;
        std::array<std::size_t, 4> points;
        for (int m = 0; m < 4; ++m) {
            v[std::size_t(m)] = k[std::size_t(tet[std::size_t(m)])] - tv.origin();
            points[std::size_t(m)] = blocks.cornerIndex(cell, tet[std::size_t(m)]);
        }
        return Tetra(v, points, margin);
    };
    for (std::size_t cell : cells) {
        const auto k = blocks.cellCorners(cell);
        Aabb box;
        for (const glm::dvec3& p : k) box.extend(p - tv.origin());
        box.min -= glm::dvec3(margin);
        box.max += glm::dvec3(margin);
        tv.near(box, near);
        if (near.empty()) {
            state[local(blocks.ijk(cell))] = kMissed;
            continue;
        }
        state[local(blocks.ijk(cell))] = kDone;
        double v = 0.0;
        for (const auto& tet : kCellTets) v += tv.volume(tetraOf(cell, k, tet), near);
        out.push_back({cell, v});
    }
    // Cells the surface misses are wholly inside or outside, as are their face neighbours
    // that it misses too: one inside test per connected group.
    std::deque<std::array<std::size_t, 3>> queue;
    for (std::size_t cell : cells) {
        if (state[local(blocks.ijk(cell))] != kMissed) continue;
        const int inside = tv.insideAtV2(tetraOf(cell, blocks.cellCorners(cell), kCellTets[0]));
        queue.push_back(blocks.ijk(cell));
        state[local(blocks.ijk(cell))] = kDone;
        while (!queue.empty()) {
            const auto c = queue.front();
            queue.pop_front();
            if (inside != 0) {
                const std::size_t id = blocks.linear(c[0], c[1], c[2]);
                out.push_back({id, double(inside) * blocks.cellVolume(id)});
            }
            for (int a = 0; a < 3; ++a)
                for (int step = -1; step <= 1; step += 2) {
                    auto nb = c;
                    if (step < 0 ? nb[std::size_t(a)] == lo[std::size_t(a)] : nb[std::size_t(a)] == hi[std::size_t(a)])
                        continue;
                    nb[std::size_t(a)] = std::size_t(std::ptrdiff_t(nb[std::size_t(a)]) + step);
                    if (state[local(nb)] != kMissed) continue;
                    state[local(nb)] = kDone;
                    queue.push_back(nb);
                }
        }
    }
    std::sort(out.begin(), out.end(), [](const CellVolume& x, const CellVolume& y) { return x.cell < y.cell; });
    std::erase_if(out, [&](const CellVolume& c) { return std::abs(c.volume) <= 1e-9 * blocks.cellVolume(c.cell); });
    return out;
}

}  // namespace geoslice
