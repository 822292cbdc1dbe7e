// glTF 2.0 / GLB reading (tinygltf, with KHR_draco_mesh_compression) and writing (own GLB
// writer; Draco through libdraco).
#include "model/gltf_io.hpp"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <tiny_gltf.h>

#include "model/loaders.hpp"

namespace geoslice {
namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;
constexpr std::uint32_t kChunkBin = 0x004E4942;
constexpr int kTriangles = 4;

// World (x east, y north, z up) <-> glTF (X, Y up, Z = -north).
glm::dvec3 worldToGltf(const glm::dvec3& w) { return {w.x, w.z, -w.y}; }
glm::dvec3 gltfToWorld(const glm::dvec3& g) { return {g.x, -g.z, g.y}; }

std::uint32_t readU32(const std::uint8_t* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

// GLB container checks with byte offsets, before tinygltf sees the bytes.
Status checkGlbContainer(const std::uint8_t* data, std::size_t size, const std::string& source) {
    auto fail = [&](std::size_t offset, const std::string& what) {
        return makeError(ErrorCode::ParseError, source + ": byte " + std::to_string(offset) + ": " + what);
    };
    if (size < 20) return fail(0, "file too short for a GLB header (" + std::to_string(size) + " bytes)");
    if (readU32(data) != kGlbMagic) return fail(0, "wrong magic, not a GLB file");
    if (readU32(data + 4) != 2) return fail(4, "GLB version " + std::to_string(readU32(data + 4)) + ", expected 2");
    std::uint32_t length = readU32(data + 8);
    if (length > size) return fail(8, "header says " + std::to_string(length) + " bytes but the file has " + std::to_string(size) + " (truncated?)");
    std::uint32_t jsonLen = readU32(data + 12);
    if (readU32(data + 16) != kChunkJson) return fail(16, "first chunk is not JSON");
    if (std::uint64_t(jsonLen) + 20 > length) return fail(12, "JSON chunk length " + std::to_string(jsonLen) + " runs past the end of the file");
    std::uint64_t binAt = 20 + std::uint64_t(jsonLen);
    if (binAt + 8 <= length) {
        std::uint32_t binLen = readU32(data + binAt);
        if (binAt + 8 + binLen > length) return fail(binAt, "BIN chunk length " + std::to_string(binLen) + " runs past the end of the file");
    }
    return {};
}

nlohmann::json parseExtras(const std::string& text) {
    if (text.empty()) return nlohmann::json();
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    return j.is_discarded() ? nlohmann::json() : j;
}

glm::dmat4 nodeMatrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        glm::dmat4 m(1.0);
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[static_cast<std::size_t>(c * 4 + r)];
        return m;
    }
    glm::dmat4 m(1.0);
    if (n.translation.size() == 3) m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
    if (n.rotation.size() == 4)
        m *= glm::mat4_cast(glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]));
    if (n.scale.size() == 3) m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
    return m;
}

// Bounds-checked view of an accessor's elements.
struct AccessorView {
    const std::uint8_t* base = nullptr;
    std::size_t stride = 0, count = 0;
    int componentType = 0, components = 0;
};

Result<AccessorView> viewAccessor(const tinygltf::Model& g, int index, const std::string& where) {
    auto fail = [&](const std::string& what) { return makeError(ErrorCode::ParseError, where + ": " + what); };
    if (index < 0 || static_cast<std::size_t>(index) >= g.accessors.size()) return fail("accessor " + std::to_string(index) + " does not exist");
    const auto& a = g.accessors[static_cast<std::size_t>(index)];
    if (a.sparse.isSparse) return fail("sparse accessors are not supported");
    if (a.bufferView < 0 || static_cast<std::size_t>(a.bufferView) >= g.bufferViews.size())
        return fail("accessor " + std::to_string(index) + " has no valid bufferView");
    const auto& bv = g.bufferViews[static_cast<std::size_t>(a.bufferView)];
    if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= g.buffers.size()) return fail("bufferView has no valid buffer");
    const auto& buf = g.buffers[static_cast<std::size_t>(bv.buffer)];
    int comps = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    int csize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
    if (comps <= 0 || csize <= 0) return fail("accessor " + std::to_string(index) + " has an unknown type");
    std::size_t elem = static_cast<std::size_t>(comps) * static_cast<std::size_t>(csize);
    std::size_t stride = bv.byteStride ? bv.byteStride : elem;
    if (stride < elem) return fail("byteStride smaller than the element");
    std::uint64_t start = std::uint64_t(bv.byteOffset) + a.byteOffset;
    std::uint64_t need = a.count == 0 ? 0 : start + std::uint64_t(stride) * (a.count - 1) + elem;
    if (std::uint64_t(bv.byteOffset) + bv.byteLength > buf.data.size() || (a.count && need > buf.data.size()) ||
        (a.count && need > std::uint64_t(bv.byteOffset) + bv.byteLength))
        return fail("accessor " + std::to_string(index) + " (" + std::to_string(a.count) + " elements) runs past its buffer of " +
                    std::to_string(buf.data.size()) + " bytes");
    return AccessorView{buf.data.data() + start, stride, a.count, a.componentType, comps};
}

