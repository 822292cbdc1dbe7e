// glTF 2.0 / GLB reading (parseGltf, model/io/loaders.hpp): tinygltf parses the JSON and
// buffers after model/io/gltf/gltf_preflight.cpp has checked them; the default scene's node tree is
// walked with accumulated transforms, each mesh becomes a part (primitives through
// model/io/gltf/gltf_primitive.cpp), and geoslice's own extras (CRS, attributes, notes, part kinds
// and records) or plain extras (a part's geology) are read back.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <new>
#include <optional>
#include <vector>

#include <tiny_gltf.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "model/io/gltf/gltf_read.hpp"
#include "model/io/loaders.hpp"

namespace geoslice {
namespace gltf {

nlohmann::json parseExtras(const std::string& text) {
    if (text.empty()) return nlohmann::json();
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    return j.is_discarded() ? nlohmann::json() : j;
}

namespace {

glm::dmat4 nodeMatrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        glm::dmat4 m(1.0);
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[static_cast<std::size_t>(c * 4 + r)];
        return m;
    }
    glm::dmat4 m(1.0);
    if (n.translation.size() == 3)
        m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
    if (n.rotation.size() == 4) {
        // glTF asks for unit quaternions; exporters write them rounded to float. Normalising
        // keeps a rotation from adding a scale of (1 + rounding error).
        glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
        const double len = glm::length(q);
        if (len > 0.0 && std::isfinite(len)) q /= len;
        m *= glm::mat4_cast(q);
    }
    if (n.scale.size() == 3) m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
    return m;
}

bool noImages(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
    return true;  // geoslice needs geometry only; textures are ignored, never decoded
}

// External buffers only from inside the model's folder: no absolute paths, no "..", no
// symbolic link that leads out (preflightJson refuses the first two with a clearer message).
bool readInsideBase(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    const std::string& base = *static_cast<const std::string*>(user);
    if (base.empty()) {
        *err = "external file \"" + path + "\" is not allowed here";
        return false;
    }
    std::error_code baseEc, pathEc;
    auto canonBase = std::filesystem::weakly_canonical(base, baseEc);
    auto canonPath = std::filesystem::weakly_canonical(path, pathEc);
    auto rel = canonPath.lexically_relative(canonBase);
    if (baseEc || pathEc || rel.empty() || *rel.begin() == "..") {
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

// The sRGB colour of a mesh's first material with a baseColorFactor (linear RGBA in glTF)
// and the material's name; nullopt when it has none or only the default white.
std::optional<std::pair<Rgba8, std::string>> materialColour(const tinygltf::Model& g, const tinygltf::Mesh& gm) {
    for (const auto& prim : gm.primitives) {
        if (prim.material < 0 || static_cast<std::size_t>(prim.material) >= g.materials.size()) continue;
        const tinygltf::Material& mat = g.materials[static_cast<std::size_t>(prim.material)];
        const std::vector<double>& f = mat.pbrMetallicRoughness.baseColorFactor;
        if (f.size() != 4 || (f[0] == 1.0 && f[1] == 1.0 && f[2] == 1.0 && f[3] == 1.0)) continue;
        auto encode = [](double linear) {
            const double v = std::clamp(std::isfinite(linear) ? linear : 0.0, 0.0, 1.0);
            const double srgb = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
            return static_cast<std::uint8_t>(std::lround(srgb * 255.0));
        };
        const double a = std::clamp(std::isfinite(f[3]) ? f[3] : 1.0, 0.0, 1.0);
        return std::make_pair(
            Rgba8{encode(f[0]), encode(f[1]), encode(f[2]), static_cast<std::uint8_t>(std::lround(a * 255.0))},
            mat.name.empty() ? "material " + std::to_string(prim.material) : mat.name);
    }
    return std::nullopt;
}

Result<Model> parseGltfChecked(const std::uint8_t* data, std::size_t size, const std::string& source,
                               const std::string& baseDir) {
    if (size == 0) return makeError(ErrorCode::ParseError, source + ": empty file");
    if (size >= 0xFFFFFFFFu)
        return makeError(ErrorCode::OutOfRange, source + ": glTF files over 4 GiB are not supported");
    const bool binary = size >= 4 && readU32(data) == kGlbMagic;
    const std::uint8_t* bytes = data;
    std::size_t byteCount = size;
    std::vector<std::uint8_t> rewrittenGlb;
    std::string rewrittenJson;
    if (binary) {
        if (auto s = checkGlbContainer(data, size, source); !s) return s.error();
        const std::uint32_t length = readU32(data + 8), jsonLen = readU32(data + 12);
        auto pre = preflightJson(reinterpret_cast<const char*>(data + 20), jsonLen, 20, source, baseDir);
        if (!pre) return pre.error();
        if (pre->has_value()) {
            // Same container with the rewritten JSON chunk; the BIN chunk is copied as it is.
            std::string& text = **pre;
            while (text.size() % 4) text.push_back(' ');
            const std::size_t binAt = 20 + std::size_t(jsonLen);
            const std::uint64_t total = 20 + std::uint64_t(text.size()) + (length - binAt);
            if (total >= 0xFFFFFFFFu)
                return makeError(ErrorCode::OutOfRange, source + ": glTF files over 4 GiB are not supported");
            rewrittenGlb.reserve(total);
            appendGlbStart(rewrittenGlb, static_cast<std::uint32_t>(total), text);
            rewrittenGlb.insert(rewrittenGlb.end(), data + binAt, data + length);
            bytes = rewrittenGlb.data();
            byteCount = rewrittenGlb.size();
        }
    } else {
        std::size_t at = 0;
        if (size >= 3 && std::memcmp(data, "\xEF\xBB\xBF", 3) == 0) at = 3;  // UTF-8 byte order mark
        while (at < size && (data[at] == ' ' || data[at] == '\t' || data[at] == '\r' || data[at] == '\n')) ++at;
        if (at == size || data[at] != '{')
            return makeError(ErrorCode::ParseError, source + ": byte " + std::to_string(std::min(at, size - 1)) +
                                                        ": not glTF: neither the GLB magic \"glTF\" nor a JSON object");
        auto pre = preflightJson(reinterpret_cast<const char*>(data), size, 0, source, baseDir);
        if (!pre) return pre.error();
        if (pre->has_value()) {
            rewrittenJson = std::move(**pre);
            bytes = reinterpret_cast<const std::uint8_t*>(rewrittenJson.data());
            byteCount = rewrittenJson.size();
        }
    }
    if (byteCount >= 0xFFFFFFFFu)
        return makeError(ErrorCode::OutOfRange, source + ": glTF files over 4 GiB are not supported");

    tinygltf::TinyGLTF loader;
    loader.SetStoreOriginalJSONForExtrasAndExtensions(true);
    loader.SetImageLoader(noImages, nullptr);
    std::string base = baseDir;
    loader.SetFsCallbacks({existsInsideBase, expandNothing, readInsideBase, writeNothing, &base});
    tinygltf::Model g;
    std::string err, warn;
    bool ok = binary ? loader.LoadBinaryFromMemory(&g, &err, &warn, bytes, static_cast<unsigned>(byteCount), baseDir)
                     : loader.LoadASCIIFromString(&g, &err, &warn, reinterpret_cast<const char*>(bytes),
                                                  static_cast<unsigned>(byteCount), baseDir);
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        if (err.size() > 2 * kMaxQuoted) err = err.substr(0, 2 * kMaxQuoted) + "...";
        return makeError(ErrorCode::ParseError,
                         source + ": " + (err.empty() ? std::string("not a valid glTF file") : err));
    }
    rewrittenGlb = {};
    rewrittenJson = {};

    Model model;
    model.source = source;
    bool ours = false;
    if (g.defaultScene < -1 || (g.defaultScene >= 0 && static_cast<std::size_t>(g.defaultScene) >= g.scenes.size()))
        return makeError(ErrorCode::ParseError,
                         source + ": the default scene " + std::to_string(g.defaultScene) + " does not exist");
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
            if (gs.contains("notes") && gs["notes"].is_object())
                for (const auto& [key, value] : gs["notes"].items())
                    if (value.is_string()) model.notes[key] = value.get<std::string>();
        }
    } else {
        // No scene: show the nodes that are nobody's child (a child listed as a root too
        // would be loaded twice, once without its parent's transform).
        std::vector<char> isChild(g.nodes.size(), 0);
        for (const auto& n : g.nodes)
            for (int c : n.children)
                if (c >= 0 && static_cast<std::size_t>(c) < g.nodes.size()) isChild[static_cast<std::size_t>(c)] = 1;
        for (std::size_t i = 0; i < g.nodes.size(); ++i)
            if (!isChild[i]) roots.push_back(static_cast<int>(i));
    }

