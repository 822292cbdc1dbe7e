// Closed-mesh queries: ray parity (point in a closed mesh, robust to grazing rays), signed
// volume by the divergence theorem, and a point deep inside a closed body for nesting
// tests. Brute force in double, O(triangles) per query.
#include "model/mesh/closed_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "model/mesh/validate.hpp"

namespace geoslice {
namespace closed_mesh {
namespace {

// Unit directions with no simple relation to axis-aligned or grid-aligned geometry.
constexpr std::array<glm::dvec3, 8> kRayDirections = {
    glm::dvec3(0.5316705, 0.2876141, 0.7966510),   glm::dvec3(-0.3120954, 0.8231507, -0.4743921),
    glm::dvec3(0.7071421, -0.6011239, 0.3723344),  glm::dvec3(-0.6432120, -0.2213412, 0.7329412),
    glm::dvec3(0.1234567, 0.9183274, 0.3761119),   glm::dvec3(-0.8712301, 0.4022134, -0.2812456),
    glm::dvec3(0.2953311, -0.3187654, -0.9006543), glm::dvec3(0.9112873, 0.1012345, -0.3991234)};

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
        if (t <= tEps) return false;                                               // the point is on the surface
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

// Nearest t > tMin where the ray org + t dir crosses a triangle of the mesh other than
// `skip` (Moller-Trumbore in double), or infinity.
double nearestHit(const Mesh& mesh, const glm::dvec3& org, const glm::dvec3& dir, std::size_t skip, double tMin) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        if (t == skip) continue;
        const glm::dvec3 a = mesh.positions[mesh.indices[3 * t]] - org;
        const glm::dvec3 e1 = mesh.positions[mesh.indices[3 * t + 1]] - org - a;
        const glm::dvec3 e2 = mesh.positions[mesh.indices[3 * t + 2]] - org - a;
        const glm::dvec3 h = glm::cross(dir, e2);
        const double det = glm::dot(e1, h);
        if (!(std::abs(det) > 0.0)) continue;
        const glm::dvec3 s = -a;
        const double u = glm::dot(s, h) / det;
        if (u < 0.0 || u > 1.0) continue;
        const glm::dvec3 q = glm::cross(s, e1);
        const double v = glm::dot(dir, q) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        const double d = glm::dot(e2, q) / det;
        if (d > tMin && d < best) best = d;
    }
    return best;
}

}  // namespace

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
    std::optional<glm::dvec3> best;
    double bestChord = 0.0;
    for (std::size_t k = 0; k < keep; ++k) {
        std::size_t t = byArea[k].second;
        const auto& a = mesh.positions[mesh.indices[3 * t]];
        const auto& b = mesh.positions[mesh.indices[3 * t + 1]];
        const auto& c = mesh.positions[mesh.indices[3 * t + 2]];
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
        const glm::dvec3 centroid = (a + b + c) / 3.0;
        const double chord = nearestHit(mesh, centroid, -n, t, 1e-9 * std::sqrt(byArea[k].first));
        if (!std::isfinite(chord) || chord <= bestChord) continue;
        const glm::dvec3 p = centroid - n * (0.5 * chord);
        if (!insideParity(mesh, nullptr, p)) continue;
        best = p;
        bestChord = chord;
    }
    return best;
}

}  // namespace closed_mesh

bool pointInClosedMesh(const Mesh& mesh, const glm::dvec3& p) { return closed_mesh::insideParity(mesh, nullptr, p); }

double signedVolume(const Mesh& mesh) { return closed_mesh::volumeOf(mesh, nullptr, mesh.bounds().centre()); }

}  // namespace geoslice