Status appendPrimitive(const tinygltf::Model& g, const tinygltf::Primitive& prim, const glm::dmat4& toWorld,
                       Mesh& mesh, const std::string& where) {
    if (prim.mode != -1 && prim.mode != kTriangles) return {};  // points and lines carry no volume or sheet
    auto posIt = prim.attributes.find("POSITION");
    if (posIt == prim.attributes.end()) return makeError(ErrorCode::ParseError, where + ": primitive has no POSITION");
    auto pos = viewAccessor(g, posIt->second, where);
    if (!pos) return pos.error();
    if (pos->componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || pos->components != 3)
        return makeError(ErrorCode::Unsupported, where + ": POSITION must be float VEC3");
    const std::size_t first = mesh.positions.size();
    if (first + pos->count > 0xFFFFFFF0u) return makeError(ErrorCode::OutOfRange, where + ": more than 4 billion vertices");
    for (std::size_t i = 0; i < pos->count; ++i) {
        float f[3];
        std::memcpy(f, pos->base + i * pos->stride, sizeof f);
        glm::dvec4 p = toWorld * glm::dvec4(f[0], f[1], f[2], 1.0);
        mesh.positions.push_back(gltfToWorld(glm::dvec3(p)));
    }
    const bool mirror = glm::determinant(glm::dmat3(toWorld)) < 0.0;
    auto pushTri = [&](std::uint64_t a, std::uint64_t b, std::uint64_t c) -> Status {
        if (a >= pos->count || b >= pos->count || c >= pos->count)
            return makeError(ErrorCode::ParseError, where + ": index " + std::to_string(std::max({a, b, c})) +
                                                        " out of range (" + std::to_string(pos->count) + " vertices)");
        mesh.indices.push_back(static_cast<std::uint32_t>(first + a));
        mesh.indices.push_back(static_cast<std::uint32_t>(first + (mirror ? c : b)));
        mesh.indices.push_back(static_cast<std::uint32_t>(first + (mirror ? b : c)));
        return {};
    };
    if (prim.indices < 0) {
        for (std::size_t i = 0; i + 2 < pos->count; i += 3)
            if (auto s = pushTri(i, i + 1, i + 2); !s) return s;
        return {};
    }
    auto idx = viewAccessor(g, prim.indices, where);
    if (!idx) return idx.error();
    if (idx->components != 1) return makeError(ErrorCode::ParseError, where + ": indices must be SCALAR");
    auto get = [&](std::size_t i) -> std::uint64_t {
        const std::uint8_t* p = idx->base + i * idx->stride;
        switch (idx->componentType) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
            default: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
        }
    };
    if (idx->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && idx->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        idx->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        return makeError(ErrorCode::ParseError, where + ": indices must be unsigned byte, short or int");
    mesh.indices.reserve(mesh.indices.size() + idx->count);
    for (std::size_t i = 0; i + 2 < idx->count; i += 3)
        if (auto s = pushTri(get(i), get(i + 1), get(i + 2)); !s) return s;
    return {};
}

bool noImages(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
    return true;  // geoslice needs geometry only; textures are ignored, never decoded
}

