// The crossing point of an edge with a plane: one function for every cut in section/ (the
// exact engine's triangles, section/cut/plane_cut.hpp; the clips of the block-model volumes,
// section/blocks/block_reserves.hpp), so that whichever triangle or level asks for an edge's point
// gets the same bits.
#pragma once

#include <utility>

#include <glm/glm.hpp>

namespace geoslice {

// The point where a plane crosses the edge pq, sp and sq the two ends' signed distances
// with opposite signs under the rule (one >= 0, the other < 0).
// Symmetric in (p, q), computed from the lexicographically smaller end (exactly the vertex
// when its distance is 0), so the two triangles of an edge get bit-identical points.
inline glm::dvec3 edgeCrossing(glm::dvec3 p, double sp, glm::dvec3 q, double sq) {
    if (sp == 0.0) return p;
    if (sq == 0.0) return q;
    const bool swap = q.x != p.x ? q.x < p.x : q.y != p.y ? q.y < p.y : q.z < p.z;
    if (swap) {
        std::swap(p, q);
        std::swap(sp, sq);
    }
    return p + (q - p) * (sp / (sp - sq));
}

}  // namespace geoslice
