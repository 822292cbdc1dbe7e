// Views of a model for the slicing pass, and the maths that turns them into local-frame
// matrices. Pure CPU code, double precision until the final float matrix; any thread.
//
// Frames: `world` (double, x east, y north, z up, metres), `local` (world - Model::origin,
// what the GPU sees), `plane u/v` (metres in the plane, see PlaneBasis), `pixel` (column,
// row with row 0 at the top of the image, pixel centres at +0.5).
#pragma once

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

// A plane (a, b, c, d) in world coordinates: a point p is kept when a*x + b*y + c*z + d >= 0.
using WorldPlane = glm::dvec4;

// Returns the plane scaled to a unit normal; an error for a zero or non-finite normal.
Result<WorldPlane> normalizePlane(const WorldPlane& plane);
// The same plane in the local frame: (n, d + n . origin), computed in double.
glm::dvec4 planeToLocal(const WorldPlane& unitPlane, const glm::dvec3& origin);

// Vertical exaggeration. Views are set up in `display` space, where world elevation is
// stretched by `factor` about the elevation `pivotZ` (metres): z' = pivotZ + factor * (z -
// pivotZ); x and y are unchanged. Cut planes, record ids and depth-to-world recovery stay in
// true world coordinates: only the picture is stretched. factor 1 = no exaggeration.
struct VerticalExaggeration {
    double factor = 1.0;
    double pivotZ = 0.0;  // world elevation that stays put, metres
    bool identity() const { return factor == 1.0; }
    glm::dvec3 toDisplay(const glm::dvec3& world) const;
    glm::dvec3 toWorld(const glm::dvec3& display) const;
    // A world plane (unit normal) as the same set of points in display space (unit normal).
    WorldPlane planeToDisplay(const WorldPlane& unitPlane) const;
    Aabb boundsToDisplay(const Aabb& worldBounds) const;
};
constexpr double kMinExaggeration = 0.01, kMaxExaggeration = 100.0;
// InvalidArgument unless factor is finite in [kMinExaggeration, kMaxExaggeration] and
// pivotZ is finite.
Status checkExaggeration(const VerticalExaggeration& exaggeration);

// Orthonormal basis of a plane, right-handed as (u, v, -n): a viewer looking along +n (from
// the removed side at the kept material, i.e. at the cut face, whose outward normal is -n)
// sees u to the right and v up. u is horizontal: u = normalize(n x z_up); for a horizontal
// plane (n = +-z) u = east. origin = the foot of the perpendicular from world (0,0,0), so
// the u/v coordinates of a point depend on the plane alone, not on the model.
struct PlaneBasis {
    glm::dvec3 origin, u, v, n;
    glm::dvec3 world(double pu, double pv) const { return origin + pu * u + pv * v; }
    glm::dvec2 toPlane(const glm::dvec3& world) const;  // projection onto the plane, u/v metres
};
PlaneBasis planeBasis(const WorldPlane& unitPlane);

// Orthographic profile: the viewer looks along +n at the plane (see PlaneBasis); the image
// spans [uMin, uMax] x [vMin, vMax] in plane u/v metres (u to the right, v up).
struct ProfileView {
    WorldPlane plane{0.0, 1.0, 0.0, 0.0};  // unit normal
    double uMin = 0.0, uMax = 1.0, vMin = 0.0, vMax = 1.0;
};
// A profile frame that covers the projection of `bounds` onto the plane, grown by
// `margin` x its size on each side, with the aspect ratio of width x height (centred).
ProfileView profileAround(const WorldPlane& unitPlane, const Aabb& worldBounds, int width, int height,
                          double margin = 0.02);
// World point at the centre of pixel (column, row), row 0 at the top.
glm::dvec3 profilePixelWorld(const ProfileView& view, int width, int height, int column, int row);

// Perspective: eye and target in world, up (world direction), vertical field of view.
struct PerspectiveView {
    glm::dvec3 eye{0.0}, target{0.0, 1.0, 0.0}, up{0.0, 0.0, 1.0};
    double fovYDegrees = 45.0;
};

// Local -> clip, and what the fragment stage needs.
struct ViewTransform {
    glm::dmat4 viewProj{1.0};            // local frame -> clip, double
    glm::dvec3 lightDir{0.0, 0.0, 1.0};  // local frame (= world directions), unit
    bool orthographic = false;
};
// Depth spans the model's bounds (worldBounds) seen from the view; `origin` is Model::origin.
Result<ViewTransform> profileTransform(const ProfileView& view, const glm::dvec3& origin, const Aabb& worldBounds);
Result<ViewTransform> perspectiveTransform(const PerspectiveView& view, const glm::dvec3& origin,
                                           const Aabb& worldBounds, int width, int height);

}  // namespace geoslice
