// Reading a baked package: the files memory-mapped (mesh.glb, section.bvh and vertices.map
// are not copied), the manifest's own checksum, format and version, every file's size and
// XXH64 against the manifest, the texture's layout and its zstd frame, the attribute table,
// then the mesh (package_mesh.cpp). Errors name the file and what is wrong.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>

#include "bake/package_internal.hpp"
#include "model/json_text.hpp"
#include "model/validate.hpp"

namespace geoslice::bake {
namespace {

using namespace package_detail;
using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

// zstd stores a 128 KiB block of one repeated byte in 4 bytes: no frame expands more than
// this, so a header that claims more is a lie and nothing is allocated for it.
constexpr std::uint64_t kMaxZstdRatio = 32768;

// A read-only file mapping (or nothing, for an empty file).
struct Mapping {
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;
    Mapping() = default;
    Mapping(const Mapping&) = delete;
    Mapping& operator=(const Mapping&) = delete;
    ~Mapping() {
        if (data) munmap(const_cast<std::uint8_t*>(data), size);
    }
};

Result<std::shared_ptr<Mapping>> mapFile(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return makeError(errno == ENOENT ? ErrorCode::NotFound : ErrorCode::IoError,
                         path + ": cannot open (" + std::strerror(errno) + ")");
    struct stat st {};
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        return makeError(ErrorCode::IoError, path + ": not a regular file");
    }
    auto m = std::make_shared<Mapping>();
    m->size = static_cast<std::size_t>(st.st_size);
    if (m->size) {
        void* p = mmap(nullptr, m->size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (p == MAP_FAILED) {
            ::close(fd);
            return makeError(ErrorCode::IoError, path + ": cannot map (" + std::strerror(errno) + ")");
        }
        m->data = static_cast<const std::uint8_t*>(p);
    }
    ::close(fd);
    return m;
}

// File `file` of the package at `root`: NotFound names the package as incomplete.
Result<std::shared_ptr<Mapping>> mapPackageFile(const fs::path& root, const char* file) {
    auto m = mapFile((root / file).string());
    if (!m && m.error().code == ErrorCode::NotFound)
        return makeError(ErrorCode::NotFound,
                         root.string() + ": not a complete baked package (" + m.error().message + ")");
    return m;
}

template <class Json>
Status checkFile(const Json& manifest, const char* file, std::span<const std::uint8_t> bytes,
                 const PackageReadOptions& options, const std::string& source) {
    const auto& entry = manifest.at("files").at(file);
    const std::uint64_t expect = entry.at("bytes").template get<std::uint64_t>();
    if (expect != bytes.size())
        return parseError(source, file,
                          "size " + std::to_string(bytes.size()) + " bytes, the manifest says " +
                              std::to_string(expect) + (bytes.size() < expect ? " (truncated)" : ""));
    if (options.verifyChecksums) {
        const std::string sum = hex64(xxh64(bytes.data(), bytes.size()));
        if (sum != entry.at("xxh64").template get<std::string>())
            return parseError(source, file, "XXH64 checksum " + sum + " differs from the manifest's (corrupt file)");
    }
    return {};
}

}  // namespace

std::size_t Package::residentBytes() const {
    std::size_t n = texels.size() * 4;
    for (const auto& p : parts) n += p.vertexCount * 20 + p.indexCount * 4;
    return n;
}

Result<Package> parsePackage(std::string_view manifestText, std::span<const std::uint8_t> mesh,
                             std::span<const std::uint8_t> texture, std::string_view attributesText,
                             const PackageReadOptions& options, const std::string& source) {
    Package pkg;
    pkg.source = source;
    // The arrays are handed out as float/uint32 pointers: a mesh buffer that is not 4-byte
    // aligned (possible in memory, never for a mapping) is copied into one that is.
    if (reinterpret_cast<std::uintptr_t>(mesh.data()) % 4 != 0) {
        auto copy = std::make_shared<std::vector<std::uint32_t>>((mesh.size() + 3) / 4);
        if (!mesh.empty()) std::memcpy(copy->data(), mesh.data(), mesh.size());
        mesh = std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(copy->data()), mesh.size());
        pkg.storage = copy;
    }
    try {
        // 1. Manifest: format, version, texture layout, file sizes and checksums.
        json manifest = json::parse(manifestText.begin(), manifestText.end(), nullptr, false);
        if (manifest.is_discarded() || !manifest.is_object())
            return parseError(source, kManifestFile, "not a JSON object (corrupt or truncated)");
        if (options.verifyChecksums) {
            if (!manifest.contains("checksum") || !manifest["checksum"].is_string())
                return parseError(source, kManifestFile, "no checksum (corrupt or not a geoslice package)");
            const std::string expect = manifest["checksum"].get<std::string>();
            manifest.erase("checksum");
            const std::string compact = jsonText(manifest);
            if (hex64(xxh64(compact.data(), compact.size())) != expect)
                return parseError(source, kManifestFile, "checksum differs from the content (corrupt file)");
        }
        if (manifest.value("format", std::string()) != kPackageFormat)
            return parseError(source, kManifestFile, std::string("format is not \"") + kPackageFormat + "\"");
        if (manifest.at("version").get<int>() != kPackageVersion)
            return makeError(ErrorCode::Unsupported, source + "/" + kManifestFile + ": package version " +
                                                         jsonText(manifest.at("version")) + ", this build reads " +
                                                         std::to_string(kPackageVersion) + " (bake the model again)");
        for (const char* f : {kMeshFile, kTextureFile, kAttributesFile})
            if (!manifest.at("files").contains(f))
                return parseError(source, kManifestFile, std::string("no entry for ") + f);
        if (auto s = checkFile(manifest, kMeshFile, mesh, options, source); !s) return s.error();
        if (auto s = checkFile(manifest, kTextureFile, texture, options, source); !s) return s.error();
        const std::span<const std::uint8_t> attrBytes(reinterpret_cast<const std::uint8_t*>(attributesText.data()),
                                                      attributesText.size());
        if (auto s = checkFile(manifest, kAttributesFile, attrBytes, options, source); !s) return s.error();
        const auto& tex = manifest.at("texture");
        pkg.width = tex.at("width").get<std::uint32_t>();
        pkg.height = tex.at("height").get<std::uint32_t>();
        pkg.pages = tex.at("pages").get<std::uint32_t>();
        if (tex.at("format").get<std::string>() != "R32UI" || tex.at("encoding").get<std::string>() != "zstd")
            return parseError(source, kManifestFile, "texture is not zstd-encoded R32UI");
        if (pkg.width == 0 || pkg.height == 0 || pkg.pages == 0 || pkg.width > 16384 || pkg.height > 16384 ||
            pkg.pages > 4096)
            return parseError(source, kManifestFile,
                              "texture size " + std::to_string(pkg.width) + "x" + std::to_string(pkg.height) + "x" +
                                  std::to_string(pkg.pages) + " pages is outside 1..16384 x 1..16384 x 1..4096");
        const auto& model = manifest.at("model");
        pkg.name = model.at("name").get<std::string>();
        pkg.crs = model.at("crs").get<std::string>();
        const auto& o = model.at("origin");
        pkg.origin = {o.at(0).get<double>(), o.at(1).get<double>(), o.at(2).get<double>()};
        pkg.manifest = manifest;

        // 2. Texture: the frame's declared size must be the manifest's, and plausible.
        const std::uint64_t rawBytes = std::uint64_t(pkg.width) * pkg.height * pkg.pages * 4;
        const unsigned long long declared = ZSTD_getFrameContentSize(texture.data(), texture.size());
        if (declared == ZSTD_CONTENTSIZE_ERROR || declared == ZSTD_CONTENTSIZE_UNKNOWN)
            return parseError(source, kTextureFile, "not a zstd frame with a content size (corrupt or truncated)");
        if (declared != rawBytes)
            return parseError(source, kTextureFile,
                              "holds " + std::to_string(declared) + " bytes, the manifest's " +
                                  "texture layout needs " + std::to_string(rawBytes));
        if (rawBytes > (std::uint64_t(texture.size()) + 1024) * kMaxZstdRatio)
            return parseError(source, kTextureFile, "declares more data than a zstd frame of this size can hold");
        pkg.texels.resize(rawBytes / 4);
        const std::size_t got = ZSTD_decompress(pkg.texels.data(), rawBytes, texture.data(), texture.size());
        if (ZSTD_isError(got) || got != rawBytes)
            return parseError(source, kTextureFile,
                              std::string("zstd: ") + (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "short frame"));

        // 3. Attributes.
        auto attrJson = nlohmann::ordered_json::parse(attributesText.begin(), attributesText.end(), nullptr, false);
        if (attrJson.is_discarded()) return parseError(source, kAttributesFile, "not JSON (corrupt or truncated)");
        auto table = AttributeTable::fromJson(attrJson, source + "/" + kAttributesFile);
        if (!table) return table.error();
        pkg.attributes = std::move(table).value();

        // 4. Mesh.
        if (auto st = parseMesh(mesh, source, pkg); !st) return st.error();
    } catch (const nlohmann::json::exception& e) {
        return makeError(ErrorCode::ParseError, source + ": missing or mistyped field (" + e.what() + ")");
    }
    return pkg;
}

