// mesh.glb of a baked package, both ways: encodeMesh writes one node + mesh per part
// (POSITION in the local frame and glTF axes, TEXCOORD_0, uint32 indices, and where float32
// would merge vertices the residual attribute); parseMesh reads it back from a mapping with
// every size, offset and index checked.
#include <algorithm>
#include <array>
#include <cstring>

#include "bake/package_internal.hpp"

namespace geoslice::bake::package_detail {
namespace {

using json = nlohmann::ordered_json;

constexpr std::uint32_t kChunkJson = kGlbChunkJson;
constexpr std::uint32_t kChunkBin = kGlbChunkBin;

std::uint32_t readU32(const std::uint8_t* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

// Would float32 alone merge vertices of this part that are distinct in double (hi + lo)?
bool floatMergesVertices(const BakedPart& part) {
    if (part.positionsLo.size() != part.positions.size()) return false;
    std::vector<std::uint32_t> order(part.positions.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
    auto key = [&](std::uint32_t i) {
        const glm::vec3& p = part.positions[i];
        return std::array<float, 3>{p.x, p.y, p.z};
    };
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    for (std::size_t k = 1; k < order.size(); ++k)
        if (key(order[k]) == key(order[k - 1]) && part.positionsLo[order[k]] != part.positionsLo[order[k - 1]])
            return true;
    return false;
}

// One accessor of our own GLB layout: tightly packed, 4-byte aligned, inside the BIN chunk.
template <class T>
Result<const T*> accessorData(const nlohmann::json& doc, std::size_t index, int componentType, const char* type,
                              std::size_t components, std::span<const std::uint8_t> bin, std::size_t& count,
                              const std::string& where) {
    const auto& acc = doc.at("accessors").at(index);
    if (acc.at("componentType").get<int>() != componentType || acc.at("type").get<std::string>() != type)
        return makeError(ErrorCode::ParseError, where + ": accessor " + std::to_string(index) + " is not " + type);
    count = acc.at("count").get<std::size_t>();
    const std::size_t accOffset = acc.value("byteOffset", std::size_t(0));
    const auto& view = doc.at("bufferViews").at(acc.at("bufferView").get<std::size_t>());
    if (view.at("buffer").get<int>() != 0 ||
        (view.contains("byteStride") && view.at("byteStride").get<std::size_t>() != components * sizeof(T)))
        return makeError(ErrorCode::ParseError,
                         where + ": accessor " + std::to_string(index) + " is not tightly packed in buffer 0");
    const std::size_t offset = view.at("byteOffset").get<std::size_t>(),
                      length = view.at("byteLength").get<std::size_t>();
    if (offset > bin.size() || length > bin.size() - offset || accOffset > length ||
        count > (length - accOffset) / (components * sizeof(T)) || (offset + accOffset) % 4 != 0)
        return makeError(ErrorCode::ParseError,
                         where + ": accessor " + std::to_string(index) +
                             " lies outside the binary chunk or is misaligned (truncated file?)");
    return reinterpret_cast<const T*>(bin.data() + offset + accOffset);
}

}  // namespace

AttributeTable mergedAttributes(const Model& model, const BakedModel& baked) {
    AttributeTable table = model.attributes;
    for (const auto& r : baked.fieldRecords) table.put(r);
    return table;
}

Result<std::vector<std::uint8_t>> encodeMesh(const Model& model, const BakedModel& baked, bool features,
                                             bool residuals) {
    const AttributeTable table = mergedAttributes(model, baked);
    if (features && baked.pages != 1)
        return makeError(ErrorCode::Unsupported, "EXT_mesh_features export needs a one-page bake (this one has " +
                                                     std::to_string(baked.pages) + " pages: raise the texture size)");
    GlbBuilder glb("geoslice bake");
    // Property-table rows: every record of the table and every part's record, by id.
    FeatureExport fx;
    if (features) fx.rows = featureRows(table, baked);
    for (const BakedPart& part : baked.parts) {
        std::vector<float> pos(part.positions.size() * 3);
        for (std::size_t i = 0; i < part.positions.size(); ++i) {
            const glm::vec3 g = worldToGltf(part.positions[i]);
            std::memcpy(&pos[3 * i], &g, sizeof g);
        }
        const std::size_t pa = glb.addPositions(pos.data(), part.positions.size());
        const std::size_t uv = glb.addView(part.uvs.data(), part.uvs.size() * 8, kGltfArrayBuffer);
        const std::size_t iv = glb.addView(part.indices.data(), part.indices.size() * 4, kGltfElementArrayBuffer);
        const std::size_t ua = glb.addAccessor(
            {{"bufferView", uv}, {"componentType", kGltfFloat}, {"count", part.uvs.size()}, {"type", "VEC2"}});
        const std::size_t ia = glb.addAccessor(
            {{"bufferView", iv}, {"componentType", kGltfUint}, {"count", part.indices.size()}, {"type", "SCALAR"}});
        json prim = {{"attributes", {{"POSITION", pa}, {"TEXCOORD_0", ua}}}, {"indices", ia}, {"mode", kGltfTriangles}};
        if (residuals && floatMergesVertices(part)) {
            // What float32 lost, for readers that want double (model/gltf_io reads it): an
            // application-specific attribute (glTF 2.0 3.7.2.1: names start with '_').
            std::vector<float> residual(part.positionsLo.size() * 3);
            for (std::size_t i = 0; i < part.positionsLo.size(); ++i) {
                const glm::vec3 g = worldToGltf(part.positionsLo[i]);
                std::memcpy(&residual[3 * i], &g, sizeof g);
            }
            const std::size_t lv = glb.addView(residual.data(), residual.size() * 4, kGltfArrayBuffer);
            prim["attributes"][kPositionResidualAttribute] = glb.addAccessor({{"bufferView", lv},
                                                                              {"componentType", kGltfFloat},
                                                                              {"count", part.positionsLo.size()},
                                                                              {"type", "VEC3"}});
        }
        if (features) prim["extensions"]["EXT_mesh_features"] = featureIdsExtension(fx.rows.size());
        glb.addPart(part.name, part.kind, part.record, std::move(prim));
    }
    if (features)
        if (auto s = addFeatureTables(glb, baked, table, fx); !s) return s.error();
    json& doc = glb.finishDocument(model, table);
    if (features) finishFeatureDocument(doc, fx);
    return glb.pack("baked mesh");
}

Status parseMesh(std::span<const std::uint8_t> mesh, const std::string& source, Package& pkg) {
    if (mesh.size() < 28 || readU32(mesh.data()) != kGlbMagic || readU32(mesh.data() + 4) != 2)
        return parseError(source, kMeshFile, "not a glTF 2.0 binary (GLB)");
    if (readU32(mesh.data() + 8) != mesh.size())
        return parseError(source, kMeshFile,
                          "GLB header length " + std::to_string(readU32(mesh.data() + 8)) +
                              " differs from the file's " + std::to_string(mesh.size()) + " bytes");
    const std::size_t jsonLen = readU32(mesh.data() + 12);
    if (readU32(mesh.data() + 16) != kChunkJson || jsonLen > mesh.size() - 28 || jsonLen % 4)
        return parseError(source, kMeshFile, "bad JSON chunk");
    const std::size_t binAt = 20 + jsonLen;
    const std::size_t binLen = readU32(mesh.data() + binAt);
    if (readU32(mesh.data() + binAt + 4) != kChunkBin || binLen > mesh.size() - binAt - 8)
        return parseError(source, kMeshFile, "bad BIN chunk (truncated?)");
    const std::span<const std::uint8_t> bin = mesh.subspan(binAt + 8, binLen);
    auto doc = nlohmann::json::parse(mesh.data() + 20, mesh.data() + 20 + jsonLen, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return parseError(source, kMeshFile, "JSON chunk is not a JSON object");
    const auto& nodes = doc.at("nodes");
    if (nodes.empty()) return parseError(source, kMeshFile, "no nodes");
    const auto& root = nodes.at(0);
    if (root.contains("translation")) {
        const auto& t = root.at("translation");
        pkg.rootTranslation = {t.at(0).get<double>(), t.at(1).get<double>(), t.at(2).get<double>()};
    }
    if (doc.contains("scenes") && !doc.at("scenes").empty()) {
        const auto& scene = doc.at("scenes").at(doc.value("scene", std::size_t(0)));
        pkg.sceneName = scene.value("name", std::string());
        if (scene.contains("extras") && scene.at("extras").contains("geoslice"))
            pkg.sceneExtras = scene.at("extras").at("geoslice");
    }
    for (std::size_t n = 1; n < nodes.size(); ++n) {
        const auto& node = nodes.at(n);
        const std::string where = source + "/" + kMeshFile + ": node " + std::to_string(n);
        PackagePart part;
        part.name = node.value("name", std::string());
        const std::size_t meshIndex = node.at("mesh").get<std::size_t>();
        // Named as model/io/gltf/gltf_io.cpp names a part: the node, else the mesh, else "mesh N".
        if (part.name.empty()) part.name = doc.at("meshes").at(meshIndex).value("name", std::string());
        if (part.name.empty()) part.name = "mesh " + std::to_string(meshIndex);
        const auto& gs = node.at("extras").at("geoslice");
        part.kind = gs.at("kind").get<std::string>() == "surface" ? PartKind::Surface : PartKind::Body;
        const std::uint64_t record = gs.at("record").get<std::uint64_t>();
        part.record = record <= 0xFFFFFFFEu ? static_cast<RecordId>(record) : kNoRecord;
        const auto& prim = doc.at("meshes").at(meshIndex).at("primitives").at(0);
        std::size_t nPos = 0, nUv = 0;
        auto pos = accessorData<float>(doc, prim.at("attributes").at("POSITION").get<std::size_t>(), kGltfFloat, "VEC3",
                                       3, bin, nPos, where);
        if (!pos) return pos.error();
        auto uv = accessorData<float>(doc, prim.at("attributes").at("TEXCOORD_0").get<std::size_t>(), kGltfFloat,
                                      "VEC2", 2, bin, nUv, where);
        if (!uv) return uv.error();
        auto idx = accessorData<std::uint32_t>(doc, prim.at("indices").get<std::size_t>(), kGltfUint, "SCALAR", 1, bin,
                                               part.indexCount, where);
        if (!idx) return idx.error();
        if (nPos != nUv) return makeError(ErrorCode::ParseError, where + ": POSITION and TEXCOORD_0 counts differ");
        if (prim.at("attributes").contains(kPositionResidualAttribute)) {
            std::size_t nLo = 0;
            auto lo = accessorData<float>(doc, prim.at("attributes").at(kPositionResidualAttribute).get<std::size_t>(),
                                          kGltfFloat, "VEC3", 3, bin, nLo, where);
            if (!lo) return lo.error();
            if (nLo != nPos)
                return makeError(ErrorCode::ParseError,
                                 where + ": " + kPositionResidualAttribute + " and POSITION counts differ");
            part.residuals = lo.value();
        }
        if (part.indexCount % 3)
            return makeError(ErrorCode::ParseError, where + ": index count is not a multiple of 3");
        part.vertexCount = nPos;
        part.positions = pos.value();
        part.uvs = uv.value();
        part.indices = idx.value();
        for (std::size_t i = 0; i < part.indexCount; ++i)
            if (part.indices[i] >= part.vertexCount)
                return makeError(ErrorCode::ParseError, where + ": index " + std::to_string(i) + " refers to vertex " +
                                                            std::to_string(part.indices[i]) + " of " +
                                                            std::to_string(part.vertexCount));
        pkg.parts.push_back(std::move(part));
    }
    return {};
}

}  // namespace geoslice::bake::package_detail
