#include "view/camera.hpp"

#include <algorithm>
#include <cmath>

namespace geoslice {

PixelRay pixelRay(const ProfileCamera& camera, int width, int height, double x, double y) {
    const FrameRect& r = camera.rect;
    const double pu = r.u0 + x * (r.u1 - r.u0) / width;
    const double pv = r.v1 - y * (r.v1 - r.v0) / height;
    const Plane p{glm::dvec3(camera.plane), camera.plane.w};
    PixelRay ray;
    ray.origin = makeSectionFrame(p, glm::dvec3(0.0)).toWorld({pu, pv});
    ray.direction = glm::normalize(glm::dvec3(camera.plane));
    return ray;
}

PixelRay pixelRay(const PerspectiveCamera& camera, int width, int height, double x, double y) {
    const glm::dvec3 f = glm::normalize(camera.target - camera.eye);
    const glm::dvec3 r = glm::normalize(glm::cross(f, camera.up));
    const glm::dvec3 u = glm::cross(r, f);
    const double t = std::tan(glm::radians(camera.fovYDegrees) * 0.5);
    const double ndcX = 2.0 * x / width - 1.0, ndcY = 1.0 - 2.0 * y / height;
    PixelRay ray;
    ray.origin = camera.eye;
    ray.direction = glm::normalize(f + ndcX * t * (double(width) / double(height)) * r + ndcY * t * u);
    return ray;
}

PixelFrame pixelFrame(const ProfileCamera& camera, int width, int height) {
    const Plane p{glm::dvec3(camera.plane), camera.plane.w};
    return PixelFrame{makeSectionFrame(p, glm::dvec3(0.0)), camera.rect, width, height};
}

ProfileCamera profileCamera(const Plane& plane, const FrameRect& f, const VerticalExaggeration& ve) {
    // Exaggeration maps true plane u/v affinely onto the display plane's u/v (u' = u + a,
    // v' = vStretch v + b): map two opposite corners of the frame through the world.
    const SectionFrame truth = makeSectionFrame(plane, glm::dvec3(0.0));
    const Plane display = ve.planeToDisplay(plane);
    const SectionFrame shown = makeSectionFrame(display, glm::dvec3(0.0));
    const glm::dvec2 a = shown.toPlane(ve.toDisplay(truth.toWorld({f.u0, f.v0})));
    const glm::dvec2 b = shown.toPlane(ve.toDisplay(truth.toWorld({f.u1, f.v1})));
    ProfileCamera c;
    c.plane = toWorldPlane(display);
    c.rect = FrameRect{std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)};
    return c;
}

ProfileCamera profileAround(const WorldPlane& plane, const Aabb& bounds, int width, int height, double margin) {
    const Plane p{glm::dvec3(plane), plane.w};
    const FrameRect tight = projectedBounds(p, bounds, glm::dvec3(0.0));
    ProfileCamera c;
    c.plane = plane;
    c.rect = fitRect({tight.u0, tight.v0}, {tight.u1, tight.v1}, width, height, 1.0, margin);
    return c;
}

PerspectiveCamera defaultCamera(const Aabb& bounds) {
    PerspectiveCamera c;
    const glm::dvec3 size = bounds.size();
    const double radius = 0.5 * glm::length(size);
    c.target = bounds.centre();
    const glm::dvec3 dir = glm::normalize(glm::dvec3(1.0, -1.0, 0.8));
    c.eye = c.target + dir * (radius / std::tan(glm::radians(c.fovYDegrees) * 0.5) * 1.05);
    return c;
}

}  // namespace geoslice
