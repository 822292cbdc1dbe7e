// The baked package: writing (GLB with TEXCOORD_0, zstd raw R32UI texture, attribute JSON,
// manifest with XXH64 checksums) and reading (mmap, every size, offset and index checked).
#include "bake/package.hpp"

#include <fcntl.h>
#include <png.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>

#include "model/gltf_io.hpp"
#include "model/loaders.hpp"
#include "model/validate.hpp"
#include "model/version.hpp"
#include "section/section_index.hpp"

namespace geoslice::bake {
namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

constexpr std::uint32_t kChunkJson = kGlbChunkJson;
constexpr std::uint32_t kChunkBin = kGlbChunkBin;
// zstd stores a 128 KiB block of one repeated byte in 4 bytes: no frame expands more than
// this, so a header that claims more is a lie and nothing is allocated for it.
constexpr std::uint64_t kMaxZstdRatio = 32768;

std::string hex64(std::uint64_t v) {
    char b[17];
    std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(v));
    return b;
}

std::uint32_t readU32(const std::uint8_t* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

Error parseError(const std::string& source, const std::string& file, const std::string& what) {
    return makeError(ErrorCode::ParseError, source + "/" + file + ": " + what);
}

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

// The feature-ID texture of EXT_mesh_features: RGBA8 PNG whose 4 channels are the bytes of a
// little-endian uint32 property-table row (kNullFeature where no geology is).
constexpr std::uint32_t kNullFeature = 0xFFFFFFFFu;

Result<std::vector<std::uint8_t>> encodeFeaturePng(const BakedModel& baked, const std::vector<RecordId>& rows) {
    std::vector<std::uint32_t> texels(baked.texels.size());
    for (std::size_t i = 0; i < texels.size(); ++i) {
        const RecordId id = baked.texels[i];
        auto it = std::lower_bound(rows.begin(), rows.end(), id);
        const std::uint32_t row = id != kNoRecord && it != rows.end() && *it == id
                                      ? static_cast<std::uint32_t>(it - rows.begin())
                                      : kNullFeature;
        const std::uint8_t b[4] = {std::uint8_t(row), std::uint8_t(row >> 8), std::uint8_t(row >> 16),
                                   std::uint8_t(row >> 24)};
        std::memcpy(&texels[i], b, 4);
    }
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = baked.width;
    image.height = baked.height;
    image.format = PNG_FORMAT_RGBA;
    png_alloc_size_t size = 0;
    if (!png_image_write_to_memory(&image, nullptr, &size, 0, texels.data(), 0, nullptr))
        return makeError(ErrorCode::Internal, std::string("libpng: ") + image.message);
    std::vector<std::uint8_t> png(size);
    if (!png_image_write_to_memory(&image, png.data(), &size, 0, texels.data(), 0, nullptr))
        return makeError(ErrorCode::Internal, std::string("libpng: ") + image.message);
    png.resize(size);
    return png;
}

// The model's records plus the bake's field-class records.
AttributeTable mergedAttributes(const Model& model, const BakedModel& baked) {
    AttributeTable table = model.attributes;
    for (const auto& r : baked.fieldRecords) table.put(r);
    return table;
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

Result<std::vector<std::uint8_t>> encodeMesh(const Model& model, const BakedModel& baked, bool features,
                                             bool residuals) {
    const AttributeTable table = mergedAttributes(model, baked);
    if (features && baked.pages != 1)
        return makeError(ErrorCode::Unsupported, "EXT_mesh_features export needs a one-page bake (this one has " +
                                                     std::to_string(baked.pages) + " pages: raise the texture size)");
    GlbBuilder glb("geoslice bake");
    // Property-table rows: every record of the table and every part's record, by id.
    std::vector<RecordId> rows;
    if (features) {
        for (const auto& [id, rec] : table.records()) rows.push_back(id);
        for (const BakedPart& part : baked.parts)
            if (part.record != kNoRecord) rows.push_back(part.record);
        std::sort(rows.begin(), rows.end());
        rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    }
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
        if (features)
            prim["extensions"]["EXT_mesh_features"] = {
                {"featureIds", json::array({{{"featureCount", rows.size()},
                                             {"nullFeatureId", kNullFeature},
                                             {"label", "record"},
                                             {"texture", {{"index", 0}, {"texCoord", 0}, {"channels", {0, 1, 2, 3}}}},
                                             {"propertyTable", 0}}})}};
        glb.addPart(part.name, part.kind, part.record, std::move(prim));
    }
    json metadata;
    std::size_t imageView = 0;
    if (features) {
        auto png = encodeFeaturePng(baked, rows);
        if (!png) return png.error();
        imageView = glb.addView(png->data(), png->size(), 0);
        // EXT_structural_metadata property table: one row per record; strings as UTF-8 values
        // plus UINT32 offsets, numbers as FLOAT64 with -1 for "not given". 8-byte aligned views.
        json schemaProps = {{"id", {{"type", "SCALAR"}, {"componentType", "UINT32"}, {"required", true}}}};
        json tableProps = json::object();
        std::vector<std::uint32_t> ids(rows.begin(), rows.end());
        tableProps["id"] = {{"values", glb.addView(ids.data(), ids.size() * 4, 0, 8)}};
        using Getter = std::string (*)(const AttributeRecord&);
        const std::pair<const char*, Getter> strings[] = {
            {"name", [](const AttributeRecord& r) { return r.name; }},
            {"kind", [](const AttributeRecord& r) { return r.kind; }},
            {"lithology", [](const AttributeRecord& r) { return r.lithology; }},
            {"age", [](const AttributeRecord& r) { return r.age; }},
            {"era", [](const AttributeRecord& r) { return r.era; }},
            {"gradeUnit", [](const AttributeRecord& r) { return r.gradeUnit; }}};
        for (const auto& [key, get] : strings) {
            std::string values;
            std::vector<std::uint32_t> offsets{0};
            for (RecordId id : rows) {
                if (const AttributeRecord* r = table.find(id)) values += get(*r);
                offsets.push_back(static_cast<std::uint32_t>(values.size()));
            }
            schemaProps[key] = {{"type", "STRING"}};
            const std::size_t vv = glb.addView(values.data(), values.size(), 0, 8);
            const std::size_t ov = glb.addView(offsets.data(), offsets.size() * 4, 0, 8);
            tableProps[key] = {{"values", vv}, {"stringOffsets", ov}, {"stringOffsetType", "UINT32"}};
        }
        for (const char* key : {"density", "grade"}) {
            std::vector<double> v;
            for (RecordId id : rows) {
                const AttributeRecord* r = table.find(id);
                const std::optional<double> x =
                    r ? (std::strcmp(key, "density") ? r->grade : r->density) : std::nullopt;
                v.push_back(x ? *x : -1.0);
            }
            schemaProps[key] = {{"type", "SCALAR"}, {"componentType", "FLOAT64"}, {"noData", -1.0}};
            tableProps[key] = {{"values", glb.addView(v.data(), v.size() * 8, 0, 8)}};
        }
        metadata = {{"schema", {{"id", "geoslice"}, {"classes", {{"geology", {{"properties", schemaProps}}}}}}},
                    {"propertyTables",
                     json::array({{{"class", "geology"}, {"count", rows.size()}, {"properties", tableProps}}})}};
    }
    json& doc = glb.finishDocument(model, table);
    if (features) {
        doc["images"] = {{{"bufferView", imageView}, {"mimeType", "image/png"}}};
        // Nearest sampling, clamped: ids must never be filtered.
        doc["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}};
        doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
        doc["extensionsUsed"] = {"EXT_mesh_features", "EXT_structural_metadata"};
        doc["extensions"]["EXT_structural_metadata"] = metadata;
    }
    return glb.pack("baked mesh");
}

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

// mesh.glb of a package: GLB header, JSON and BIN chunks, the scene (name, extras, root
// translation), then each part's accessors. Throws nlohmann::json exceptions for missing or
// mistyped fields (the callers turn them into ParseError).
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
        // Named as model/gltf_io.cpp names a part: the node, else the mesh, else "mesh N".
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

// What validate() found about one part, as the manifest stores it (every MeshReport field).
json reportJson(const MeshReport& r) {
    json edges = json::array();
    for (const auto& e : r.problemEdges) edges.push_back({e.x, e.y, e.z});
    return {{"triangles", r.triangles},
            {"vertices", r.vertices},
            {"boundaryEdges", r.boundaryEdges},
            {"nonManifoldEdges", r.nonManifoldEdges},
            {"splitEdges", r.splitEdges},
            {"splitVertices", r.splitVertices},
            {"inconsistentEdges", r.inconsistentEdges},
            {"degenerateTriangles", r.degenerateTriangles},
            {"duplicateTriangles", r.duplicateTriangles},
            {"nonFiniteVertices", r.nonFiniteVertices},
            {"components", r.components},
            {"closed", r.closed},
            {"consistentlyOriented", r.consistentlyOriented},
            {"signedVolume", r.signedVolume},
            {"flipped", r.flipped},
            {"nestingDepth", r.nestingDepth},
            {"parent", r.parent},
            {"problemEdges", edges}};
}

MeshReport reportFromJson(const nlohmann::json& j) {
    MeshReport r;
    r.triangles = j.at("triangles").get<std::size_t>();
    r.vertices = j.at("vertices").get<std::size_t>();
    r.boundaryEdges = j.at("boundaryEdges").get<std::size_t>();
    r.nonManifoldEdges = j.at("nonManifoldEdges").get<std::size_t>();
    r.splitEdges = j.at("splitEdges").get<std::size_t>();
    r.splitVertices = j.at("splitVertices").get<std::size_t>();
    r.inconsistentEdges = j.at("inconsistentEdges").get<std::size_t>();
    r.degenerateTriangles = j.at("degenerateTriangles").get<std::size_t>();
    r.duplicateTriangles = j.at("duplicateTriangles").get<std::size_t>();
    r.nonFiniteVertices = j.at("nonFiniteVertices").get<std::size_t>();
    r.components = j.at("components").get<std::size_t>();
    r.closed = j.at("closed").get<bool>();
    r.consistentlyOriented = j.at("consistentlyOriented").get<bool>();
    r.signedVolume = j.at("signedVolume").get<double>();
    r.flipped = j.at("flipped").get<bool>();
    r.nestingDepth = j.at("nestingDepth").get<int>();
    r.parent = j.at("parent").get<int>();
    for (const auto& e : j.at("problemEdges"))
        r.problemEdges.emplace_back(e.at(0).get<double>(), e.at(1).get<double>(), e.at(2).get<double>());
    return r;
}

const char* severityName(ValidationIssue::Severity s) {
    return s == ValidationIssue::Severity::Error     ? "error"
           : s == ValidationIssue::Severity::Warning ? "warning"
                                                     : "note";
}

// The manifest's "validation": the reports and findings of validate() on the package's own
// mesh, and whether the stored mesh with vertices.map replayed is exactly the validated model
// (`trusted`: only then may a loader use them instead of validating again).
json validationJson(const Model& validated, bool trusted) {
    json bodies = json::array(), surfaces = json::array(), issues = json::array();
    for (const Part& p : validated.bodies) bodies.push_back(reportJson(p.report));
    for (const Part& p : validated.surfaces) surfaces.push_back(reportJson(p.report));
    for (const auto& i : validated.validation.issues)
        issues.push_back({{"severity", severityName(i.severity)}, {"part", i.part}, {"message", i.message}});
    return {{"trusted", trusted}, {"bodies", bodies}, {"surfaces", surfaces}, {"issues", issues}};
}

Status applyValidation(Model& model, const nlohmann::json& v, const std::string& source) {
    const auto& bodies = v.at("bodies");
    const auto& surfaces = v.at("surfaces");
    if (bodies.size() != model.bodies.size() || surfaces.size() != model.surfaces.size())
        return parseError(source, kManifestFile,
                          "validation lists " + std::to_string(bodies.size()) + " bodies and " +
                              std::to_string(surfaces.size()) + " surfaces, the mesh has " +
                              std::to_string(model.bodies.size()) + " and " + std::to_string(model.surfaces.size()));
    for (std::size_t i = 0; i < bodies.size(); ++i) model.bodies[i].report = reportFromJson(bodies.at(i));
    for (std::size_t i = 0; i < surfaces.size(); ++i) model.surfaces[i].report = reportFromJson(surfaces.at(i));
    for (const Part& p : model.bodies)
        if (p.report.parent < -1 || p.report.parent >= static_cast<int>(model.bodies.size()) ||
            p.report.nestingDepth < 0)
            return parseError(source, kManifestFile, "validation of \"" + p.name + "\": parent or depth out of range");
    model.validation.issues.clear();
    for (const auto& i : v.at("issues")) {
        const std::string sev = i.at("severity").get<std::string>();
        ValidationIssue issue;
        issue.severity = sev == "error"     ? ValidationIssue::Severity::Error
                         : sev == "warning" ? ValidationIssue::Severity::Warning
                                            : ValidationIssue::Severity::Note;
        issue.part = i.at("part").get<std::string>();
        issue.message = i.at("message").get<std::string>();
        model.validation.issues.push_back(std::move(issue));
    }
    return {};
}

// The package's model as model/gltf_io.cpp + finishLoadedModel read its mesh.glb, without
// validation: world = glTF-to-world axes of (POSITION + _POSITION_LO) + the root translation,
// in that order of double operations (the loader's node transform is that translation).
Result<Model> unvalidatedModel(const Package& pkg) {
    Model model;
    model.source = pkg.source + "/" + kMeshFile;
    model.name = pkg.sceneName;
    const nlohmann::json& gs = pkg.sceneExtras;
    if (gs.is_object()) {
        if (gs.contains("crs") && gs.at("crs").is_string()) {
            auto crs = Crs::parse(gs.at("crs").get<std::string>());
            if (!crs) return makeError(ErrorCode::ParseError, model.source + ": scene extras: " + crs.error().message);
            model.crs = crs.value();
        }
        if (gs.contains("attributes")) {
            auto table = AttributeTable::fromJson(gs.at("attributes"), model.source + ": scene extras attributes");
            if (!table) return table.error();
            model.attributes = std::move(table.value());
        }
        if (gs.contains("notes") && gs.at("notes").is_object())
            for (const auto& [key, value] : gs.at("notes").items())
                if (value.is_string()) model.notes[key] = value.get<std::string>();
    }
    const glm::dvec3 t = pkg.rootTranslation;
    for (const PackagePart& pp : pkg.parts) {
        if (pp.indexCount == 0) continue;
        Part part;
        part.name = pp.name;
        part.kind = pp.kind;
        part.kindDeclared = true;
        part.record = pp.record;
        part.mesh.positions.reserve(pp.vertexCount);
        for (std::size_t i = 0; i < pp.vertexCount; ++i) {
            const float* f = pp.positions + 3 * i;
            const float* r = pp.residuals ? pp.residuals + 3 * i : nullptr;
            const double gx = (double(f[0]) + (r ? double(r[0]) : 0.0)) + t.x;
            const double gy = (double(f[1]) + (r ? double(r[1]) : 0.0)) + t.y;
            const double gz = (double(f[2]) + (r ? double(r[2]) : 0.0)) + t.z;
            part.mesh.positions.push_back(gltfToWorld(glm::dvec3(gx, gy, gz)));
        }
        part.mesh.indices.assign(pp.indices, pp.indices + pp.indexCount);
        (part.kind == PartKind::Body ? model.bodies : model.surfaces).push_back(std::move(part));
    }
    if (model.bodies.empty() && model.surfaces.empty())
        return makeError(ErrorCode::ParseError, model.source + ": no triangle meshes in the default scene");
    finishLoadedModel(model, /*classifyByClosure=*/false, /*validateModel=*/false);
    if (model.name.empty()) model.name = fs::path(kMeshFile).stem().string();
    return model;
}

// vertices.map: how validate() turns each stored part into the model's part (bake splits
// vertices along chart seams, which validation welds again; pinch-outs stay split). Per part
// (bodies then surfaces, as the model lists them): uint32 stored vertex count S and served
// vertex count V (S = 0: the part is served as stored), then S uint32 served ids (served
// index = fwd[stored index]; 0xFFFFFFFF for a vertex no triangle uses) and V uint32 stored ids
// (served vertex v = stored vertex src[v]). Header: "GSVMAP01", uint32 part count, uint32 0.
constexpr char kVmapMagic[8] = {'G', 'S', 'V', 'M', 'A', 'P', '0', '1'};
constexpr std::uint32_t kUnmapped = 0xFFFFFFFFu;

std::vector<Part*> partsOf(Model& m) {
    std::vector<Part*> out;
    for (auto* list : {&m.bodies, &m.surfaces})
        for (Part& p : *list) out.push_back(&p);
    return out;
}

// The map from `stored` to `validated`, or nothing when validate() did more than weld and
// split vertices (e.g. flipped triangles), which no vertex map can replay.
std::optional<std::vector<std::uint8_t>> vertexMap(const Model& stored, const Model& validated) {
    std::vector<std::uint32_t> words;
    std::vector<const Part*> a, b;
    for (auto* list : {&stored.bodies, &stored.surfaces})
        for (const Part& p : *list) a.push_back(&p);
    for (auto* list : {&validated.bodies, &validated.surfaces})
        for (const Part& p : *list) b.push_back(&p);
    if (a.size() != b.size()) return std::nullopt;
    words.push_back(static_cast<std::uint32_t>(a.size()));
    words.push_back(0);
    for (std::size_t k = 0; k < a.size(); ++k) {
        const Mesh& s = a[k]->mesh;
        const Mesh& v = b[k]->mesh;
        if (s.indices == v.indices && s.positions == v.positions) {
            words.push_back(0);
            words.push_back(0);
            continue;
        }
        if (s.indices.size() != v.indices.size() || s.positions.size() >= kUnmapped) return std::nullopt;
        std::vector<std::uint32_t> fwd(s.positions.size(), kUnmapped), src(v.positions.size(), kUnmapped);
        for (std::size_t c = 0; c < s.indices.size(); ++c) {
            const std::uint32_t from = s.indices[c], to = v.indices[c];
            if (fwd[from] != kUnmapped && fwd[from] != to) return std::nullopt;
            fwd[from] = to;
            if (src[to] == kUnmapped) src[to] = from;
        }
        for (std::uint32_t x : src)
            if (x == kUnmapped) return std::nullopt;
        words.push_back(static_cast<std::uint32_t>(fwd.size()));
        words.push_back(static_cast<std::uint32_t>(src.size()));
        words.insert(words.end(), fwd.begin(), fwd.end());
        words.insert(words.end(), src.begin(), src.end());
    }
    std::vector<std::uint8_t> bytes(8 + words.size() * 4);
    std::memcpy(bytes.data(), kVmapMagic, 8);
    std::memcpy(bytes.data() + 8, words.data(), words.size() * 4);
    return bytes;
}

// Replays a vertex map on the stored model (every index and size checked first).
Status applyVertexMap(Model& model, std::span<const std::uint8_t> bytes, const std::string& source) {
    auto bad = [&](const std::string& what) { return parseError(source, kVertexMapFile, what); };
    if (bytes.size() < 16 || bytes.size() % 4 || std::memcmp(bytes.data(), kVmapMagic, 8) != 0)
        return bad("not a vertex map (truncated or corrupt)");
    const auto* w = reinterpret_cast<const std::uint32_t*>(bytes.data() + 8);
    const std::size_t n = (bytes.size() - 8) / 4;
    std::vector<Part*> parts = partsOf(model);
    if (w[0] != parts.size())
        return bad("lists " + std::to_string(w[0]) + " parts, the mesh has " + std::to_string(parts.size()));
    std::size_t at = 2;
    for (Part* p : parts) {
        if (n - at < 2) return bad("truncated");
        const std::size_t storedCount = w[at], servedCount = w[at + 1];
        at += 2;
        if (storedCount == 0) continue;
        if (storedCount != p->mesh.positions.size()) return bad("\"" + p->name + "\": vertex count differs");
        if (n - at < storedCount + servedCount) return bad("truncated");
        const std::uint32_t* fwd = w + at;
        const std::uint32_t* src = fwd + storedCount;
        at += storedCount + servedCount;
        std::vector<glm::dvec3> positions;
        positions.reserve(servedCount);
        for (std::size_t v = 0; v < servedCount; ++v) {
            if (src[v] >= storedCount) return bad("\"" + p->name + "\": vertex out of range");
            positions.push_back(p->mesh.positions[src[v]]);
        }
        for (std::uint32_t& i : p->mesh.indices) {
            if (fwd[i] >= servedCount) return bad("\"" + p->name + "\": vertex out of range");
            i = fwd[i];
        }
        p->mesh.positions = std::move(positions);
    }
    if (at != n) return bad("longer than its parts");
    return {};
}

bool sameMeshes(const Model& a, const Model& b) {
    auto same = [](const std::vector<Part>& x, const std::vector<Part>& y) {
        if (x.size() != y.size()) return false;
        for (std::size_t i = 0; i < x.size(); ++i)
            if (x[i].mesh.indices != y[i].mesh.indices || x[i].mesh.positions != y[i].mesh.positions) return false;
        return true;
    };
    return same(a.bodies, b.bodies) && same(a.surfaces, b.surfaces);
}

}  // namespace

std::uint64_t xxh64(const void* data, std::size_t size, std::uint64_t seed) { return XXH64(data, size, seed); }

std::size_t Package::residentBytes() const {
    std::size_t n = texels.size() * 4;
    for (const auto& p : parts) n += p.vertexCount * 20 + p.indexCount * 4;
    return n;
}

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
    json validation;
    std::vector<std::uint8_t> sectionBvh, vertexMapBytes;
    {
        Package probe;
        probe.source = dir;
        try {
            if (auto s = parseMesh(std::span<const std::uint8_t>(mesh->data(), mesh->size()), dir, probe); !s)
                return s.error();
        } catch (const nlohmann::json::exception& e) {
            return makeError(ErrorCode::Internal, "baked mesh does not parse back: " + std::string(e.what()));
        }
        auto stored = unvalidatedModel(probe);
        if (!stored) return stored.error();
        Model checked = stored.value();
        validate(checked);
        // The model a loader gets with the vertex map replayed must be the validated one,
        // exactly; else the loader validates (trusted = false).
        bool trusted = false;
        if (auto map = vertexMap(stored.value(), checked)) {
            Model replay = stored.value();
            if (applyVertexMap(replay, *map, dir) && sameMeshes(replay, checked)) {
                trusted = true;
                vertexMapBytes = std::move(*map);
            }
        }
        if (!trusted) vertexMapBytes = vertexMap(stored.value(), stored.value()).value();  // identity
        validation = validationJson(checked, trusted);
        // The BVH over the model packageModel() will return (the stored one when validation
        // leaves it unchanged, else the validated one, which the loader makes again).
        auto index = buildSectionIndex(checked);
        if (!index) return index.error();
        sectionBvh = saveBvh(index.value()->bvh);
    }

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
    const std::string attributes = table.toJson().dump(1);

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
    manifest["checksum"] = hex64(xxh64(manifest.dump().data(), manifest.dump().size()));
    const std::string text = manifest.dump(2) + "\n";
    return writeFile(root / kManifestFile, text.data(), text.size());
}

