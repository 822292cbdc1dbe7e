// Exact tetrahedron ∩ body volumes of curvilinear (Hexahedron) block models, local to the
// body's surface (private to section/: cellBodyVolumes in section/blocks/block_reserves.hpp is the
// interface; the method is described there).
#pragma once

#include <vector>

#include "model/blocks/block_model.hpp"
#include "model/model.hpp"
#include "section/blocks/block_reserves.hpp"

namespace geoslice {

// cellBodyVolumes for blocks.shape == CellShape::Hexahedron.
std::vector<CellVolume> tetCellBodyVolumes(const BlockModel& blocks, const Mesh& body);

}  // namespace geoslice
