// Writing a baked package: the mesh (package_mesh.cpp) and the validation stored with it
// (package_validation.cpp), the zstd-compressed R32UI texture, the attribute table, and last
// the manifest with every file's size and XXH64 checksum and its own. Every file is written
// under a temporary name and renamed, so a reader never sees a half-written package as complete.
#include <xxhash.h>
#include <zstd.h>

#include <algorithm>
#include <fstream>

#include "bake/package_internal.hpp"
#include "model/json_text.hpp"
#include "model/version.hpp"

namespace geoslice::bake {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace package_detail {

Status writeFile(const fs::path& path, const void* data, std::size_t size) {
    const fs::path tmp = path.string() + ".partial";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) return makeError(ErrorCode::IoError, "cannot create " + tmp.string());
        f.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
        if (!f) return makeError(ErrorCode::IoError, "cannot write " + tmp.string() + " (disk full?)");
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) return makeError(ErrorCode::IoError, "cannot rename " + tmp.string() + ": " + ec.message());
    return {};
}

}  // namespace package_detail

using namespace package_detail;

std::uint64_t xxh64(const void* data, std::size_t size, std::uint64_t seed) { return XXH64(data, size, seed); }

Status writePackage(const Model& model, const BakedModel& baked, const std::string& dir, int zstdLevel,
                    bool positionResiduals) {
    if (baked.texels.size() != std::size_t(baked.pages) * baked.width * baked.height)
        return makeError(ErrorCode::InvalidArgument, "baked texture size does not match its pages x height x width");
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return makeError(ErrorCode::IoError, "cannot create directory " + dir + ": " + ec.message());
    auto mesh = encodeMesh(model, baked, false, positionResiduals);
    if (!mesh) return mesh.error();
    // Validate the mesh as a loader will read it (float32 positions + residuals), once, here:
    // a package that passes its checksums is not validated again (packageModel()).
    auto stored = validateStoredMesh(std::span<const std::uint8_t>(mesh->data(), mesh->size()), dir);
    if (!stored) return stored.error();
    json validation = std::move(stored->manifestEntry);
    const std::vector<std::uint8_t>& sectionBvh = stored->sectionBvh;
    const std::vector<std::uint8_t>& vertexMapBytes = stored->vertexMap;

    const std::size_t rawBytes = baked.texels.size() * 4;
    std::vector<std::uint8_t> texture(ZSTD_compressBound(rawBytes));
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    if (!cctx) return makeError(ErrorCode::Internal, "zstd: cannot create a compression context");
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, std::clamp(zstdLevel, 1, 19));
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 1);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 1);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_nbWorkers, 2);  // ignored when libzstd lacks threads
    const std::size_t packed = ZSTD_compress2(cctx, texture.data(), texture.size(), baked.texels.data(), rawBytes);
    ZSTD_freeCCtx(cctx);
    if (ZSTD_isError(packed)) return makeError(ErrorCode::Internal, std::string("zstd: ") + ZSTD_getErrorName(packed));
    texture.resize(packed);
    const AttributeTable table = mergedAttributes(model, baked);
    const std::string attributes = jsonText(table.toJson(), 1);

    const fs::path root(dir);
    if (auto s = writeFile(root / kMeshFile, mesh->data(), mesh->size()); !s) return s;
    if (auto s = writeFile(root / kTextureFile, texture.data(), texture.size()); !s) return s;
    if (auto s = writeFile(root / kAttributesFile, attributes.data(), attributes.size()); !s) return s;
    if (auto s = writeFile(root / kSectionBvhFile, sectionBvh.data(), sectionBvh.size()); !s) return s;
    if (auto s = writeFile(root / kVertexMapFile, vertexMapBytes.data(), vertexMapBytes.size()); !s) return s;

    std::size_t vertices = 0, triangles = 0;
    for (const auto& p : baked.parts) {
        vertices += p.positions.size();
        triangles += p.indices.size() / 3;
    }
    const BakeStats& st = baked.stats;
    json manifest;
    manifest["format"] = kPackageFormat;
    manifest["version"] = kPackageVersion;
    manifest["generator"] = kGeneratorName;
    manifest["model"] = {{"name", model.name},
                         {"source", model.source},
                         {"crs", model.crs.id()},
                         {"origin", {model.origin.x, model.origin.y, model.origin.z}}};
    manifest["texture"] = {{"file", kTextureFile},
                           {"format", "R32UI"},
                           {"encoding", "zstd"},
                           {"layout", "pages x rows x columns, little-endian uint32, row 0 is v = 0; u holds page + u"},
                           {"width", baked.width},
                           {"height", baked.height},
                           {"pages", baked.pages},
                           {"texelsPerMetre", baked.density},
                           {"sampling", "nearest"}};
    manifest["mesh"] = {
        {"file", kMeshFile}, {"parts", baked.parts.size()}, {"vertices", vertices}, {"triangles", triangles}};
    manifest["attributes"] = {{"file", kAttributesFile}, {"records", table.size()}};
    manifest["validation"] = std::move(validation);
    manifest["bake"] = {{"charts", st.charts},
                        {"splitCharts", st.splitCharts},
                        {"texelUtilisation", st.texelUtilisation},
                        {"angleDistortion", {{"mean", st.distortion.meanAngle}, {"max", st.distortion.maxAngle}}},
                        {"areaDistortion", {{"mean", st.distortion.meanArea}, {"max", st.distortion.maxArea}}}};
    manifest["files"] = {
        {kMeshFile, {{"bytes", mesh->size()}, {"xxh64", hex64(xxh64(mesh->data(), mesh->size()))}}},
        {kTextureFile, {{"bytes", texture.size()}, {"xxh64", hex64(xxh64(texture.data(), texture.size()))}}},
        {kAttributesFile,
         {{"bytes", attributes.size()}, {"xxh64", hex64(xxh64(attributes.data(), attributes.size()))}}},
        {kSectionBvhFile,
         {{"bytes", sectionBvh.size()}, {"xxh64", hex64(xxh64(sectionBvh.data(), sectionBvh.size()))}}},
        {kVertexMapFile,
         {{"bytes", vertexMapBytes.size()}, {"xxh64", hex64(xxh64(vertexMapBytes.data(), vertexMapBytes.size()))}}}};
    // The manifest's own checksum: XXH64 of its compact dump without this field.
    const std::string compactManifest = jsonText(manifest);
    manifest["checksum"] = hex64(xxh64(compactManifest.data(), compactManifest.size()));
    const std::string text = jsonText(manifest, 2) + "\n";
    return writeFile(root / kManifestFile, text.data(), text.size());
}

}  // namespace geoslice::bake
