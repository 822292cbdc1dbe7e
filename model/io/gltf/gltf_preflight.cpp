// glTF / GLB reading: the checks made before tinygltf sees the bytes. The GLB container
// (magic, version, chunk lengths, with byte offsets), JSON nesting depth and validity,
// external buffers only inside the model's folder, image bufferViews inside their buffers;
// Draco primitives are renamed so that tinygltf leaves them to model/io/gltf/gltf_primitive.cpp.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "model/io/gltf/gltf_read.hpp"
#include "model/json_text.hpp"

namespace geoslice::gltf {
namespace {

std::string quoted(const std::string& s) {
    if (s.size() <= kMaxQuoted) return "\"" + s + "\"";
    return "\"" + s.substr(0, kMaxQuoted) + "...\" (" + std::to_string(s.size()) + " characters)";
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

}  // namespace

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
    if (readU32(data + 16) != kGlbChunkJson) return fail(16, "first chunk is not JSON");
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
        if (readU32(data + binAt + 4) != kGlbChunkBin) return fail(binAt + 4, "second chunk is not BIN");
    }
    return {};
}

bool isUnsigned(const nlohmann::json& j) {
    return j.is_number_unsigned() || (j.is_number_integer() && j.get<std::int64_t>() >= 0);
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
                auto draco = exts->find(kGltfDracoExtension);
                if (draco == exts->end()) continue;
                if (!draco->is_object())
                    return failJson("mesh " + std::to_string(m) + " primitive " + std::to_string(p) + ": " +
                                    kGltfDracoExtension + " is not an object");
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
    return std::optional<std::string>(jsonText(doc));
}

}  // namespace geoslice::gltf
