#include "api/catalog.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <limits>
#include <string_view>

#include "api/context_layer.hpp"
#include "api/plan.hpp"
#include "model/clock.hpp"
#include "model/io/loaders.hpp"
#include "model/json_text.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "model/synthetic/synthetic_holes.hpp"
#include "section/blocks/block_section.hpp"
#include "section/index/leaf_order.hpp"

namespace geoslice::api {
namespace {

Status indexModel(CatalogModel& m, RayBuild rays) {
    if (m.model.validation.hasErrors()) {
        std::string first;
        for (const auto& issue : m.model.validation.issues)
            if (issue.severity == ValidationIssue::Severity::Error) {
                first = (issue.part.empty() ? "" : issue.part + ": ") + issue.message;
                break;
            }
        return makeError(ErrorCode::InvalidArgument,
                         "model '" + m.id + "' (" + m.source + ") failed validation: " + first);
    }
    if (m.model.triangleCount() == 0)
        return makeError(ErrorCode::InvalidArgument, "model '" + m.id + "' (" + m.source + ") has no triangles");
    // The section index: the package's BVH when there is one, else built.
    Result<std::unique_ptr<SectionIndex>> index = makeError(ErrorCode::Internal, "not built");
    if (m.package && !m.package->sectionBvh.empty()) {
        index = loadSectionIndex(m.model, m.package->sectionBvh, m.source + "/" + bake::kSectionBvhFile);
        if (!index)
            m.loadWarning = "the package's section BVH was not used (" + index.error().message + "); built instead";
    }
    if (!index) index = buildSectionIndex(m.model);
    if (!index) return index.error();
    m.index = std::move(index.value());
    // The one ray scene that every ray query of the model shares (classifier, tracer), built
    // after the model is served: it was 2.9 of the 3.3 CPU-s of a baked L4's start.
    // Low build quality (Morton-code BVH): measured on a baked L4 (bench_coldstart, load
    // 15-17), 2.8-2.9 CPU-s to build instead of 4.8 s at medium, the same answers, rays as
    // fast to 3x slower (a classify 27-85 us against 29 us, a vertical borehole 77-235 us
    // against 65 us under that load): microseconds on a query that costs a tenth of a
    // millisecond over HTTP.
    RaySceneOptions sceneOptions;
    sceneOptions.quality = RTC_BUILD_QUALITY_LOW;
    m.rays = RayQueries::create(m.model, sceneOptions);
    for (const auto& [id, record] : m.model.attributes.records()) m.recordJson[id] = jsonText(record.toJson());
    for (const Part& p : m.model.bodies) m.bodyName.emplace(p.record, p.name);
    if (m.model.blocks) m.blockRecords = blockClipRecords(m.model, *m.model.blocks);
    Wgs84Choice w = chooseWgs84Transform(m.model.crs, m.index->bounds);
    m.toWgs84 = std::move(w.exact);
    m.wgs84Note = std::move(w.exactNote);
    m.lonLat = std::move(w.lonLat);
    m.lonLatNote = std::move(w.lonLatNote);
    if (rays == RayBuild::Now) m.rays->start();
    return {};
}

nlohmann::ordered_json recordOf(const AttributeTable& table, RecordId id) {
    if (const AttributeRecord* r = table.find(id)) return r->toJson();
    return {{"id", id}};
}

}  // namespace

Wgs84Choice chooseWgs84Transform(const Crs& crs, const Aabb& b) {
    Wgs84Choice c;
    if (crs.isLocal()) {
        c.exactNote = c.lonLatNote = "no WGS 84 coordinates: the model has no CRS";
        return c;
    }
    auto box = lonLatBoxOf(crs, {b.min.x, b.min.y}, {b.max.x, b.max.y});
    if (!box) {
        c.exactNote = c.lonLatNote =
            "no WGS 84 coordinates: the model's extent has no lon/lat (" + box.error().message + ")";
        return c;
    }
    auto wgs84 = Crs::fromEpsg(4326);
    if (!wgs84) {
        c.exactNote = c.lonLatNote = "no WGS 84 coordinates: " + wgs84.error().message;
        return c;
    }
    auto t = CrsTransform::forArea(crs, wgs84.value(), box.value());
    if (!t) {
        c.exactNote = c.lonLatNote = "no WGS 84 coordinates: " + t.error().message;
        return c;
    }
    if (!t->isBallpark()) {
        c.exact = c.lonLat = std::make_shared<const CrsTransform>(std::move(t.value()));
        return c;
    }
    c.exactNote = "no WGS 84 coordinates: PROJ knows only a ballpark transformation from " + crs.geographicName() +
                  " to WGS 84 over this model's extent (" + t->operationName() + "), which ignores the datum shift";
    if (crs.isCgcs2000()) {
        c.lonLat = std::make_shared<const CrsTransform>(std::move(t.value()));
        c.lonLatNote =
            "CGCS2000 written as WGS 84 without a datum shift (PROJ has only a ballpark operation; both are "
            "ITRF-aligned and agree to about 1 m)";
    } else {
        c.lonLatNote = c.exactNote;
    }
    return c;
}

bool isValidModelId(std::string_view id) {
    if (id.empty() || id.size() > 64) return false;
    auto ok = [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
               c == '-';
    };
    if (!std::isalnum(static_cast<unsigned char>(id[0]))) return false;
    return std::all_of(id.begin(), id.end(), ok) && id.find("..") == std::string_view::npos;
}

nlohmann::ordered_json CatalogModel::legend() const {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    std::map<RecordId, std::size_t> entryOf;  // fault blocks of one stratum share a record
    auto add = [&](const Part& p, const char* partKind) {
        if (p.record != kNoRecord)
            if (const auto it = entryOf.find(p.record); it != entryOf.end()) {
                out[it->second]["parts"].push_back(p.name);
                return;
            }
        nlohmann::ordered_json e = recordOf(model.attributes, p.record);
        e["parts"] = {p.name};
        e["partKind"] = partKind;
        if (const AttributeRecord* r = model.attributes.find(p.record)) e["colour"] = formatColour(r->colour);
        if (p.record != kNoRecord) entryOf[p.record] = out.size();
        out.push_back(std::move(e));
    };
    for (const Part& p : model.bodies) add(p, "body");
    for (const Part& p : model.surfaces) add(p, "surface");
    return out;
}

nlohmann::ordered_json CatalogModel::summary() const {
    nlohmann::ordered_json j;
    j["id"] = id;
    j["version"] = version;
    j["name"] = model.name;
    const Crs& crs = model.crs;
    j["crs"] = {{"id", crs.id()}, {"name", crs.name()}, {"axes", {"easting", "northing", "elevation"}}, {"units", "m"}};
    if (crs.isGaussKruger()) j["crs"]["zone"] = crs.zone();
    if (!crs.isLocal()) {
        j["crs"]["geographic"] = {{"id", crs.geographicId()}, {"name", crs.geographicName()}};
        if (toWgs84)
            j["crs"]["wgs84"] = {
                {"operation", toWgs84->operationName()},
                {"accuracyM", toWgs84->accuracyM() >= 0.0 ? nlohmann::ordered_json(toWgs84->accuracyM())
                                                          : nlohmann::ordered_json(nullptr)}};
        else
            j["crs"]["wgs84Note"] = wgs84Note;
    }
    if (auto it = model.notes.find("crs_warning"); it != model.notes.end()) j["crs"]["warning"] = it->second;
    const Aabb b = model.bounds();
    j["bounds"] = {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}};
    if (crs.isProjected()) {
        // The envelope of the box's edges (model/crs/crs.hpp lonLatBoxOf), as `geoslice info`.
        if (auto ll = lonLatBoxOf(crs, {b.min.x, b.min.y}, {b.max.x, b.max.y}))
            j["lonlatBounds"] = {{"min", {ll->west, ll->south}},
                                 {"max", {ll->east, ll->north}},
                                 {"axes", {"lon", "lat"}},
                                 {"crs", crs.geographicId()}};
    }
    j["triangles"] = model.triangleCount();
    j["bodies"] = model.bodies.size();
    j["surfaces"] = model.surfaces.size();
    if (package)
        j["baked"] = {{"pages", package->pages},
                      {"width", package->width},
                      {"height", package->height},
                      {"residentBytes", package->residentBytes()},
                      {"note", "attribute-indexed texture (R32UI record ids) from the baked package"}};
    if (model.blocks) {
        const BlockModel& bm = *model.blocks;
        nlohmann::ordered_json props = nlohmann::ordered_json::array();
        for (const BlockProperty& p : bm.properties) props.push_back({{"name", p.name}, {"unit", p.unit}});
        nlohmann::ordered_json clip = nlohmann::ordered_json::array();
        for (std::uint32_t body : bm.clipBodyIndex) clip.push_back(model.bodies[body].name);
        const bool box = bm.shape == CellShape::Box;
        j["blocks"] = {{"source", bm.source},
                       {"dims", {bm.dims[0], bm.dims[1], bm.dims[2]}},
                       {"cellShape", box ? "box" : "hexahedron (curvilinear: six tetrahedra each)"},
                       {"cellSize", box ? nlohmann::ordered_json({bm.size[0], bm.size[1], bm.size[2]})
                                        : nlohmann::ordered_json(nullptr)},
                       {"origin", {bm.origin.x, bm.origin.y, bm.origin.z}},
                       {"properties", props},
                       {"clipBodies", clip}};
    }
    j["legend"] = legend();
    return j;
}