// External buffers only from inside the model's folder: no absolute paths, no "..".
bool readInsideBase(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    const std::string& base = *static_cast<const std::string*>(user);
    std::error_code ec;
    if (base.empty()) {
        *err = "external file \"" + path + "\" is not allowed here";
        return false;
    }
    auto canonBase = std::filesystem::weakly_canonical(base, ec);
    auto canonPath = std::filesystem::weakly_canonical(path, ec);
    auto rel = canonPath.lexically_relative(canonBase);
    if (ec || rel.empty() || *rel.begin() == "..") {
        *err = "external file \"" + path + "\" lies outside the model's folder";
        return false;
    }
    auto bytes = readFile(canonPath.string(), std::size_t(2) << 30);
    if (!bytes) {
        *err = bytes.error().message;
        return false;
    }
    out->assign(bytes->begin(), bytes->end());
    return true;
}
bool existsInsideBase(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}
std::string expandNothing(const std::string& path, void*) { return path; }
bool writeNothing(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    *err = "writing is disabled";
    return false;
}

}  // namespace

Result<Model> parseGltf(const std::uint8_t* data, std::size_t size, const std::string& source, const std::string& baseDir) {
    if (size == 0) return makeError(ErrorCode::ParseError, source + ": empty file");
    if (size >= 0xFFFFFFFFu) return makeError(ErrorCode::OutOfRange, source + ": glTF files over 4 GiB are not supported");
    const bool binary = size >= 4 && readU32(data) == kGlbMagic;
    if (binary)
        if (auto s = checkGlbContainer(data, size, source); !s) return s.error();

    tinygltf::TinyGLTF loader;
    loader.SetStoreOriginalJSONForExtrasAndExtensions(true);
    loader.SetImageLoader(noImages, nullptr);
    std::string base = baseDir;
    loader.SetFsCallbacks({existsInsideBase, expandNothing, readInsideBase, writeNothing, &base});
    tinygltf::Model g;
    std::string err, warn;
    bool ok = binary ? loader.LoadBinaryFromMemory(&g, &err, &warn, data, static_cast<unsigned>(size), baseDir)
                     : loader.LoadASCIIFromString(&g, &err, &warn, reinterpret_cast<const char*>(data),
                                                  static_cast<unsigned>(size), baseDir);
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        return makeError(ErrorCode::ParseError, source + ": " + (err.empty() ? std::string("not a valid glTF file") : err));
    }

    Model model;
    model.source = source;
    bool ours = false;
    int sceneIndex = g.defaultScene >= 0 ? g.defaultScene : 0;
    std::vector<int> roots;
    if (static_cast<std::size_t>(sceneIndex) < g.scenes.size()) {
        const auto& scene = g.scenes[static_cast<std::size_t>(sceneIndex)];
        roots = scene.nodes;
        model.name = scene.name;
        nlohmann::json ex = parseExtras(scene.extras_json_string);
        if (ex.is_object() && ex.contains("geoslice") && ex["geoslice"].is_object()) {
            const auto& gs = ex["geoslice"];
            ours = true;
            if (gs.contains("crs") && gs["crs"].is_string()) {
                auto crs = Crs::parse(gs["crs"].get<std::string>());
                if (!crs) return makeError(ErrorCode::ParseError, source + ": scene extras: " + crs.error().message);
                model.crs = crs.value();
            }
            if (gs.contains("attributes")) {
                auto table = AttributeTable::fromJson(gs["attributes"], source + ": scene extras attributes");
                if (!table) return table.error();
                model.attributes = std::move(table.value());
            }
        }
    } else {
        for (std::size_t i = 0; i < g.nodes.size(); ++i) roots.push_back(static_cast<int>(i));
    }

    // Depth-first over the scene graph with accumulated transforms; a node visit budget
    // stops cycles (invalid glTF) from hanging.
    std::size_t budget = g.nodes.size() * 4 + 16;
    bool allKinds = true;
    struct Item { int node; glm::dmat4 parent; };
    std::vector<Item> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::dmat4(1.0)});
    while (!stack.empty()) {
        Item item = stack.back();
        stack.pop_back();
        if (budget-- == 0) return makeError(ErrorCode::ParseError, source + ": the node hierarchy has a cycle");
        if (item.node < 0 || static_cast<std::size_t>(item.node) >= g.nodes.size())
            return makeError(ErrorCode::ParseError, source + ": node " + std::to_string(item.node) + " does not exist");
        const auto& node = g.nodes[static_cast<std::size_t>(item.node)];
        glm::dmat4 m = item.parent * nodeMatrix(node);
        for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.push_back({*it, m});
        if (node.mesh < 0) continue;
        if (static_cast<std::size_t>(node.mesh) >= g.meshes.size())
            return makeError(ErrorCode::ParseError, source + ": node \"" + node.name + "\" uses mesh " + std::to_string(node.mesh) + " which does not exist");
        const auto& gm = g.meshes[static_cast<std::size_t>(node.mesh)];
        Part part;
        part.name = !node.name.empty() ? node.name : !gm.name.empty() ? gm.name : "mesh " + std::to_string(node.mesh);
        std::string where = source + ": mesh \"" + part.name + "\"";
        for (const auto& prim : gm.primitives)
            if (auto s = appendPrimitive(g, prim, m, part.mesh, where); !s) return s.error();
        if (part.mesh.indices.empty()) continue;

        nlohmann::json ex = parseExtras(node.extras_json_string);
        if (!ex.is_object()) ex = parseExtras(gm.extras_json_string);
        bool kindKnown = false;
        if (ex.is_object() && ex.contains("geoslice") && ex["geoslice"].is_object()) {
            const auto& gs = ex["geoslice"];
            if (gs.contains("kind") && gs["kind"].is_string()) {
                part.kind = gs["kind"] == "surface" ? PartKind::Surface : PartKind::Body;
                kindKnown = true;
            }
            if (gs.contains("record") && gs["record"].is_number_unsigned()) part.record = gs["record"].get<RecordId>();
        } else if (ex.is_object() && !ex.empty()) {
            // Plain extras describe the part's geology: they become its record.
            nlohmann::json rec = ex;
            if (!rec.contains("name")) rec["name"] = part.name;
            rec["id"] = model.attributes.nextId();
            auto t = AttributeTable::fromJson(nlohmann::json::array({rec}), where + " extras");
            if (!t) return t.error();
            for (const auto& [id, r] : t->records()) model.attributes.put(r);
            part.record = rec["id"].get<RecordId>();
        }
        allKinds = allKinds && kindKnown;
        (part.kind == PartKind::Body ? model.bodies : model.surfaces).push_back(std::move(part));
    }
    if (model.bodies.empty() && model.surfaces.empty())
        return makeError(ErrorCode::ParseError, source + ": no triangle meshes in the default scene");
    finishLoadedModel(model, /*classifyByClosure=*/!(ours && allKinds));
    return model;
}

