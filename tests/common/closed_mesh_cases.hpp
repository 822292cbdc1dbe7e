// Closed meshes whose volume, point classification and axis-aligned sections are known in
// closed form, in many windings and triangulations, and the properties every one of them
// must have once loaded (tests/unit/closed_mesh_property_test.cpp draws the cases from a
// fixed seed; tests/fuzz/fuzz_closed_mesh.cpp decodes them from bytes).
//
// Shapes (canonical frame, then mapped to world by an axis permutation, mirrors and an
// offset up to Gauss-Kruger size, x 3.5e7 m, y 3.4e6 m):
//   box          an axis-aligned box;
//   prism        a regular n-gon prism: volume (n/2) r^2 sin(2 pi/n) x height;
//   bipyramid    an n-gon with an apex above and below (octahedron: n = 4, ring halfway);
//   frame        a box with a square hole through it: one shell of genus 1;
//   nested       a box with a box cavity (and maybe an island box inside the cavity) in the
//                same mesh: the cavity shell must come out facing inward;
//   edge touch   two boxes sharing one edge (a pinch-out along the edge);
//   vertex touch two boxes sharing one corner (a pinch-out at the vertex);
//   wedge fan    2 to 4 triangular prisms round one common edge with gaps between them (4 to
//                8 triangles at each piece of that edge, their shells wound either way).
// Box-built shapes are the boundary of a union of cells of an irregular tensor grid (the
// structure's planes plus random extra lines on each axis), each boundary quad split along
// a random diagonal or fanned from its centre, so one solid comes in many triangulations;
// the prism's side is cut at random levels and its caps triangulated at random. Each shell
// is wound either way at random; then the triangle order and the vertex array are shuffled
// (indices remapped), every triangle's corners rotated, and vertices welded by position, per
// shell, partly, or not at all (a triangle soup).
//
// The closed forms are evaluated in double on the world box corners where the shape is
// built of boxes (exact: axis-aligned faces stay on their planes after the offset), and from
// r, n and the world heights otherwise: the rounding of a vertex at 3.5e7 m (3.7e-9 m) moves
// an n-gon's area by at most 7.4e-9 / r relatively, so convex shapes keep r >= 25 m there.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "model/model.hpp"
#include "section/cut/contours.hpp"
#include "section/index/section_index.hpp"
#include "section/rays/classify.hpp"
#include "section/volumes/reserves.hpp"
#include "view/plane.hpp"

namespace geoslice::test::closed {

// Relative: closed-form volumes and areas against the mesh's (sums of a few hundred
// products in double; the vertex rounding at Gauss-Kruger coordinates is below 3e-10, see above).
constexpr double kRelTol = 1e-9;

enum class Shape : std::uint8_t { Box, Prism, Bipyramid, Frame, Nested, EdgeTouch, VertexTouch, WedgeFan };
constexpr int kShapeCount = 8;
inline const char* shapeName(Shape s) {
    static const char* names[] = {"box",    "prism",      "bipyramid",    "frame",
                                  "nested", "edge-touch", "vertex-touch", "wedge-fan"};
    return names[static_cast<int>(s)];
}
// Shapes whose closed forms come from a polygon (r, n, angles) rather than from boxes.
inline bool polygonBuilt(Shape s) { return s == Shape::Prism || s == Shape::Bipyramid || s == Shape::WedgeFan; }

enum class Weld : std::uint8_t { Position, PerShell, Partial, Soup };
constexpr int kWeldCount = 4;

// Everything that chooses a case; `seed` draws the rest (grid lines, diagonals, fans, cap
// triangulations, shuffles, corner rotations, hole and cavity placement).
struct CaseParams {
    Shape shape = Shape::Box;
    int offsetKind = 0;              // 0: none; 1: within +-1000 m; 2: Gauss-Kruger (3.5e7, 3.4e6, +-1000)
    glm::dvec3 size{10.0};           // m: canonical extents of the whole structure
    int axisPerm = 0;                // 0..5: which world axis each canonical axis becomes
    int mirror = 0;                  // bits 0..2: mirror world x, y, z
    std::uint32_t windingFlips = 0;  // bit s: shell s wound against its right orientation (s < 4)
    Weld weld = Weld::Position;      //
    int sides = 6;                   // prism / bipyramid polygon (3..24)
    int extraLines = 2;              // extra grid lines per axis, prism side levels (0..5)
    int variant = 0;                 // nested: 1 = island in the cavity; bipyramid: 1 = subdivided,
                                     // 2 = regular octahedron; wedge fan: 2 + variant wedges
    std::uint64_t seed = 0;

    std::string text() const {
        char buf[320];
        std::snprintf(buf, sizeof buf,
                      "shape=%s offset=%d size=(%.17g, %.17g, %.17g) perm=%d mirror=%d flips=0x%x weld=%d "
                      "sides=%d lines=%d variant=%d seed=%llu",
                      shapeName(shape), offsetKind, size.x, size.y, size.z, axisPerm, mirror, windingFlips,
                      static_cast<int>(weld), sides, extraLines, variant, static_cast<unsigned long long>(seed));
        return buf;
    }
};

// Brings any params into the generator's range (the fuzz target's bytes can say anything).
inline CaseParams normalised(CaseParams p) {
    p.shape = static_cast<Shape>(static_cast<int>(p.shape) % kShapeCount);
    p.offsetKind = ((p.offsetKind % 3) + 3) % 3;
    p.axisPerm = ((p.axisPerm % 6) + 6) % 6;
    p.mirror &= 7;
    p.weld = static_cast<Weld>(static_cast<int>(p.weld) % kWeldCount);
    p.sides = 3 + ((p.sides % 22) + 22) % 22;
    p.extraLines = ((p.extraLines % 6) + 6) % 6;
    p.variant = ((p.variant % 3) + 3) % 3;
    const double lo = polygonBuilt(p.shape) ? (p.offsetKind == 2 ? 50.0 : 2.0) : 0.5;
    for (int k = 0; k < 3; ++k) {
        double& s = p.size[k];
        if (!std::isfinite(s)) s = 10.0;
        s = std::clamp(std::abs(s), lo, 3000.0);
    }
    if (p.shape == Shape::Bipyramid && p.variant == 2) {  // regular octahedron
        p.sides = 4;
        p.size = glm::dvec3(p.size.x);
    }
    return p;
}

// canonical -> world: world[k] = offset[k] + sign[k] * canonical[perm[k]].
struct AxisMap {
    std::array<int, 3> perm{0, 1, 2};
    glm::dvec3 sign{1.0}, offset{0.0};