namespace {

// A baked package directory, loaded and checked (checksums), shared by its CatalogModel.
Result<std::shared_ptr<const bake::Package>> openPackage(const std::string& dir) {
    auto pkg = bake::loadPackage(dir);
    if (!pkg) return pkg.error();
    return std::shared_ptr<const bake::Package>(std::make_shared<bake::Package>(std::move(pkg.value())));
}

// N of a "<id>.corrupt-N" name for package directory name `id`; 0 when `name` is not one.
long corruptCopyNumber(const std::string& name, const std::string& id) {
    const std::string prefix = id + ".corrupt-";
    if (name.size() <= prefix.size() || name.size() > prefix.size() + 9 || name.compare(0, prefix.size(), prefix) != 0)
        return 0;
    long n = 0;
    for (std::size_t i = prefix.size(); i < name.size(); ++i) {
        if (name[i] < '0' || name[i] > '9') return 0;
        n = n * 10 + (name[i] - '0');
    }
    return n;
}

// Moves the corrupt package `dir` aside to <dir>.corrupt-N (N one above the highest there),
// then deletes all but the newest kCorruptCopiesKept copies (highest N), appending their paths
// to `deleted`. The new copy's path, or why `dir` could not be moved.
Result<std::string> moveAsideCorrupt(const std::string& dir, std::vector<std::string>& deleted) {
    namespace fs = std::filesystem;
    const fs::path parent = fs::path(dir).parent_path();
    const std::string id = fs::path(dir).filename().string();
    std::vector<std::pair<long, fs::path>> copies;
    std::error_code ec;
    for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec))
        if (const long n = corruptCopyNumber(it->path().filename().string(), id); n > 0)
            copies.emplace_back(n, it->path());
    if (ec) return makeError(ErrorCode::IoError, "cannot list " + parent.string() + ": " + ec.message());
    std::sort(copies.begin(), copies.end());
    const long next = copies.empty() ? 1 : copies.back().first + 1;
    const std::string aside = dir + ".corrupt-" + std::to_string(next);
    fs::rename(dir, aside, ec);
    if (ec) return makeError(ErrorCode::IoError, "cannot rename it to " + aside + ": " + ec.message());
    copies.emplace_back(next, aside);
    for (std::size_t i = 0; i + kCorruptCopiesKept < copies.size(); ++i) {
        std::error_code rm;
        fs::remove_all(copies[i].second, rm);
        deleted.push_back(copies[i].second.string() + (rm ? " (failed: " + rm.message() + ")" : ""));
    }
    return aside;
}

}  // namespace

