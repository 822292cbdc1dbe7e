// Validation of a loaded model: per part topology (closed 2-manifold, boundary and
// non-manifold edges, orientation), outward normals (inward closed bodies are flipped and
// reported), degenerate and duplicate triangles, NaN/Inf, and the nesting of closed bodies
// (an orebody lens inside its stratum without a hole in the host is supported: the lens
// gets nestingDepth 1 and parent = the host).
//
// Topology is computed on vertices welded by exact position, so meshes that split
// vertices (per-face normals in glTF/OBJ) are judged by their geometry.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace geoslice {

// Fills a MeshReport. When `fixOrientation` and the mesh is a closed, consistently
// oriented shell set with inward components, those components are flipped in place.
MeshReport analyseMesh(Mesh& mesh, bool fixOrientation);

// Analyses every part (in parallel), flips inward bodies, computes nesting; the report is
// also stored in model.validation.
// Errors: a body that is not closed or not consistently oriented, non-finite vertices.
// Warnings: degenerate or duplicate triangles. Notes: flipped bodies.
ValidationReport validate(Model& model);

// Brute-force ray parity in double: is p inside the closed mesh? Robust to rays that graze
// an edge or vertex (such rays are re-cast in another direction). O(triangles).
bool pointInClosedMesh(const Mesh& mesh, const glm::dvec3& p);

// Signed volume of a closed mesh in m^3 (divergence theorem), positive when outward.
double signedVolume(const Mesh& mesh);

}  // namespace geoslice