    glm::dvec3 toWorld(const glm::dvec3& c) const {
        glm::dvec3 w;
        for (int k = 0; k < 3; ++k) w[k] = offset[k] + sign[k] * c[perm[k]];
        return w;
    }
    double worldCoord(int k, double canonical) const { return offset[k] + sign[k] * canonical; }
    glm::dvec3 toCanonical(const glm::dvec3& w) const {
        glm::dvec3 c;
        for (int k = 0; k < 3; ++k) c[perm[k]] = (w[k] - offset[k]) * sign[k];
        return c;
    }
    int worldAxisOf(int canonicalAxis) const {
        for (int k = 0; k < 3; ++k)
            if (perm[k] == canonicalAxis) return k;
        return 0;
    }
    // Whether the map reverses orientation (odd permutation times the mirrors).
    bool reverses() const {
        int inversions = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = i + 1; j < 3; ++j) inversions += perm[i] > perm[j];
        return ((inversions % 2 == 1) != (sign.x * sign.y * sign.z < 0.0));
    }
};

// A structural box of a box-built shape, in world coordinates.
struct SignedBox {
    glm::dvec3 lo{0.0}, hi{0.0};
    int sign = 1;   // +1 solid, -1 removed (cavity, hole)
    int shell = 0;  // the shell its faces belong to
};

// A generated case and its closed forms.
struct Case {
    CaseParams params;
    AxisMap map;
    Mesh mesh;
    std::vector<int> shellOfTriangle;
    std::vector<double> shellVolume;  // m^3, signed: what each shell must hold after the fix
    std::size_t shells = 0;
    bool anyWrong = false;  // some shell was wound against its right orientation
    std::size_t splitEdges = 0, splitVertices = 0;
    double volume = 0.0;  // m^3
    Aabb bounds;          // world
    // Box-built shapes.
    std::vector<SignedBox> boxes;
    int holeAxis = -1;  // frame: world axis of the hole
    // Polygon-built shapes: canonical polygon about (cx, cy) in the plane z (the prism's and
    // bipyramid's), levels z0 < z1 (ring zr), the area of the cross-section (closed form, m^2:
    // the n-gon, or the sum of the wedges' triangles) and its number of pieces.
    std::vector<glm::dvec2> polygon;
    double polygonArea = 0.0;
    std::vector<double> pieceAreas;  // per shell
    std::size_t sectionPolygons = 1;
    double z0 = 0.0, z1 = 0.0, zr = 0.0;
    // Convex pieces (one per shell), canonical: outward unit normals n and offsets d, n.p + d.
    std::vector<std::vector<std::pair<glm::dvec3, double>>> pieces;

    bool convex() const { return polygonBuilt(params.shape); }
    bool extruded() const { return params.shape == Shape::Prism || params.shape == Shape::WedgeFan; }

    // Signed distance bound (m): > 0 inside, < 0 outside, at least |value| from the surface.
    double depth(const glm::dvec3& world) const {
        if (convex()) {
            // Inside a piece, its least face distance is the distance to its boundary; outside
            // every piece, the greatest violation bounds the distance to each from below.
            const glm::dvec3 c = map.toCanonical(world);
            double best = -std::numeric_limits<double>::infinity();
            for (const auto& planes : pieces) {
                double d = std::numeric_limits<double>::infinity();
                for (const auto& [n, off] : planes) d = std::min(d, -(glm::dot(n, c) + off));
                best = std::max(best, d);
            }
            return best;
        }
        int count = 0;
        double margin = std::numeric_limits<double>::infinity();
        for (const SignedBox& b : boxes) {
            bool in = true;
            double inside = std::numeric_limits<double>::infinity(), outside2 = 0.0;
            for (int k = 0; k < 3; ++k) {
                in = in && world[k] > b.lo[k] && world[k] < b.hi[k];
                inside = std::min({inside, world[k] - b.lo[k], b.hi[k] - world[k]});
                const double o = std::max({b.lo[k] - world[k], 0.0, world[k] - b.hi[k]});
                outside2 += o * o;
            }
            if (in) count += b.sign;
            margin = std::min(margin, in ? inside : std::sqrt(outside2));
        }
        return count > 0 ? margin : -margin;
    }

