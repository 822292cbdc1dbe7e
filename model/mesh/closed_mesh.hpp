// Internal to model/: the closed-mesh queries that validation shares between its files
// (model/mesh/closed_mesh.cpp): ray parity and signed volume over all triangles or a subset, and a
// point deep inside a closed body. World coordinates, metres, double throughout. The public
// forms are pointInClosedMesh and signedVolume (model/mesh/validate.hpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"

namespace geoslice::closed_mesh {

inline bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// Ray parity of p against `subset` (triangle indices; null: every triangle), re-cast in
// other directions when a ray grazes an edge or vertex; outside when every ray grazes.
bool insideParity(const Mesh& mesh, const std::vector<std::uint32_t>* subset, const glm::dvec3& p);
// Signed volume (m^3, positive when outward) of `subset` (null: every triangle) about `ref`.
double volumeOf(const Mesh& mesh, const std::vector<std::uint32_t>* subset, const glm::dvec3& ref);
// A point deep inside a closed, outward body: from the centroids of its largest triangles,
// inward along the normal to the next face, the midpoint of the longest such chord. Deep,
// not just inside: a probe a few millimetres under a face would lie inside a neighbour
// that overlaps the body by centimetres and make the body look nested in it.
std::optional<glm::dvec3> interiorPoint(const Mesh& mesh);

}  // namespace geoslice::closed_mesh
