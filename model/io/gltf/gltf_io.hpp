// glTF 2.0 / GLB writing (reading is parseGltf in model/io/loaders.hpp).
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

// The one axis swap between world (x east, y north, z up) and glTF (X east, Y up, Z = -north),
// for double and float vectors alike.
template <class V>
V worldToGltf(const V& w) {
    return {w.x, w.z, -w.y};
}
template <class V>
V gltfToWorld(const V& g) {
    return {g.x, -g.z, g.y};
}

// glTF 2.0 constants geoslice writes (glTF 2.0 spec, accessor.componentType, bufferView.target,
// primitive.mode).
constexpr int kGltfFloat = 5126, kGltfUint = 5125;
constexpr int kGltfArrayBuffer = 34962, kGltfElementArrayBuffer = 34963;
constexpr int kGltfTriangles = 4;
// The extension of Draco-compressed primitives (written with GlbWriteOptions::draco, read by
// parseGltf).
constexpr const char* kGltfDracoExtension = "KHR_draco_mesh_compression";

// The one GLB builder: every GLB geoslice writes (encodeGlb's model, bake/'s package mesh) is
// built by it, in the layout at the top of this file. Use: the constructor writes "asset"; add
// top-level members that go before the scene through doc() (e.g. extensionsUsed); add buffer
// views, accessors and one part per mesh; finishDocument() appends scene, scenes (the root
// node's translation = the model origin in glTF axes, scene extras.geoslice = sceneExtras),
// nodes, meshes, accessors, bufferViews and buffers; add what goes after; pack().
class GlbBuilder {
public:
    using json = nlohmann::ordered_json;
    explicit GlbBuilder(const std::string& generator);
    json& doc() { return doc_; }
    // Appends n bytes as a buffer view, first padding the binary chunk to `align` bytes;
    // target: kGltfArrayBuffer, kGltfElementArrayBuffer or 0 (none). Returns its index.
    std::size_t addView(const void* bytes, std::size_t n, int target, std::size_t align = 4);
    // Appends an accessor; returns its index.
    std::size_t addAccessor(json accessor);
    // The POSITION accessor of `count` float32 glTF-axis positions (3 per vertex, metres, the
    // local frame) with its min and max; in a buffer view unless `inView` is false (Draco keeps
    // them in its own). Returns the accessor index.
    std::size_t addPositions(const float* xyz, std::size_t count, bool inView = true);
    // One mesh of one primitive and its node, a child of the root, with extras.geoslice {kind,
    // record}.
    void addPart(const std::string& name, PartKind kind, RecordId record, json primitive);
    json& finishDocument(const Model& model, const AttributeTable& attributes);
    // The same for content in a frame of its own (3D Tiles): the root node `rootName` has no
    // translation and the scene's extras.geoslice is `sceneExtras`.
    json& finishDocument(const std::string& rootName, json sceneExtras);
    // The GLB of the document (finishDocument first); OutOfRange naming `what` past 4 GiB.
    Result<std::vector<std::uint8_t>> pack(const std::string& what) const;

private:
    // Both finishDocument()s: `root` (name, maybe translation) gets the parts as children.
    json& finish(json root, const std::string& sceneName, json extras);
    std::vector<std::uint8_t> bin_;
    json doc_, accessors_ = json::array(), views_ = json::array(), meshes_ = json::array(),
               nodes_ = json::array({json::object()}), children_ = json::array();
};

// GLB container constants (glTF 2.0 spec, "Binary glTF Layout").
constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kGlbChunkJson = 0x4E4F534A;
constexpr std::uint32_t kGlbChunkBin = 0x004E4942;
// Packs a glTF JSON document and its binary buffer into one GLB (JSON padded with spaces to
// 4 bytes; `bin` must already be 4-byte padded). OutOfRange naming `what` past 4 GiB.
Result<std::vector<std::uint8_t>> packGlb(std::string json, const std::vector<std::uint8_t>& bin,
                                          const std::string& what);
// Appends the start of a GLB to `out`: the 12-byte header of a file of `totalBytes` and the
// JSON chunk holding `json` (its length already a multiple of 4). packGlb and the reader's
// rewrite of Draco files both begin so.
void appendGlbStart(std::vector<std::uint8_t>& out, std::uint32_t totalBytes, const std::string& json);
Status writeGlb(const Model& model, const std::string& path, const GlbWriteOptions& options = {});

}  // namespace geoslice