    // Area (m^2) of the section by the world plane x_axis = c, with the expected numbers of
    // polygons and holes; nullopt when the plane is within `margin` of a structural plane or
    // has no closed form here.
    struct AreaForm {
        double area = 0.0;
        std::size_t polygons = 0, holes = 0;
    };
    std::optional<AreaForm> area(int axis, double c, double margin) const {
        AreaForm f;
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        if (!convex()) {
            for (const SignedBox& b : boxes) {
                if (std::abs(c - b.lo[axis]) < margin || std::abs(c - b.hi[axis]) < margin) return std::nullopt;
                if (!(c > b.lo[axis] && c < b.hi[axis])) continue;
                f.area += b.sign * (b.hi[u] - b.lo[u]) * (b.hi[v] - b.lo[v]);
                (b.sign > 0 ? f.polygons : f.holes) += 1;
            }
            if (holeAxis >= 0 && axis != holeAxis && f.holes == 1) {
                f.polygons = 2;  // the cut runs through the hole: two pieces of the frame
                f.holes = 0;
            }
            return f;
        }
        const int cAxis = map.perm[axis];  // canonical axis the plane is normal to
        const double cc = (c - map.offset[axis]) * map.sign[axis];
        const int zAxis = map.worldAxisOf(2);
        const double w0 = map.worldCoord(zAxis, z0), w1 = map.worldCoord(zAxis, z1), wr = map.worldCoord(zAxis, zr);
        const double height = std::abs(w1 - w0);
        if (cAxis == 2) {
            if (std::abs(cc - z0) < margin || std::abs(cc - z1) < margin) return std::nullopt;
            if (!(cc > z0 && cc < z1)) return f;
            f.polygons = sectionPolygons;
            if (extruded()) {
                f.area = polygonArea;
            } else {
                if (std::abs(cc - zr) < margin) return std::nullopt;
                const double apex = cc > zr ? w1 : w0;
                const double t = (c - wr) / (apex - wr);  // world values: the mesh's own rounding
                // Near the apex the section is small and the apex's rounding weighs more: up to
                // three quarters of the way there, (1 - t)^2 >= 1/16 keeps it below 1e-9.
                if (t > 0.75) return std::nullopt;
                f.area = polygonArea * (1.0 - t) * (1.0 - t);
            }
            return f;
        }
        if (params.shape != Shape::Prism) return std::nullopt;
        // A plane along the prism's axis: chord of the polygon at cc times the height, only in
        // the central band, where the chord is long and varies slowly with cc.
        double lo = std::numeric_limits<double>::infinity(), hi = -lo, mid = 0.0;
        for (const auto& p : polygon) {
            lo = std::min(lo, p[cAxis]);
            hi = std::max(hi, p[cAxis]);
        }
        mid = 0.5 * (lo + hi);
        if (std::abs(cc - mid) > 0.3 * (hi - lo)) return std::nullopt;
        const int other = 1 - cAxis;
        double a = std::numeric_limits<double>::infinity(), b = -a;
        for (std::size_t i = 0; i < polygon.size(); ++i) {
            const glm::dvec2 p = polygon[i], q = polygon[(i + 1) % polygon.size()];
            if ((p[cAxis] - cc) * (q[cAxis] - cc) > 0.0 || p[cAxis] == q[cAxis]) continue;
            const double t = (cc - p[cAxis]) / (q[cAxis] - p[cAxis]);
            const double x = p[other] + t * (q[other] - p[other]);
            a = std::min(a, x);
            b = std::max(b, x);
        }
        f.area = (b - a) * height;
        f.polygons = 1;
        return f;
    }

    // Volume (m^3) on the side x_axis >= c; nullopt where there is no closed form here.
    std::optional<double> keptVolume(int axis, double c, double margin) const {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        if (!convex()) {
            double vol = 0.0;
            for (const SignedBox& b : boxes) {
                if (std::abs(c - b.lo[axis]) < margin || std::abs(c - b.hi[axis]) < margin) return std::nullopt;
                vol += b.sign * (b.hi[u] - b.lo[u]) * (b.hi[v] - b.lo[v]) *
                       std::max(0.0, b.hi[axis] - std::max(c, b.lo[axis]));
            }
            return vol;
        }
        if (!extruded() || map.perm[axis] != 2) return std::nullopt;
        const double w0 = map.worldCoord(axis, z0), w1 = map.worldCoord(axis, z1);
        const double lo = std::min(w0, w1), hi = std::max(w0, w1);
        if (std::abs(c - lo) < margin || std::abs(c - hi) < margin) return std::nullopt;
        return polygonArea * std::max(0.0, hi - std::max(c, lo));
    }
};

namespace detail {

constexpr double kPi = 3.14159265358979323846;

struct Builder {
    std::mt19937_64& rng;
    std::vector<glm::dvec3> corners;  // canonical, 3 per triangle
    std::vector<int> shellOf;         // per triangle

    double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
    int below(int n) { return static_cast<int>(std::uniform_int_distribution<int>(0, n - 1)(rng)); }

