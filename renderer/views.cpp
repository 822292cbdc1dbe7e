#include "renderer/views.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

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
    glm::dvec3 n(plane);
    double len = glm::length(n);
    if (!std::isfinite(len) || !std::isfinite(plane.w) || len < 1e-12)
        return makeError(ErrorCode::InvalidArgument, "plane (a,b,c,d) needs a finite non-zero normal (a,b,c)");
    return plane / len;
}

glm::dvec4 planeToLocal(const WorldPlane& p, const glm::dvec3& origin) {
    return {p.x, p.y, p.z, p.w + glm::dot(glm::dvec3(p), origin)};
}

glm::dvec3 VerticalExaggeration::toDisplay(const glm::dvec3& w) const {
    return {w.x, w.y, pivotZ + factor * (w.z - pivotZ)};
}

glm::dvec3 VerticalExaggeration::toWorld(const glm::dvec3& d) const {
    return {d.x, d.y, pivotZ + (d.z - pivotZ) / factor};
}

WorldPlane VerticalExaggeration::planeToDisplay(const WorldPlane& p) const {
    // n . x + d with x.z = pivot + (z' - pivot) / f: the z coefficient shrinks by f and d
    // takes up the pivot term; then back to a unit normal.
    const WorldPlane q(p.x, p.y, p.z / factor, p.w + p.z * pivotZ * (1.0 - 1.0 / factor));
    return q / glm::length(glm::dvec3(q));
}

Aabb VerticalExaggeration::boundsToDisplay(const Aabb& b) const {
    Aabb out;
    out.extend(toDisplay(b.min));
    out.extend(toDisplay(b.max));
    return out;
}

Status checkExaggeration(const VerticalExaggeration& e) {
    if (!(e.factor >= kMinExaggeration && e.factor <= kMaxExaggeration))
        return makeError(ErrorCode::InvalidArgument, "vertical exaggeration " + std::to_string(e.factor) +
                                                         " is outside " + std::to_string(kMinExaggeration) + ".." +
                                                         std::to_string(kMaxExaggeration));
    if (!std::isfinite(e.pivotZ))
        return makeError(ErrorCode::InvalidArgument, "vertical exaggeration pivot elevation is not finite");
    return {};
}

glm::dvec2 PlaneBasis::toPlane(const glm::dvec3& w) const { return {glm::dot(w - origin, u), glm::dot(w - origin, v)}; }

PlaneBasis planeBasis(const WorldPlane& p) {
    PlaneBasis b;
    b.n = glm::dvec3(p);
    b.origin = -p.w * b.n;
    glm::dvec3 u = glm::cross(b.n, glm::dvec3(0.0, 0.0, 1.0));
    b.u = glm::length(u) < 1e-9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::normalize(u);
    if (glm::length(u) < 1e-9) b.u = glm::normalize(b.u - glm::dot(b.u, b.n) * b.n);
    b.v = glm::cross(-b.n, b.u);
    return b;
}

ProfileView profileAround(const WorldPlane& plane, const Aabb& bounds, int width, int height, double margin) {
    PlaneBasis basis = planeBasis(plane);
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const glm::dvec3& c : corners(bounds)) {
        glm::dvec2 q = basis.toPlane(c);
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    glm::dvec2 size = glm::max(hi - lo, glm::dvec2(1e-3));
    glm::dvec2 centre = 0.5 * (lo + hi);
    size *= 1.0 + 2.0 * margin;
    const double aspect = double(width) / double(std::max(height, 1));
    if (size.x / size.y < aspect)
        size.x = size.y * aspect;
    else
        size.y = size.x / aspect;
    ProfileView v;
    v.plane = plane;
    v.uMin = centre.x - 0.5 * size.x;
    v.uMax = centre.x + 0.5 * size.x;
    v.vMin = centre.y - 0.5 * size.y;
    v.vMax = centre.y + 0.5 * size.y;
    return v;
}

glm::dvec3 profilePixelWorld(const ProfileView& view, int width, int height, int column, int row) {
    const double pu = view.uMin + (column + 0.5) * (view.uMax - view.uMin) / width;
    const double pv = view.vMax - (row + 0.5) * (view.vMax - view.vMin) / height;
    return planeBasis(view.plane).world(pu, pv);
}

Result<ViewTransform> profileTransform(const ProfileView& view, const glm::dvec3& origin, const Aabb& worldBounds) {
    auto unit = normalizePlane(view.plane);
    if (!unit) return unit.error();
    if (!(view.uMax > view.uMin) || !(view.vMax > view.vMin))
        return makeError(ErrorCode::InvalidArgument, "profile frame needs uMax > uMin and vMax > vMin");
    PlaneBasis b = planeBasis(*unit);
    // Depth: signed distance s along +n from the plane; the kept side is s >= 0. The range
    // starts a little on the removed side so that the plane itself is not at the near plane.
    // The range covers the whole model (union mode keeps material on the removed side too)
    // and starts a little before the plane, so that the plane is never at the near plane.
    double sMin = 0.0, sMax = 1.0;
    for (const glm::dvec3& c : corners(worldBounds)) {
        const double s = glm::dot(b.n, c) + unit->w;
        sMin = std::min(sMin, s);
        sMax = std::max(sMax, s);
    }
    const double pad = 0.01 * (sMax - sMin);
    const double sNear = sMin - pad, sFar = sMax + pad;
    // Each clip coordinate is an affine function of the local position q:
    // u = q.u + uOff, v = q.v + vOff, s = q.n + sOff, with the offsets in double.
    const double uOff = glm::dot(origin - b.origin, b.u), vOff = glm::dot(origin - b.origin, b.v);
    const double sOff = glm::dot(b.n, origin) + unit->w;
    auto row = [](const glm::dvec3& axis, double off, double lo, double hi) {
        const double k = 2.0 / (hi - lo);
        return glm::dvec4(axis * k, (off - lo) * k - 1.0);
    };
    const glm::dvec4 rx = row(b.u, uOff, view.uMin, view.uMax);
    const glm::dvec4 ry = row(b.v, vOff, view.vMin, view.vMax);
    const glm::dvec4 rz = row(b.n, sOff, sNear, sFar);
    ViewTransform t;
    t.orthographic = true;
    for (int c = 0; c < 4; ++c) t.viewProj[c] = glm::dvec4(rx[c], ry[c], rz[c], c == 3 ? 1.0 : 0.0);
    t.lightDir = defaultLight();
    return t;
}

Result<ViewTransform> perspectiveTransform(const PerspectiveView& view, const glm::dvec3& origin,
                                           const Aabb& worldBounds, int width, int height) {
    const glm::dvec3 dir = view.target - view.eye;
    if (!(glm::length(dir) > 0.0) || !std::isfinite(glm::length(dir)))
        return makeError(ErrorCode::InvalidArgument, "perspective view needs eye != target (finite)");
    if (glm::length(glm::cross(glm::normalize(dir), view.up)) < 1e-9)
        return makeError(ErrorCode::InvalidArgument, "perspective view: up is parallel to the view direction");
    if (!(view.fovYDegrees > 0.0 && view.fovYDegrees < 179.0))
        return makeError(ErrorCode::InvalidArgument, "perspective view: fov must be in (0, 179) degrees");
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
