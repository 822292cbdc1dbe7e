// Exact cell ∩ body volumes and grade-tonnage tables (issue 15 item 3).
//
// Volume of body ∩ cell, exactly (up to rounding), by the divergence theorem applied three
// times, one dimension lower each time. In the block model's grid frame (model/
// block_model.hpp) cell (i, j, k) is the box (X_i, X_i+1] x (Y_j, Y_j+1] x (Z_k, Z_k+1].
//  3D: with F = (x - X_i, 0, 0) (div F = 1), the boundary of body ∩ cell is the body's
//      surface inside the cell plus the cell's faces inside the body; F . n vanishes on the
//      face x = X_i and on the four faces y, z = const, so
//        V = sum over the body's triangles clipped to the cell of  A_yz(piece) (x̄ - X_i)
//            + dx * C,  C = area of the body's section by the plane x = X_i+1 inside the face,
//      where A_yz is the piece's signed area projected on the y-z plane (= n_x A for the
//      outward normal) and x̄ its centroid's x (x is linear on a planar piece).
//  2D: the section region in the plane x = X (the triangles crossing it give segments whose
//      in-plane outward normal is the projection of the triangle's); with G = (y - Y_j, 0),
//        C = sum over segments clipped to the face of  (ȳ - Y_j) dz (segment oriented with the
//            region on its left)  +  dy * L,  L = length of the line y = Y_j+1 of the face
//            inside the body.
//  1D: along that line, L = sum over its crossings z_c in (Z_k, Z_k+1] of (z_c - Z_k) o_c
//      + dz * inside(Z_k+1), o_c = +1 where the line leaves the body going up, -1 where it
//      enters, and inside(Z) = the count of entries minus exits at or below Z.
// Every side test uses one rule: a coordinate equal to a grid plane counts as below it (the
// grid planes are moved up by an infinitesimal, x first, then y, then z). The three levels
// decide alike, so faces, edges and vertices of a body lying exactly on grid planes (a box
// orebody on the grid) are counted once: the result is the exact volume of body ∩ cell for
// the limit of the moved grid, which is the volume itself (volume is continuous).
// Requires a closed, consistently outward-oriented surface (validation's closed bodies, or
// keptSideShell's closed chain below): every term is linear in the surface, so overlapping
// triangles of opposite orientation cancel.
// Cost: the triangles' cells, plus the grid planes, lines and cells inside the body's
// bounding box.
//
// Kept side of a plane (cell ∩ body ∩ {n . p + d >= 0}): keptSideShell closes the body's
// part on the kept side into a closed surface that the same three-level sum measures
// exactly. Each triangle is clipped to the kept side (Sutherland-Hodgman, a vertex with
// n . p + d = 0 kept, shared/DESIGN.md's rule; the cut point of an edge computed from its
// endpoints in a fixed order, so both triangles of an edge get the same point). Every edge
// of a kept piece whose two ends lie on the plane (cut points, or vertices at distance 0:
// known combinatorially, not from rounded distances) gets the cap triangle (o, q, p) that
// runs it backwards, o one point on the plane (the mean of the cut points, projected). The
// cap is a fan of signed triangles whose boundary cancels every on-plane edge, so pieces +
// fan is a closed 2-cycle whose enclosed volume (winding number 1 on body ∩ half-space, 0
// elsewhere) is the kept part; the fan's overlaps cancel in every cell up to rounding. No
// loop building, no triangulation of the section polygons.
//
// Hexahedral cells (SGrid, model/blocks/block_model.hpp): a cell is six tetrahedra, and
// tetrahedron ∩ body is the same divergence sum generalised to a simplex, from the body's
// triangles near the tetrahedron only (section/blocks/block_tet_volumes.cpp). Tetrahedron T =
// (v0, v1, v2, v3), positively oriented; face i is the face opposite v_i, side_i(p) >= 0 on
// v_i's side.
//  3D: with F = p - v0 (div F = 3), F . n vanishes on the three faces through v0 and is
//      h0, v0's height over face 0, on face 0, so  vol = sum over the body's triangles
//      clipped to T of orient(v0, piece) / 6  +  (h0 / 3) area(body ∩ face 0).
//  2D: that area with G = q - v1 in face 0's plane: G . m vanishes on the edges through v1,
//      so (h0 / 3) area = sum over the body's section edges a -> b clipped to the face (the
//      clipped pieces' edges on face 0) of orient(v1, a, b, v0) / 6  +  vol(T) L / |v3 - v2|,
//      L the length of edge v2 v3 inside the body.
//  1D: L = sum over the section edges' crossings of the line v2 v3 within the edge of
//      +-(|v3 - v2| - t_c), plus |v3 - v2| x inside(v2); inside(v2) is the winding number
//      of the section at v2: the signed crossings of the same line beyond v2 (a ray through
//      the body's triangle BVH).
// Tie rule: per tetrahedron, a point with side_i = 0 counts as inside face i (the faces
// moved outward by an infinitesimal), and every decision, at every level, is that test on
// the same bits: the pieces are clipped by face 0 first, from the body's own vertices, with
// cut points from section/cut/edge_crossing.hpp (one point per edge, whichever triangle asks), so
// the lid's edges are the section edges, whose crossings of face 1 and sides of faces 2
// and 3 decide the 1D sum and the ray count alike. Body vertices on lattice points, faces
// on lattice planes or on the cells' diagonal planes are counted once (tested against the
// analytic volumes). The cells whose bounds meet no triangle are wholly inside or outside:
// one ray per face-connected group of them. Coordinates are relative to the body's centre
// (rounding of large eastings). Cost: the triangles near each tetrahedron near the surface
// (a BVH over the body's triangles, section/index/bvh.hpp), a ray to the body's bounds for each
// lattice point v2 farther than the margin from every triangle's bounds (its winding number
// is then the body's in any plane: cached) and for each tetrahedron whose v2 is not, and
// the cells in the body's bounds. clippedCellBodyVolumes, the whole body clipped to
// each tetrahedron (keptSideShell once per face: clipToConvex), is the tests' oracle.
//
// Grade-tonnage: per body, for each cut-off c, the cells whose grade >= c (cells with no
// grade value are left out and their volume reported): tonnage = sum V rho, mean grade =
// sum V rho g / tonnage, metal = section/volumes/reserves.hpp metalContent(tonnage, mean grade).
// rho: the block property named "density" (t/m³) where the cell has one, else the body's
// record density; a body with neither has volumes only.
// Thread-safety: pure functions.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/blocks/block_model.hpp"
#include "model/model.hpp"
#include "model/result.hpp"
#include "view/plane.hpp"

