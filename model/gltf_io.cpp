// glTF 2.0 / GLB reading (tinygltf for the JSON and buffers; KHR_draco_mesh_compression decoded
// here through libdraco, with bounds checks) and writing (own GLB writer; Draco through libdraco).
#include "model/gltf_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <tiny_gltf.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "model/loaders.hpp"
#include "model/version.hpp"

namespace geoslice {
namespace {

constexpr std::uint32_t kChunkJson = kGlbChunkJson;
constexpr std::uint32_t kChunkBin = kGlbChunkBin;
constexpr int kTriangles = kGltfTriangles;
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
constexpr const char* kDracoExtension = "KHR_draco_mesh_compression";
// preflightJson() renames the Draco extension of every primitive to this key, so that
// tinygltf 2.7 (which indexes bufferViews, accessors and Draco attributes straight from the
// file, unchecked) never decodes it; appendPrimitive() decodes it with bounds checks.
constexpr const char* kDracoDeferred = "GEOSLICE_draco_deferred";

std::uint32_t readU32(const std::uint8_t* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

std::string quoted(const std::string& s) {
    if (s.size() <= kMaxQuoted) return "\"" + s + "\"";
    return "\"" + s.substr(0, kMaxQuoted) + "...\" (" + std::to_string(s.size()) + " characters)";
}

// GLB container checks with byte offsets, before tinygltf sees the bytes. On success the
// JSON chunk is bytes [20, 20 + readU32(data + 12)) and the file ends at readU32(data + 8).
Status checkGlbContainer(const std::uint8_t* data, std::size_t size, const std::string& source) {
    auto fail = [&](std::uint64_t offset, const std::string& what) {
        return makeError(ErrorCode::ParseError, source + ": byte " + std::to_string(offset) + ": " + what);
    };
    if (size < 20) return fail(0, "file too short for a GLB header (" + std::to_string(size) + " bytes)");
    if (readU32(data) != kGlbMagic) return fail(0, "wrong magic, not a GLB file");
    if (readU32(data + 4) != 2) return fail(4, "GLB version " + std::to_string(readU32(data + 4)) + ", expected 2");
    std::uint32_t length = readU32(data + 8);
    if (length > size)
        return fail(8, "header says " + std::to_string(length) + " bytes but the file has " + std::to_string(size) +
                           " (truncated?)");
    std::uint32_t jsonLen = readU32(data + 12);
    if (readU32(data + 16) != kChunkJson) return fail(16, "first chunk is not JSON");
    if (jsonLen == 0) return fail(12, "the JSON chunk is empty");
    if (std::uint64_t(jsonLen) + 20 > length)
        return fail(12, "JSON chunk length " + std::to_string(jsonLen) + " runs past the end of the file");
    std::uint64_t binAt = 20 + std::uint64_t(jsonLen);
    if (binAt < length) {
        // Same rules as tinygltf, which would refuse these without saying where.
        if (binAt + 12 > length)
            return fail(binAt, "a chunk after the JSON chunk needs at least 12 bytes, the file has " +
                                   std::to_string(length - binAt) + " left");
        std::uint32_t binLen = readU32(data + binAt);
        if (binAt + 8 + binLen > length)
            return fail(binAt, "BIN chunk length " + std::to_string(binLen) + " runs past the end of the file");
        if (binLen < 4 || binLen % 4 != 0)
            return fail(binAt, "BIN chunk length " + std::to_string(binLen) + " is not a positive multiple of 4");
        if (readU32(data + binAt + 4) != kChunkBin) return fail(binAt + 4, "second chunk is not BIN");
    }
    return {};
}

// Offset of the first '[' or '{' nested deeper than kMaxJsonDepth, or npos. Exact for valid
// JSON; for invalid JSON the parser reports the error anyway.
std::size_t tooDeepAt(const char* text, std::size_t size) {
    int depth = 0;
    bool inString = false, escaped = false;
    for (std::size_t i = 0; i < size; ++i) {
        const char c = text[i];
        if (inString) {
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth) return i;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return std::string::npos;
}

bool isUnsigned(const nlohmann::json& j) {
    return j.is_number_unsigned() || (j.is_number_integer() && j.get<std::int64_t>() >= 0);
}

// A relative path that stays inside the model's folder: not absolute, no scheme or drive
// ("file:", "C:"), no ".." segment.
bool staysInsideFolder(const std::string& path) {
    if (path.empty() || path[0] == '/' || path[0] == '\\') return false;
    if (path.find(':') != std::string::npos || path.find('\0') != std::string::npos) return false;
    std::size_t segment = 0;
    for (std::size_t i = 0; i <= path.size(); ++i) {
        if (i < path.size() && path[i] != '/' && path[i] != '\\') continue;
        if (path.compare(segment, i - segment, "..") == 0 && i - segment == 2) return false;
        segment = i + 1;
    }
    return true;
}

// The path tinygltf will open for a buffer URI: its dlib::urldecode, rule for rule ('+' is a
// space; "%" and any two characters is a byte, non-hex digits counting as 0).
std::string percentDecoded(const std::string& s) {
    auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return 0;
    };
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '+') {
            out.push_back(' ');
        } else if (s[i] == '%' && s.size() > i + 2) {
            out.push_back(static_cast<char>(hex(s[i + 1]) * 16 + hex(s[i + 2])));
            i += 2;
        } else {
            out.push_back(s[i]);
        }
    }
    return out;
}

// Checks on the glTF JSON that tinygltf 2.7 does not make, before it parses it: nesting
// depth, valid JSON (with a byte offset), external buffers only inside the model's folder,
// image bufferViews inside their buffers. Returns rewritten JSON when some primitive uses
// KHR_draco_mesh_compression (renamed to kDracoDeferred and without "indices"; see
// appendPrimitive), else nothing: load the bytes as they are. `fileOffset` is the byte
// offset of the JSON in the input, for messages.
Result<std::optional<std::string>> preflightJson(const char* text, std::size_t size, std::size_t fileOffset,
                                                 const std::string& source, const std::string& baseDir) {
    auto fail = [&](std::size_t offset, const std::string& what) {
        return makeError(ErrorCode::ParseError, source + ": byte " + std::to_string(fileOffset + offset) + ": " + what);
    };
    auto failJson = [&](const std::string& what) { return makeError(ErrorCode::ParseError, source + ": " + what); };
    if (std::size_t at = tooDeepAt(text, size); at != std::string::npos)
        return fail(at, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(text, text + size);
    } catch (const nlohmann::json::parse_error& e) {
        std::string what = e.what();
        if (auto p = what.find("] "); p != std::string::npos) what.erase(0, p + 2);
        return fail(e.byte > 0 ? e.byte - 1 : 0, "invalid JSON: " + what);
    } catch (const nlohmann::json::exception& e) {
        return failJson(std::string("invalid JSON: ") + e.what());
    }
    if (!doc.is_object()) return fail(0, "the JSON root is not an object, so this is not glTF");

    auto array = [&](const char* key) -> nlohmann::json* {
        auto it = doc.find(key);
        return it != doc.end() && it->is_array() ? &*it : nullptr;
    };
    nlohmann::json* buffers = array("buffers");
    if (buffers) {
        for (std::size_t i = 0; i < buffers->size(); ++i) {
            const nlohmann::json& b = (*buffers)[i];
            if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string()) continue;
            const std::string uri = b["uri"].get<std::string>();
            if (uri.rfind("data:", 0) == 0) continue;  // embedded; tinygltf decodes and size-checks it
            const std::string where = "buffer " + std::to_string(i) + " refers to the external file " + quoted(uri);
            if (!staysInsideFolder(percentDecoded(uri)))
                return failJson(where + ", which lies outside the model's folder");
            if (baseDir.empty()) return failJson(where + ", but this input has no folder to read it from");
        }
    }
    // tinygltf hands an image's bytes to the (ignoring) image loader as &data[byteOffset]
    // after checking only the indices: check the range too.
    if (const nlohmann::json* images = array("images")) {
        const nlohmann::json* views = array("bufferViews");
        for (std::size_t i = 0; i < images->size(); ++i) {
            const nlohmann::json& im = (*images)[i];
            if (!im.is_object() || !im.contains("bufferView") || !im["bufferView"].is_number_integer()) continue;
            const std::string where = "image " + std::to_string(i) + ": ";
            const std::int64_t v = im["bufferView"].get<std::int64_t>();
            if (!views || v < 0 || static_cast<std::uint64_t>(v) >= views->size())
                return failJson(where + "bufferView " + std::to_string(v) + " does not exist");
            const nlohmann::json& bv = (*views)[static_cast<std::size_t>(v)];
            const nlohmann::json* b = nullptr;
            if (bv.is_object() && bv.contains("buffer") && bv["buffer"].is_number_integer() && buffers) {
                const std::int64_t bi = bv["buffer"].get<std::int64_t>();
                if (bi >= 0 && static_cast<std::uint64_t>(bi) < buffers->size())
                    b = &(*buffers)[static_cast<std::size_t>(bi)];
            }
            const std::uint64_t offset = bv.is_object() && bv.contains("byteOffset") && isUnsigned(bv["byteOffset"])
                                             ? bv["byteOffset"].get<std::uint64_t>()
                                             : 0;
            const bool sized = b && b->is_object() && b->contains("byteLength") && isUnsigned((*b)["byteLength"]) &&
                               bv.contains("byteLength") && isUnsigned(bv["byteLength"]);
            if (!sized || offset > (*b)["byteLength"].get<std::uint64_t>() ||
                bv["byteLength"].get<std::uint64_t>() > (*b)["byteLength"].get<std::uint64_t>() - offset)
                return failJson(where + "bufferView " + std::to_string(v) + " does not lie inside a buffer");
        }
    }

