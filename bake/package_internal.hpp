// What the files of the baked package share; not part of bake/'s API (bake/package.hpp is).
//
//   package_write.cpp       writePackage: the texture, the manifest (sizes, XXH64 checksums),
//                           files written under temporary names and renamed, manifest last
//   package_read.cpp        loadPackage / parsePackage / verifyPackage: mapping, checksums,
//                           format version, texture layout, attributes
//   package_mesh.cpp        mesh.glb both ways: encodeMesh (GLB with TEXCOORD_0 and position
//                           residuals) and parseMesh (every size, offset and index checked)
//   package_validation.cpp  the validation a bake stores (manifest "validation", vertices.map)
//                           and packageModel, which replays it instead of validating again
//   feature_glb.cpp         writeFeatureGlb: EXT_mesh_features + EXT_structural_metadata
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bake/package.hpp"
#include "model/io/gltf/gltf_io.hpp"

namespace geoslice::bake::package_detail {

// 16 lower-case hex digits, as the manifest stores XXH64 sums.
inline std::string hex64(std::uint64_t v) {
    char b[17];
    std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(v));
    return b;
}

// ParseError "<source>/<file>: <what>".
inline Error parseError(const std::string& source, const std::string& file, const std::string& what) {
    return makeError(ErrorCode::ParseError, source + "/" + file + ": " + what);
}

// Writes `path` under a temporary name, then renames it (package_write.cpp).
Status writeFile(const std::filesystem::path& path, const void* data, std::size_t size);

// The model's records plus the bake's field-class records (package_mesh.cpp).
AttributeTable mergedAttributes(const Model& model, const BakedModel& baked);

// The baked mesh as GLB (package_mesh.cpp): one node + mesh per part, POSITION, TEXCOORD_0,
// uint32 indices; with `residuals`, kPositionResidualAttribute where float32 would merge
// vertices; with `features`, the EXT_mesh_features export (feature_glb.cpp; one-page bakes).
Result<std::vector<std::uint8_t>> encodeMesh(const Model& model, const BakedModel& baked, bool features,
                                             bool residuals);

// mesh.glb of a package: GLB header, JSON and BIN chunks, the scene (name, extras, root
// translation), then each part's accessors (package_mesh.cpp). Throws nlohmann::json
// exceptions for missing or mistyped fields (the callers turn them into ParseError).
Status parseMesh(std::span<const std::uint8_t> mesh, const std::string& source, Package& pkg);

// What a bake stores about the validation of its own mesh (package_validation.cpp).
struct StoredValidation {
    nlohmann::ordered_json manifestEntry;  // the manifest's "validation"
    std::vector<std::uint8_t> vertexMap;   // vertices.map
    std::vector<std::uint8_t> sectionBvh;  // section.bvh over the model packageModel() returns
};
// Validates the encoded mesh as a loader will read it (float32 positions + residuals), once,
// at bake time; `dir` names the package in errors.
Result<StoredValidation> validateStoredMesh(std::span<const std::uint8_t> mesh, const std::string& dir);

// The EXT_mesh_features export (feature_glb.cpp), in the order encodeMesh calls it.
struct FeatureExport {
    std::vector<RecordId> rows;       // property-table rows: every record of the table and of a part, ascending
    std::size_t imageView = 0;        // buffer view of the feature-ID PNG
    nlohmann::ordered_json metadata;  // EXT_structural_metadata
};
// The property-table rows.
std::vector<RecordId> featureRows(const AttributeTable& table, const BakedModel& baked);
// A primitive's EXT_mesh_features object (feature ids from texture 0, channels 0-3).
nlohmann::ordered_json featureIdsExtension(std::size_t rowCount);
// Appends the feature-ID PNG and the property table's views to `glb` (after every part's).
Status addFeatureTables(GlbBuilder& glb, const BakedModel& baked, const AttributeTable& table, FeatureExport& fx);
// The document's images, sampler, texture and extensions (after finishDocument).
void finishFeatureDocument(nlohmann::ordered_json& doc, const FeatureExport& fx);

}  // namespace geoslice::bake::package_detail
