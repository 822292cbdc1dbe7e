// The cameras of geoslice's images, and their pixel rays: one definition for HTTP plans
// (api/plan.hpp), the GL renderer's view matrices (renderer/views.hpp), pixel queries
// (api/view.hpp) and the CLI (issue 14: the renderer, the plans and the query each had their
// own copy of the perspective camera and its projection).
//
//   ProfileCamera      orthographic, looking along a plane's normal at a rectangle of the plane
//   PerspectiveCamera  eye, target, up, vertical field of view (gluPerspective)
//
// Coordinates: world metres (x east, y north, z up), or display metres when the camera looks
// at an exaggerated model (view/exaggeration.hpp: a renderer request takes display cameras,
// a plan's camera is world and api::displayCamera maps it). Pixels: x to the right, y down,
// row 0 at the top; pixel (i, j) covers [i, i+1) x [j, j+1), its centre is (i + 0.5, j + 0.5).
// Pure functions, any thread.
#pragma once

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "view/exaggeration.hpp"
#include "view/plane.hpp"
#include "view/view_frame.hpp"

namespace geoslice {

// A ray: origin (metres) and unit direction.
struct PixelRay {
    glm::dvec3 origin{0.0}, direction{0.0, 0.0, -1.0};
};

// Orthographic profile: the viewer looks along +n at the plane, from the removed side at the
// cut face, and sees the plane's u to the right and v up (SectionFrame of view/plane.hpp,
// its origin the foot of the perpendicular from world (0, 0, 0)); the image spans `rect`
// (plane u/v metres).
struct ProfileCamera {
    WorldPlane plane{0.0, 1.0, 0.0, 0.0};  // (a, b, c, d), unit normal (a, b, c)
    FrameRect rect;                        // u0 < u1, v0 < v1
};

// Perspective: the image's vertical side spans fovYDegrees, its aspect is width / height.
// Limits (view/view_limits.hpp): eye to target at least kMinCameraDistanceMetres, fov in
// kMinFovDeg..kMaxFovDeg (checked where a camera comes in: api::parseViewPlan, the CLI).
struct PerspectiveCamera {
    glm::dvec3 eye{0.0};               // metres
    glm::dvec3 target{0.0, 1.0, 0.0};  // metres, the point at the image centre
    glm::dvec3 up{0.0, 0.0, 1.0};      // direction, not parallel to target - eye
    double fovYDegrees = 45.0;         // vertical field of view, degrees
};

// The ray through pixel coordinates (x, y) of a width x height image: for a profile, from
// the point of the plane at (x, y) along +n; for a perspective camera, from the eye, as the
// GL renderer projects (renderer/views.hpp perspectiveTransform).
PixelRay pixelRay(const ProfileCamera& camera, int width, int height, double x, double y);
PixelRay pixelRay(const PerspectiveCamera& camera, int width, int height, double x, double y);

// A profile's pixel <-> plane <-> world mapping (view/view_frame.hpp), Model::origin 0.
PixelFrame pixelFrame(const ProfileCamera& camera, int width, int height);

// The display-space profile that shows `frame` (true plane u/v metres of `plane`, e.g.
// defaultFrame or a request's frame) with exaggeration `ve`: the same picture the exact
// engine draws for that frame (view/exaggeration.hpp).
ProfileCamera profileCamera(const Plane& plane, const FrameRect& frame, const VerticalExaggeration& ve = {});
// The profile of `unitPlane` framed by the default frame rule (fitRect of
// view/view_frame.hpp) around `worldBounds` projected on it, square pixels.
ProfileCamera profileAround(const WorldPlane& unitPlane, const Aabb& worldBounds, int width, int height,
                            double margin = kDefaultFrameMargin);

// The default perspective camera around `bounds`: from the south-east and above (direction
// (1, -1, 0.8)), looking at the centre, 45 degrees vertical, at the distance where the image's
// half-height at the target is 1.05 x the bounding sphere's radius (so the sphere's section
// through the target fits with 5 % to spare; its near half may reach past the edges).
PerspectiveCamera defaultCamera(const Aabb& bounds);

}  // namespace geoslice