    bool deferred = false;
    if (nlohmann::json* meshes = array("meshes")) {
        for (std::size_t m = 0; m < meshes->size(); ++m) {
            nlohmann::json& mesh = (*meshes)[m];
            if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
            for (std::size_t p = 0; p < mesh["primitives"].size(); ++p) {
                nlohmann::json& prim = mesh["primitives"][p];
                if (!prim.is_object()) continue;
                auto exts = prim.find("extensions");
                if (exts == prim.end() || !exts->is_object()) continue;
                auto draco = exts->find(kDracoExtension);
                if (draco == exts->end()) continue;
                if (!draco->is_object())
                    return failJson("mesh " + std::to_string(m) + " primitive " + std::to_string(p) + ": " +
                                    kDracoExtension + " is not an object");
                nlohmann::json ext = std::move(*draco);
                exts->erase(draco);
                (*exts)[kDracoDeferred] = std::move(ext);
                // tinygltf requires the indices accessor to have a bufferView, which a Draco
                // primitive's does not: the decoded faces replace it.
                prim.erase("indices");
                deferred = true;
            }
        }
    }
    if (!deferred) return std::optional<std::string>();
    return std::optional<std::string>(doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
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

// Bounds-checked view of an accessor's elements.
struct AccessorView {
    const std::uint8_t* base = nullptr;
    std::size_t stride = 0, count = 0;
    int componentType = 0, components = 0;
};

Result<AccessorView> viewAccessor(const tinygltf::Model& g, int index, const std::string& where) {
    auto fail = [&](const std::string& what) { return makeError(ErrorCode::ParseError, where + ": " + what); };
    if (index < 0 || static_cast<std::size_t>(index) >= g.accessors.size())
        return fail("accessor " + std::to_string(index) + " does not exist");
    const auto& a = g.accessors[static_cast<std::size_t>(index)];
    if (a.sparse.isSparse) return makeError(ErrorCode::Unsupported, where + ": sparse accessors are not supported");
    if (a.bufferView < 0 || static_cast<std::size_t>(a.bufferView) >= g.bufferViews.size())
        return fail("accessor " + std::to_string(index) + " has no valid bufferView");
    const auto& bv = g.bufferViews[static_cast<std::size_t>(a.bufferView)];
    if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= g.buffers.size())
        return fail("bufferView has no valid buffer");
    const auto& buf = g.buffers[static_cast<std::size_t>(bv.buffer)];
    int comps = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    int csize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
    if (comps <= 0 || csize <= 0) return fail("accessor " + std::to_string(index) + " has an unknown type");
    std::size_t elem = static_cast<std::size_t>(comps) * static_cast<std::size_t>(csize);
    std::size_t stride = bv.byteStride ? bv.byteStride : elem;
    if (stride < elem) return fail("byteStride smaller than the element");
    // Each comparison subtracts only what is known to be smaller: offsets and lengths come
    // straight from the file (up to 2^64 - 1) and a sum could wrap.
    const std::uint64_t size = buf.data.size();
    auto pastEnd = [&] {
        return fail("accessor " + std::to_string(index) + " (" + std::to_string(a.count) +
                    " elements) runs past its buffer of " + std::to_string(size) + " bytes");
    };
    if (bv.byteOffset > size || bv.byteLength > size - bv.byteOffset) return pastEnd();
    if (a.count > 0) {
        if (a.byteOffset > bv.byteLength || elem > bv.byteLength - a.byteOffset) return pastEnd();
        const std::uint64_t room = bv.byteLength - a.byteOffset - elem;  // bytes after the first element
        if (a.count - 1 > room / stride) return pastEnd();
    }
    const std::uint64_t start = std::uint64_t(bv.byteOffset) + (a.count > 0 ? a.byteOffset : 0);
    return AccessorView{buf.data.data() + start, stride, a.count, a.componentType, comps};
}

// A decoded KHR_draco_mesh_compression primitive and its checked POSITION attribute.
struct DracoPrimitive {
    std::unique_ptr<draco::Mesh> mesh;
    const draco::PointAttribute* position = nullptr;
};

Result<DracoPrimitive> decodeDraco(const tinygltf::Model& g, const tinygltf::Primitive& prim,
                                   const std::string& where) {
    auto fail = [&](const std::string& what) {
        return makeError(ErrorCode::ParseError, where + ": " + std::string(kDracoExtension) + ": " + what);
    };
    nlohmann::json exts = parseExtras(prim.extensions_json_string);
    if (!exts.is_object() || !exts.contains(kDracoDeferred) || !exts[kDracoDeferred].is_object())
        return fail("not an object");
    const nlohmann::json& ext = exts[kDracoDeferred];
    if (!ext.contains("bufferView") || !ext["bufferView"].is_number_integer()) return fail("no bufferView");
    const std::int64_t v = ext["bufferView"].get<std::int64_t>();
    if (v < 0 || static_cast<std::uint64_t>(v) >= g.bufferViews.size())
        return fail("bufferView " + std::to_string(v) + " does not exist");
    const auto& view = g.bufferViews[static_cast<std::size_t>(v)];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= g.buffers.size())
        return fail("bufferView " + std::to_string(v) + " has no valid buffer");
    const auto& buf = g.buffers[static_cast<std::size_t>(view.buffer)];
    if (view.byteOffset > buf.data.size() || view.byteLength > buf.data.size() - view.byteOffset)
        return fail("bufferView " + std::to_string(v) + " runs past its buffer of " + std::to_string(buf.data.size()) +
                    " bytes");
    if (!ext.contains("attributes") || !ext["attributes"].is_object() || !ext["attributes"].contains("POSITION") ||
        !isUnsigned(ext["attributes"]["POSITION"]) || ext["attributes"]["POSITION"].get<std::uint64_t>() > 0xFFFFFFFFu)
        return fail("attributes.POSITION is not a Draco attribute id");
    const auto id = ext["attributes"]["POSITION"].get<std::uint32_t>();

