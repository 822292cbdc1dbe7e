// The models a server answers for: each loaded once, validated, indexed for the exact
// section engine (BVH) and the ray oracle (Embree), and summarised for /v1/models.
//
// Model ids are the file stem and must match [A-Za-z0-9][A-Za-z0-9._-]{0,63}: an id never
// contains '/' or "..", so no request can name a path outside the models directory.
// A model's `version` is a hash of its source bytes (or of the demo generator's options):
// cache keys and ETags carry it, so a changed file never serves stale images.
//
// Thread-safety: a CatalogModel is immutable once built and is read from any thread.
// Catalog::add/find/list are guarded by a mutex.
#pragma once

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/saved_sections.hpp"
#include "bake/package.hpp"
#include "model/drillholes/drillholes.hpp"
#include "model/drillholes/hole_index.hpp"
#include "model/io/loaders.hpp"
#include "model/model.hpp"
#include "model/result.hpp"
#include "section/index/section_index.hpp"
#include "section/rays/ray_queries.hpp"

namespace geoslice::api {

struct CatalogModel {
    std::string id;
    std::string source;   // file path, or "demo (generated)"
    std::string version;  // 16 hex digits
    Model model;
    std::unique_ptr<SectionIndex> index;
    // The point classifier and borehole tracer (one Embree scene), built on a background
    // thread after the model is served (section/rays/ray_queries.hpp): pixel queries without a
    // cached ID buffer, perspective pixel queries and boreholes wait for it (rays->wait).
    // Declared after `model`, which it reads: destroyed first (a build under way is cancelled).
    std::unique_ptr<RayQueries> rays;
    // The baked package (index texture, UVs) when the model came from one or was baked on
    // load; null for a raw model.
    std::shared_ptr<const bake::Package> package;
    double loadMs = 0.0;
    // Set when the bake dir held a package that failed its checks (checksums, format) while
    // its source was intact: the package was moved aside to this path and baked again.
    std::string rebakedFrom;
    // Set when loading fell back to slower work it should not have needed (logged).
    std::string loadWarning;
    // Set when the model was to be baked into the bake dir and the bake failed (a full disk,
    // a file size limit, a bake error): what this bake wrote was removed and the model is
    // served from memory, unbaked (baking is an optimisation). Logged and shown by /readyz.
    std::string bakeWarning;
    // Older <id>.corrupt-N copies deleted when this load moved a corrupt package aside
    // (kCorruptCopiesKept), for the log.
    std::vector<std::string> deletedCorruptCopies;
    // The model's CRS to WGS 84 (EPSG:4326): one operation chosen at load for the model's
    // lon/lat extent (model/crs/crs.hpp CrsTransform). Null for a local model, and where PROJ
    // has no operation or only a ballpark one; then `wgs84Note` says why, and answers give
    // that note instead of WGS 84 coordinates.
    std::shared_ptr<const CrsTransform> toWgs84;
    std::string wgs84Note;
    // WGS 84 lon/lat for maps (GeoJSON space=world, RFC 7946): `toWgs84`, or for a CGCS2000
    // model PROJ's ballpark operation (a null datum shift: CGCS2000 and WGS 84 are both
    // ITRF-aligned and agree to about a metre), with `lonLatNote` saying so. Null where
    // neither exists (local, or a datum whose only operation ignores a real shift).
    std::shared_ptr<const CrsTransform> lonLat;
    std::string lonLatNote;
    // Serialised attribute record per record id, and the first body's name per record,
    // made once at load so that a query answer is a few appends.
    std::unordered_map<RecordId, std::string> recordJson;
    std::unordered_map<RecordId, std::string> bodyName;
    // Records of the bodies that clip the block model (model.blocks), sorted; empty without one.
    std::vector<RecordId> blockRecords;
    // The drillhole database drawn on sections (api/holes.hpp): the <stem>.drillholes.json
    // sidecar beside the model file, or the demo's generated holes; null without one. When
    // there is one, `version` also hashes its contents (a changed database changes every
    // cache key). `drillholeWarning`: the sidecar exists but did not load (why; logged).
    std::shared_ptr<const DrillholeDatabase> drillholes;
    std::shared_ptr<const HoleIndex> holeIndex;
    std::string drillholeWarning;
    // The model's exploration lines (api/saved_sections.hpp): the <stem>.sections.json sidecar
    // beside the model file, or the demo's; `sectionsWarning`: the sidecar exists but did not
    // load (why; logged, in /readyz, and the list of saved sections says so). Sections saved
    // through the API are not here: they live in the server's SavedSectionStore.
    std::vector<SavedSection> sections;
    std::string sectionsWarning;
    // The plan's context layer (api/context_layer.hpp): the <stem>.context.geojson sidecar as
    // GeoJSON in the model's CRS, or the demo's; null without one. `contextWarning`: the
    // sidecar exists but did not load (why; logged and in /readyz).
    std::shared_ptr<const std::string> context;
    std::string contextWarning;