Result<std::shared_ptr<const CatalogModel>> loadCatalogModel(const std::string& id, const std::string& path,
                                                             const std::string& bakeDir, bool mayBake, RayBuild rays,
                                                             std::uint64_t maxFileBytes) {
    namespace fs = std::filesystem;
    if (!isValidModelId(id)) return makeError(ErrorCode::InvalidArgument, "model id '" + id + "' is not valid");
    const auto t0 = std::chrono::steady_clock::now();
    auto m = std::make_shared<CatalogModel>();
    m->id = id;
    m->source = path;
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        // A baked package: the checksummed manifest identifies the content, and the model is
        // the package's as validated when it was baked (bake::packageModel).
        auto pkg = openPackage(path);
        if (!pkg) return pkg.error();
        auto manifest = readFile((fs::path(path) / bake::kManifestFile).string(), 64 << 20);
        if (!manifest) return manifest.error();
        m->version = hex64(fnv1a64(manifest.value()));
        auto model = bake::packageModel(*pkg.value());
        if (!model) return model.error();
        m->model = std::move(model.value());
        m->package = std::move(pkg.value());
    } else {
        // Size and first bytes before the file is read whole (a sparse 2 GB file is refused here).
        if (auto s = probeModelFile(path, maxFileBytes); !s) return s.error();
        auto bytes = readFile(path, maxFileBytes);
        if (!bytes) return bytes.error();
        std::uint64_t h = fnv1a64(bytes.value());
        // Sidecar attribute tables and a <stem>.crs change what a model answers, so they enter
        // its version.
        const fs::path p(path);
        for (const char* ext : {".attributes.json", ".attributes.csv", ".crs"}) {
            const auto side = p.parent_path() / (p.stem().string() + ext);
            if (fs::exists(side, ec))
                if (auto sb = readFile(side.string())) h = fnv1a64(sb.value(), h);
        }
        for (const std::string& side : blockModelFiles(path, {}))
            if (auto sb = readFile(side)) h = fnv1a64(sb.value(), h);
        bytes.value().clear();
        bytes.value().shrink_to_fit();
        m->version = hex64(h);
        if (bakeDir.empty()) {
            if (!mayBake)
                return makeError(ErrorCode::Unsupported, "model '" + id + "' (" + path +
                                                             ") is not a baked package, and this server does not bake "
                                                             "(--no-bake): bake it with `geoslice bake` first");
            auto model = loadModel(path);
            if (!model) return model.error();
            m->model = std::move(model.value());
        } else {
            // The package in bakeDir/<id>/ serves while its stamp (source.version) is this
            // source's version and it passes its checks; the source is parsed only to bake.
            const std::string dir = (fs::path(bakeDir) / id).string();
            const std::string stamp = (fs::path(dir) / "source.version").string();
            auto usePackage = [&](std::shared_ptr<const bake::Package> pkg) -> Status {
                auto model = bake::packageModel(*pkg);
                if (!model) return model.error();
                m->model = std::move(model.value());
                m->package = std::move(pkg);
                return {};
            };
            // Parses the source (an error here refuses the model) and bakes it into `dir`. Baking
            // is an optimisation: when it fails, what it wrote is removed (a full disk must not
            // stay full) and the parsed model is served from memory (bakeWarning says why).
            auto bakeOrServe = [&]() -> Status {
                auto model = loadModel(path);
                if (!model) return model.error();
                // The package stores the mesh in the section BVH's leaf order (section/index/leaf_order.hpp).
                if (auto s = reorderForSection(model.value()); !s) return s.error();
                Status baked = [&]() -> Status {
                    auto b = bake::bakeModel(model.value());
                    if (!b) return makeError(b.error().code, "baking: " + b.error().message);
                    if (auto s = bake::writePackage(model.value(), b.value(), dir); !s) return s;
                    return bake::writeFileAtomically(stamp, m->version.data(), m->version.size());
                }();
                if (baked) {
                    auto pkg = openPackage(dir);
                    if (pkg) {
                        auto used = usePackage(std::move(pkg.value()));
                        if (used) return used;
                        baked = used.error();
                    } else {
                        baked = makeError(pkg.error().code,
                                          "the package just written fails to load: " + pkg.error().message);
                    }
                }
                std::error_code rm;
                fs::remove_all(dir, rm);
                m->bakeWarning = "not baked into " + dir + " (" + baked.error().message + ")" +
                                 (rm ? "; removing what the bake wrote failed too: " + rm.message()
                                     : "; what the bake wrote was removed") +
                                 "; served from memory, unbaked";
                m->model = std::move(model.value());
                m->package.reset();
                return {};
            };
            auto refuse = [&](const std::string& why) {
                return makeError(ErrorCode::Unsupported, "model '" + id + "' (" + path + "): " + why +
                                                             ", and this server does not bake (--no-bake): run the "
                                                             "bake job (geoslice bake, or serve with --bake-only)");
            };
            auto previous = readFile(stamp, 64);
            Result<std::shared_ptr<const bake::Package>> pkg = makeError(ErrorCode::NotFound, "not baked yet");
            if (previous && previous.value() == m->version) pkg = openPackage(dir);
            if (pkg) {
                if (auto s = usePackage(std::move(pkg.value())); !s) return s.error();
            } else if (previous && previous.value() == m->version && pkg.error().code == ErrorCode::Unsupported) {
                // Another package format version: bake again in place.
                if (!mayBake) return refuse("its package in " + dir + " is stale (" + pkg.error().message + ")");
                m->rebakedFrom = dir + " (" + pkg.error().message + ")";
                if (auto s = bakeOrServe(); !s) return s.error();
            } else if (previous && previous.value() == m->version) {
                // The stamp matches but the package fails its checks (a corrupt or truncated
                // file): the source is intact, so keep the package aside (the newest
                // kCorruptCopiesKept copies; never deleted silently) and bake again (issue 11 item 6).
                const std::string why = pkg.error().message;
                if (!mayBake) return refuse("its package in " + dir + " fails its checks (" + why + ")");
                auto aside = moveAsideCorrupt(dir, m->deletedCorruptCopies);
                if (aside) {
                    m->rebakedFrom = aside.value() + " (" + why + ")";
                    if (auto s = bakeOrServe(); !s) return s.error();
                } else {
                    // It cannot be moved: serve the source from memory, leave the package be.
                    auto model = loadModel(path);
                    if (!model) return model.error();
                    m->model = std::move(model.value());
                    m->bakeWarning = "package " + dir + " fails its checks (" + why + ") and cannot be moved aside (" +
                                     aside.error().message + "); served from memory, unbaked";
                }
            } else {
                if (!mayBake)
                    return refuse(previous ? "its package in " + dir + " was baked from another version of the source"
                                           : "it has no baked package in " + dir);
                if (auto s = bakeOrServe(); !s) return s.error();
            }
        }
    }
    if (auto s = indexModel(*m, rays); !s) return s.error();
    if (const std::string sidecar = drillholeSidecarFor(path); !sidecar.empty()) {
        auto db = loadDrillholes(sidecar);
        Status placed = db ? placeDrillholes(db.value(), m->model.crs, m->index->bounds) : Status(db.error());
        if (db && placed)
            attachDrillholes(*m, std::move(db.value()));
        else
            m->drillholeWarning =
                "drillholes " + sidecar + " did not load: " + (db ? placed : Status(db.error())).error().message;
    }
    if (const std::string sidecar = sectionsSidecarFor(path); !sidecar.empty()) {
        auto lines = loadSectionsSidecar(sidecar, sectionTarget(*m));
        if (lines)
            m->sections = std::move(lines.value());
        else
            m->sectionsWarning = "sections " + sidecar + " did not load: " + lines.error().message;
    }
    if (const std::string sidecar = contextSidecarFor(path); !sidecar.empty()) {
        auto layer = loadContextLayer(sidecar, m->model.crs, m->index->bounds);
        if (layer)
            m->context = std::make_shared<const std::string>(jsonText(layer.value()));
        else
            m->contextWarning = "context layer " + sidecar + " did not load: " + layer.error().message;
    }
    m->loadMs = msSince(t0);
    return std::shared_ptr<const CatalogModel>(std::move(m));
}

