// glTF 2.0 / GLB writing (reading is parseGltf in model/loaders.hpp).
//
// Layout written by geoslice: one node + mesh per part, children of a root node whose
// translation is the model origin. Positions are float32 in the local frame, converted to
// glTF's y-up axes: glTF (X, Y, Z) = (east, up, -north). The root scene's
// extras.geoslice holds {version, crs, origin (world x,y,z), attributes}; each node's
// extras.geoslice holds {kind: "body"|"surface", record}.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

struct GlbWriteOptions {
    bool draco = false;          // KHR_draco_mesh_compression on every primitive
    int dracoPositionBits = 20;  // quantisation: step = model extent / 2^bits per axis
    int dracoSpeed = 5;          // 0 (best compression) .. 10 (fastest)
};

Result<std::vector<std::uint8_t>> encodeGlb(const Model& model, const GlbWriteOptions& options = {});

// The scene's extras.geoslice object that every GLB geoslice writes carries and parseGltf
// reads back: {version, crs, origin (world, metres), attributes (records), notes}.
// `attributes` may differ from model.attributes (a bake adds its grade-class records).
nlohmann::ordered_json sceneExtras(const Model& model, const AttributeTable& attributes);

// GLB container constants (glTF 2.0 spec, "Binary glTF Layout").
constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kGlbChunkJson = 0x4E4F534A;
constexpr std::uint32_t kGlbChunkBin = 0x004E4942;
// Packs a glTF JSON document and its binary buffer into one GLB (JSON padded with spaces to
// 4 bytes; `bin` must already be 4-byte padded). OutOfRange naming `what` past 4 GiB.
Result<std::vector<std::uint8_t>> packGlb(std::string json, const std::vector<std::uint8_t>& bin,
                                          const std::string& what);
Status writeGlb(const Model& model, const std::string& path, const GlbWriteOptions& options = {});

}  // namespace geoslice
