// The records of a model as the property table of glTF's EXT_structural_metadata (class
// "geology"), shared by every glTF geoslice exports with per-feature metadata: the package's
// feature GLB (bake/feature_glb.cpp, feature ids from a texture) and the 3D Tiles content
// (renderer/tiles3d/tileset3d.cpp, feature ids per vertex). One row per record; a feature id
// is a row number.
//
// Properties: id (UINT32), name, kind, lithology, age, era, gradeUnit, colour ("#rrggbb" or
// "#rrggbbaa", the colour every geoslice view draws the record in) as STRING, density (t/m^3)
// and grade as FLOAT64 with noData -1, and every key of the records' free-form `extra`
// object as a STRING (text as written, other JSON values serialised), named by the key where
// it is a valid metadata identifier ([A-Za-z_][A-Za-z0-9_]*, not one of the names above) and
// otherwise by the key with each other character made '_' and a leading '_' (duplicates
// after that are left out). Spec: github.com/CesiumGS/glTF/tree/3d-tiles-next/extensions/2.0/
// Vendor/EXT_structural_metadata (binary property tables: STRING values with UINT32 offsets,
// buffer views 8-byte aligned).
#pragma once

#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/attributes.hpp"
#include "model/io/gltf/gltf_io.hpp"

namespace geoslice::bake {

// The property-table rows: every record of `table` and every record in `partRecords`
// (kNoRecord skipped), ascending and unique.
std::vector<RecordId> featureRows(const AttributeTable& table, std::span<const RecordId> partRecords);

// Appends the property table's buffer views to `glb` and returns the document's
// EXT_structural_metadata object (schema + one property table).
nlohmann::ordered_json addPropertyTable(GlbBuilder& glb, const std::vector<RecordId>& rows,
                                        const AttributeTable& table);

}  // namespace geoslice::bake
