// Closed section contours: segments (section/cut/plane_cut.hpp) -> loops per body -> polygons
// with holes and islands; open surfaces -> traces (polylines). All in plane u/v metres.
//
// Chaining is topological: segments meet where they share a welded mesh edge key, never
// by comparing floats, so a closed 2-manifold body always gives closed loops (the sign
// rule of view/plane.hpp guarantees each crossed edge is crossed by exactly its two
// triangles).
//
// Polygons: the loops of a body's region are its own loops plus the loops of the bodies
// nested directly in it (SectionPart::parent, from validation): an orebody lens inside
// its host stratum is a hole in the host's section. Each loop's depth is the number of
// region loops that contain it (even-odd rule, tested at a point of the loop); even
// depth -> an outer ring (made counter-clockwise), odd -> a hole (made clockwise) of the
// loop one level up. This is the standard even-odd assembly, e.g. GEOS's
// polygonizer / Clipper's PolyTree, for loops that do not cross each other.
#pragma once

#include <cstdint>
#include <vector>

#include "model/result.hpp"
#include "section/cut/partner_thread.hpp"
#include "section/cut/plane_cut.hpp"
#include "section/index/section_index.hpp"

namespace geoslice {

using Ring = std::vector<glm::dvec2>;  // plane u/v metres; closed implicitly (last != first)

// Signed shoelace area (m²), positive when counter-clockwise in u/v.
double ringArea(const Ring& ring);
// Even-odd point-in-ring test (half-open crossing rule).
bool pointInRing(const glm::dvec2& p, const Ring& ring);

struct SectionPolygon {
    Ring outer;               // counter-clockwise
    std::vector<Ring> holes;  // clockwise
};

struct BodySection {
    std::uint32_t part = 0;  // SectionIndex part index (= Model::bodies index)
    RecordId record = kNoRecord;
    std::vector<SectionPolygon> polygons;
    double area = 0.0;           // m²: outer rings minus holes (cavities and nested bodies)
    std::size_t openChains = 0;  // chains that did not close: 0 for a closed body
};

struct SectionTrace {
    std::uint32_t part = 0;  // SectionIndex part index of the surface
    RecordId record = kNoRecord;
    std::vector<glm::dvec2> points;  // plane u/v metres
    bool closed = false;             // the trace is a loop (points[0] follows the last)
};

struct Section {
    Plane plane;  // world, unit normal
    SectionFrame frame;
    std::vector<BodySection> bodies;   // bodies the plane cuts, ascending part index
    std::vector<SectionTrace> traces;  // surfaces the plane cuts
    glm::dvec2 lo{0.0}, hi{0.0};       // bounding box of all rings and traces, u/v metres
    bool empty() const { return bodies.empty() && traces.empty(); }
};

// Chains `cut` and assembles polygons and traces into `out` (frame and plane copied).
// threads = 2 shares the parts' chaining and the bodies' assembly between two threads
// (above a few thousand segments); the output is the same for any thread count.
void assembleContours(const SectionIndex& index, const PlaneCut& cut, Section& out, unsigned threads = 1);

struct SectionTimings {
    double queryMs = 0.0, cutMs = 0.0, contourMs = 0.0;
    std::size_t trianglesTested = 0, segments = 0;
};

struct SectionOptions {
    // 1 or 2: the BVH traversal and cut (see cutWithBvh), then contour assembly; or
    // kThreadsWhenIdle (section/cut/partner_thread.hpp): 2 while a core is idle, else 1 (servers).
    unsigned threads = 1;
    // Closed bodies' crossing points computed once each, at the triangle the ring leaves by
    // (PlaneCut::exitsOnly), not twice: the same output; false only to compare the two.
    bool exitsOnly = true;
};

// Sections computed beside other work (a server's concurrent requests): two threads while a
// core is idle, one otherwise (PartnerThread::coreIdle).
inline SectionOptions besideOtherWork() {
    SectionOptions o;
    o.threads = kThreadsWhenIdle;
    return o;
}

// Validates the plane, queries the BVH, cuts and assembles.
// Errors: InvalidArgument (non-finite plane, zero normal); OutOfRange when the plane
// misses the model's bounding box (names the plane and the bounds).
Result<Section> computeSection(const SectionIndex& index, const Plane& plane, const SectionOptions& options = {},
                               SectionTimings* timings = nullptr);

// checkPlaneMeetsBounds (view/plane.hpp) against the index's model: the engine's own entry
// points check what they are given; callers above section/ call the view check directly.
Result<Plane> checkSectionPlane(const SectionIndex& index, const Plane& plane);

}  // namespace geoslice
