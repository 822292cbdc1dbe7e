// Writing a baked package: the mesh (package_mesh.cpp) and the validation stored with it
// (package_validation.cpp), the zstd-compressed R32UI texture, the attribute table, and last
// the manifest with every file's size and XXH64 checksum and its own. Every file is written
// under a temporary name and renamed, so a reader never sees a half-written package as complete.
#include <fcntl.h>
#include <unistd.h>
#include <xxhash.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "bake/package_internal.hpp"
#include "model/json_text.hpp"
#include "model/version.hpp"

namespace geoslice::bake {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace package_detail {

Status writeFile(const fs::path& path, const void* data, std::size_t size) {
    return writeFileAtomically(path.string(), data, size);
}

}  // namespace package_detail

using namespace package_detail;

Status writeFileAtomically(const std::string& path, const void* data, std::size_t size) {
    const std::string tmp = path + ".partial";
    // Every failure removes the partial file: a bake that fails on a full disk (ENOSPC) or
    // past a file size limit (EFBIG; the server ignores SIGXFSZ) leaves nothing behind.
    auto fail = [&](int fd, const std::string& what, int err) {
        if (fd >= 0) ::close(fd);
        ::unlink(tmp.c_str());
        return makeError(ErrorCode::IoError, what + ": " + std::strerror(err));
    };
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        const int e = errno;
        return fail(-1, "cannot create " + tmp, e);
    }
    const char* p = static_cast<const char*>(data);
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::write(fd, p + done, std::min<std::size_t>(size - done, std::size_t(1) << 30));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            const int e = errno;
            return fail(
                fd, "cannot write " + tmp + " (" + std::to_string(done) + " of " + std::to_string(size) + " bytes)", e);
        }
        done += std::size_t(n);
    }
    if (::close(fd) != 0) {
        const int e = errno;
        return fail(-1, "cannot write " + tmp + " (at close)", e);
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        return fail(-1, "cannot rename " + tmp + " to " + path, e);
    }
    return {};
}

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
