#include "renderer/views.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "view/view_limits.hpp"

namespace geoslice {
namespace {

std::array<glm::dvec3, 8> corners(const Aabb& b) {
    std::array<glm::dvec3, 8> c;
    for (int i = 0; i < 8; ++i)
        c[std::size_t(i)] = {i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z};
    return c;
}

glm::dvec3 defaultLight() { return glm::normalize(glm::dvec3(-0.45, 0.35, 0.82)); }

}  // namespace

Result<WorldPlane> normalizePlane(const WorldPlane& plane) {
    // The one normalisation of a plane (view/plane.hpp: overflow-safe, errors named).
    auto unit = makePlane(plane.x, plane.y, plane.z, plane.w);
    if (!unit) return unit.error();
    return toWorldPlane(unit.value());
}

glm::dvec4 planeToLocal(const WorldPlane& p, const glm::dvec3& origin) {
    return {p.x, p.y, p.z, p.w + glm::dot(glm::dvec3(p), origin)};
}

Result<ViewTransform> profileTransform(const ProfileCamera& view, const glm::dvec3& origin, const Aabb& worldBounds) {
    auto unit = normalizePlane(view.plane);
    if (!unit) return unit.error();
    const FrameRect& r = view.rect;
    if (Status s = checkFrameNotEmpty(r); !s) return s.error();
    const SectionFrame b = makeSectionFrame(Plane{glm::dvec3(*unit), unit->w}, glm::dvec3(0.0));
    const glm::dvec3 planeOrigin = b.originWorld();
    // Depth: signed distance s along +n from the plane; the kept side is s >= 0. The range
    // starts a little on the removed side so that the plane itself is not at the near plane.
    // The range covers the whole model (union mode keeps material on the removed side too)
    // and starts a little before the plane, so that the plane is never at the near plane.
    double sMin = 0.0, sMax = 1.0;
    for (const glm::dvec3& c : corners(worldBounds)) {
        const double s = glm::dot(b.normal, c) + unit->w;
        sMin = std::min(sMin, s);
        sMax = std::max(sMax, s);
    }
    const double pad = 0.01 * (sMax - sMin);
    const double sNear = sMin - pad, sFar = sMax + pad;
    // Each clip coordinate is an affine function of the local position q:
    // u = q.u + uOff, v = q.v + vOff, s = q.n + sOff, with the offsets in double.
    const double uOff = glm::dot(origin - planeOrigin, b.u), vOff = glm::dot(origin - planeOrigin, b.v);
    const double sOff = glm::dot(b.normal, origin) + unit->w;
    auto row = [](const glm::dvec3& axis, double off, double lo, double hi) {
        const double k = 2.0 / (hi - lo);
        return glm::dvec4(axis * k, (off - lo) * k - 1.0);
    };
    const glm::dvec4 rx = row(b.u, uOff, r.u0, r.u1);
    const glm::dvec4 ry = row(b.v, vOff, r.v0, r.v1);
    const glm::dvec4 rz = row(b.normal, sOff, sNear, sFar);
    ViewTransform t;
    t.orthographic = true;
    for (int c = 0; c < 4; ++c) t.viewProj[c] = glm::dvec4(rx[c], ry[c], rz[c], c == 3 ? 1.0 : 0.0);
    t.lightDir = defaultLight();
    return t;
}

Result<ViewTransform> perspectiveTransform(const PerspectiveCamera& view, const glm::dvec3& origin,
                                           const Aabb& worldBounds, int width, int height) {
    const glm::dvec3 dir = view.target - view.eye;
    if (!(glm::length(dir) > 0.0) || !std::isfinite(glm::length(dir)))
        return makeError(ErrorCode::InvalidArgument, "perspective view needs eye != target (finite)");
    if (glm::length(glm::cross(glm::normalize(dir), view.up)) < 1e-9)
        return makeError(ErrorCode::InvalidArgument, "perspective view: up is parallel to the view direction");
    if (auto s = checkFov("perspective view: fov", view.fovYDegrees); !s) return s.error();
    const glm::dvec3 eyeLocal = view.eye - origin, targetLocal = view.target - origin;
    const glm::dmat4 viewM = glm::lookAt(eyeLocal, targetLocal, view.up);
    const glm::dvec3 fwd = glm::normalize(dir);
    double zMin = std::numeric_limits<double>::infinity(), zMax = 0.0;
    for (const glm::dvec3& c : corners(worldBounds)) {
        const double z = glm::dot(c - view.eye, fwd);
        zMin = std::min(zMin, z);
        zMax = std::max(zMax, z);
    }
    const double farZ = std::max(zMax * 1.01, 1.0);
    const double nearZ = std::max(zMin * 0.99, farZ * 1e-5);
    const glm::dmat4 proj =
        glm::perspective(glm::radians(view.fovYDegrees), double(width) / double(height), nearZ, farZ);
    ViewTransform t;
    t.viewProj = proj * viewM;
    t.lightDir = defaultLight();
    return t;
}

}  // namespace geoslice