namespace geoslice {

struct CellVolume {
    std::size_t cell = 0;  // BlockModel linear index
    double volume = 0.0;   // m³
};

// The cells of `blocks` that `body` (closed, outward, world coordinates) meets, with the
// volume of cell ∩ body, ascending cell order. Cells of zero volume are left out (Box: exact
// zeros; Hexahedron: |volume| <= 1e-9 of the cell's, the rounding left where a body only
// touches a cell).
std::vector<CellVolume> cellBodyVolumes(const BlockModel& blocks, const Mesh& body);

// Hexahedral cells only: the same volumes by clipping the whole body to each tetrahedron of
// the cells whose bounds meet the body's (clipToConvex, then meshVolume), O(tetrahedra x
// triangles): the independent oracle of the tests for cellBodyVolumes's local sum. Empty
// for Box cells.
std::vector<CellVolume> clippedCellBodyVolumes(const BlockModel& blocks, const Mesh& body);

// `closed` (a closed, outward surface) clipped to the convex polyhedron where every
// n . p + d >= 0: keptSideShell once per plane (unit normals). Its meshVolume is the volume
// of body ∩ polyhedron. Empty when nothing is kept.
Mesh clipToConvex(const Mesh& closed, const std::vector<Plane>& planes);

// The closed surface of body ∩ {n . p + d >= 0} (see above): the kept pieces (fanned into
// triangles) and the signed cap fan, unwelded (3 vertices per triangle). Empty when nothing
// of the body is kept. Its meshVolume is the kept volume (section/volumes/reserves.hpp).
Mesh keptSideShell(const Mesh& body, const Plane& plane);

// cellBodyVolumes of keptSideShell(body, plane), less the cells whose |volume| is at most
// 1e-9 of their cell's (the fan's cancelling overlaps leave rounding there, ~1e-15 of a cell).
std::vector<CellVolume> cellBodyVolumes(const BlockModel& blocks, const Mesh& body, const Plane& plane);

struct GradeTonnageRow {
    double cutoff = 0.0;
    double volume = 0.0;            // m³ of the cells at or above the cut-off
    std::optional<double> tonnage;  // t
    std::optional<double> meanGrade;
    std::optional<double> metal;
    std::string metalUnit;
    std::size_t cells = 0;
};

struct BodyGradeTonnage {
    std::uint32_t body = 0;  // Model::bodies index
    RecordId record = kNoRecord;
    double volume = 0.0;                // m³ of body ∩ grid (net: nested bodies taken out)
    double volumeNoGrade = 0.0;         // m³ of it in cells with no grade value
    std::string densitySource;          // "block property 'density'", "record", or "none"
    std::vector<GradeTonnageRow> rows;  // one per cut-off, ascending
};

struct GradeTonnage {
    std::string property, unit;  // the grade property and its unit
    std::vector<double> cutoffs;
    std::optional<Plane> plane;            // when the tables are of the kept side only (normalised)
    std::vector<BodyGradeTonnage> bodies;  // the block model's clipping bodies, Model::bodies order
};

// Grade-tonnage tables of every clipping body of the model's block model, with `plane` of
// each body's part on the kept side only. Volumes are net: a body's cells lose the volumes
// of the bodies nested directly inside it (validation's nesting parents; with `plane`,
// their kept parts), as in its section region. Errors: InvalidArgument when the model has
// no block model, the property is unknown (listed), cut-offs are not finite and increasing,
// or the plane is bad (non-finite, zero normal); OutOfRange for more than 64 cut-offs.
Result<GradeTonnage> computeGradeTonnage(const Model& model, const std::string& property,
                                         const std::vector<double>& cutoffs,
                                         const std::optional<Plane>& plane = std::nullopt);

}  // namespace geoslice