void attachDrillholes(CatalogModel& model, DrillholeDatabase db) {
    // The database's contents, hashed: ids, collars, stations, intervals and their cells.
    std::uint64_t h = fnv1a64("drillholes");
    auto add = [&h](const void* p, std::size_t n) { h = fnv1a64(std::string_view(static_cast<const char*>(p), n), h); };
    auto addText = [&](const std::string& t) { add(t.data(), t.size() + 1); };
    for (const Drillhole& d : db.holes) {
        addText(d.id);
        add(&d.collar, sizeof d.collar);
        add(&d.totalDepth, sizeof d.totalDepth);
        for (const glm::dvec3& p : d.path.position) add(&p, sizeof p);
        add(d.path.depth.data(), d.path.depth.size() * sizeof(double));
    }
    for (const IntervalTable& t : db.intervals) {
        addText(t.name);
        add(t.hole.data(), t.hole.size() * sizeof(std::uint32_t));
        add(t.from.data(), t.from.size() * sizeof(double));
        add(t.to.data(), t.to.size() * sizeof(double));
        for (const IntervalColumn& c : t.columns) {
            addText(c.name);
            add(c.numbers.data(), c.numbers.size() * sizeof(double));
            for (const std::string& x : c.texts) addText(x);
        }
    }
    model.version = hex64(fnv1a64(model.version + ":" + hex64(h)));
    model.holeIndex = std::make_shared<const HoleIndex>(db);
    model.drillholes = std::make_shared<const DrillholeDatabase>(std::move(db));
}

