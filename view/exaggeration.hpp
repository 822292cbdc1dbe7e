// Vertical exaggeration: the one rule behind HTTP `vx=`, the CLI's `--exaggeration`, profile
// frames, tile grids and perspective views (issue 14: the CLI pivoted at 0, HTTP at the
// bounds' centre).
//
// Display space stretches world elevation by `factor` about the elevation `pivotZ`:
//   z' = pivotZ + factor (z - pivotZ),  x' = x,  y' = y        (world metres)
// Pivot rule: the centre elevation of the model's bounds (aboutCentreOf). Because the map
// is affine, the pivot only translates display space: views fitted to the model, and
// cameras given as world points, look the same for any pivot. Cut planes, record ids,
// pixel queries and coordinates stay in true world coordinates; only the picture is
// stretched.
//
// Profile views: a plane's u axis is horizontal (view/plane.hpp), so exaggeration leaves
// plane u alone and scales plane v by vStretch(n) = sqrt(nz^2 + factor^2 (1 - nz^2)) for a
// unit normal n: `factor` on a vertical plane, 1 on a horizontal one (a plan map is not
// stretched). The exact engine draws that as pixels vStretch times shorter (in metres)
// along v than along u; the GL renderer draws the display-space plane with square pixels.
// Both give the same picture (tests/server/cli_http_agree_test.cpp). Any thread.
#pragma once

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"
#include "view/plane.hpp"
#include "view/view_limits.hpp"

namespace geoslice {

// Exaggeration factors accepted everywhere: kMinExaggeration..kMaxExaggeration (view/view_limits.hpp).

struct VerticalExaggeration {
    double factor = 1.0;  // dimensionless, kMinExaggeration..kMaxExaggeration; 1 = none
    double pivotZ = 0.0;  // world elevation that stays put, metres

    // The pivot rule: `factor` about the centre elevation of `worldBounds`.
    static VerticalExaggeration aboutCentreOf(double factor, const Aabb& worldBounds) {
        return {factor, 0.5 * (worldBounds.min.z + worldBounds.max.z)};
    }

    bool identity() const { return factor == 1.0; }
    glm::dvec3 toDisplay(const glm::dvec3& world) const {
        return {world.x, world.y, pivotZ + factor * (world.z - pivotZ)};
    }
    glm::dvec3 toWorld(const glm::dvec3& display) const {
        return {display.x, display.y, pivotZ + (display.z - pivotZ) / factor};
    }
    // A world plane (unit normal) as the same set of points in display space (unit normal).
    WorldPlane planeToDisplay(const WorldPlane& unitPlane) const;
    Plane planeToDisplay(const Plane& plane) const;
    Aabb boundsToDisplay(const Aabb& worldBounds) const;
    // Display metres per true metre along the plane's v axis (u is unchanged); see above.
    double vStretch(const glm::dvec3& unitNormal) const;
};

// InvalidArgument unless factor is finite in [kMinExaggeration, kMaxExaggeration] and
// pivotZ is finite.
Status checkExaggeration(const VerticalExaggeration& exaggeration);

}  // namespace geoslice