Result<std::vector<std::uint8_t>> encodeGlb(const Model& model, const GlbWriteOptions& options) {
    using json = nlohmann::ordered_json;
    std::vector<std::uint8_t> bin;
    auto align4 = [&] { while (bin.size() % 4) bin.push_back(0); };
    json accessors = json::array(), views = json::array(), meshes = json::array(), nodes = json::array();
    json rootChildren = json::array();
    nodes.push_back(json::object());  // root, filled below

    auto addView = [&](const void* bytes, std::size_t n, int target) {
        align4();
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", n}};
        if (target) v["target"] = target;
        const auto* p = static_cast<const std::uint8_t*>(bytes);
        bin.insert(bin.end(), p, p + n);
        views.push_back(v);
        return static_cast<int>(views.size() - 1);
    };

    auto addPart = [&](const Part& part) -> Status {
        const Mesh& mesh = part.mesh;
        if (mesh.positions.empty() || mesh.indices.empty()) return {};
        std::vector<float> pos(mesh.positions.size() * 3);
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            glm::vec3 g(worldToGltf(mesh.positions[i] - model.origin));
            pos[3 * i] = g.x;
            pos[3 * i + 1] = g.y;
            pos[3 * i + 2] = g.z;
            lo = glm::min(lo, g);
            hi = glm::max(hi, g);
        }
        json posAcc = {{"componentType", 5126}, {"count", mesh.positions.size()}, {"type", "VEC3"},
                       {"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}};
        json idxAcc = {{"componentType", 5125}, {"count", mesh.indices.size()}, {"type", "SCALAR"}};
        json prim = {{"mode", kTriangles}};
        if (options.draco) {
            draco::Mesh dm;
            draco::GeometryAttribute ga;
            ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, sizeof(float) * 3, 0);
            int att = dm.AddAttribute(ga, true, static_cast<std::uint32_t>(mesh.positions.size()));
            for (std::size_t i = 0; i < mesh.positions.size(); ++i)
                dm.attribute(att)->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(i)), &pos[3 * i]);
            for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
                dm.AddFace({draco::PointIndex(mesh.indices[3 * t]), draco::PointIndex(mesh.indices[3 * t + 1]),
                            draco::PointIndex(mesh.indices[3 * t + 2])});
            draco::Encoder enc;
            enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.dracoPositionBits);
            enc.SetSpeedOptions(options.dracoSpeed, options.dracoSpeed);
            draco::EncoderBuffer out;
            draco::Status st = enc.EncodeMeshToBuffer(dm, &out);
            if (!st.ok()) return makeError(ErrorCode::Internal, "Draco encoding of \"" + part.name + "\" failed: " + st.error_msg_string());
            int view = addView(out.data(), out.size(), 0);
            prim["extensions"]["KHR_draco_mesh_compression"] = {{"bufferView", view},
                                                                {"attributes", {{"POSITION", dm.attribute(att)->unique_id()}}}};
        } else {
            posAcc["bufferView"] = addView(pos.data(), pos.size() * sizeof(float), 34962);
            idxAcc["bufferView"] = addView(mesh.indices.data(), mesh.indices.size() * 4, 34963);
        }
        accessors.push_back(posAcc);
        prim["attributes"] = {{"POSITION", accessors.size() - 1}};
        accessors.push_back(idxAcc);
        prim["indices"] = accessors.size() - 1;
        meshes.push_back({{"name", part.name}, {"primitives", json::array({prim})}});
        nodes.push_back({{"name", part.name}, {"mesh", meshes.size() - 1},
                         {"extras", {{"geoslice", {{"kind", part.kind == PartKind::Body ? "body" : "surface"}, {"record", part.record}}}}}});
        rootChildren.push_back(nodes.size() - 1);
        return {};
    };
    for (const auto& p : model.bodies)
        if (auto s = addPart(p); !s) return s.error();
    for (const auto& p : model.surfaces)
        if (auto s = addPart(p); !s) return s.error();
    align4();

    glm::dvec3 o = worldToGltf(model.origin);
    nodes[0] = {{"name", model.name.empty() ? "model" : model.name}, {"translation", {o.x, o.y, o.z}}, {"children", rootChildren}};
    json doc;
    doc["asset"] = {{"version", "2.0"}, {"generator", "geoslice 0.1.0"}};
    if (options.draco) {
        doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
        doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    }
    doc["scene"] = 0;
    doc["scenes"] = {{{"name", model.name}, {"nodes", {0}},
                      {"extras", {{"geoslice", {{"version", 1}, {"crs", model.crs.id()},
                                                {"origin", {model.origin.x, model.origin.y, model.origin.z}},
                                                {"attributes", model.attributes.toJson()["records"]}}}}}}};
    doc["nodes"] = nodes;
    doc["meshes"] = meshes;
    doc["accessors"] = accessors;
    doc["bufferViews"] = views;
    doc["buffers"] = {{{"byteLength", bin.size()}}};
    std::string text = doc.dump();
    while (text.size() % 4) text.push_back(' ');

    std::uint64_t total = 12 + 8 + text.size() + 8 + bin.size();
    if (total >= 0xFFFFFFFFull) return makeError(ErrorCode::OutOfRange, "model too large for one GLB (" + std::to_string(total) + " bytes)");
    std::vector<std::uint8_t> out;
    out.reserve(total);
    auto u32 = [&](std::uint32_t v) {
        std::uint8_t b[4];
        std::memcpy(b, &v, 4);
        out.insert(out.end(), b, b + 4);
    };
    u32(kGlbMagic);
    u32(2);
    u32(static_cast<std::uint32_t>(total));
    u32(static_cast<std::uint32_t>(text.size()));
    u32(kChunkJson);
    out.insert(out.end(), text.begin(), text.end());
    u32(static_cast<std::uint32_t>(bin.size()));
    u32(kChunkBin);
    out.insert(out.end(), bin.begin(), bin.end());
    return out;
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

}  // namespace geoslice
