// The GL matrices of the cameras of view/camera.hpp for the slicing pass: local frame ->
// clip. Pure CPU code, double precision until the final float matrix; any thread.
//
// Frames: `world` (double, x east, y north, z up, metres), `local` (world - Model::origin,
// what the GPU sees), `plane u/v` (metres in the plane, SectionFrame of view/plane.hpp), `pixel` (column,
// row with row 0 at the top of the image, pixel centres at +0.5).
#pragma once

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"
#include "view/camera.hpp"
#include "view/exaggeration.hpp"
#include "view/plane.hpp"
#include "view/view_frame.hpp"

namespace geoslice {

// Planes (Plane, WorldPlane = its (a, b, c, d) form) and the plane frame: view/plane.hpp.
// Vertical exaggeration (display space): view/exaggeration.hpp. Profile frames (FrameRect,
// the default frame): view/view_frame.hpp.

// Returns the plane scaled to a unit normal; an error for a zero or non-finite normal.
Result<WorldPlane> normalizePlane(const WorldPlane& plane);
// The same plane in the local frame: (n, d + n . origin), computed in double.
glm::dvec4 planeToLocal(const WorldPlane& unitPlane, const glm::dvec3& origin);

// The cameras (ProfileCamera, PerspectiveCamera), their pixel rays and the default frames
// and camera: view/camera.hpp. In a SliceRequest they are in display space (see
// SliceRequest::exaggeration). Below: their GL matrices.

// Local -> clip, and what the fragment stage needs.
struct ViewTransform {
    glm::dmat4 viewProj{1.0};            // local frame -> clip, double
    glm::dvec3 lightDir{0.0, 0.0, 1.0};  // local frame (= world directions), unit
    bool orthographic = false;
};
// Depth spans the model's bounds (worldBounds) seen from the view; `origin` is Model::origin.
Result<ViewTransform> profileTransform(const ProfileCamera& view, const glm::dvec3& origin, const Aabb& worldBounds);
Result<ViewTransform> perspectiveTransform(const PerspectiveCamera& view, const glm::dvec3& origin,
                                           const Aabb& worldBounds, int width, int height);

}  // namespace geoslice
