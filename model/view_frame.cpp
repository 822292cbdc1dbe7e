#include "model/view_frame.hpp"

#include <algorithm>
#include <limits>

namespace geoslice {

FrameRect fitRect(const glm::dvec2& lo, const glm::dvec2& hi, int width, int height, double vStretch, double margin) {
    glm::dvec2 size = glm::max(hi - lo, glm::dvec2(1e-3));
    const glm::dvec2 centre = (lo + hi) * 0.5;
    size *= 1.0 + 2.0 * margin;
    // Metres per pixel along u = vStretch x metres per pixel along v.
    const double mppU = std::max(size.x / width, size.y * vStretch / height);
    const glm::dvec2 half{0.5 * mppU * width, 0.5 * mppU / vStretch * height};
    return FrameRect{centre.x - half.x, centre.y - half.y, centre.x + half.x, centre.y + half.y};
}

FrameRect projectedBounds(const Plane& plane, const Aabb& bounds, const glm::dvec3& modelOrigin) {
    const SectionFrame f = makeSectionFrame(plane, modelOrigin);
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner{(c & 1) ? bounds.max.x : bounds.min.x, (c & 2) ? bounds.max.y : bounds.min.y,
                                (c & 4) ? bounds.max.z : bounds.min.z};
        const glm::dvec2 uv = f.toPlane(corner - modelOrigin);
        lo = glm::min(lo, uv);
        hi = glm::max(hi, uv);
    }
    return FrameRect{lo.x, lo.y, hi.x, hi.y};
}

FrameRect defaultFrame(const Plane& plane, const Aabb& worldBounds, const glm::dvec3& modelOrigin, int width,
                       int height, const VerticalExaggeration& ve) {
    const FrameRect tight = projectedBounds(plane, worldBounds, modelOrigin);
    return fitRect({tight.u0, tight.v0}, {tight.u1, tight.v1}, width, height, ve.vStretch(plane.normal));
}

FrameRect defaultLineFrame(double length, const Aabb& worldBounds, int width, int height,
                           const VerticalExaggeration& ve) {
    return fitRect({0.0, worldBounds.min.z}, {length, worldBounds.max.z}, width, height, ve.factor);
}

}  // namespace geoslice
