// The crossing point of an edge with a plane, the same bits from whichever side it is asked
// (private to section/block_*: the clips of section/block_reserves.hpp share it so that the
// triangles of a shared edge, and the levels of one sum, see one point).
#pragma once

#include <utility>

#include <glm/glm.hpp>

namespace geoslice {

// The point of edge ab where the signed distance (sa at a, sb at b, of opposite signs) is 0,
// computed from the endpoints in lexicographic (x, y, z) order: cutAt(a, b, sa, sb) and
// cutAt(b, a, sb, sa) give the same bits.
inline glm::dvec3 cutAt(glm::dvec3 a, glm::dvec3 b, double sa, double sb) {
    if (b.x < a.x || (b.x == a.x && (b.y < a.y || (b.y == a.y && b.z < a.z)))) {
        std::swap(a, b);
        std::swap(sa, sb);
    }
    return a + (b - a) * (sa / (sa - sb));
}

}  // namespace geoslice
