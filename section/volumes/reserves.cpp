#include "section/volumes/reserves.hpp"

#include <cmath>

namespace geoslice {
namespace {

double tet(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) { return glm::dot(a, glm::cross(b, c)); }

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

double meshVolume(const Mesh& mesh, const Plane* plane) {
    const Aabb box = mesh.bounds();
    if (!box.valid()) return 0.0;
    glm::dvec3 o = box.centre();
    if (plane) o -= (glm::dot(plane->normal, o) + plane->d) * plane->normal;  // o on the plane
    double sum = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        glm::dvec3 p[3];
        for (int k = 0; k < 3; ++k) p[k] = mesh.positions[mesh.indices[3 * t + static_cast<std::size_t>(k)]] - o;
        if (!plane) {
            sum += tet(p[0], p[1], p[2]);
            continue;
        }
        // Relative to o (on the plane) the signed distance is n . p.
        double s[3];
        int kept = 0;
        for (int k = 0; k < 3; ++k) {
            s[k] = glm::dot(plane->normal, p[k]);
            kept += s[k] >= 0.0;
        }
        if (kept == 0) continue;
        if (kept == 3) {
            sum += tet(p[0], p[1], p[2]);
            continue;
        }
        // Sutherland-Hodgman against s >= 0: at most 4 vertices, in the triangle's order.
        glm::dvec3 poly[4];
        int n = 0;
        for (int k = 0; k < 3; ++k) {
            const int k1 = (k + 1) % 3;
            if (s[k] >= 0.0) poly[n++] = p[k];
            if ((s[k] >= 0.0) != (s[k1] >= 0.0)) poly[n++] = p[k] + (p[k1] - p[k]) * (s[k] / (s[k] - s[k1]));
        }
        for (int k = 1; k + 1 < n; ++k) sum += tet(poly[0], poly[k], poly[k + 1]);
    }
    return sum / 6.0;
}

std::pair<double, std::string> metalContent(double tonnage, double grade, const std::string& unit) {
    if (startsWith(unit, "%")) return {tonnage * grade / 100.0, "t"};
    if (startsWith(unit, "g/t") || startsWith(unit, "ppm")) return {tonnage * grade, "g"};
    if (startsWith(unit, "kg/t")) return {tonnage * grade, "kg"};
    if (startsWith(unit, "mg/t") || startsWith(unit, "ppb")) return {tonnage * grade, "mg"};
    return {tonnage * grade, "t x " + (unit.empty() ? std::string("grade") : unit)};
}

Result<Reserves> computeReserves(const Model& model, const std::optional<Plane>& plane) {
    Reserves r;
    if (plane) {
        auto p = makePlane(plane->normal.x, plane->normal.y, plane->normal.z, plane->d);
        if (!p) return p.error();
        r.plane = p.value();
    }
    const std::size_t n = model.bodies.size();
    std::vector<double> gross(n, 0.0);
    std::vector<char> closed(n, 0);
    for (std::size_t b = 0; b < n; ++b) {
        closed[b] = model.bodies[b].report.closed;
        if (!closed[b]) {
            ++r.skippedOpenBodies;
            continue;
        }
        gross[b] = meshVolume(model.bodies[b].mesh, r.plane ? &*r.plane : nullptr);
    }
    for (std::size_t b = 0; b < n; ++b) {
        if (!closed[b]) continue;
        const Part& part = model.bodies[b];
        BodyReserves br;
        br.body = static_cast<std::uint32_t>(b);
        br.record = part.record;
        br.grossVolume = gross[b];
        br.netVolume = gross[b];
        for (std::size_t c = 0; c < n; ++c)
            if (closed[c] && model.bodies[c].report.parent == static_cast<int>(b)) br.netVolume -= gross[c];
        if (const AttributeRecord* rec = model.attributes.find(part.record)) {
            br.density = rec->density;
            br.grade = rec->grade;
            br.gradeUnit = rec->gradeUnit;
        }
        if (br.density) br.tonnage = br.netVolume * *br.density;
        if (br.tonnage && br.grade) {
            auto [amount, unit] = metalContent(*br.tonnage, *br.grade, br.gradeUnit);
            br.metal = amount;
            br.metalUnit = unit;
        }
        r.bodies.push_back(std::move(br));
    }
    return r;
}

}  // namespace geoslice
