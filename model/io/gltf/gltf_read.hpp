// glTF / GLB reading, internal: what the reader's files share (model/io/gltf/gltf_loader.cpp reads
// the scene graph, model/io/gltf/gltf_preflight.cpp checks the container and JSON before tinygltf
// sees them, model/io/gltf/gltf_primitive.cpp turns primitives, Draco-compressed or not, into
// triangles). Not a public header; parseGltf is declared in model/io/loaders.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "model/io/gltf/gltf_io.hpp"
#include "model/model.hpp"
#include "model/result.hpp"

namespace tinygltf {
class Model;
struct Primitive;
}  // namespace tinygltf

namespace geoslice::gltf {

constexpr int kTriangleStrip = 5;
constexpr int kTriangleFan = 6;
// glTF's own JSON nests about 6 levels deep. tinygltf converts extras and extensions to its
// Value type recursively, so hostile nesting would overflow the stack: refuse it up front.
constexpr int kMaxJsonDepth = 128;
// tinygltf's messages can quote whole data: URIs; keep ours readable.
constexpr std::size_t kMaxQuoted = 200;
// Geometry a file may expand to, in bytes of Mesh storage (24 per vertex, 4 per index):
// instancing (many nodes sharing one mesh) and Draco multiply a small file into a large
// model. 64 times the file covers Draco's compression of real models (about 10 here) and
// the constant covers heavy instancing in small files; past that, a file could exhaust
// memory on purpose.
constexpr std::uint64_t kExpansionFactor = 64;
constexpr std::uint64_t kExpansionAllowance = std::uint64_t(256) << 20;
// preflightJson() renames the Draco extension of every primitive to this key, so that
// tinygltf 2.7 (which indexes bufferViews, accessors and Draco attributes straight from the
// file, unchecked) never decodes it; appendPrimitive() decodes it with bounds checks.
constexpr const char* kDracoDeferred = "GEOSLICE_draco_deferred";

inline std::uint32_t readU32(const std::uint8_t* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

// A JSON value that is a whole number >= 0.
bool isUnsigned(const nlohmann::json& j);
// extras / extensions text that tinygltf kept as written -> JSON; null when empty or invalid.
nlohmann::json parseExtras(const std::string& text);

// GLB container checks with byte offsets, before tinygltf sees the bytes. On success the
// JSON chunk is bytes [20, 20 + readU32(data + 12)) and the file ends at readU32(data + 8).
Status checkGlbContainer(const std::uint8_t* data, std::size_t size, const std::string& source);

// Checks on the glTF JSON that tinygltf 2.7 does not make, before it parses it: nesting
// depth, valid JSON (with a byte offset), external buffers only inside the model's folder,
// image bufferViews inside their buffers. Returns rewritten JSON when some primitive uses
// KHR_draco_mesh_compression (renamed to kDracoDeferred and without "indices"; see
// appendPrimitive), else nothing: load the bytes as they are. `fileOffset` is the byte
// offset of the JSON in the input, for messages.
Result<std::optional<std::string>> preflightJson(const char* text, std::size_t size, std::size_t fileOffset,
                                                 const std::string& source, const std::string& baseDir);

// Appends one primitive's triangles to `mesh`: positions through `toWorld` (node to glTF
// scene frame, in double) and then to world axes. Under a mirroring transform (negative
// determinant) each triangle's winding is reversed, so outward normals stay outward.
// `budget` is what is left of the file's expansion allowance (kExpansionFactor), in bytes.
Status appendPrimitive(const tinygltf::Model& g, const tinygltf::Primitive& prim, const glm::dmat4& toWorld, Mesh& mesh,
                       const std::string& where, std::uint64_t& budget);

}  // namespace geoslice::gltf