    // Depth-first over the scene graph with accumulated transforms. glTF's hierarchy is a
    // set of disjoint trees: a node reached twice means a cycle or two parents, refused
    // (it would otherwise hang or duplicate geometry).
    std::vector<char> seen(g.nodes.size(), 0);
    std::uint64_t budget = kExpansionFactor * size + kExpansionAllowance;
    bool allKinds = true;
    struct Item {
        int node;
        glm::dmat4 parent;
    };
    std::vector<Item> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::dmat4(1.0)});
    while (!stack.empty()) {
        Item item = stack.back();
        stack.pop_back();
        if (item.node < 0 || static_cast<std::size_t>(item.node) >= g.nodes.size())
            return makeError(ErrorCode::ParseError, source + ": node " + std::to_string(item.node) + " does not exist");
        if (seen[static_cast<std::size_t>(item.node)])
            return makeError(ErrorCode::ParseError,
                             source + ": node " + std::to_string(item.node) +
                                 " is reached twice: the node hierarchy has a cycle or a node with two parents");
        seen[static_cast<std::size_t>(item.node)] = 1;
        const auto& node = g.nodes[static_cast<std::size_t>(item.node)];
        glm::dmat4 m = item.parent * nodeMatrix(node);
        for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.push_back({*it, m});
        if (node.mesh < 0) continue;
        if (static_cast<std::size_t>(node.mesh) >= g.meshes.size())
            return makeError(ErrorCode::ParseError, source + ": node \"" + node.name + "\" uses mesh " +
                                                        std::to_string(node.mesh) + " which does not exist");
        const auto& gm = g.meshes[static_cast<std::size_t>(node.mesh)];
        Part part;
        part.name = !node.name.empty() ? node.name : !gm.name.empty() ? gm.name : "mesh " + std::to_string(node.mesh);
        std::string where = source + ": mesh \"" + part.name + "\"";
        for (const auto& prim : gm.primitives)
            if (auto s = appendPrimitive(g, prim, m, part.mesh, where, budget); !s) return s.error();
        if (part.mesh.indices.empty()) continue;

        nlohmann::json ex = parseExtras(node.extras_json_string);
        if (!ex.is_object()) ex = parseExtras(gm.extras_json_string);
        bool kindKnown = false;
        if (ex.is_object() && ex.contains("geoslice") && ex["geoslice"].is_object()) {
            const auto& gs = ex["geoslice"];
            if (gs.contains("kind") && gs["kind"].is_string()) {
                part.kind = gs["kind"] == "surface" ? PartKind::Surface : PartKind::Body;
                part.kindDeclared = true;
                kindKnown = true;
            }
            if (gs.contains("record") && gs["record"].is_number_unsigned() &&
                gs["record"].get<std::uint64_t>() <= 0xFFFFFFFEu)
                part.record = gs["record"].get<RecordId>();
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
        // The material's baseColorFactor (linear) colours a part whose record has no colour.
        if (auto mc = materialColour(g, gm)) {
            AttributeRecord* r = part.record != kNoRecord ? model.attributes.find(part.record) : nullptr;
            if (!r) {
                AttributeRecord rec;
                rec.name = part.name;
                rec.nameSource = "file (glTF node or mesh name)";
                part.record = model.attributes.add(std::move(rec));
                r = model.attributes.find(part.record);
            }
            if (r->colourSource.empty()) {
                r->colour = mc->first;
                r->colourSource = "file (glTF material '" + mc->second + "' baseColorFactor)";
            }
        }
        allKinds = allKinds && kindKnown;
        (part.kind == PartKind::Body ? model.bodies : model.surfaces).push_back(std::move(part));
    }
    if (model.bodies.empty() && model.surfaces.empty())
        return makeError(ErrorCode::ParseError, source + ": no triangle meshes in the default scene");
    finishLoadedModel(model, /*classifyByClosure=*/!(ours && allKinds));
    return model;
}

}  // namespace
}  // namespace gltf

Result<Model> parseGltf(const std::uint8_t* data, std::size_t size, const std::string& source,
                        const std::string& baseDir) {
    // tinygltf, libdraco and the containers may throw (bad_alloc, length_error) on inputs
    // that pass every check above; a bad file is an error value, never an escaped exception.
    try {
        return gltf::parseGltfChecked(data, size, source, baseDir);
    } catch (const std::bad_alloc&) {
        return makeError(ErrorCode::OutOfRange, source + ": out of memory while loading");
    } catch (const std::exception& e) {
        return makeError(ErrorCode::ParseError, source + ": " + e.what());
    }
}

}  // namespace geoslice
