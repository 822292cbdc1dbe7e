#include "view/plane.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "view/view_limits.hpp"

namespace geoslice {

Result<Plane> makePlane(double a, double b, double c, double d) {
    const char* names[4] = {"a", "b", "c", "d"};
    const double values[4] = {a, b, c, d};
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(values[i]))
            return makeError(ErrorCode::InvalidArgument,
                             std::string("plane component ") + names[i] + " is not a finite number");
    // Scaled by the largest component first, so that neither 1e308 nor 1e-300 overflows
    // or underflows the length.
    const double scale = std::max({std::abs(a), std::abs(b), std::abs(c)});
    if (!(scale > 0.0))
        return makeError(ErrorCode::InvalidArgument, "plane normal (a, b, c) = (" + limitNumber(a) + ", " +
                                                         limitNumber(b) + ", " + limitNumber(c) + ") has zero length");
    const glm::dvec3 n(a / scale, b / scale, c / scale);
    const double len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    Plane p;
    p.normal = n / len;
    p.d = d / scale / len;
    if (!std::isfinite(p.d))
        return makeError(ErrorCode::OutOfRange, "plane offset d / |(a, b, c)| = " + limitNumber(d) + " / " +
                                                    limitNumber(scale) + " is not a finite number");
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

Result<Plane> checkPlaneMeetsBounds(const Plane& plane, const Aabb& b, const glm::dvec3& origin) {
    auto p = makePlane(plane.normal.x, plane.normal.y, plane.normal.z, plane.d);
    if (!p) return p.error();
    if (!b.valid()) return makeError(ErrorCode::InvalidArgument, "the model has no finite vertices to cut");
    double smin = std::numeric_limits<double>::infinity(), smax = -smin;
    const LocalPlane lp = toLocal(p.value(), origin);
    for (int i = 0; i < 8; ++i) {
        const glm::dvec3 c((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y, (i & 4) ? b.max.z : b.min.z);
        const double s = lp.distanceWorld(c, origin);
        smin = std::min(smin, s);
        smax = std::max(smax, s);
    }
    if (smin >= 0.0 || smax < 0.0) {
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      "plane (%.9g, %.9g, %.9g, %.9g) misses the model: its bounds [%.3f, %.3f, %.3f] - [%.3f, %.3f, "
                      "%.3f] lie entirely on the %s side",
                      p->normal.x, p->normal.y, p->normal.z, p->d, b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z,
                      smin >= 0.0 ? "kept" : "removed");
        return makeError(ErrorCode::OutOfRange, buf);
    }
    return p;
}

}  // namespace geoslice
