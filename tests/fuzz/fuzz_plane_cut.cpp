// libFuzzer target for the section engine's plane cut (section/cut/plane_cut.hpp, contours.hpp):
// random small closed meshes cut by a random plane must give closed loops (no open chain on
// a closed body) and non-negative areas (outer rings counter-clockwise, holes clockwise, a
// body's area outer minus holes >= 0), never a crash or a hang.
//
// The meshes are star-shaped about their centre, so they are embedded closed 2-manifolds
// whatever the bytes say: an octahedron subdivided 0-2 times (8, 32 or 128 triangles), its
// vertices pushed out to 0.4-1 x the radius along their directions, coordinates rounded to
// 1/16 m so that planes through vertices and edges (the degenerate cases) come up often. An
// input is skipped unless every triangle faces away from the centre (positive solid angle)
// and the solid angles sum to 4 pi (the radial projection covers the sphere once): then the
// mesh is a radial graph over the sphere, hence embedded. Up to three bodies side by side
// (disjoint by construction) and optionally a fourth nested in the first (inside the ball
// the first surely contains), as an orebody lens in its host.
//
// Input: byte 0 = subdivision levels and body count, byte 1 = flags (nested body; plane
// through a vertex), bytes 2-5 = plane normal (3 signed bytes) and offset, then one byte per
// vertex radius, reused cyclically.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "model/mesh/validate.hpp"
#include "model/model.hpp"
#include "section/cut/contours.hpp"
#include "section/index/section_index.hpp"

namespace {

using namespace geoslice;

constexpr double kRadius = 100.0;     // m: body radius before the per-vertex factor
constexpr double kGrid = 1.0 / 16.0;  // m: coordinate rounding (exact in double)
constexpr double kPi = 3.14159265358979323846;
// Signed areas are sums of products of coordinates of ~1e2 m, rounded in double: 1e-9 m^2 is
// far above that rounding (~1e-11 m^2) and far below any real area on the 1/16 m grid.
constexpr double kAreaRounding = 1e-9;

struct Bytes {
    const std::uint8_t* data;
    std::size_t size;
    std::size_t at = 0;
    std::uint8_t next() { return size ? data[at++ % size] : 0; }
};

// Octahedron subdivided `levels` times; unit directions and outward (counter-clockwise
// seen from outside) triangles.
void octasphere(int levels, std::vector<glm::dvec3>& dirs, std::vector<std::uint32_t>& tris) {
    dirs = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    tris = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            dirs.push_back(glm::normalize(dirs[a] + dirs[b]));
            const auto id = static_cast<std::uint32_t>(dirs.size() - 1);
            mid.emplace(key, id);
            return id;
        };
        std::vector<std::uint32_t> next;
        for (std::size_t t = 0; t < tris.size(); t += 3) {
            const std::uint32_t a = tris[t], b = tris[t + 1], c = tris[t + 2];
            const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
        }
        tris = std::move(next);
    }
}

// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee 1983).
double solidAngle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = glm::dot(a, glm::cross(b, c));
    const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    return 2.0 * std::atan2(num, den);
}

// A star-shaped body about `centre`; false when the bytes give one that is not a radial graph.
// `inner` receives a radius of a ball about the centre the body surely contains.
bool starBody(Bytes& in, int levels, const glm::dvec3& centre, double radius, Mesh& mesh, double& inner) {
    std::vector<glm::dvec3> dirs;
    std::vector<std::uint32_t> tris;
    octasphere(levels, dirs, tris);
    mesh.positions.clear();
    for (const auto& d : dirs) {
        const double r = radius * (0.4 + 0.6 * double(in.next()) / 255.0);
        const glm::dvec3 q = glm::round(centre / kGrid + r * d / kGrid) * kGrid;
        mesh.positions.push_back(q);
    }
    mesh.indices = tris;
    double total = 0.0;
    inner = radius;
    for (std::size_t t = 0; t < tris.size(); t += 3) {
        const glm::dvec3 a = mesh.positions[tris[t]] - centre, b = mesh.positions[tris[t + 1]] - centre,
                         c = mesh.positions[tris[t + 2]] - centre;
        const glm::dvec3 n = glm::cross(b - a, c - a);
        if (!(glm::dot(n, a) > 0.0)) return false;  // faces the centre or has no area
        const double omega = solidAngle(a, b, c);
        if (!(omega > 0.0)) return false;
        total += omega;
        inner = std::min(inner, glm::dot(n, a) / glm::length(n));  // distance of the plane
    }
    return std::abs(total - 4.0 * kPi) < 1e-6;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 6) return 0;
    Bytes in{data, size};
    const std::uint8_t shape = in.next(), flags = in.next();
    const int levels = shape % 3, bodies = 1 + (shape / 3) % 3;
    const glm::dvec3 normal(double(std::int8_t(in.next())), double(std::int8_t(in.next())),
                            double(std::int8_t(in.next())));
    const std::uint8_t offset = in.next();
    if (normal == glm::dvec3(0.0)) return 0;

    Model model;
    std::vector<double> inner(std::size_t(bodies), 0.0);
    for (int b = 0; b < bodies; ++b) {
        Part p;
        p.name = "body" + std::to_string(b);
        p.record = RecordId(b + 1);
        const glm::dvec3 centre(3.0 * kRadius * b, 0.0, 0.0);  // 3 R apart: disjoint
        if (!starBody(in, levels, centre, kRadius, p.mesh, inner[std::size_t(b)])) return 0;
        model.bodies.push_back(std::move(p));
    }
    if (flags & 1) {  // a lens nested in body 0: inside the ball body 0 surely contains
        Part p;
        p.name = "lens";
        p.record = 9;
        double lensInner = 0.0;
        if (inner[0] < 1.0) return 0;  // the 1/16 m rounding must stay well inside body 0
        if (!starBody(in, levels, glm::dvec3(0.0), 0.8 * inner[0], p.mesh, lensInner)) return 0;
        model.bodies.push_back(std::move(p));
    }
    model.recentre();
    if (validate(model).hasErrors()) __builtin_trap();  // closed and embedded by construction
    auto index = buildSectionIndex(model);
    if (!index) return 0;

    // The plane: through a vertex (exactly on the grid) or at a fraction of the bounds.
    const Aabb bounds = model.bounds();
    glm::dvec3 through = bounds.min + (bounds.max - bounds.min) * (double(offset) / 255.0);
    if (flags & 2) {
        const Mesh& m = model.bodies[offset % model.bodies.size()].mesh;
        through = m.positions[std::size_t(offset) % m.positions.size()];
    }
    const Plane plane{normal, -glm::dot(normal, through)};
    auto section = computeSection(*index.value(), plane);
    if (!section) return 0;  // the plane misses the bounds: a clear error, checked elsewhere
    for (const BodySection& body : section->bodies) {
        if (!(*index)->parts[body.part].closed) continue;
        if (body.openChains != 0) __builtin_trap();
        if (!(body.area >= -kAreaRounding)) __builtin_trap();
        for (const SectionPolygon& poly : body.polygons) {
            if (!(ringArea(poly.outer) >= -kAreaRounding)) __builtin_trap();
            for (const Ring& hole : poly.holes)
                if (!(ringArea(hole) <= kAreaRounding)) __builtin_trap();
        }
    }
    return 0;
}