Result<Package> loadPackage(const std::string& dir, const PackageReadOptions& options) {
    const fs::path root(dir);
    std::shared_ptr<Mapping> files[4];
    const char* names[4] = {kManifestFile, kMeshFile, kTextureFile, kAttributesFile};
    for (int i = 0; i < 4; ++i) {
        auto m = mapPackageFile(root, names[i]);
        if (!m) return m.error();
        files[i] = std::move(m).value();
    }
    auto text = [](const Mapping& m) { return std::string_view(reinterpret_cast<const char*>(m.data), m.size); };
    auto bytes = [](const Mapping& m) { return std::span<const std::uint8_t>(m.data, m.size); };
    auto pkg = parsePackage(text(*files[0]), bytes(*files[1]), bytes(*files[2]), text(*files[3]), options, dir);
    if (!pkg) return pkg.error();
    // The files only a server needs: mapped and checked here (parsePackage reads the four).
    std::shared_ptr<Mapping> extra[2];
    const char* extraNames[2] = {kSectionBvhFile, kVertexMapFile};
    for (int i = 0; i < 2; ++i) {
        auto m = mapPackageFile(root, extraNames[i]);
        if (!m) return m.error();
        extra[i] = std::move(m).value();
        try {
            if (!pkg->manifest.at("files").contains(extraNames[i]))
                return parseError(dir, kManifestFile, std::string("no entry for ") + extraNames[i]);
            if (auto s = checkFile(pkg->manifest, extraNames[i], bytes(*extra[i]), options, dir); !s) return s.error();
        } catch (const nlohmann::json::exception& e) {
            return makeError(ErrorCode::ParseError, dir + ": missing or mistyped field (" + e.what() + ")");
        }
    }
    pkg->sectionBvh = bytes(*extra[0]);
    pkg->vertexMap = bytes(*extra[1]);
    struct Mappings {
        std::shared_ptr<Mapping> mesh, bvh, vmap;
    };
    pkg->storage = std::make_shared<Mappings>(Mappings{files[1], extra[0], extra[1]});
    return pkg;
}

Status verifyPackage(const std::string& dir) {
    auto pkg = loadPackage(dir);
    if (!pkg) return makeError(pkg.error().code, "the package would be refused: " + pkg.error().message);
    auto model = packageModel(pkg.value());
    if (!model) return makeError(model.error().code, "the package would be refused: " + model.error().message);
    for (const auto& issue : model->validation.issues)
        if (issue.severity == ValidationIssue::Severity::Error)
            return makeError(ErrorCode::InvalidArgument,
                             "the package would be refused: part \"" + issue.part + "\": " + issue.message);
    return {};
}

}  // namespace geoslice::bake