    draco::DecoderBuffer in;
    in.Init(reinterpret_cast<const char*>(buf.data.data() + view.byteOffset), view.byteLength);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&in);
    if (!decoded.ok()) return fail("cannot decode: " + decoded.status().error_msg_string());
    DracoPrimitive out;
    out.mesh = std::move(decoded).value();
    if (!out.mesh) return fail("cannot decode: no mesh");
    const draco::PointAttribute* att = out.mesh->GetAttributeByUniqueId(id);
    if (!att) return fail("no Draco attribute with id " + std::to_string(id) + " (POSITION)");
    if (att->num_components() != 3)
        return fail("POSITION has " + std::to_string(att->num_components()) + " components, expected 3");
    const std::int64_t component = draco::DataTypeLength(att->data_type());
    if (component <= 0 || !att->buffer() || att->byte_stride() < 3 * component || att->byte_offset() < 0)
        return fail("POSITION has an unusable data layout");
    const std::uint64_t need = att->size() == 0 ? 0
                                                : std::uint64_t(att->byte_offset()) +
                                                      std::uint64_t(att->byte_stride()) * (att->size() - 1) +
                                                      3 * std::uint64_t(component);
    if (need > att->buffer()->data_size()) return fail("POSITION values run past their storage");
    out.position = att;
    return out;
}

