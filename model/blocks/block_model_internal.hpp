#pragma once
// Private to model/block_*.cpp: what the cell geometry (block_model.cpp) shares with the
// builders that read CSV and grids into block models (block_sources.cpp).
#include <glm/vec3.hpp>

namespace geoslice {

// Six times the signed volume of tetrahedron abcd (positive when d lies on the side of abc
// that its counter-clockwise normal points to).
double tetVolume6(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

}  // namespace geoslice