Status writeFeatureGlb(const Model& model, const BakedModel& baked, const std::string& path) {
    auto glb = encodeMesh(model, baked, true, true);
    if (!glb) return glb.error();
    return writeFile(fs::path(path), glb->data(), glb->size());
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
            const std::string compact = manifest.dump();
            if (hex64(xxh64(compact.data(), compact.size())) != expect)
                return parseError(source, kManifestFile, "checksum differs from the content (corrupt file)");
        }
        if (manifest.value("format", std::string()) != kPackageFormat)
            return parseError(source, kManifestFile, std::string("format is not \"") + kPackageFormat + "\"");
        if (manifest.at("version").get<int>() != kPackageVersion)
            return makeError(ErrorCode::Unsupported, source + "/" + kManifestFile + ": package version " +
                                                         manifest.at("version").dump() + ", this build reads " +
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
        auto m = mapFile((root / names[i]).string());
        if (!m) {
            if (m.error().code == ErrorCode::NotFound)
                return makeError(ErrorCode::NotFound,
                                 dir + ": not a complete baked package (" + m.error().message + ")");
            return m.error();
        }
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
        auto m = mapFile((root / extraNames[i]).string());
        if (!m) {
            if (m.error().code == ErrorCode::NotFound)
                return makeError(ErrorCode::NotFound,
                                 dir + ": not a complete baked package (" + m.error().message + ")");
            return m.error();
        }
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

Result<Model> packageModel(const Package& pkg) {
    auto model = unvalidatedModel(pkg);
    if (!model) return model;
    try {
        const auto& v = pkg.manifest.at("validation");
        if (v.at("trusted").get<bool>() && !pkg.vertexMap.empty()) {
            if (auto s = applyVertexMap(model.value(), pkg.vertexMap, pkg.source); !s) return s.error();
            if (auto s = applyValidation(model.value(), v, pkg.source); !s) return s.error();
        } else {
            validate(model.value());
        }
    } catch (const nlohmann::json::exception& e) {
        return makeError(ErrorCode::ParseError, pkg.source + "/" + kManifestFile +
                                                    ": validation: missing or mistyped field (" + e.what() + ")");
    }
    return model;
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
