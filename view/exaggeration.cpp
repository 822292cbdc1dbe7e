#include "view/exaggeration.hpp"

#include <cmath>
#include <string>

#include "view/view_limits.hpp"

namespace geoslice {

WorldPlane VerticalExaggeration::planeToDisplay(const WorldPlane& p) const {
    // n . x + d with x.z = pivot + (z' - pivot) / f: the z coefficient shrinks by f and d
    // takes up the pivot term; then back to a unit normal.
    const WorldPlane q(p.x, p.y, p.z / factor, p.w + p.z * pivotZ * (1.0 - 1.0 / factor));
    return q / glm::length(glm::dvec3(q));
}

Plane VerticalExaggeration::planeToDisplay(const Plane& plane) const {
    const WorldPlane q = planeToDisplay(toWorldPlane(plane));
    return Plane{glm::dvec3(q), q.w};
}

Aabb VerticalExaggeration::boundsToDisplay(const Aabb& b) const {
    Aabb out;
    out.extend(toDisplay(b.min));
    out.extend(toDisplay(b.max));
    return out;
}

double VerticalExaggeration::vStretch(const glm::dvec3& n) const {
    // v = u x n is the unit in-plane direction orthogonal to the horizontal u; its vertical
    // component is |n_horizontal| and its horizontal one |nz|. Display scales only z.
    const double nz2 = std::min(1.0, n.z * n.z);
    return std::sqrt(nz2 + factor * factor * (1.0 - nz2));
}

Status checkExaggeration(const VerticalExaggeration& e) {
    if (auto s = checkExaggerationFactor("vertical exaggeration", e.factor); !s)
        return makeError(ErrorCode::InvalidArgument, s.error().message);
    if (!std::isfinite(e.pivotZ))
        return makeError(ErrorCode::InvalidArgument, "vertical exaggeration pivot elevation is not finite");
    return {};
}

}  // namespace geoslice