    void tri(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int shell) {
        corners.insert(corners.end(), {a, b, c});
        shellOf.push_back(shell);
    }
    // A planar quad a b c d (counter-clockwise seen from outside): one of its diagonals, or a
    // fan from its centre.
    void quad(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d, int shell) {
        switch (below(5)) {
            case 0: {
                const glm::dvec3 m = (a + b + c + d) * 0.25;
                tri(a, b, m, shell);
                tri(b, c, m, shell);
                tri(c, d, m, shell);
                tri(d, a, m, shell);
                break;
            }
            case 1:
            case 2:
                tri(a, b, c, shell);
                tri(a, c, d, shell);
                break;
            default:
                tri(a, b, d, shell);
                tri(b, c, d, shell);
                break;
        }
    }
    // A random triangulation of a convex polygon given counter-clockwise (as seen from
    // outside): a random diagonal splits it, recursively.
    void polygon(std::vector<glm::dvec3> ring, int shell) {
        if (ring.size() < 3) return;
        if (ring.size() == 3) {
            tri(ring[0], ring[1], ring[2], shell);
            return;
        }
        const int n = static_cast<int>(ring.size());
        const int i = below(n);
        const int j = (i + 2 + below(n - 3)) % n;  // not i, not a neighbour of i
        std::vector<glm::dvec3> a, b;
        for (int k = i;; k = (k + 1) % n) {
            a.push_back(ring[static_cast<std::size_t>(k)]);
            if (k == j) break;
        }
        for (int k = j;; k = (k + 1) % n) {
            b.push_back(ring[static_cast<std::size_t>(k)]);
            if (k == i) break;
        }
        polygon(std::move(a), shell);
        polygon(std::move(b), shell);
    }
};

// Grid lines on one canonical axis: the structural coordinates plus `extra` random ones, each
// at least 1e-3 of the extent from the others.
inline std::vector<double> gridLines(Builder& b, std::vector<double> lines, int extra) {
    std::sort(lines.begin(), lines.end());
    lines.erase(std::unique(lines.begin(), lines.end()), lines.end());
    const double lo = lines.front(), hi = lines.back(), gap = 1e-3 * (hi - lo);
    for (int e = 0, tries = 0; e < extra && tries < 50; ++tries) {
        const double x = b.uniform(lo, hi);
        bool far = true;
        for (double l : lines) far = far && std::abs(x - l) > gap;
        if (!far) continue;
        lines.push_back(x);
        std::sort(lines.begin(), lines.end());
        ++e;
    }
    return lines;
}

// The boundary of a union of cells of the tensor grid over canonical `boxes` (solid where the
// signed count is positive). A face's shell is that of the innermost box on either side.
inline void boxBuilt(Builder& b, const std::vector<SignedBox>& boxes, int extra) {
    std::array<std::vector<double>, 3> lines;
    for (int k = 0; k < 3; ++k) {
        std::vector<double> l;
        for (const SignedBox& s : boxes) l.insert(l.end(), {s.lo[k], s.hi[k]});
        lines[static_cast<std::size_t>(k)] = gridLines(b, l, extra);
    }
    const int nx = static_cast<int>(lines[0].size()) - 1, ny = static_cast<int>(lines[1].size()) - 1,
              nz = static_cast<int>(lines[2].size()) - 1;
    // Region of a cell: the innermost box containing its centre, -1 outside every box and
    // outside the grid; solid when the signed count there is positive.
    auto region = [&](int i, int j, int k) -> std::pair<int, bool> {
        if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return {-1, false};
        const glm::dvec3 c(0.5 * (lines[0][static_cast<std::size_t>(i)] + lines[0][static_cast<std::size_t>(i + 1)]),
                           0.5 * (lines[1][static_cast<std::size_t>(j)] + lines[1][static_cast<std::size_t>(j + 1)]),
                           0.5 * (lines[2][static_cast<std::size_t>(k)] + lines[2][static_cast<std::size_t>(k + 1)]));
        int r = -1, count = 0;
        for (std::size_t s = 0; s < boxes.size(); ++s)
            if (glm::all(glm::greaterThan(c, boxes[s].lo)) && glm::all(glm::lessThan(c, boxes[s].hi))) {
                r = static_cast<int>(s);
                count += boxes[s].sign;
            }
        return {r, count > 0};
    };
    auto at = [&](const std::array<int, 3>& idx) {
        glm::dvec3 p;
        for (std::size_t k = 0; k < 3; ++k) p[static_cast<int>(k)] = lines[k][static_cast<std::size_t>(idx[k])];
        return p;
    };
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
            for (int k = 0; k < nz; ++k) {
                const auto [r, solid] = region(i, j, k);
                if (!solid) continue;
                for (int axis = 0; axis < 3; ++axis)
                    for (int side : {0, 1}) {
                        std::array<int, 3> n{i, j, k};
                        n[static_cast<std::size_t>(axis)] += side ? 1 : -1;
                        const auto [rn, solidN] = region(n[0], n[1], n[2]);
                        if (solidN) continue;
                        const int shell = boxes[static_cast<std::size_t>(std::max(r, rn))].shell;
                        // The face at the cell's `side` on `axis`; u, v the next axes (u x v = axis).
                        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                        std::array<int, 3> base{i, j, k};
                        base[static_cast<std::size_t>(axis)] += side;
                        auto corner = [&](int du, int dv) {
                            std::array<int, 3> q = base;
                            q[static_cast<std::size_t>(u)] += du;
                            q[static_cast<std::size_t>(v)] += dv;
                            return at(q);
                        };
                        const glm::dvec3 a = corner(0, 0), bb = corner(1, 0), c = corner(1, 1), d = corner(0, 1);
                        if (side)
                            b.quad(a, bb, c, d, shell);  // normal +axis
                        else
                            b.quad(a, d, c, bb, shell);  // normal -axis
                    }
            }
}

}  // namespace detail

