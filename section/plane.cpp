#include "section/plane.hpp"

#include <cmath>
#include <string>

namespace geoslice {

Result<Plane> makePlane(double a, double b, double c, double d) {
    const char* names[4] = {"a", "b", "c", "d"};
    const double values[4] = {a, b, c, d};
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(values[i]))
            return makeError(ErrorCode::InvalidArgument,
                             std::string("plane component ") + names[i] + " is not a finite number");
    const double len = std::sqrt(a * a + b * b + c * c);
    if (!(len > 1e-12))
        return makeError(ErrorCode::InvalidArgument, "plane normal (a, b, c) = (" + std::to_string(a) + ", " +
                                                         std::to_string(b) + ", " + std::to_string(c) +
                                                         ") has zero length");
    Plane p;
    p.normal = glm::dvec3(a, b, c) / len;
    p.d = d / len;
    return p;
}

Plane horizontalPlane(double elevation) {
    Plane p;
    p.normal = {0.0, 0.0, -1.0};
    p.d = elevation;
    return p;
}

LocalPlane toLocal(const Plane& plane, const glm::dvec3& origin) {
    LocalPlane lp;
    lp.n = plane.normal;
    lp.d = plane.d + glm::dot(plane.normal, origin);
    return lp;
}

SectionFrame makeSectionFrame(const Plane& plane, const glm::dvec3& modelOrigin) {
    SectionFrame f;
    f.normal = plane.normal;
    f.modelOrigin = modelOrigin;
    const glm::dvec3 nz = glm::cross(plane.normal, glm::dvec3(0.0, 0.0, 1.0));
    const double len = glm::length(nz);
    f.u = len < 1e-9 ? glm::dvec3(1.0, 0.0, 0.0) : nz / len;
    if (len < 1e-9) {
        // Make u exactly orthogonal to a nearly vertical normal.
        f.u = glm::normalize(f.u - plane.normal * glm::dot(f.u, plane.normal));
    }
    f.v = glm::cross(f.u, plane.normal);
    // The foot of the perpendicular from world (0, 0, 0), as the renderer's PlaneBasis:
    // u/v coordinates depend on the plane alone, so both engines share pixel frames.
    f.originLocal = -plane.d * plane.normal - modelOrigin;
    return f;
}

}  // namespace geoslice
