#include "view/view_frame.hpp"
#include "view/view_limits.hpp"

#include <algorithm>
#include <limits>
#include <string>

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

Status checkFrameNotEmpty(const FrameRect& rect) {
    if (!(rect.u1 > rect.u0) || !(rect.v1 > rect.v0))
        return makeError(ErrorCode::InvalidArgument, "frame rectangle is empty: u " + limitNumber(rect.u0) + ".." +
                                                         limitNumber(rect.u1) + ", v " + limitNumber(rect.v0) + ".." +
                                                         limitNumber(rect.v1) + " (needs u0 < u1 and v0 < v1)");
    return {};
}

Status checkFrame(const FrameRect& rect, int width, int height) {
    if (Status s = checkImageSize("image size", width, height); !s) return s;
    const double c[4] = {rect.u0, rect.u1, rect.v0, rect.v1};
    const char* names[4] = {"u0", "u1", "v0", "v1"};
    for (int i = 0; i < 4; ++i)
        if (Status s = checkCoordinate(std::string("frame ") + names[i], c[i]); !s) return s;
    if (Status s = checkFrameNotEmpty(rect); !s) return s;
    if (Status s = checkPixelSize("frame u0..u1", rect.u0, rect.u1, width); !s) return s;
    if (Status s = checkPixelSize("frame v0..v1", rect.v0, rect.v1, height); !s) return s;
    return {};
}

}  // namespace geoslice