// Builds the case `params` describes (normalised first).
inline Case makeCase(const CaseParams& raw) {
    Case cs;
    cs.params = normalised(raw);
    const CaseParams& p = cs.params;
    std::mt19937_64 rng(p.seed);
    detail::Builder b{rng, {}, {}};

    static const std::array<std::array<int, 3>, 6> kPerms = {
        {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}}};
    cs.map.perm = kPerms[static_cast<std::size_t>(p.axisPerm)];
    for (int k = 0; k < 3; ++k) cs.map.sign[k] = (p.mirror >> k) & 1 ? -1.0 : 1.0;
    if (p.offsetKind == 0)
        cs.map.offset = glm::dvec3(0.0);
    else if (p.offsetKind == 1)
        cs.map.offset = glm::dvec3(b.uniform(-1000, 1000), b.uniform(-1000, 1000), b.uniform(-1000, 1000));
    else
        cs.map.offset = glm::dvec3(3.5e7 + b.uniform(-1e5, 1e5), 3.4e6 + b.uniform(-1e5, 1e5), b.uniform(-1000, 1000));

    const glm::dvec3 s = p.size;
    std::vector<SignedBox> canonical;  // box-built shapes, canonical frame
    auto frac = [&](double lo, double hi) { return b.uniform(lo, hi); };
    switch (p.shape) {
        case Shape::Box:
            canonical = {{glm::dvec3(0.0), s, 1, 0}};
            break;
        case Shape::Frame: {
            const glm::dvec3 lo(s.x * frac(0.15, 0.45), s.y * frac(0.15, 0.45), 0.0);
            const glm::dvec3 hi(s.x * frac(0.55, 0.85), s.y * frac(0.55, 0.85), s.z);
            canonical = {{glm::dvec3(0.0), s, 1, 0}, {lo, hi, -1, 0}};
            break;
        }
        case Shape::Nested: {
            const glm::dvec3 lo = s * glm::dvec3(frac(0.1, 0.3), frac(0.1, 0.3), frac(0.1, 0.3));
            const glm::dvec3 hi = s * glm::dvec3(frac(0.7, 0.9), frac(0.7, 0.9), frac(0.7, 0.9));
            canonical = {{glm::dvec3(0.0), s, 1, 0}, {lo, hi, -1, 1}};
            if (p.variant == 1) {
                const glm::dvec3 e = hi - lo;
                canonical.push_back({lo + e * frac(0.2, 0.4), lo + e * frac(0.6, 0.8), 1, 2});
            }
            break;
        }
        case Shape::EdgeTouch: {
            const glm::dvec3 m(s.x * frac(0.3, 0.7), s.y * frac(0.3, 0.7), 0.0);
            canonical = {{glm::dvec3(0.0), glm::dvec3(m.x, m.y, s.z), 1, 0}, {m, s, 1, 1}};
            break;
        }
        case Shape::VertexTouch: {
            const glm::dvec3 m = s * glm::dvec3(frac(0.3, 0.7), frac(0.3, 0.7), frac(0.3, 0.7));
            canonical = {{glm::dvec3(0.0), m, 1, 0}, {m, s, 1, 1}};
            break;
        }
        case Shape::Prism:
        case Shape::Bipyramid: {
            const int n = p.sides;
            const double r = 0.5 * std::min(s.x, s.y);
            const glm::dvec2 c(0.5 * s.x, 0.5 * s.y);
            const double phase = p.variant == 2 ? 0.0 : b.uniform(0.0, 2.0 * detail::kPi);
            for (int i = 0; i < n; ++i) {
                const double a = phase + 2.0 * detail::kPi * i / n;
                cs.polygon.push_back(c + r * glm::dvec2(std::cos(a), std::sin(a)));
            }
            cs.polygonArea = 0.5 * n * r * r * std::sin(2.0 * detail::kPi / n);
            cs.pieceAreas = {cs.polygonArea};
            cs.pieces.emplace_back();
            cs.z0 = 0.0;
            cs.z1 = s.z;
            cs.zr = p.shape == Shape::Bipyramid ? (p.variant == 2 ? 0.5 * s.z : s.z * frac(0.3, 0.7)) : 0.0;
            auto ring = [&](double z) {
                std::vector<glm::dvec3> out;
                for (const auto& q : cs.polygon) out.emplace_back(q.x, q.y, z);
                return out;
            };
            auto plane = [&](const glm::dvec3& a, const glm::dvec3& bb, const glm::dvec3& cc) {
                const glm::dvec3 nn = glm::normalize(glm::cross(bb - a, cc - a));
                cs.pieces.back().emplace_back(nn, -glm::dot(nn, a));
            };
            if (p.shape == Shape::Prism) {
                std::vector<double> levels = detail::gridLines(b, {0.0, s.z}, p.extraLines);
                for (std::size_t l = 0; l + 1 < levels.size(); ++l) {
                    const auto lo = ring(levels[l]), hi = ring(levels[l + 1]);
                    for (int i = 0; i < n; ++i) {
                        const auto j = static_cast<std::size_t>((i + 1) % n), ii = static_cast<std::size_t>(i);
                        b.quad(lo[ii], lo[j], hi[j], hi[ii], 0);
                    }
                }
                auto top = ring(s.z), bottom = ring(0.0);
                std::reverse(bottom.begin(), bottom.end());
                for (auto* cap : {&top, &bottom}) {
                    if (b.below(3) == 0) {  // a fan from the centre
                        const glm::dvec3 m(c.x, c.y, (*cap)[0].z);
                        for (std::size_t i = 0; i < cap->size(); ++i)
                            b.tri((*cap)[i], (*cap)[(i + 1) % cap->size()], m, 0);
                    } else {
                        b.polygon(*cap, 0);
                    }
                }
                const auto lo = ring(0.0), hi = ring(s.z);
                for (int i = 0; i < n; ++i)
                    plane(lo[static_cast<std::size_t>(i)], lo[static_cast<std::size_t>((i + 1) % n)],
                          hi[static_cast<std::size_t>(i)]);
                cs.pieces.back().emplace_back(glm::dvec3(0, 0, 1), -s.z);
                cs.pieces.back().emplace_back(glm::dvec3(0, 0, -1), 0.0);
            } else {
                const auto mid = ring(cs.zr);
                const glm::dvec3 top(c.x, c.y, s.z), bottom(c.x, c.y, 0.0);
                std::vector<std::array<glm::dvec3, 3>> faces;
                for (int i = 0; i < n; ++i) {
                    const glm::dvec3 a = mid[static_cast<std::size_t>(i)],
                                     bb = mid[static_cast<std::size_t>((i + 1) % n)];
                    faces.push_back({a, bb, top});
                    faces.push_back({bb, a, bottom});
                    plane(a, bb, top);
                    plane(bb, a, bottom);
                }
                for (const auto& f : faces) {
                    if (p.variant != 1) {
                        b.tri(f[0], f[1], f[2], 0);
                        continue;
                    }
                    // 1 -> 4 with edge midpoints; (a + b) * 0.5 is the same bits from either side.
                    const glm::dvec3 m01 = (f[0] + f[1]) * 0.5, m12 = (f[1] + f[2]) * 0.5, m20 = (f[2] + f[0]) * 0.5;
                    b.tri(f[0], m01, m20, 0);
                    b.tri(m01, f[1], m12, 0);
                    b.tri(m20, m12, f[2], 0);
                    b.tri(m01, m12, m20, 0);
                }
            }
            break;
        }
        case Shape::WedgeFan: {
            // Wedge w lies in its own sector of 2 pi / k about the axis (cx, cy), its angle a
            // quarter to four fifths of the sector, so neighbours leave a gap; the axis is one
            // edge of every wedge, cut at the shared side levels.
            const int k = 2 + p.variant;
            const double r = 0.5 * std::min(s.x, s.y), sector = 2.0 * detail::kPi / k;
            const glm::dvec2 o(0.5 * s.x, 0.5 * s.y);
            const double phase = b.uniform(0.0, 2.0 * detail::kPi);
            const std::vector<double> levels = detail::gridLines(b, {0.0, s.z}, p.extraLines);
            cs.z0 = 0.0;
            cs.z1 = s.z;
            cs.sectionPolygons = static_cast<std::size_t>(k);
            for (int w = 0; w < k; ++w) {
                const double alpha = sector * frac(0.25, 0.8);
                const double a0 = phase + w * sector + (sector - alpha) * frac(0.1, 0.9);
                const std::array<glm::dvec2, 3> tri2 = {
                    o, o + r * glm::dvec2(std::cos(a0), std::sin(a0)),
                    o + r * glm::dvec2(std::cos(a0 + alpha), std::sin(a0 + alpha))};  // counter-clockwise
                const double area = 0.5 * r * r * std::sin(alpha);
                cs.pieceAreas.push_back(area);
                cs.polygonArea += area;
                auto at = [&](int i, double z) { return glm::dvec3(tri2[static_cast<std::size_t>(i % 3)], z); };
                for (std::size_t l = 0; l + 1 < levels.size(); ++l)
                    for (int i = 0; i < 3; ++i)
                        b.quad(at(i, levels[l]), at(i + 1, levels[l]), at(i + 1, levels[l + 1]), at(i, levels[l + 1]),
                               w);
                b.tri(at(0, s.z), at(1, s.z), at(2, s.z), w);
                b.tri(at(0, 0.0), at(2, 0.0), at(1, 0.0), w);
                cs.pieces.emplace_back();
                for (int i = 0; i < 3; ++i) {
                    const glm::dvec3 a = at(i, 0.0), e = at(i + 1, 0.0) - a;
                    const glm::dvec3 nn = glm::normalize(glm::cross(e, glm::dvec3(0, 0, 1)));
                    cs.pieces.back().emplace_back(nn, -glm::dot(nn, a));
                }
                cs.pieces.back().emplace_back(glm::dvec3(0, 0, 1), -s.z);
                cs.pieces.back().emplace_back(glm::dvec3(0, 0, -1), 0.0);
            }
            cs.splitEdges = levels.size() - 1;
            cs.splitVertices = levels.size() * static_cast<std::size_t>(k - 1);
            break;
        }
    }
    if (!canonical.empty()) {
        detail::boxBuilt(b, canonical, p.extraLines);
        if (p.shape == Shape::Frame) cs.holeAxis = cs.map.worldAxisOf(2);
    }

    // To world; an orientation-reversing map is undone by reversing every triangle.
    const bool reverse = cs.map.reverses();
    std::vector<glm::dvec3> world(b.corners.size());
    for (std::size_t i = 0; i < world.size(); ++i) world[i] = cs.map.toWorld(b.corners[i]);
    for (const SignedBox& sb : canonical) {
        const glm::dvec3 a = cs.map.toWorld(sb.lo), c = cs.map.toWorld(sb.hi);
        cs.boxes.push_back({glm::min(a, c), glm::max(a, c), sb.sign, sb.shell});
    }
    cs.shells = 0;
    for (int sh : b.shellOf) cs.shells = std::max(cs.shells, static_cast<std::size_t>(sh) + 1);
    cs.shellVolume.assign(cs.shells, 0.0);
    if (cs.convex()) {
        const int zAxis = cs.map.worldAxisOf(2);
        const double h = std::abs(cs.map.worldCoord(zAxis, cs.z1) - cs.map.worldCoord(zAxis, cs.z0));
        for (std::size_t sh = 0; sh < cs.shells; ++sh)
            cs.shellVolume[sh] = cs.pieceAreas[sh] * h / (p.shape == Shape::Bipyramid ? 3.0 : 1.0);
    } else {
        for (const SignedBox& sb : cs.boxes) {
            const glm::dvec3 e = sb.hi - sb.lo;
            cs.shellVolume[static_cast<std::size_t>(sb.shell)] += sb.sign * e.x * e.y * e.z;
        }
    }
    for (double v : cs.shellVolume) cs.volume += v;
    if (p.shape == Shape::EdgeTouch) {
        // The shared edge runs along canonical z, cut at every z grid line.
        std::vector<double> zs;
        for (const auto& q : b.corners)
            if (q.x == canonical[0].hi.x && q.y == canonical[0].hi.y) zs.push_back(q.z);
        std::sort(zs.begin(), zs.end());
        zs.erase(std::unique(zs.begin(), zs.end()), zs.end());
        cs.splitEdges = zs.size() - 1;
        cs.splitVertices = zs.size();
    } else if (p.shape == Shape::VertexTouch) {
        cs.splitVertices = 1;
    }

    // Winding per shell, then the triangle order, vertex order and corner rotations.
    const std::size_t nt = b.shellOf.size();
    std::vector<std::size_t> order(nt);
    for (std::size_t t = 0; t < nt; ++t) order[t] = t;
    std::shuffle(order.begin(), order.end(), rng);
    std::map<std::tuple<int, double, double, double>, std::uint32_t> ids;
    for (std::size_t t : order) {
        const int shell = b.shellOf[t];
        const bool flip = reverse != (((p.windingFlips >> (shell & 31)) & 1u) != 0);
        if (((p.windingFlips >> (shell & 31)) & 1u) != 0) cs.anyWrong = true;
        std::array<glm::dvec3, 3> q{world[3 * t], world[3 * t + 1], world[3 * t + 2]};
        if (flip) std::swap(q[1], q[2]);
        std::rotate(q.begin(), q.begin() + b.below(3), q.end());
        for (const glm::dvec3& v : q) {
            bool own = p.weld == Weld::Soup || (p.weld == Weld::Partial && b.below(5) == 0);
            const int key = p.weld == Weld::Position ? 0 : shell;
            std::uint32_t id = 0;
            if (own) {
                id = static_cast<std::uint32_t>(cs.mesh.positions.size());
                cs.mesh.positions.push_back(v);
            } else {
                auto [it, fresh] = ids.emplace(std::make_tuple(key, v.x, v.y, v.z),
                                               static_cast<std::uint32_t>(cs.mesh.positions.size()));
                if (fresh) cs.mesh.positions.push_back(v);
                id = it->second;
            }
            cs.mesh.indices.push_back(id);
        }
        cs.shellOfTriangle.push_back(shell);
    }
    // Shuffle the vertex array, remapping the indices.
    std::vector<std::uint32_t> perm(cs.mesh.positions.size());
    for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = static_cast<std::uint32_t>(i);
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<glm::dvec3> shuffled(perm.size());
    for (std::size_t i = 0; i < perm.size(); ++i) shuffled[perm[i]] = cs.mesh.positions[i];
    for (auto& i : cs.mesh.indices) i = perm[i];
    cs.mesh.positions = std::move(shuffled);
    cs.bounds = cs.mesh.bounds();
    return cs;
}