// Appends one primitive's triangles to `mesh`: positions through `toWorld` (node to glTF
// scene frame, in double) and then to world axes. Under a mirroring transform (negative
// determinant) each triangle's winding is reversed, so outward normals stay outward.
// `budget` is what is left of the file's expansion allowance (kExpansionFactor), in bytes.
Status appendPrimitive(const tinygltf::Model& g, const tinygltf::Primitive& prim, const glm::dmat4& toWorld, Mesh& mesh,
                       const std::string& where, std::uint64_t& budget) {
    if (prim.mode < 0 || prim.mode > kTriangleFan)
        return makeError(ErrorCode::ParseError,
                         where + ": primitive mode " + std::to_string(prim.mode) + " is not a glTF mode");
    if (prim.mode < kTriangles) return {};  // points and lines carry no volume or sheet
    const bool draco = prim.extensions.count(kDracoDeferred) != 0;
    auto posIt = prim.attributes.find("POSITION");
    if (posIt == prim.attributes.end() && !draco)
        return makeError(ErrorCode::ParseError, where + ": primitive has no POSITION");

    const std::size_t first = mesh.positions.size();
    const bool mirror = glm::determinant(glm::dmat3(toWorld)) < 0.0;
    auto addVertex = [&](double x, double y, double z) {
        glm::dvec4 p = toWorld * glm::dvec4(x, y, z, 1.0);
        mesh.positions.push_back(gltfToWorld(glm::dvec3(p)));
    };
    std::size_t vertexCount = 0;
    // Checked before anything is reserved: 24 bytes per vertex, at most 3 indices per corner.
    auto spend = [&](std::uint64_t vertices, std::uint64_t corners) -> Status {
        if (vertices > budget / 24 || corners > (budget - 24 * vertices) / 12)
            return makeError(ErrorCode::OutOfRange, where + ": the file expands to more geometry than " +
                                                        std::to_string(kExpansionFactor) +
                                                        " times its size plus 256 MiB (a mesh instanced too often?)");
        budget -= 24 * vertices + 12 * corners;
        return {};
    };
    auto pushTri = [&](std::uint64_t a, std::uint64_t b, std::uint64_t c) -> Status {
        if (a >= vertexCount || b >= vertexCount || c >= vertexCount)
            return makeError(ErrorCode::ParseError, where + ": index " + std::to_string(std::max({a, b, c})) +
                                                        " out of range (" + std::to_string(vertexCount) + " vertices)");
        mesh.indices.push_back(static_cast<std::uint32_t>(first + a));
        mesh.indices.push_back(static_cast<std::uint32_t>(first + (mirror ? c : b)));
        mesh.indices.push_back(static_cast<std::uint32_t>(first + (mirror ? b : c)));
        return {};
    };
    // Triangles from n corners in glTF's list, strip or fan order (glTF 2.0, 3.7.2.1).
    auto pushCorners = [&](int mode, std::size_t n, auto&& corner) -> Status {
        if (mode == kTriangles) {
            mesh.indices.reserve(mesh.indices.size() + n);
            for (std::size_t i = 0; i + 2 < n; i += 3)
                if (auto s = pushTri(corner(i), corner(i + 1), corner(i + 2)); !s) return s;
        } else if (mode == kTriangleStrip) {
            for (std::size_t i = 0; i + 2 < n; ++i) {
                std::uint64_t a = corner(i), b = corner(i + 1 + i % 2), c = corner(i + 2 - i % 2);
                if (a == b || b == c || a == c) continue;  // strips join runs with degenerate triangles
                if (auto s = pushTri(a, b, c); !s) return s;
            }
        } else {
            for (std::size_t i = 1; i + 1 < n; ++i)
                if (auto s = pushTri(corner(i), corner(i + 1), corner(0)); !s) return s;
        }
        return {};
    };

    if (draco) {
        auto d = decodeDraco(g, prim, where);
        if (!d) return d.error();
        const draco::Mesh& dm = *d->mesh;
        const draco::PointAttribute& att = *d->position;
        vertexCount = dm.num_points();
        if (first + vertexCount > 0xFFFFFFF0u)
            return makeError(ErrorCode::OutOfRange, where + ": more than 4 billion vertices");
        // Every point needs a POSITION value; checked here so that the reservation below is
        // bounded by storage libdraco has already allocated.
        if ((att.is_mapping_identity() ? att.size() : att.indices_map_size()) < vertexCount)
            return makeError(ErrorCode::ParseError,
                             where + ": Draco POSITION has fewer values than the mesh has points");
        if (auto s = spend(vertexCount, std::uint64_t(dm.num_faces()) * 3); !s) return s;
        mesh.positions.reserve(first + vertexCount);
        for (draco::PointIndex p(0); p < dm.num_points(); ++p) {
            if (!att.is_mapping_identity() && p.value() >= att.indices_map_size())
                return makeError(ErrorCode::ParseError,
                                 where + ": Draco point " + std::to_string(p.value()) + " has no POSITION");
            const draco::AttributeValueIndex value = att.mapped_index(p);
            double xyz[3];
            if (value.value() >= att.size() || !att.ConvertValue<double>(value, 3, xyz))
                return makeError(ErrorCode::ParseError,
                                 where + ": Draco point " + std::to_string(p.value()) + " has no POSITION");
            addVertex(xyz[0], xyz[1], xyz[2]);
        }
        // Draco stores triangle lists whatever the primitive's mode says.
        return pushCorners(kTriangles, std::size_t(dm.num_faces()) * 3, [&](std::size_t i) -> std::uint64_t {
            return dm.face(draco::FaceIndex(static_cast<std::uint32_t>(i / 3)))[i % 3].value();
        });
    }

    auto pos = viewAccessor(g, posIt->second, where);
    if (!pos) return pos.error();
    if (pos->componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || pos->components != 3)
        return makeError(ErrorCode::Unsupported, where + ": POSITION must be float VEC3");
    vertexCount = pos->count;
    if (first + vertexCount > 0xFFFFFFF0u)
        return makeError(ErrorCode::OutOfRange, where + ": more than 4 billion vertices");
    AccessorView idx;
    if (prim.indices >= 0) {
        auto view = viewAccessor(g, prim.indices, where);
        if (!view) return view.error();
        idx = view.value();
        if (idx.components != 1) return makeError(ErrorCode::ParseError, where + ": indices must be SCALAR");
        if (idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            return makeError(ErrorCode::ParseError, where + ": indices must be unsigned byte, short or int");
    }
    // geoslice's baked packages add what float32 lost where it would merge vertices
    // (bake/package.hpp kPositionResidualAttribute): position = POSITION + _POSITION_LO, in double.
    AccessorView lo;
    if (auto loIt = prim.attributes.find("_POSITION_LO"); loIt != prim.attributes.end()) {
        auto view = viewAccessor(g, loIt->second, where);
        if (!view) return view.error();
        lo = view.value();
        if (lo.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || lo.components != 3 || lo.count != vertexCount)
            return makeError(ErrorCode::ParseError,
                             where + ": _POSITION_LO must be float VEC3 with one value per POSITION");
    }
    if (auto s = spend(vertexCount, prim.indices >= 0 ? idx.count : vertexCount); !s) return s;
    mesh.positions.reserve(first + vertexCount);
    for (std::size_t i = 0; i < pos->count; ++i) {
        float f[3], r[3] = {0.0f, 0.0f, 0.0f};
        std::memcpy(f, pos->base + i * pos->stride, sizeof f);
        if (lo.base) std::memcpy(r, lo.base + i * lo.stride, sizeof r);
        addVertex(double(f[0]) + double(r[0]), double(f[1]) + double(r[1]), double(f[2]) + double(r[2]));
    }
    if (prim.indices < 0) return pushCorners(prim.mode, pos->count, [](std::size_t i) -> std::uint64_t { return i; });
    return pushCorners(prim.mode, idx.count, [&](std::size_t i) -> std::uint64_t {
        const std::uint8_t* p = idx.base + i * idx.stride;
        switch (idx.componentType) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                return *p;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t v;
                std::memcpy(&v, p, 2);
                return v;
            }
            default: {
                std::uint32_t v;
                std::memcpy(&v, p, 4);
                return v;
            }
        }
    });
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
            auto u32 = [&](std::uint32_t v) {
                std::uint8_t b[4];
                std::memcpy(b, &v, 4);
                rewrittenGlb.insert(rewrittenGlb.end(), b, b + 4);
            };
            u32(kGlbMagic);
            u32(2);
            u32(static_cast<std::uint32_t>(total));
            u32(static_cast<std::uint32_t>(text.size()));
            u32(kChunkJson);
            rewrittenGlb.insert(rewrittenGlb.end(), text.begin(), text.end());
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
        allKinds = allKinds && kindKnown;
        (part.kind == PartKind::Body ? model.bodies : model.surfaces).push_back(std::move(part));
    }
    if (model.bodies.empty() && model.surfaces.empty())
        return makeError(ErrorCode::ParseError, source + ": no triangle meshes in the default scene");
    finishLoadedModel(model, /*classifyByClosure=*/!(ours && allKinds));
    return model;
}

}  // namespace

