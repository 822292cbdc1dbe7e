// glTF 2.0 / GLB writing (model/io/gltf/gltf_io.hpp): the one GLB builder, a model's GLB with or
// without Draco, the scene extras, GLB packing and the atomic file write. Reading is
// model/io/gltf/gltf_loader.cpp.
#include "model/io/gltf/gltf_io.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include "model/json_text.hpp"
#include "model/version.hpp"

namespace geoslice {
namespace {

// v in little-endian byte order (the GLB container's; every platform geoslice builds for).
void appendU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    std::uint8_t b[4];
    std::memcpy(b, &v, 4);
    out.insert(out.end(), b, b + 4);
}

}  // namespace

GlbBuilder::GlbBuilder(const std::string& generator) { doc_["asset"] = {{"version", "2.0"}, {"generator", generator}}; }

std::size_t GlbBuilder::addView(const void* bytes, std::size_t n, int target, std::size_t align) {
    while (bin_.size() % align) bin_.push_back(0);
    views_.push_back({{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", n}});
    if (target) views_.back()["target"] = target;
    const auto* p = static_cast<const std::uint8_t*>(bytes);
    bin_.insert(bin_.end(), p, p + n);
    return views_.size() - 1;
}

std::size_t GlbBuilder::addAccessor(json accessor) {
    accessors_.push_back(std::move(accessor));
    return accessors_.size() - 1;
}

std::size_t GlbBuilder::addPositions(const float* xyz, std::size_t count, bool inView) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::size_t i = 0; i < count; ++i) {
        const glm::vec3 g(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
        lo = glm::min(lo, g);
        hi = glm::max(hi, g);
    }
    json a = json::object();
    if (inView) a["bufferView"] = addView(xyz, count * 3 * sizeof(float), kGltfArrayBuffer);
    a["componentType"] = kGltfFloat;
    a["count"] = count;
    a["type"] = "VEC3";
    a["min"] = {lo.x, lo.y, lo.z};
    a["max"] = {hi.x, hi.y, hi.z};
    return addAccessor(std::move(a));
}

void GlbBuilder::addPart(const std::string& name, PartKind kind, RecordId record, json primitive) {
    meshes_.push_back({{"name", name}, {"primitives", json::array({std::move(primitive)})}});
    nodes_.push_back(
        {{"name", name},
         {"mesh", meshes_.size() - 1},
         {"extras", {{"geoslice", {{"kind", kind == PartKind::Body ? "body" : "surface"}, {"record", record}}}}}});
    children_.push_back(nodes_.size() - 1);
}

GlbBuilder::json& GlbBuilder::finishDocument(const Model& model, const AttributeTable& attributes) {
    const glm::dvec3 o = worldToGltf(model.origin);
    return finish({{"name", model.name.empty() ? "model" : model.name}, {"translation", {o.x, o.y, o.z}}}, model.name,
                  sceneExtras(model, attributes));
}

GlbBuilder::json& GlbBuilder::finishDocument(const std::string& rootName, json extras) {
    return finish({{"name", rootName}}, rootName, std::move(extras));
}

GlbBuilder::json& GlbBuilder::finish(json root, const std::string& sceneName, json extras) {
    while (bin_.size() % 4) bin_.push_back(0);
    root["children"] = children_;
    nodes_[0] = std::move(root);
    doc_["scene"] = 0;
    doc_["scenes"] = {{{"name", sceneName}, {"nodes", {0}}, {"extras", {{"geoslice", std::move(extras)}}}}};
    doc_["nodes"] = nodes_;
    doc_["meshes"] = meshes_;
    doc_["accessors"] = accessors_;
    doc_["bufferViews"] = views_;
    doc_["buffers"] = {{{"byteLength", bin_.size()}}};
    return doc_;
}

Result<std::vector<std::uint8_t>> GlbBuilder::pack(const std::string& what) const {
    return packGlb(jsonText(doc_), bin_, what);
}

Result<std::vector<std::uint8_t>> encodeGlb(const Model& model, const GlbWriteOptions& options) {
    using json = nlohmann::ordered_json;
    GlbBuilder glb(kGeneratorName);
    if (options.draco) {
        glb.doc()["extensionsUsed"] = {kGltfDracoExtension};
        glb.doc()["extensionsRequired"] = {kGltfDracoExtension};
    }
    auto addPart = [&](const Part& part) -> Status {
        const Mesh& mesh = part.mesh;
        if (mesh.positions.empty() || mesh.indices.empty()) return {};
        std::vector<float> pos(mesh.positions.size() * 3);
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            const glm::vec3 g(worldToGltf(mesh.positions[i] - model.origin));
            pos[3 * i] = g.x;
            pos[3 * i + 1] = g.y;
            pos[3 * i + 2] = g.z;
        }
        json prim = {{"mode", kGltfTriangles}};
        if (options.draco) {
            draco::Mesh dm;
            draco::GeometryAttribute ga;
            ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, sizeof(float) * 3, 0);
            int att = dm.AddAttribute(ga, true, static_cast<std::uint32_t>(mesh.positions.size()));
            for (std::size_t i = 0; i < mesh.positions.size(); ++i)
                dm.attribute(att)->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(i)),
                                                     &pos[3 * i]);
            for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
                dm.AddFace({draco::PointIndex(mesh.indices[3 * t]), draco::PointIndex(mesh.indices[3 * t + 1]),
                            draco::PointIndex(mesh.indices[3 * t + 2])});
            draco::Encoder enc;
            enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.dracoPositionBits);
            enc.SetSpeedOptions(options.dracoSpeed, options.dracoSpeed);
            draco::EncoderBuffer out;
            draco::Status st = enc.EncodeMeshToBuffer(dm, &out);
            if (!st.ok())
                return makeError(ErrorCode::Internal,
                                 "Draco encoding of \"" + part.name + "\" failed: " + st.error_msg_string());
            const std::size_t view = glb.addView(out.data(), out.size(), 0);
            prim["extensions"][kGltfDracoExtension] = {{"bufferView", view},
                                                       {"attributes", {{"POSITION", dm.attribute(att)->unique_id()}}}};
            prim["attributes"] = {{"POSITION", glb.addPositions(pos.data(), mesh.positions.size(), false)}};
            prim["indices"] =
                glb.addAccessor({{"componentType", kGltfUint}, {"count", mesh.indices.size()}, {"type", "SCALAR"}});
        } else {
            prim["attributes"] = {{"POSITION", glb.addPositions(pos.data(), mesh.positions.size())}};
            const std::size_t iv = glb.addView(mesh.indices.data(), mesh.indices.size() * 4, kGltfElementArrayBuffer);
            prim["indices"] = glb.addAccessor(
                {{"bufferView", iv}, {"componentType", kGltfUint}, {"count", mesh.indices.size()}, {"type", "SCALAR"}});
        }
        glb.addPart(part.name, part.kind, part.record, std::move(prim));
        return {};
    };
    for (const auto& p : model.bodies)
        if (auto s = addPart(p); !s) return s.error();
    for (const auto& p : model.surfaces)
        if (auto s = addPart(p); !s) return s.error();
    glb.finishDocument(model, model.attributes);
    return glb.pack("model");
}

