// Random section planes shared by the section tests and bench/section: the same plane
// mix everywhere, so test and benchmark figures describe the same workload.
#pragma once

#include <cmath>
#include <random>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "view/plane.hpp"

namespace geoslice::test {

// A plane through a random point of the middle 80% of the bounds: a third vertical, a
// third near-horizontal, a third any direction.
inline Plane randomPlane(const Aabb& b, std::mt19937_64& rng, int kind) {
    std::uniform_real_distribution<double> u01(0.1, 0.9), ang(0.0, 6.283185307179586), sym(-1.0, 1.0);
    const glm::dvec3 p(b.min.x + u01(rng) * (b.max.x - b.min.x), b.min.y + u01(rng) * (b.max.y - b.min.y),
                       b.min.z + u01(rng) * (b.max.z - b.min.z));
    glm::dvec3 n;
    const double t = ang(rng);
    if (kind % 3 == 0)
        n = {std::cos(t), std::sin(t), 0.0};
    else if (kind % 3 == 1)
        n = glm::normalize(glm::dvec3(0.1 * std::cos(t), 0.1 * std::sin(t), sym(rng) < 0 ? -1.0 : 1.0));
    else
        n = glm::normalize(glm::dvec3(sym(rng), sym(rng), sym(rng)) + glm::dvec3(1e-9));
    return Plane{n, -glm::dot(n, p)};
}

}  // namespace geoslice::test