Result<std::shared_ptr<const CatalogModel>> makeDemoModel(std::size_t triangles) {
    const auto t0 = std::chrono::steady_clock::now();
    SyntheticOptions o;
    o.triangles = triangles;
    o.seed = 1;
    auto crs = Crs::fromEpsg(4523);
    if (!crs) return crs.error();
    o.crs = crs.value();
    o.atLonLat = glm::dvec2(105.05, 30.62);
    auto model = generateSynthetic(o);
    if (!model) return model.error();
    auto m = std::make_shared<CatalogModel>();
    m->id = "demo";
    m->source = "demo (generated: synthetic mine, EPSG:4523, 105.05E 30.62N)";
    m->version = hex64(fnv1a64("geoslice-demo-v1:" + std::to_string(triangles)));
    m->model = std::move(model.value());
    m->model.name = "demo";
    validate(m->model);  // closed flags and nesting, as every loader does
    if (auto s = indexModel(*m, RayBuild::Now); !s) return s.error();
    // The demo's drillholes are logged from the model itself: its top by a vertical ray, its
    // unit at each metre by the point classifier (the ray scene, waited for here).
    auto rays = m->rays->wait();
    if (!rays) return rays.error();
    const BoreholeTracer* tracer = rays.value().tracer;
    const Classifier* classifier = rays.value().classifier;
    auto holes = syntheticHoleSources(
        m->model,
        [tracer](double x, double y) {
            auto b = tracer->traceVertical(x, y);
            return b && !std::isnan(b.value().collarDepth) ? b.value().collar.z
                                                           : std::numeric_limits<double>::quiet_NaN();
        },
        [classifier](const glm::dvec3& p) { return classifier->classify(p); });
    auto db = buildDrillholes(std::move(holes.sources));
    if (!db) return db.error();
    attachDrillholes(*m, std::move(db.value()));
    // Exploration lines as a mine numbers them: north-south lines across the strata, 0 in the
    // middle, odd numbers to the west and even to the east, and the east-west fence of holes.
    const Aabb& b = m->index->bounds;
    const double sx = b.max.x - b.min.x, yMid = 0.5 * (b.min.y + b.max.y);
    nlohmann::json lines = nlohmann::json::array();
    const std::pair<const char*, double> numbered[] = {{"3", 0.2}, {"1", 0.35}, {"0", 0.5}, {"2", 0.65}, {"4", 0.8}};
    for (const auto& [number, f] : numbered) {
        const double x = std::round(b.min.x + f * sx);
        lines.push_back({{"number", number},
                         {"vertices", {{x, std::ceil(b.min.y) + 1.0}, {x, std::floor(b.max.y) - 1.0}}},
                         {"vx", 1}});
    }
    lines.push_back(
        {{"name", "East-west fence of holes"},
         {"vertices", {{std::ceil(b.min.x) + 1.0, std::round(yMid)}, {std::floor(b.max.x) - 1.0, std::round(yMid)}}},
         {"vx", 2}});
    for (std::size_t i = 0; i < lines.size(); ++i) {
        auto s = parseSavedSection(lines[i], "demo section " + std::to_string(i), sectionTarget(*m), "model");
        if (!s) return s.error();
        m->sections.push_back(std::move(s.value()));
    }
    // A context layer as a mine office draws it, in the model's CRS: the mining lease, the
    // decline from the portal and the shaft.
    {
        const double sy = b.max.y - b.min.y;
        auto at = [&](double fx, double fy) {
            return nlohmann::json::array({std::round(b.min.x + fx * sx), std::round(b.min.y + fy * sy)});
        };
        nlohmann::json lease =
            nlohmann::json::array({at(0.04, 0.04), at(0.96, 0.04), at(0.96, 0.96), at(0.04, 0.96), at(0.04, 0.04)});
        nlohmann::json layer = {{"type", "FeatureCollection"},
                                {"crs", {{"type", "name"}, {"properties", {{"name", "urn:ogc:def:crs:EPSG::4523"}}}}},
                                {"features",
                                 {{{"type", "Feature"},
                                   {"properties", {{"name", "采矿许可证 Mining lease"}, {"kind", "lease"}}},
                                   {"geometry", {{"type", "Polygon"}, {"coordinates", {lease}}}}},
                                  {{"type", "Feature"},
                                   {"properties", {{"name", "主斜坡道 Main decline"}, {"kind", "working"}}},
                                   {"geometry",
                                    {{"type", "LineString"},
                                     {"coordinates", {at(0.12, 0.2), at(0.3, 0.3), at(0.45, 0.42), at(0.5, 0.5)}}}}},
                                  {{"type", "Feature"},
                                   {"properties", {{"name", "1号竖井 No. 1 shaft"}, {"kind", "shaft"}}},
                                   {"geometry", {{"type", "Point"}, {"coordinates", at(0.62, 0.7)}}}}}}};
        auto parsed = parseContextLayer(jsonText(layer), "the demo's context layer", m->model.crs, b);
        if (!parsed) return parsed.error();
        m->context = std::make_shared<const std::string>(jsonText(parsed.value()));
    }
    m->loadMs = msSince(t0);
    return std::shared_ptr<const CatalogModel>(std::move(m));
}