// Draws the params of one case from `rng` (the unit test's distribution).
inline CaseParams drawParams(std::mt19937_64& rng) {
    auto below = [&](int n) { return static_cast<int>(std::uniform_int_distribution<int>(0, n - 1)(rng)); };
    auto logUniform = [&](double lo, double hi) {
        return std::exp(std::uniform_real_distribution<double>(std::log(lo), std::log(hi))(rng));
    };
    CaseParams p;
    p.shape = static_cast<Shape>(below(kShapeCount));
    p.offsetKind = below(3);
    const double lo = polygonBuilt(p.shape) ? (p.offsetKind == 2 ? 50.0 : 2.0) : 0.5;
    p.size = glm::dvec3(logUniform(lo, 3000.0), logUniform(lo, 3000.0), logUniform(lo, 3000.0));
    p.axisPerm = below(6);
    p.mirror = below(8);
    p.windingFlips = static_cast<std::uint32_t>(below(16));
    p.weld = static_cast<Weld>(below(kWeldCount));
    p.sides = 3 + below(22);
    p.extraLines = below(6);
    p.variant = below(3);
    p.seed = rng();
    return p;
}

// Failures of one case, one line each; empty when every property holds.
// `samples` scales the number of points and planes tried.
inline std::vector<std::string> checkCase(const Case& cs, std::mt19937_64& rng, int samples = 1) {
    std::vector<std::string> fail;
    auto say = [&](const char* fmt, auto... args) {
        char buf[400];
        std::snprintf(buf, sizeof buf, fmt, args...);
        fail.emplace_back(buf);
    };
    auto relNear = [](double a, double b) { return std::abs(a - b) <= kRelTol * std::max(std::abs(b), 1e-300); };
    const double scale = glm::length(cs.bounds.size());

    // 1. analyseMesh on its own: closed, the right shells, the closed-form volume, each shell
    // the right way round, the split 2-manifold written back, and idempotent.
    Mesh mesh = cs.mesh;
    const MeshReport r = analyseMesh(mesh, true);
    if (!r.closed || !r.consistentlyOriented)
        say("analyseMesh: closed %d oriented %d (boundary %zu, non-manifold %zu, inconsistent %zu)", r.closed,
            r.consistentlyOriented, r.boundaryEdges, r.nonManifoldEdges, r.inconsistentEdges);
    if (r.components != cs.shells) say("analyseMesh: %zu shells, expected %zu", r.components, cs.shells);
    if (!relNear(r.signedVolume, cs.volume))
        say("analyseMesh: volume %.17g, expected %.17g", r.signedVolume, cs.volume);
    if (!relNear(signedVolume(mesh), cs.volume))
        say("signedVolume after the fix: %.17g, expected %.17g", signedVolume(mesh), cs.volume);
    if (r.flipped != cs.anyWrong) say("analyseMesh: flipped %d, expected %d", r.flipped, cs.anyWrong);
    if (r.splitEdges != cs.splitEdges || r.splitVertices != cs.splitVertices)
        say("analyseMesh: split at %zu edges and %zu vertices, expected %zu and %zu", r.splitEdges, r.splitVertices,
            cs.splitEdges, cs.splitVertices);
    if (r.degenerateTriangles || r.duplicateTriangles)
        say("analyseMesh: %zu degenerate and %zu duplicate triangles", r.degenerateTriangles, r.duplicateTriangles);
    if (!fail.empty()) return fail;  // the rest reads a mesh that is not what it should be
    {
        std::vector<double> vol(cs.shells, 0.0);
        const glm::dvec3 ref = cs.bounds.centre();
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            const glm::dvec3 a = mesh.positions[mesh.indices[3 * t]] - ref,
                             b = mesh.positions[mesh.indices[3 * t + 1]] - ref,
                             c = mesh.positions[mesh.indices[3 * t + 2]] - ref;
            vol[static_cast<std::size_t>(cs.shellOfTriangle[t])] += glm::dot(a, glm::cross(b, c)) / 6.0;
        }
        for (std::size_t sh = 0; sh < cs.shells; ++sh)
            if (!relNear(vol[sh], cs.shellVolume[sh]))
                say("shell %zu holds %.17g m3 after the fix, expected %.17g (a cavity must face inward)", sh, vol[sh],
                    cs.shellVolume[sh]);
        // Index topology is the 2-manifold: every directed edge once, its reverse once, and
        // the index-connected components are the shells.
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
            for (int k = 0; k < 3; ++k)
                ++directed[{mesh.indices[3 * t + static_cast<std::size_t>(k)],
                            mesh.indices[3 * t + static_cast<std::size_t>((k + 1) % 3)]}];
        std::size_t bad = 0;
        for (const auto& [e, n] : directed) {
            auto rev = directed.find({e.second, e.first});
            if (n != 1 || rev == directed.end() || rev->second != 1) ++bad;
        }
        if (bad) say("the fixed mesh's indices are not a 2-manifold: %zu directed edges unmatched", bad);
        std::vector<std::uint32_t> parent(mesh.positions.size());
        for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<std::uint32_t>(i);
        auto find = [&](std::uint32_t x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
            for (int k = 1; k < 3; ++k)
                parent[find(mesh.indices[3 * t])] = find(mesh.indices[3 * t + static_cast<std::size_t>(k)]);
        std::size_t roots = 0;
        for (std::size_t i = 0; i < parent.size(); ++i) roots += find(static_cast<std::uint32_t>(i)) == i;
        if (roots != cs.shells)
            say("the fixed mesh's indices have %zu vertex-connected pieces, expected %zu", roots, cs.shells);
        Mesh again = mesh;
        const MeshReport r2 = analyseMesh(again, true);
        if (r2.flipped || again.indices != mesh.indices || again.positions != mesh.positions)
            say("analyseMesh is not idempotent (flipped again %d)", r2.flipped);
    }

    // 2. The model path: a part of unknown kind, classified by closure and validated as every
    // loader does (what `geoslice info` reports).
    Model model;
    {
        Part part;
        part.name = "solid";
        part.kind = PartKind::Surface;
        part.mesh = cs.mesh;
        model.bodies.push_back(std::move(part));
    }
    finishLoadedModel(model, /*classifyByClosure=*/true);
    if (model.bodies.size() != 1 || !model.surfaces.empty()) {
        say("model: %zu bodies and %zu surfaces, expected one body", model.bodies.size(), model.surfaces.size());
        return fail;
    }
    if (model.validation.hasErrors()) {
        for (const auto& i : model.validation.issues)
            if (i.severity == ValidationIssue::Severity::Error) say("model: validation error: %s", i.message.c_str());
        return fail;
    }
    const Part& body = model.bodies[0];
    const double infoVolume = body.report.signedVolume;
    if (!relNear(infoVolume, cs.volume)) say("info volume %.17g, expected %.17g", infoVolume, cs.volume);
    if (body.report.components != cs.shells) say("model: %zu shells, expected %zu", body.report.components, cs.shells);

    // `geoslice reserves`: the same volume.
    auto reserves = computeReserves(model);
    if (!reserves || reserves->bodies.size() != 1) {
        say("reserves: %s", reserves ? "not one body" : reserves.error().message.c_str());
    } else {
        const double gross = reserves->bodies[0].grossVolume;
        if (!relNear(gross, cs.volume)) say("reserves %.17g m3, expected %.17g", gross, cs.volume);
        if (!relNear(gross, infoVolume)) say("reserves %.17g m3 but info %.17g", gross, infoVolume);
    }

    // `geoslice classify`: points away from the surface by a margin.
    auto classifier = Classifier::build(model);
    if (!classifier) {
        say("classifier: %s", classifier.error().message.c_str());
        return fail;
    }
    const double margin = 4.0 * (*classifier)->tolerance() + 1e-6 * scale;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Aabb& bb = cs.bounds;
    const glm::dvec3 ext = bb.size();
    int inside = 0, outside = 0;
    for (int i = 0; i < 60 * samples; ++i) {
        glm::dvec3 q;
        if (i % 2 == 0) {  // anywhere in the bounds and a tenth beyond
            for (int k = 0; k < 3; ++k) q[k] = bb.min[k] - 0.1 * ext[k] + 1.2 * ext[k] * unit(rng);
        } else {  // near a vertex of the mesh: just inside or outside the surface
            const glm::dvec3 v =
                cs.mesh.positions[static_cast<std::size_t>(unit(rng) * double(cs.mesh.positions.size())) %
                                  cs.mesh.positions.size()];
            const glm::dvec3 dir = glm::normalize(glm::dvec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5));
            q = v + dir * (margin * (1.5 + 20.0 * unit(rng)));
        }
        const double d = cs.depth(q);
        if (std::abs(d) < margin) continue;
        const bool in = d > 0.0;
        (in ? inside : outside) += 1;
        const RecordId got = (*classifier)->classify(q);
        if ((got == body.record) != in || (got != body.record && got != kNoRecord))
            say("classify (%.17g, %.17g, %.17g) = %u, expected %u (%.3g m %s)", q.x, q.y, q.z, got,
                in ? body.record : kNoRecord, std::abs(d), in ? "inside" : "outside");
        if (pointInClosedMesh(body.mesh, q) != in)
            say("pointInClosedMesh (%.17g, %.17g, %.17g) = %d, expected %d", q.x, q.y, q.z, !in, in);
        if (fail.size() > 20) return fail;
    }
    (void)inside;
    (void)outside;

    // `geoslice section --areas`: axis-aligned planes through the solid.
    auto index = buildSectionIndex(model);
    if (!index) {
        say("section index: %s", index.error().message.c_str());
        return fail;
    }
    const double planeMargin = 1e-6 * scale;
    for (int i = 0, done = 0; i < 40 * samples && done < 12 * samples; ++i) {
        const int axis = static_cast<int>(unit(rng) * 3.0) % 3;
        double c = bb.min[axis] + ext[axis] * (0.02 + 0.96 * unit(rng));
        if (i % 4 == 3) {  // exactly through a vertex of the mesh (the sign rule's case)
            c = cs.mesh.positions[static_cast<std::size_t>(unit(rng) * double(cs.mesh.positions.size())) %
                                  cs.mesh.positions.size()][axis];
        }
        const auto form = cs.area(axis, c, planeMargin);
        if (!form) continue;
        ++done;
        glm::dvec3 n(0.0);
        n[axis] = 1.0;
        const Plane plane{n, -c};
        for (unsigned threads : {1u, 2u}) {
            SectionOptions so;
            so.threads = threads;
            auto s = computeSection(*index.value(), plane, so);
            if (!s) {
                say("section x%d = %.17g: %s", axis, c, s.error().message.c_str());
                continue;
            }
            double area = 0.0;
            std::size_t polygons = 0, holes = 0, open = 0;
            for (const BodySection& bs : s->bodies) {
                area += bs.area;
                polygons += bs.polygons.size();
                for (const auto& poly : bs.polygons) holes += poly.holes.size();
                open += bs.openChains;
            }
            if (!relNear(area, form->area) && !(form->area == 0.0 && area == 0.0))
                say("section x%d = %.17g (%u threads): area %.17g, expected %.17g", axis, c, threads, area, form->area);
            if (open) say("section x%d = %.17g: %zu open chains", axis, c, open);
            if (polygons != form->polygons || holes != form->holes)
                say("section x%d = %.17g: %zu polygons with %zu holes, expected %zu with %zu", axis, c, polygons, holes,
                    form->polygons, form->holes);
        }
        // `geoslice reserves --plane`: the kept side's volume.
        if (const auto kept = cs.keptVolume(axis, c, planeMargin)) {
            auto rk = computeReserves(model, plane);
            const double got = rk && !rk->bodies.empty() ? rk->bodies[0].grossVolume : std::nan("");
            if (!(std::abs(got - *kept) <= kRelTol * std::abs(cs.volume)))
                say("reserves kept of x%d >= %.17g: %.17g m3, expected %.17g", axis, c, got, *kept);
        }
        if (fail.size() > 20) return fail;
    }
    return fail;
}

}  // namespace geoslice::test::closed
