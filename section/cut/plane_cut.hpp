// Plane ∩ triangles -> oriented segments per part, in plane u/v metres.
//
// Every value is computed in double from the parts' double vertices in the local frame
// (world - origin). Signs follow the rule of view/plane.hpp (distance 0 counts as
// positive), so each triangle is either uncut or crossed on exactly two edges. The point
// on a crossed edge is a function of the edge's two positions only (computed from the
// lexicographically smaller endpoint; exactly the vertex when its distance is 0), so the
// two triangles that share an edge, and two parts with coincident faces, produce
// bit-identical points. Segments carry the welded edge keys they start and end on:
// chaining (section/cut/contours.hpp) is topological.
//
// Orientation: a segment runs from the crossing on the triangle edge that goes from the
// removed side to the kept side (in the triangle's vertex order) to the crossing on the
// edge that leaves the kept side. For an outward, counter-clockwise body this puts the
// body's interior on the left in plane u/v (SectionFrame: u x v = -n), so outer loops are
// counter-clockwise and cavities clockwise.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "section/cut/edge_crossing.hpp"
#include "section/index/section_index.hpp"
#include "view/plane.hpp"

namespace geoslice {

struct CutSegment {
    std::uint64_t keyA = 0, keyB = 0;  // welded edge (lo << 32 | hi) at a and at b
    glm::dvec2 a{0.0}, b{0.0};         // plane u/v, metres
};

// A closed body's crossing triangle when the cut computes exit points only: its entry and
// exit edge keys and the exit point. Its entry point is the exit point of the triangle
// before it on the ring (each crossed edge of a closed, consistently oriented body is one
// triangle's exit and the other's entry, and edgeCrossing gives both the same bits), so
// each crossing point is computed once.
struct ExitSegment {
    std::uint64_t keyA = 0, keyB = 0;  // welded edge (lo << 32 | hi) entered and left by
    glm::dvec2 b{0.0};                 // plane u/v, metres
    std::uint32_t triangle = 0;        // global id: to cut it whole when its part is not a matching
};

struct PlaneCut {
    SectionFrame frame;
    LocalPlane plane;
    std::vector<std::vector<CutSegment>> parts;  // per SectionIndex part
    // With `exitsOnly`, closed bodies' crossings go here instead of `parts` (per part).
    std::vector<std::vector<ExitSegment>> exits;
    bool exitsOnly = false;
    std::size_t segments = 0;  // segments and exit segments
};

// Prepares `out` for a cut of `index` by `plane` (world): frame, local plane, empty parts
// (vectors keep their capacity between calls). `exitsOnly`: closed bodies' crossings as
// ExitSegments (contour assembly chains them, section/cut/contours.hpp); only for cuts whose
// rings close (no rectangle), as a ring's first entry point is the exit point of its last
// triangle.
void beginCut(const SectionIndex& index, const Plane& plane, PlaneCut& out, bool exitsOnly = false);

// Cuts the listed global triangles (e.g. from queryPlane), appending to out.parts.
void cutTriangles(const SectionIndex& index, const std::uint32_t* triangles, std::size_t count, PlaneCut& out);

struct CutStats {
    std::size_t nodesVisited = 0, leaves = 0, trianglesTested = 0;
    double queryMs = 0.0, cutMs = 0.0;  // BVH traversal, then the leaves' triangles
};

// The cut through the BVH: the leaves that straddle the plane (and overlap `rect` when not
// null) are found first, then their triangles are cut from the leaf tables
// (section/index/leaf_tables.hpp): each distinct vertex of a leaf read and measured once. With
// threads = 2 the calling thread's partner (section/cut/partner_thread.hpp) takes traversal
// units and chunks of leaves (equal triangle counts) from common counters, its chunks from
// the back; the segments are appended in chunk order, so the output never depends on
// timing or on how much the partner took (nothing when it had not started in time).
void cutWithBvh(const SectionIndex& index, const PlaneRect* rect, PlaneCut& out, unsigned threads = 1,
                CutStats* stats = nullptr);

// Brute force: cuts every triangle of every part, no BVH (the paper's "CPU geometric
// intersection" baseline, and the reference the BVH path is checked against).
void cutAllTriangles(const SectionIndex& index, PlaneCut& out);

}  // namespace geoslice