    // {id, version, crs, bounds, triangles, bodies: [...], surfaces: [...], legend: [...]}
    nlohmann::ordered_json summary() const;
    // Legend entries in body order: {record, name, colour, kind, lithology, age, ...}.
    nlohmann::ordered_json legend() const;
};

bool isValidModelId(std::string_view id);

// What a saved section of `m` is checked against (api/saved_sections.hpp).
SectionTarget sectionTarget(const CatalogModel& m);

// The model-CRS -> WGS 84 operations for a model extent (CatalogModel::toWgs84 / lonLat and
// their notes), for the catalog and the CLI alike.
struct Wgs84Choice {
    std::shared_ptr<const CrsTransform> exact, lonLat;
    std::string exactNote, lonLatNote;
};
Wgs84Choice chooseWgs84Transform(const Crs& crs, const Aabb& bounds);

// When the model's ray scene is built (CatalogModel::rays): Now starts the background build
// as the model is loaded; Deferred leaves it to the caller (rays->start()), e.g. a server
// that starts every model's build once all its models are loaded.
enum class RayBuild { Now, Deferred };

// How long a query may wait for CatalogModel::rays: until `deadline`, or until *cancel turns
// true (then DeadlineExceeded); the default waits as long as the build takes (CLI, tests).
struct RayWait {
    std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
    const std::atomic<bool>* cancel = nullptr;
};

// How many <id>.corrupt-N copies of a corrupt baked package the bake dir keeps per id: moving
// one aside deletes all but the newest kCorruptCopiesKept (highest N, this one included), so a
// package that keeps failing its checks cannot fill the disk.
constexpr int kCorruptCopiesKept = 2;

// Loads, validates and indexes a model (the ray scene on a background thread, see `rays`): a file (glTF/GLB, OBJ,
// TSurf, Geo3DML), or a baked package directory (bake/package.hpp: checksums verified, its mesh.glb is the geometry
// with the validation stored at bake time (bake::packageModel), its manifest checksum the version). With `bakeDir`
// non-empty a raw model is served from bakeDir/<id>/, baked there on first load and again when the source's version,
// the package format or its checksums change (a corrupt package is moved aside to <id>.corrupt-N); while the package is
// current the source is read only for its version hash, never parsed. `mayBake` false (serve --no-bake: replicas on a
// read-only models volume): nothing is baked; a raw model without a current package is refused (Unsupported, naming
// why: missing, baked from another source version, stale format, failing its checks). A bake that fails (a full disk,
// a file size limit, a bake error) removes bakeDir/<id>/ (what it wrote, and the unusable package it replaced) and the
// model is served from memory with `bakeWarning` saying why. A model file is first checked with probeModelFile
// (model/io/loaders.hpp) against `maxFileBytes`. Errors: the loader's or the package reader's, and InvalidArgument when
// validation found errors (named).
Result<std::shared_ptr<const CatalogModel>> loadCatalogModel(const std::string& id, const std::string& path,
                                                             const std::string& bakeDir = "", bool mayBake = true,
                                                             RayBuild rays = RayBuild::Now,
                                                             std::uint64_t maxFileBytes = kDefaultMaxModelBytes);
// A loaded, validated model indexed as the server does (tests and benchmarks build models
// in memory); `version` as the caller chooses.
// `drillholes`: attached as a sidecar's would be (attachDrillholes).
Result<std::shared_ptr<const CatalogModel>> catalogModelOf(const std::string& id, Model model,
                                                           const std::string& version, RayBuild rays = RayBuild::Now,
                                                           std::optional<DrillholeDatabase> drillholes = std::nullopt);
// Attaches a drillhole database (and its index) to a model being built, and folds the
// database's contents into its version.
void attachDrillholes(CatalogModel& model, DrillholeDatabase db);
// The built-in demo mine (synthetic, EPSG:4523 at 105.05 E 30.62 N), `triangles` in total,
// with its generated drillholes (model/synthetic/synthetic_holes.hpp).
Result<std::shared_ptr<const CatalogModel>> makeDemoModel(std::size_t triangles = 200000);
// An entry of a models directory that is not loaded, and why (for the log and /readyz).
struct SkippedEntry {
    std::string entry;   // its name in the directory
    std::string reason;  // e.g. "a FIFO (named pipe), not a regular file: never opened"
};

struct ModelsDirScan {
    std::map<std::string, std::string> models;  // id -> path, sorted by id
    std::vector<SkippedEntry> skipped;          // in name order
};

// The models in `dir`: model files directly in it (by extension: .glb .gltf .obj .ts .ml .so
// .gp .xml .vtu) whose stem is a valid id and that pass probeModelFile(maxFileBytes), and
// package directories (holding a manifest.json) whose name is a valid id. A package wins over
// a file of the same id; of two files of one id the first by name wins. Without blocking or
// reading any file whole, entries that look like models or cannot be told apart are skipped
// with a reason: FIFOs, sockets and devices (never opened for reading), dangling symlinks and
// symlink loops, directories that are not packages (a package folder without manifest.json, a
// directory named like a model file), model files without read permission, empty, too large,
// or whose first bytes are not the format's, names that are not valid ids, a second file of
// one id. Hidden entries (".name"), packages moved aside as corrupt (<id>.corrupt-N) and files
// of other extensions (sidecars, notes) are passed over silently.
Result<ModelsDirScan> scanModelsDir(const std::string& dir, std::uint64_t maxFileBytes = kDefaultMaxModelBytes);
// scanModelsDir(dir).models.
Result<std::map<std::string, std::string>> listModelFiles(const std::string& dir);

class Catalog {
public:
    void add(std::shared_ptr<const CatalogModel> model);
    std::shared_ptr<const CatalogModel> find(const std::string& id) const;
    std::vector<std::shared_ptr<const CatalogModel>> list() const;
    std::size_t size() const;

private:
    mutable std::mutex mutex_;
    std::map<std::string, std::shared_ptr<const CatalogModel>> models_;  // guarded by mutex_
};

}  // namespace geoslice::api
