// Views of a model for the slicing pass, and the maths that turns them into local-frame
// matrices. Pure CPU code, double precision until the final float matrix; any thread.
//
// Frames: `world` (double, x east, y north, z up, metres), `local` (world - Model::origin,
// what the GPU sees), `plane u/v` (metres in the plane, SectionFrame of model/plane.hpp), `pixel` (column,
// row with row 0 at the top of the image, pixel centres at +0.5).
#pragma once

#include <glm/glm.hpp>

#include "model/exaggeration.hpp"
#include "model/model.hpp"
#include "model/plane.hpp"
#include "model/result.hpp"
#include "model/view_frame.hpp"

namespace geoslice {

// Planes (Plane, WorldPlane = its (a, b, c, d) form) and the plane frame: model/plane.hpp.
// Vertical exaggeration (display space): model/exaggeration.hpp. Profile frames (FrameRect,
// the default frame): model/view_frame.hpp.

// Returns the plane scaled to a unit normal; an error for a zero or non-finite normal.
Result<WorldPlane> normalizePlane(const WorldPlane& plane);
// The same plane in the local frame: (n, d + n . origin), computed in double.
glm::dvec4 planeToLocal(const WorldPlane& unitPlane, const glm::dvec3& origin);

// Orthographic profile: the viewer looks along +n at the plane, from the removed side at
// the cut face, and sees the plane's u to the right and v up (SectionFrame of
// model/plane.hpp, its origin the foot of the perpendicular from world (0, 0, 0)); the image
// spans [uMin, uMax] x [vMin, vMax] in plane u/v metres. In a SliceRequest the plane and
// its frame are in display space (see SliceRequest::exaggeration).
struct ProfileView {
    WorldPlane plane{0.0, 1.0, 0.0, 0.0};  // unit normal
    double uMin = 0.0, uMax = 1.0, vMin = 0.0, vMax = 1.0;
};
// The display-space profile that shows `frame` (true plane u/v metres of `plane`, e.g.
// defaultFrame or a request's frame) with exaggeration `ve`: the same picture the exact
// engine draws for that frame (model/exaggeration.hpp).
ProfileView profileView(const Plane& plane, const FrameRect& frame, const VerticalExaggeration& ve = {});
// The profile of `unitPlane` framed by the default frame rule (fitRect of
// model/view_frame.hpp) around `worldBounds` projected on it, square pixels.
ProfileView profileAround(const WorldPlane& unitPlane, const Aabb& worldBounds, int width, int height,
                          double margin = kDefaultFrameMargin);
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
