// The baked package: one directory per model, self-describing, loadable by mmap.
//
//   manifest.json    format name and version, model (name, CRS, origin), texture layout, bake
//                    figures, and for every other file its size in bytes and XXH64 checksum
//   mesh.glb         glTF 2.0 binary: one node + mesh per part, POSITION (float32, local frame
//                    in glTF axes: X east, Y up, Z = -north; the root node's translation is the
//                    origin), TEXCOORD_0 (float32, page + u, v; see bake/bake.hpp), uint32
//                    indices; node extras.geoslice = {kind, record}, scene extras.geoslice as
//                    model/io/gltf/gltf_io.hpp writes them, so geoslice's own loader reads it as a model
//   ids.r32ui.zst    the index texture T_ID: one zstd frame holding pages x height x width
//                    little-endian uint32 record ids, row 0 (v = 0) first
//   attributes.json  the attribute table, {"records": [...]} (model/attributes.hpp)
//   section.bvh      the section engine's BVH over the model as packageModel() reads it
//                    (section/index/bvh.hpp saveBvh: flat arrays, memory-mapped and copied once)
//   vertices.map     per part, how validation turns the stored (chart-split) vertices into
//                    the model's (welded) ones: packageModel() replays it

// The manifest's "validation" holds validate()'s reports and findings for that model.
//
// Why zstd-compressed raw for T_ID: lossless by construction, decodes straight into the
// bytes glTexImage3D(GL_R32UI) takes (no conversion, no 8-bit channel packing), the content
// size sits in the frame header (checked before any allocation), and a texture of large
// constant chart regions compresses many times over and decodes fast; KTX2 would need
// libktx, which Debian 12 does not package, and a 32-bit TIFF goes through libtiff's
// strip machinery for no gain.
//
// Threads: the functions are reentrant; a Package is immutable once loaded and may be read
// from any thread.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "bake/bake.hpp"
#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice::bake {

// 2: the manifest carries the validation of the package's own mesh ("validation"), so a
// package that passes its checksums is not validated again when it is loaded, and the
// package holds the section BVH (section.bvh).
// 3: the mesh is stored in the section BVH's leaf order and the BVH's leaves list their
// triangle ids in ascending order (section/index/leaf_order.hpp), so a version-2 package, which
// would still cut correctly but slower, is baked again.
constexpr int kPackageVersion = 3;
constexpr const char* kPackageFormat = "geoslice-baked-model";
constexpr const char* kManifestFile = "manifest.json";
constexpr const char* kMeshFile = "mesh.glb";
constexpr const char* kTextureFile = "ids.r32ui.zst";
constexpr const char* kAttributesFile = "attributes.json";
// The section engine's BVH over the package's model (section/index/bvh.hpp saveBvh), so that a
// server loads it instead of building it.
constexpr const char* kSectionBvhFile = "section.bvh";
// How validation turns the stored mesh into the served model (bake/package_validation.cpp: chart seams
// welded again), so that packageModel() replays it instead of validating.
constexpr const char* kVertexMapFile = "vertices.map";
// mesh.glb primitive attribute (float VEC3, glTF axes) with position - float(position).
constexpr const char* kPositionResidualAttribute = "_POSITION_LO";

// XXH64 (Yann Collet's xxHash, 64-bit variant), from Debian's libxxhash.
std::uint64_t xxh64(const void* data, std::size_t size, std::uint64_t seed = 0);

// Writes the package into `dir` (created if missing; files written under temporary names and
// renamed, the manifest last, so a reader never sees a half-written package as complete).
// zstdLevel: 1 (fast) .. 19. positionResiduals: for each part whose float32 positions would
// merge vertices that are distinct in double (vertices a fraction of a millimetre apart far
// from the origin), also store what float32 lost (attribute kPositionResidualAttribute), so
// that the model loader restores them; false only to test what happens without.
Status writePackage(const Model& model, const BakedModel& baked, const std::string& dir, int zstdLevel = 3,
                    bool positionResiduals = true);

// Writes `size` bytes to `path` under the name `path`.partial, then renames it. On any failure
// (a full disk: ENOSPC; a file size limit: EFBIG) the partial file is removed and the error
// names the file and the system's reason. Any thread.
Status writeFileAtomically(const std::string& path, const void* data, std::size_t size);