Status writeGlb(const Model& model, const std::string& path, const GlbWriteOptions& options) {
    auto bytes = encodeGlb(model, options);
    if (!bytes) return bytes.error();
    // Write to a temporary name and rename, so a crash never leaves a half-written model.
    std::string tmp = path + ".partial";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) return makeError(ErrorCode::IoError, path + ": cannot open for writing");
        f.write(reinterpret_cast<const char*>(bytes->data()), static_cast<std::streamsize>(bytes->size()));
        if (!f) return makeError(ErrorCode::IoError, path + ": write failed (disk full?)");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) return makeError(ErrorCode::IoError, path + ": cannot rename from " + tmp + ": " + ec.message());
    return {};
}

nlohmann::ordered_json sceneExtras(const Model& model, const AttributeTable& attributes) {
    return {{"version", 1},
            {"crs", model.crs.id()},
            {"origin", {model.origin.x, model.origin.y, model.origin.z}},
            {"attributes", attributes.toJson()["records"]},
            {"notes", model.notes}};
}

Result<std::vector<std::uint8_t>> packGlb(std::string text, const std::vector<std::uint8_t>& bin,
                                          const std::string& what) {
    while (text.size() % 4) text.push_back(' ');
    const std::uint64_t total = 12 + 8 + text.size() + 8 + bin.size();
    if (total >= 0xFFFFFFFFull)
        return makeError(ErrorCode::OutOfRange, what + " too large for one GLB (" + std::to_string(total) + " bytes)");
    std::vector<std::uint8_t> out;
    out.reserve(total);
    appendGlbStart(out, static_cast<std::uint32_t>(total), text);
    appendU32(out, static_cast<std::uint32_t>(bin.size()));
    appendU32(out, kGlbChunkBin);
    out.insert(out.end(), bin.begin(), bin.end());
    return out;
}

void appendGlbStart(std::vector<std::uint8_t>& out, std::uint32_t totalBytes, const std::string& json) {
    appendU32(out, kGlbMagic);
    appendU32(out, 2);
    appendU32(out, totalBytes);
    appendU32(out, static_cast<std::uint32_t>(json.size()));
    appendU32(out, kGlbChunkJson);
    out.insert(out.end(), json.begin(), json.end());
}

}  // namespace geoslice
