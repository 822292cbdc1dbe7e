// Cut-outs: up to six planes over one perspective view, and the region of the model they
// keep. The query of a pixel and the GL image of the same plan follow the same rule.
//
// Every plane (a, b, c, d) (world, unit normal) has a kept half-space a*x + b*y + c*z + d >= 0
// and a removed half-space (< 0), as a single section plane has (shared/DESIGN.md). The
// parameter `cut` says how the removed half-spaces combine:
//   cut=union         removed = the union of the removed half-spaces; kept = the points on
//                     the kept side of every plane (a convex region): two planes keep a
//                     wedge, six a box and take away all the model outside it.
//   cut=intersection  removed = the intersection of the removed half-spaces (a convex
//                     region); kept = the points on the kept side of at least one plane: two
//                     planes take a wedge out, three an octant, six a box (each plane's kept
//                     side facing out of the box).
// With one plane both are the same cut (the kept half-space).
//
// Request parameters (read by api/plan.hpp's parseSectionDef):
//   plane=a,b,c,d             repeated up to 6 times (the server joins the values with ';'), or
//   planes=a,b,c,d;a,b,c,d... the same list in one parameter; not both in one request
//   cut=union|intersection    required with two or more planes (there is no default: the
//                             two readings of "cut with these planes" differ)
// Canonical text (cache keys, ETags, section ids): one plane `plane=a,b,c,d`; two or more
// `planes=p1;p2;...&cut=MODE` with the planes normalised and sorted (the region does not
// depend on their order). Two or more planes cut perspective views and their queries only.
// Pure functions, any thread.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"
#include "view/plane.hpp"

namespace geoslice::api {

constexpr std::size_t kMaxCutPlanes = 6;  // the renderer's kMaxPlanes

enum class CutMode { Union, Intersection };
const char* cutModeName(CutMode mode);  // "union", "intersection"

// A span [from, to] of a ray's parameter t (metres along a unit direction).
struct RaySpan {
    double from = 0.0, to = 0.0;
};

struct CutOut {
    std::vector<Plane> planes;  // world, unit normals, 1..kMaxCutPlanes
    CutMode mode = CutMode::Union;

    // Is the world point kept (on the boundary counts as kept)?
    bool keeps(const glm::dvec3& world) const;
    // The kept parts of the ray origin + t * direction, t >= 0 (world, unit direction): at
    // most two spans, in order, each from < to or a span to infinity. Union: the kept region
    // is convex, one span; intersection: the removed region is convex, the ray minus one span.
    std::vector<RaySpan> keptSpans(const glm::dvec3& origin, const glm::dvec3& direction) const;
};

// One plane "a,b,c,d" (finite, |(a, b, c)| > 0, normalised; a normal already unit to rounding
// is kept bit for bit, so canonical text parses back to itself). Errors start with
// "parameter 'NAME'" + `which` (e.g. ": plane 2").
Result<Plane> parsePlane(std::string_view name, std::string_view text, std::string_view which = "");
// A list "p1;p2;..." of 1..kMaxCutPlanes planes, in the order given; errors name `name`
// ("parameter 'planes': ..."): too many planes, a bad plane (with its number), two planes
// that are the same plane (normals within 1e-12, offsets within 1e-9 m).
Result<std::vector<Plane>> parsePlaneList(std::string_view name, std::string_view text);
// "union" or "intersection"; errors name `name`.
Result<CutMode> parseCutMode(std::string_view name, std::string_view text);
// The planes in canonical order (lexicographic by a, b, c, d).
void sortPlanes(std::vector<Plane>& planes);
// "a,b,c,d" with shortest round-trip numbers.
std::string planeText(const Plane& plane);

// InvalidArgument naming `name` when the cut keeps no point of `bounds` (world; the model's
// bounds): a view of it would show nothing of the model.
Status checkCutKeepsSomething(std::string_view name, const CutOut& cut, const Aabb& bounds);

}  // namespace geoslice::api
