// Validation of a loaded model: per part topology (closed 2-manifold, boundary and
// non-manifold edges, orientation), outward normals (inward closed bodies are flipped and
// reported), degenerate and duplicate triangles, NaN/Inf, and the nesting of closed bodies
// (an orebody lens inside its stratum without a hole in the host is supported: the lens
// gets nestingDepth 1 and parent = the host).
//
// Topology is computed on vertices welded by exact position, so meshes that split
// vertices (per-face normals in glTF/OBJ) are judged by their geometry. A body that touches
// itself along an edge or at a vertex (a pinch-out: every model built from tetrahedra or a
// partition has them) is split there into closed, consistently oriented shells: around an
// edge used by 4, 6... triangles, the triangles are paired by their angular order about the
// edge and their directions along it (each pair bounds one wedge of solid; the shells may be
// wound either way, each is flipped on its own), and a vertex whose triangles form several
// fans becomes one vertex per fan. The split is physical: validate() rewrites each closed
// body's vertices (welded, then duplicated per shell and fan), so every engine that follows
// index topology (section contours, BVH, bake charts) sees the 2-manifold.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace geoslice {

// Fills a MeshReport. When `fix` and the mesh is a closed, consistently oriented shell
// set: inward components are flipped in place and the vertices are rewritten as the split
// 2-manifold (see above; the mesh is left alone when its indices already are that).
MeshReport analyseMesh(Mesh& mesh, bool fix);

// Analyses every part (in parallel), flips inward bodies, computes nesting; the report is
// also stored in model.validation.
// Errors: a body that is not closed (named with its open and non-manifold edge counts and
// where a few of them are) or not consistently oriented, non-finite vertices.
// Notes: bodies split at pinch-outs.
// Warnings: degenerate or duplicate triangles. Notes: flipped bodies.
ValidationReport validate(Model& model);

// Brute-force ray parity in double: is p inside the closed mesh? Robust to rays that graze
// an edge or vertex (such rays are re-cast in another direction). O(triangles).
bool pointInClosedMesh(const Mesh& mesh, const glm::dvec3& p);

// Signed volume of a closed mesh in m^3 (divergence theorem), positive when outward.
double signedVolume(const Mesh& mesh);

}  // namespace geoslice
