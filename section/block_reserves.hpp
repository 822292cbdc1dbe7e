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
// Hexahedral cells (SGrid, model/block_model.hpp): a cell is six tetrahedra, and
// tetrahedron ∩ body is the body clipped to the tetrahedron's four planes: keptSideShell
// applied once per plane (clipToConvex: each result is again a closed surface, so the next
// clip and meshVolume are exact), the same clip-and-cap that measures the kept side of a
// plane, generalised from one half-space to any convex polyhedron. Coordinates are taken
// relative to the body's centre first (rounding of large eastings). Cost: the whole body is
// clipped for every tetrahedron of the cells whose bounds meet the body's: O(tetrahedra x
// triangles); computeGradeTonnage refuses (OutOfRange, naming the body) above
// kMaxTetClipWork. (A k-d split of the body into closed pieces, each capped with
// keptSideShell's fans, was tried to localise it: the fans of one split are cut again by
// the next and the caps grow geometrically with depth.)
//
// Grade-tonnage: per body, for each cut-off c, the cells whose grade >= c (cells with no
// grade value are left out and their volume reported): tonnage = sum V rho, mean grade =
// sum V rho g / tonnage, metal = section/reserves.hpp metalContent(tonnage, mean grade).
// rho: the block property named "density" (t/m³) where the cell has one, else the body's
// record density; a body with neither has volumes only.
// Thread-safety: pure functions.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/block_model.hpp"
#include "model/model.hpp"
#include "model/plane.hpp"
#include "model/result.hpp"

namespace geoslice {

// The most tetrahedra x triangles computeGradeTonnage clips for a curvilinear block model.
constexpr double kMaxTetClipWork = 1e8;

struct CellVolume {
    std::size_t cell = 0;  // BlockModel linear index
    double volume = 0.0;   // m³
};

// The cells of `blocks` that `body` (closed, outward, world coordinates) meets, with the
// volume of cell ∩ body, ascending cell order. Cells of zero volume are left out (Box: exact
// zeros; Hexahedron: |volume| <= 1e-9 of the cell's, the rounding left where a body only
// touches a cell).
std::vector<CellVolume> cellBodyVolumes(const BlockModel& blocks, const Mesh& body);

// `closed` (a closed, outward surface) clipped to the convex polyhedron where every
// n . p + d >= 0: keptSideShell once per plane (unit normals). Its meshVolume is the volume
// of body ∩ polyhedron. Empty when nothing is kept.
Mesh clipToConvex(const Mesh& closed, const std::vector<Plane>& planes);

// The closed surface of body ∩ {n . p + d >= 0} (see above): the kept pieces (fanned into
// triangles) and the signed cap fan, unwelded (3 vertices per triangle). Empty when nothing
// of the body is kept. Its meshVolume is the kept volume (section/reserves.hpp).
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
// no block model, the property is unknown (listed), cut-offs are not finite and increasing
// or more than 64, or the plane is bad (non-finite, zero normal); OutOfRange above
// kMaxTetClipWork (curvilinear cells, see above).
Result<GradeTonnage> computeGradeTonnage(const Model& model, const std::string& property,
                                         const std::vector<double>& cutoffs,
                                         const std::optional<Plane>& plane = std::nullopt);

}  // namespace geoslice
