// Frames of profile views: which plane u/v rectangle an image shows, how its pixels map to
// the plane and the world, and the one default frame used by HTTP plans, the CLI's
// `section` and `render`, tiles and the GL renderer's profiles (issue 14: three functions
// framed the same plane three ways).
//
// Frames: plane u/v metres (SectionFrame, view/plane.hpp; for a polyline section u is the
// chainage s and v the elevation z) -> pixel: x = (u - u0) / pu to the right,
// y = (v1 - v) / pv downwards, row 0 at the top; pixel (i, j) covers [i, i+1) x [j, j+1)
// and its centre is (i + 0.5, j + 0.5). Pure functions, any thread.
#pragma once

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "view/exaggeration.hpp"
#include "view/plane.hpp"

namespace geoslice {

// A rectangle of the section plane, u/v metres: [u0, u1] left to right, [v0, v1] bottom to top.
struct FrameRect {
    double u0 = 0.0, v0 = 0.0, u1 = 1.0, v1 = 1.0;
};

// Pixel <-> plane u/v <-> world.
// The one empty-frame check: InvalidArgument unless u1 > u0 and v1 > v0 (NaN fails).
Status checkFrameNotEmpty(const FrameRect& rect);
// Checks a frame against view/view_limits.hpp before any work: size 1..kMaxImageSide
// per side and at most kMaxImagePixels, a finite rectangle within kMaxCoordinateMetres
// with u1 > u0 and v1 > v0, and pixels of at least kMinPixelMetres (and kMinPixelUlps
// double steps) along both axes. Errors: OutOfRange / InvalidArgument naming the value.
Status checkFrame(const FrameRect& rect, int width, int height);

struct PixelFrame {
    SectionFrame section;
    FrameRect rect;
    int width = 0, height = 0;

    double pixelU() const { return (rect.u1 - rect.u0) / width; }   // metres per pixel along u
    double pixelV() const { return (rect.v1 - rect.v0) / height; }  // metres per pixel along v
    glm::dvec2 pixelToPlane(double x, double y) const { return {rect.u0 + x * pixelU(), rect.v1 - y * pixelV()}; }
    glm::dvec2 planeToPixel(const glm::dvec2& uv) const {
        return {(uv.x - rect.u0) / pixelU(), (rect.v1 - uv.y) / pixelV()};
    }
    // World point of the centre of pixel (i, j).
    glm::dvec3 pixelCentreWorld(int i, int j) const { return section.toWorld(pixelToPlane(i + 0.5, j + 0.5)); }
    // The same as an affine map: world = worldAtCorner + x * worldPerPixelX + y * worldPerPixelY.
    glm::dvec3 worldAtCorner() const { return section.toWorld(pixelToPlane(0.0, 0.0)); }
    glm::dvec3 worldPerPixelX() const { return section.u * pixelU(); }
    glm::dvec3 worldPerPixelY() const { return -section.v * pixelV(); }
};

// Margin of default frames on each side, as a fraction of the contents' size.
constexpr double kDefaultFrameMargin = 0.02;

// The framing rule: the rectangle [lo, hi] (u/v metres; a side under 1 mm counts as 1 mm)
// grown by `margin` x its size on each side, then along one axis, about its centre, until
// its pixels satisfy (metres per pixel along u) = vStretch x (metres per pixel along v)
// for a width x height image (vStretch 1: square pixels; see VerticalExaggeration).
FrameRect fitRect(const glm::dvec2& lo, const glm::dvec2& hi, int width, int height, double vStretch = 1.0,
                  double margin = kDefaultFrameMargin);

// `worldBounds` projected on the plane's u/v axes (SectionFrame of `plane` with
// `modelOrigin`): the tight u/v rectangle around its eight corners.
FrameRect projectedBounds(const Plane& plane, const Aabb& worldBounds, const glm::dvec3& modelOrigin);

// The default frame of a profile of `plane`: the model's bounds projected on the plane,
// fitted by fitRect with the plane's exaggeration stretch (ve.vStretch(plane.normal)).
FrameRect defaultFrame(const Plane& plane, const Aabb& worldBounds, const glm::dvec3& modelOrigin, int width,
                       int height, const VerticalExaggeration& ve = {});

// The default frame of a vertical section along a map polyline `length` metres long:
// chainage 0..length by the model's elevation range, fitted with stretch ve.factor.
FrameRect defaultLineFrame(double length, const Aabb& worldBounds, int width, int height,
                           const VerticalExaggeration& ve = {});

}  // namespace geoslice