SectionTarget sectionTarget(const CatalogModel& m) { return {m.id, m.model.crs, m.index->bounds, m.index->origin}; }

Result<std::shared_ptr<const CatalogModel>> catalogModelOf(const std::string& id, Model model,
                                                           const std::string& version, RayBuild rays,
                                                           std::optional<DrillholeDatabase> drillholes) {
    const auto t0 = std::chrono::steady_clock::now();
    auto m = std::make_shared<CatalogModel>();
    m->id = id;
    m->source = model.source.empty() ? "(in memory)" : model.source;
    m->version = version;
    m->model = std::move(model);
    if (auto s = indexModel(*m, rays); !s) return s.error();
    if (drillholes) attachDrillholes(*m, std::move(*drillholes));
    m->loadMs = msSince(t0);
    return std::shared_ptr<const CatalogModel>(std::move(m));
}

Result<ModelsDirScan> scanModelsDir(const std::string& dir, std::uint64_t maxFileBytes) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        return makeError(ErrorCode::NotFound, "models directory '" + dir + "' does not exist or is not a directory");
    // Names first, sorted: what wins between two files of one id must not depend on the
    // file system's order.
    std::vector<fs::path> entries;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) entries.push_back(it->path());
    if (ec) return makeError(ErrorCode::IoError, "cannot list models directory '" + dir + "': " + ec.message());
    std::sort(entries.begin(), entries.end());
    // GOCAD Model3d (.ml), TSolid (.so) and groups (.gp) hold bodies; Voxet/SGrid/PLine
    // and Surpac string files (.str) alone hold nothing a section draws yet (a .dtm is read
    // with its .str).
    static constexpr std::string_view kModelExts[] = {".glb", ".gltf", ".obj", ".ts",  ".ml",  ".so", ".gp",
                                                      ".xml", ".vtu",  ".stl", ".ply", ".dxf", ".dtm"};
    auto modelExtension = [](const fs::path& p) {
        std::string ext = p.extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        return std::find(std::begin(kModelExts), std::end(kModelExts), ext) != std::end(kModelExts);
    };
    ModelsDirScan out;
    std::map<std::string, std::string> files;  // id -> file, before packages take their ids
    auto skip = [&](const std::string& name, std::string reason) { out.skipped.push_back({name, std::move(reason)}); };
    for (const fs::path& p : entries) {
        const std::string name = p.filename().string();
        if (name.empty() || name[0] == '.') continue;  // hidden: a bake dir, an editor's swap file
        std::error_code e2;
        // lstat, then stat through a symlink: a symlink's target is what is judged (never opened here).
        struct stat lst {};
        if (::lstat(p.c_str(), &lst) != 0) {
            skip(name, std::string("cannot stat: ") + std::strerror(errno));
            continue;
        }
        struct stat st {};
        if (::stat(p.c_str(), &st) != 0) {
            const int e = errno;
            if (S_ISLNK(lst.st_mode) && e == ELOOP)
                skip(name, "a symlink loop (" + std::string(std::strerror(e)) + ")");
            else if (S_ISLNK(lst.st_mode) && e == ENOENT)
                skip(name, "a dangling symlink (its target does not exist)");
            else
                skip(name,
                     std::string(S_ISLNK(lst.st_mode) ? "a symlink whose target cannot be read: " : "cannot stat: ") +
                         std::strerror(e));
            continue;
        }
        if (S_ISDIR(st.st_mode)) {
            // <id>.corrupt-N: a package moved aside by the bake dir, kept for inspection only.
            if (name.find(".corrupt-") != std::string::npos) continue;
            const bool manifest = fs::exists(p / bake::kManifestFile, e2);
            if (manifest && isValidModelId(name)) {
                out.models[name] = p.string();
            } else if (manifest) {
                skip(name, "a baked package whose name is not a valid model id ([A-Za-z0-9][A-Za-z0-9._-]{0,63})");
            } else if (modelExtension(p)) {
                skip(name, "a directory, not a model file (and not a baked package: no " +
                               std::string(bake::kManifestFile) + ")");
            } else {
                bool packageFiles = false;
                for (const char* f : {bake::kMeshFile, bake::kTextureFile, bake::kAttributesFile, bake::kSectionBvhFile,
                                      bake::kVertexMapFile, "source.version"})
                    packageFiles = packageFiles || fs::exists(p / f, e2);
                skip(name, packageFiles
                               ? "a package folder without " + std::string(bake::kManifestFile) +
                                     " (an interrupted bake or copy?): not loaded"
                               : "a directory without " + std::string(bake::kManifestFile) + ": not a baked package");
            }
            continue;
        }
        if (!S_ISREG(st.st_mode)) {
            skip(name, fileKindName(st.st_mode) + (S_ISLNK(lst.st_mode) ? " behind a symlink" : "") +
                           ", not a regular file: never opened");
            continue;
        }
        if (!modelExtension(p)) continue;  // sidecars (.attributes.json, .crs, .blocks.csv), notes
        const std::string stem = p.stem().string();
        if (stem.size() > 11 && stem.ends_with(".attributes")) continue;
        if (!isValidModelId(stem)) {
            skip(name, "'" + stem + "' is not a valid model id ([A-Za-z0-9][A-Za-z0-9._-]{0,63}, no '..')");
            continue;
        }
        if (const auto it = files.find(stem); it != files.end()) {
            skip(name, "model id '" + stem + "' is taken by " + fs::path(it->second).filename().string() +
                           " (one file per id)");
            continue;
        }
        if (auto s = probeModelFile(p.string(), maxFileBytes); !s) {
            // The entry names the file: the reason without its path.
            std::string why = s.error().message;
            if (why.starts_with(p.string() + ": ")) why.erase(0, p.string().size() + 2);
            skip(name, std::move(why));
            continue;
        }
        files.emplace(stem, p.string());
    }
    for (auto& [id, path] : files) out.models.emplace(id, path);  // a package of the same id wins
    return out;
}

Result<std::map<std::string, std::string>> listModelFiles(const std::string& dir) {
    auto scan = scanModelsDir(dir);
    if (!scan) return scan.error();
    return std::move(scan.value().models);
}

void Catalog::add(std::shared_ptr<const CatalogModel> model) {
    std::lock_guard lock(mutex_);
    models_[model->id] = std::move(model);
}

std::shared_ptr<const CatalogModel> Catalog::find(const std::string& id) const {
    std::lock_guard lock(mutex_);
    const auto it = models_.find(id);
    return it == models_.end() ? nullptr : it->second;
}

std::vector<std::shared_ptr<const CatalogModel>> Catalog::list() const {
    std::lock_guard lock(mutex_);
    std::vector<std::shared_ptr<const CatalogModel>> out;
    for (const auto& [id, m] : models_) out.push_back(m);
    return out;
}

std::size_t Catalog::size() const {
    std::lock_guard lock(mutex_);
    return models_.size();
}

}  // namespace geoslice::api