// Loads a written package as the server does (checksums, packageModel() with the validation
// the bake stored) and fails, naming the part and the finding, where the server would refuse it.
Status verifyPackage(const std::string& dir);

// The baked model as one glTF 2.0 binary for CesiumJS and other glTF tools: the package's
// mesh plus EXT_mesh_features (a feature-ID texture: RGBA8 PNG, nearest sampling, channels
// 0-3 = the little-endian bytes of a property-table row, 0xFFFFFFFF = no geology) and
// EXT_structural_metadata (class "geology": id, name, kind, lithology, age, era, gradeUnit,
// density, grade; -1 = not given). Rows are the records in ascending id. One-page bakes only
// (Unsupported otherwise: glTF has no texture arrays).
Status writeFeatureGlb(const Model& model, const BakedModel& baked, const std::string& path);

// One part of a loaded package. The arrays point into the package's storage (the mapped
// mesh.glb): valid while the Package (or a copy of its `storage`) lives.
struct PackagePart {
    std::string name;
    PartKind kind = PartKind::Body;
    RecordId record = kNoRecord;
    const float* positions = nullptr;  // 3 per vertex, local frame in glTF axes (X east, Y up, Z -north)
    const float* uvs = nullptr;        // 2 per vertex
    const float* residuals = nullptr;  // kPositionResidualAttribute (3 per vertex, glTF axes) or null
    const std::uint32_t* indices = nullptr;
    std::size_t vertexCount = 0, indexCount = 0;
};

struct Package {
    std::string source;  // the package directory (or the name parsePackage was given), for messages
    nlohmann::json manifest;
    AttributeTable attributes;
    std::string name, crs;
    glm::dvec3 origin{0.0};  // world, metres
    std::uint32_t width = 0, height = 0, pages = 0;
    std::vector<std::uint32_t> texels;  // pages * height * width, row 0 first
    std::vector<PackagePart> parts;
    std::shared_ptr<const void> storage;  // keeps the mesh and BVH bytes (mappings or copy) alive
    // section.bvh's bytes (loadPackage; checksum verified), empty from parsePackage.
    std::span<const std::uint8_t> sectionBvh;
    std::span<const std::uint8_t> vertexMap;  // vertices.map, likewise
    // mesh.glb's scene: its name, the geoslice scene extras (CRS, notes; model/io/gltf/gltf_io.hpp)
    // and the root node's translation (glTF axes), which packageModel() needs.
    std::string sceneName;
    nlohmann::json sceneExtras;
    glm::dvec3 rootTranslation{0.0};

    RecordId fetch(glm::dvec2 uv) const { return fetchId(texels.data(), width, height, pages, uv); }
    // Bytes this package keeps in memory: the texture plus the mesh arrays.
    std::size_t residentBytes() const;
};

struct PackageReadOptions {
    bool verifyChecksums = true;  // XXH64 of every file against the manifest
};

// The model a loaded package holds, as loadModel() reads and validates its mesh.glb (the same
// double world positions, indices, parts, records, attribute table, CRS, notes, origin, part
// reports and findings, bit for bit) without validating it again: the bake validated this
// very mesh and stored what validation did to it (vertices.map: the chart seams it welds) and
// what it found (the manifest's "validation"); checksums vouch that nothing changed since.
// When the bake found that a vertex map cannot replay validation ("trusted": false, e.g.
// validation flipped triangles), the model is validated here.
Result<Model> packageModel(const Package& pkg);

// Loads a package directory (mesh.glb is memory-mapped, not copied). Errors name the file and
// what is wrong: NotFound/IoError for missing or unreadable files, ParseError for a corrupt,
// truncated or inconsistent package, Unsupported for another format version.
Result<Package> loadPackage(const std::string& dir, const PackageReadOptions& options = {});

// The same checks on the four files' contents in memory (what the fuzz target drives). The
// parts point into `mesh`, which must outlive the result (when `mesh` is not 4-byte aligned it
// is copied into `storage` instead); `source` names the package in errors.
Result<Package> parsePackage(std::string_view manifest, std::span<const std::uint8_t> mesh,
                             std::span<const std::uint8_t> texture, std::string_view attributes,
                             const PackageReadOptions& options, const std::string& source);

}  // namespace geoslice::bake