Result<Model> parseGltf(const std::uint8_t* data, std::size_t size, const std::string& source,
                        const std::string& baseDir) {
    // tinygltf, libdraco and the containers may throw (bad_alloc, length_error) on inputs
    // that pass every check above; a bad file is an error value, never an escaped exception.
    try {
        return parseGltfChecked(data, size, source, baseDir);
    } catch (const std::bad_alloc&) {
        return makeError(ErrorCode::OutOfRange, source + ": out of memory while loading");
    } catch (const std::exception& e) {
        return makeError(ErrorCode::ParseError, source + ": " + e.what());
    }
}

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
    while (bin_.size() % 4) bin_.push_back(0);
    const glm::dvec3 o = worldToGltf(model.origin);
    nodes_[0] = {
        {"name", model.name.empty() ? "model" : model.name}, {"translation", {o.x, o.y, o.z}}, {"children", children_}};
    doc_["scene"] = 0;
    doc_["scenes"] = {
        {{"name", model.name}, {"nodes", {0}}, {"extras", {{"geoslice", sceneExtras(model, attributes)}}}}};
    doc_["nodes"] = nodes_;
    doc_["meshes"] = meshes_;
    doc_["accessors"] = accessors_;
    doc_["bufferViews"] = views_;
    doc_["buffers"] = {{{"byteLength", bin_.size()}}};
    return doc_;
}

Result<std::vector<std::uint8_t>> GlbBuilder::pack(const std::string& what) const {
    return packGlb(doc_.dump(), bin_, what);
}

Result<std::vector<std::uint8_t>> encodeGlb(const Model& model, const GlbWriteOptions& options) {
    using json = nlohmann::ordered_json;
    GlbBuilder glb(kGeneratorName);
    if (options.draco) {
        glb.doc()["extensionsUsed"] = {kDracoExtension};
        glb.doc()["extensionsRequired"] = {kDracoExtension};
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
            prim["extensions"][kDracoExtension] = {{"bufferView", view},
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
    auto u32 = [&](std::uint32_t v) {
        std::uint8_t b[4];
        std::memcpy(b, &v, 4);
        out.insert(out.end(), b, b + 4);
    };
    u32(kGlbMagic);
    u32(2);
    u32(static_cast<std::uint32_t>(total));
    u32(static_cast<std::uint32_t>(text.size()));
    u32(kGlbChunkJson);
    out.insert(out.end(), text.begin(), text.end());
    u32(static_cast<std::uint32_t>(bin.size()));
    u32(kGlbChunkBin);
    out.insert(out.end(), bin.begin(), bin.end());
    return out;
}

}  // namespace geoslice
