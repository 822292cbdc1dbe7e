// Volume meshes (tetrahedra, hexahedra, wedges, pyramids with a region per cell, as GOCAD
// TSolid, VTK .vtu and Geo3DML volumes deliver them) and their region boundaries: the
// closed triangle shells the rest of geoslice works with.
//
// Frame: world (double, the model's CRS, metres). Cells use VTK's vertex order
// (https://examples.vtk.org/site/VTKBook/05Chapter5/ figure 5-2); an inverted cell (negative
// signed volume, as some exporters write) is fine: faces are oriented from each cell's own
// signed volume, not from the vertex order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

// A volume mesh: cells (VTK vertex order) with a region per cell. World coordinates.
struct VolumeMesh {
    enum class CellType : std::uint8_t { Tetra = 10, Hexahedron = 12, Wedge = 13, Pyramid = 14 };  // VTK ids
    std::vector<glm::dvec3> positions;
    std::vector<CellType> cellTypes;
    std::vector<std::uint32_t> cellOffsets;  // cellVertices[cellOffsets[c] .. cellOffsets[c+1])  (size cells+1)
    std::vector<std::uint32_t> cellVertices;
    std::vector<std::int32_t> cellRegions;  // region index per cell, >= 0

    std::size_t cellCount() const { return cellTypes.size(); }
    // Appends one cell; `vertices` in VTK order, as many as the type has.
    void addCell(CellType type, std::initializer_list<std::uint32_t> vertices, std::int32_t region);
};

// Vertices of a cell type (4, 8, 6, 5), 0 for an unknown type value.
std::size_t cellVertexCount(VolumeMesh::CellType type);

// Signed volume of cell c in m^3 (positive for VTK's standard orientation). Exact for
// tetrahedra; for cells with non-planar quad faces, the volume of the solid bounded by
// the faces split as regionBoundaries() splits them. Requires a valid cell.
double cellVolume(const VolumeMesh& mesh, std::size_t cell);

// Boundary of each region: cell faces not shared with another cell of the same region,
// oriented outward (orientation from each cell's signed volume, so inverted cells are
// fine), quads split into two triangles along the diagonal through their smallest vertex
// index (so two cells sharing a quad split it alike). Faces are matched by vertex index,
// not position: vertices of the mesh are shared between the regions' meshes as indices of
// `positions`, and each returned Mesh holds only its region's vertices (renumbered).
// A face that collapses (repeated vertex index) loses the repeat; one left with fewer than
// three distinct vertices is dropped. A region that touches itself along an edge or at a
// vertex (a pinch-out) comes back with that edge or vertex shared: validate() splits it.
// Returns one Mesh per region index [0, regionCount); a region without cells is empty.
// Errors (InvalidArgument) name the cell: vertex index out of range, unknown type, wrong
// vertex count, offsets out of order, region outside [0, regionCount), non-finite vertex.
Result<std::vector<Mesh>> regionBoundaries(const VolumeMesh& mesh, std::size_t regionCount);

}  // namespace geoslice
