// Planes and the plane frame (plane u/v coordinates): the one definition every engine
// uses (section/ cuts, renderer/ clip planes and profile views, api/ plans, cli/).
//
// Frames: `world` is double (x east, y north, z up, metres, the model's CRS); `local` is
// world - Model::origin, kept in double here (the BVH's float bounds are rounded outward
// from it); `plane u/v` is metres in the section plane from SectionFrame::originLocal.
//
// Contract (shared/DESIGN.md, paper eq. 3): a plane is (a, b, c, d) with a unit normal in
// world coordinates, and a point p is kept when a*x + b*y + c*z + d >= 0.
//
// Robustness rule used by every cut in section/ (symbolic perturbation, after Edelsbrunner
// & Muecke, "Simulation of Simplicity", ACM TOG 9(1), 1990): a vertex whose signed
// distance is exactly 0 counts as strictly positive. The cut is then the limit of cuts by
// planes moved an infinitesimal distance towards the removed side, so it never passes
// through a vertex, every closed body gives closed loops, and a face lying in the plane
// belongs to the cut only when its body extends to the removed side.
#pragma once

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

// A plane in world coordinates: normal . p + d = 0; `normal` is unit (dimensionless), `d`
// metres; the kept side is normal . p + d >= 0.
struct Plane {
    glm::dvec3 normal{0.0, 0.0, 1.0};
    double d = 0.0;
};

// The same plane as the 4-vector (a, b, c, d) that GL clip planes take (renderer/): a point
// p is kept when dot((a, b, c), p) + d >= 0. Not necessarily unit until normalised.
using WorldPlane = glm::dvec4;
inline WorldPlane toWorldPlane(const Plane& p) { return {p.normal.x, p.normal.y, p.normal.z, p.d}; }

// Validates (a, b, c, d): all finite, |(a, b, c)| > 0. A normal that is not unit is
// normalised (d scaled with it), so the kept side is unchanged.
// Errors: InvalidArgument naming the bad component.
Result<Plane> makePlane(double a, double b, double c, double d);

// Checks a plane (a, b, c, d) against a model's bounds: makePlane, then InvalidArgument
// when the bounds are empty and OutOfRange when the plane misses them (naming the plane,
// the bounds and the side they lie on). `origin`: the model's local origin (distances are
// taken from it, as the section engine takes them).
Result<Plane> checkPlaneMeetsBounds(const Plane& plane, const Aabb& bounds, const glm::dvec3& origin);

// The horizontal plane z = elevation (world, metres), keeping what lies below it
// (normal (0, 0, -1)): a plan map seen from above.
Plane horizontalPlane(double elevation);

// The same plane in the local frame: n . p_local + d = 0 with d = d_world + n . origin.
struct LocalPlane {
    glm::dvec3 n{0.0, 0.0, 1.0};
    double d = 0.0;
    // Signed distance (metres) of a local point; the one formula every cut uses, so a
    // vertex gets the same sign in every triangle that shares it.
    double distance(const glm::dvec3& local) const { return n.x * local.x + n.y * local.y + n.z * local.z + d; }
    // Signed distance of a world point given the model origin: the subtraction is done
    // first, in double, identically for every caller.
    double distanceWorld(const glm::dvec3& world, const glm::dvec3& origin) const { return distance(world - origin); }
};

LocalPlane toLocal(const Plane& plane, const glm::dvec3& origin);

// The section frame: orthonormal world axes u (horizontal), v and the plane normal n,
// with v = u x n (so v points up on vertical planes) and u x v = -n (the renderer's
// PlaneBasis, right-handed as (u, v, -n)): a viewer on the
// removed side, looking along +n at the cut face of the kept half, sees u to the right
// and v up; counter-clockwise loops in u/v are outer boundaries.
//   u = normalize(n x z) for non-horizontal planes, world x for horizontal ones
//   (|n x z| < 1e-9): a plan map keeping the part below (n = -z) has u east, v north.
struct SectionFrame {
    glm::dvec3 normal{0.0, 0.0, 1.0};  // world unit normal (kept side)
    glm::dvec3 u{1.0, 0.0, 0.0};       // world unit vector, horizontal
    glm::dvec3 v{0.0, -1.0, 0.0};      // world unit vector, v = u x n
    glm::dvec3 originLocal{0.0};       // local point on the plane that is (u, v) = (0, 0): world -d n
    glm::dvec3 modelOrigin{0.0};       // Model::origin (world)

    // local (metres) -> plane u/v (metres); the point is projected onto the plane.
    glm::dvec2 toPlane(const glm::dvec3& local) const {
        const glm::dvec3 r = local - originLocal;
        return {glm::dot(r, u), glm::dot(r, v)};
    }
    glm::dvec3 toLocal(const glm::dvec2& uv) const { return originLocal + uv.x * u + uv.y * v; }
    glm::dvec3 toWorld(const glm::dvec2& uv) const { return modelOrigin + toLocal(uv); }
    glm::dvec3 originWorld() const { return modelOrigin + originLocal; }
};

// The frame of `plane`, its u/v origin the foot of the perpendicular from world (0, 0, 0)
// (-d n): the same u, v and origin as renderer/views.hpp's PlaneBasis, so a u/v rectangle
// names the same pixels in both engines. Far from the world origin (Gauss-Kruger eastings)
// u/v values are large (3.5e7 m) but double keeps them to 1e-8 m.
SectionFrame makeSectionFrame(const Plane& plane, const glm::dvec3& modelOrigin);

}  // namespace geoslice
