// The validation a bake stores, and its replay: the manifest's "validation" (validate()'s
// reports and findings on the package's own mesh) and vertices.map (how validation welds the
// chart-split vertices again), made once at bake time (validateStoredMesh) so that
// packageModel() gives the validated model without validating again.
#include <cstring>
#include <optional>

#include "bake/package_internal.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "section/index/section_index.hpp"

namespace geoslice::bake {
namespace package_detail {
namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

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

// The package's model as model/io/gltf/gltf_io.cpp + finishLoadedModel read its mesh.glb, without
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

Result<StoredValidation> validateStoredMesh(std::span<const std::uint8_t> mesh, const std::string& dir) {
    StoredValidation out;
    Package probe;
    probe.source = dir;
    try {
        if (auto s = parseMesh(mesh, dir, probe); !s) return s.error();
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
            out.vertexMap = std::move(*map);
        }
    }
    if (!trusted) out.vertexMap = vertexMap(stored.value(), stored.value()).value();  // identity
    out.manifestEntry = validationJson(checked, trusted);
    // The BVH over the model packageModel() will return (the stored one when validation
    // leaves it unchanged, else the validated one, which the loader makes again).
    auto index = buildSectionIndex(checked);
    if (!index) return index.error();
    out.sectionBvh = saveBvh(index.value()->bvh);
    return out;
}

}  // namespace package_detail

using namespace package_detail;

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

}  // namespace geoslice::bake
