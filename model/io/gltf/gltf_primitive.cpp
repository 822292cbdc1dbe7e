// glTF / GLB reading: one mesh primitive -> triangles of a Mesh. Bounds-checked accessor
// views, KHR_draco_mesh_compression decoded through libdraco with its own checks, list /
// strip / fan modes, geoslice's _POSITION_LO residuals, and the expansion budget that keeps
// a small file from growing into an unbounded model.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>
#include <tiny_gltf.h>

#include "model/io/gltf/gltf_read.hpp"

namespace geoslice::gltf {
namespace {

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
        return makeError(ErrorCode::ParseError, where + ": " + std::string(kGltfDracoExtension) + ": " + what);
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

}  // namespace

// Appends one primitive's triangles to `mesh`: positions through `toWorld` (node to glTF
// scene frame, in double) and then to world axes. Under a mirroring transform (negative
// determinant) each triangle's winding is reversed, so outward normals stay outward.
// `budget` is what is left of the file's expansion allowance (kExpansionFactor), in bytes.
Status appendPrimitive(const tinygltf::Model& g, const tinygltf::Primitive& prim, const glm::dmat4& toWorld, Mesh& mesh,
                       const std::string& where, std::uint64_t& budget) {
    if (prim.mode < 0 || prim.mode > kTriangleFan)
        return makeError(ErrorCode::ParseError,
                         where + ": primitive mode " + std::to_string(prim.mode) + " is not a glTF mode");
    if (prim.mode < kGltfTriangles) return {};  // points and lines carry no volume or sheet
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
        if (mode == kGltfTriangles) {
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
        return pushCorners(kGltfTriangles, std::size_t(dm.num_faces()) * 3, [&](std::size_t i) -> std::uint64_t {
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

}  // namespace geoslice::gltf
