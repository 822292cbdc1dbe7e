// A static index over the desurveyed traces of a drillhole database: every hole's path
// (HolePath, minimum curvature arcs) as straight chord segments, in a bounding-volume
// hierarchy of axis-aligned boxes, so that the segments within a distance of a plane are
// found without looking at the others (a section, a tile or a query asks this of every
// new plane; bench/drillholes.cpp times it).
//
// Frames: world metres (x east, y north, z up); depths metres along the hole.
// Chords: each arc between two nodes of the path is split into pieces whose chord lies
// within kMaxChordError of the arc (the sagitta bound L*beta/(8 k^2) for k pieces of an
// arc of length L and dogleg beta); a hole is drawn from depth 0 to the deepest of its
// path's last node, its total depth and its deepest interval.
// Build once, then read from any thread (immutable).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "model/drillholes/drillholes.hpp"

namespace geoslice {

constexpr double kMaxChordError = 0.05;  // m: chord to arc

// One chord of one hole: world endpoints `a` (depth `from`) and `b` (depth `to`); a depth in
// between maps to a + (d - from) / (to - from) * (b - a).
struct HoleSegment {
    std::uint32_t hole = 0;  // index into DrillholeDatabase::holes
    double from = 0.0, to = 0.0;
    glm::dvec3 a{0.0}, b{0.0};
};

class HoleIndex {
public:
    HoleIndex() = default;
    explicit HoleIndex(const DrillholeDatabase& db);

    // Segments by hole (database order) then depth.
    const std::vector<HoleSegment>& segments() const { return segments_; }
    // The deepest depth drawn for each hole (see above), metres.
    const std::vector<double>& endDepth() const { return endDepth_; }
    std::size_t nodeCount() const { return nodes_.size(); }

    // The indices of the segments with a point within `window` metres of the plane
    // normal . p + d = 0 (world; `normal` unit), ascending (so by hole, then depth).
    void segmentsNearPlane(const glm::dvec3& normal, double d, double window, std::vector<std::uint32_t>& out) const;
    // The holes with a segment within `window` of the plane, ascending.
    std::vector<std::uint32_t> holesNearPlane(const glm::dvec3& normal, double d, double window) const;

private:
    struct Node {
        glm::dvec3 lo{0.0}, hi{0.0};
        std::uint32_t first = 0;  // leaf: first entry of order_; inner: index of the right child
        std::uint32_t count = 0;  // leaf: entries; 0: inner (the left child is this node + 1)
    };
    std::uint32_t buildNode(std::uint32_t begin, std::uint32_t end);
    template <typename Visit>
    void visitNearPlane(const glm::dvec3& normal, double d, double window, const Visit& visit) const;

    std::vector<HoleSegment> segments_;
    std::vector<double> endDepth_;
    std::vector<Node> nodes_;
    std::vector<std::uint32_t> order_;  // segment indices in leaf order
};

}  // namespace geoslice
