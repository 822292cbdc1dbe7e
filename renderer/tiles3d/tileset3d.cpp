#include "renderer/tiles3d/tileset3d.hpp"

#include <GeographicLib/Geocentric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include "bake/feature_table.hpp"
#include "model/io/gltf/gltf_io.hpp"
#include "model/version.hpp"
#include "renderer/lod/cluster_build.hpp"

namespace geoslice {

using json = nlohmann::ordered_json;

struct Tileset3d::PartData {
    std::string name;
    PartKind kind = PartKind::Body;
    RecordId record = kNoRecord;
    std::uint32_t row = 0;                                // property-table row of `record`
    std::vector<glm::vec3> enu;                           // vertices, east-north-up metres about the centre
    const std::vector<std::uint32_t>* indices = nullptr;  // the model part's triangles (build only)
    std::vector<std::uint32_t> sorted, lodIndices;
    GpuModel::DrawPart draw;  // clusters and groups (renderer/lod/cluster_build.hpp)
};

Tileset3d::Tileset3d() = default;
Tileset3d::~Tileset3d() = default;
std::size_t Tileset3d::partCount() const { return parts_.size(); }
PartKind Tileset3d::partKind(std::uint32_t part) const { return parts_.at(part).kind; }

namespace {

// One way to draw a cluster: its own level, or a group it belongs to.
struct Rep {
    const std::uint32_t* indices = nullptr;
    std::size_t count = 0;
    float error = 0.0f;
    int group = -1;  // index into DrawPart::groups, or -1 for a cluster level
};

float srgbToLinear(std::uint8_t c) {
    const double v = c / 255.0;
    return float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
}

}  // namespace

Result<std::shared_ptr<const Tileset3d>> Tileset3d::build(const Model& model, const ToGeodetic& toGeodetic,
                                                          const Tiles3dOptions& options,
                                                          const std::atomic<bool>* cancel) {
    const auto t0 = std::chrono::steady_clock::now();
    std::shared_ptr<Tileset3d> ts(new Tileset3d());
    ts->name_ = model.name.empty() ? "model" : model.name;
    ts->attributes_ = model.attributes;
    ts->crsId_ = model.crs.isLocal() ? "local" : model.crs.id();
    auto cancelled = [cancel] { return cancel && cancel->load(std::memory_order_relaxed); };

    // The ENU frame at the centre of the model's bounds.
    const Aabb worldBounds = model.bounds();
    if (!worldBounds.valid() || model.triangleCount() == 0)
        return makeError(ErrorCode::InvalidArgument, "3D Tiles: the model has no triangles");
    const GeographicLib::Geocentric& earth = GeographicLib::Geocentric::WGS84();
    auto centre = toGeodetic(worldBounds.centre());
    if (!centre) return makeError(centre.error().code, "3D Tiles: the model's centre: " + centre.error().message);
    ts->centreLonLatH_ = centre.value();
    glm::dvec3 c;
    std::vector<double> m(9);
    earth.Forward(centre->y, centre->x, centre->z, c.x, c.y, c.z, m);
    // m (row-major) takes ENU components to ECEF ones: column 0 east, 1 north, 2 up.
    glm::dmat3 enuToEcef;
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) enuToEcef[col][row] = m[std::size_t(row * 3 + col)];
    const glm::dmat3 ecefToEnu = glm::transpose(enuToEcef);
    ts->enuToEcef_ = glm::dmat4(enuToEcef);
    ts->enuToEcef_[3] = glm::dvec4(c, 1.0);

    // Parts with triangles, their vertices placed exactly.
    Aabb enuBounds;
    std::size_t triangles = 0;
    for (const std::vector<Part>* list : {&model.bodies, &model.surfaces}) {
        for (const Part& part : *list) {
            if (part.mesh.indices.size() < 3) continue;
            PartData pd;
            pd.name = part.name;
            pd.kind = part.kind;
            pd.record = part.record;
            pd.indices = &part.mesh.indices;
            pd.enu.resize(part.mesh.positions.size());
            for (std::size_t v = 0; v < part.mesh.positions.size(); ++v) {
                if ((v & 4095) == 0 && cancelled())
                    return makeError(ErrorCode::DeadlineExceeded, "3D Tiles: cancelled");
                const glm::dvec3& w = part.mesh.positions[v];
                auto g = toGeodetic(w);
                if (!g)
                    return makeError(g.error().code, "3D Tiles: vertex " + std::to_string(v) + " of '" + part.name +
                                                         "': " + g.error().message);
                if (!std::isfinite(g->x) || !std::isfinite(g->y) || !std::isfinite(g->z))
                    return makeError(ErrorCode::InvalidArgument,
                                     "3D Tiles: vertex " + std::to_string(v) + " of '" + part.name +
                                         "' has no WGS 84 position (outside the CRS's domain)");
                glm::dvec3 p;
                earth.Forward(g->y, g->x, g->z, p.x, p.y, p.z);
                const glm::dvec3 e = ecefToEnu * (p - c);
                pd.enu[v] = glm::vec3(e);
                enuBounds.extend(e);
            }
            triangles += part.mesh.indices.size() / 3;
            ts->parts_.push_back(std::move(pd));
        }
    }
    ts->triangles_ = triangles;

    // The cluster hierarchy over the ENU positions.
    const CellGrid grid = makeGrid(enuBounds, triangles, options.trianglesPerTile, options.maxTiles);
    std::vector<Aabb> cellBounds(grid.count());
    std::vector<std::uint32_t> remap;
    std::vector<RecordId> records;
    for (PartData& pd : ts->parts_) {
        if (cancelled()) return makeError(ErrorCode::DeadlineExceeded, "3D Tiles: cancelled");
        buildClusters(grid, pd.enu, *pd.indices, true, std::clamp(options.lodLevels, 1, 8), pd.draw, pd.sorted,
                      pd.lodIndices, cellBounds, remap);
        pd.indices = nullptr;  // the model is the caller's: not kept
        records.push_back(pd.record);
    }
    ts->rows_ = bake::featureRows(ts->attributes_, records);
    for (PartData& pd : ts->parts_)
        pd.row = std::uint32_t(std::lower_bound(ts->rows_.begin(), ts->rows_.end(), pd.record) - ts->rows_.begin());

    // Per part: the clusters of each cell, and the cell-coordinate box and chain of each group.
    struct ClusterRef {
        std::uint32_t part, cluster;
    };
    std::vector<std::vector<ClusterRef>> inCell(grid.count());
    std::vector<std::vector<std::pair<glm::ivec3, glm::ivec3>>> groupBox(ts->parts_.size());
    std::vector<std::vector<std::vector<std::uint32_t>>> groupsOf(ts->parts_.size());
    for (std::uint32_t pi = 0; pi < ts->parts_.size(); ++pi) {
        const GpuModel::DrawPart& d = ts->parts_[pi].draw;
        for (std::uint32_t ci = 0; ci < d.clusters.size(); ++ci) inCell[d.clusters[ci].cell].push_back({pi, ci});
        groupsOf[pi].resize(d.clusters.size());
        for (std::uint32_t g = 0; g < d.groups.size(); ++g) {
            glm::ivec3 lo(1 << 30), hi(-1);
            for (std::uint32_t mb : d.groups[g].members) {
                const glm::ivec3 cc = grid.coordsOf(d.clusters[mb].cell);
                lo = glm::min(lo, cc);
                hi = glm::max(hi, cc);
                groupsOf[pi][mb].push_back(g);  // ascending: finer first
            }
            groupBox[pi].emplace_back(lo, hi);
        }
    }
    auto repsOf = [&](std::uint32_t pi, std::uint32_t ci) {
        const PartData& pd = ts->parts_[pi];
        const GpuModel::DrawPart::Cluster& cl = pd.draw.clusters[ci];
        std::vector<Rep> reps;
        for (int l = 0; l < cl.levels; ++l)
            reps.push_back({l == 0 ? pd.sorted.data() + cl.first[0] : pd.lodIndices.data() + cl.first[l],
                            std::size_t(cl.count[l]), cl.error[l], -1});
        for (std::uint32_t g : groupsOf[pi][ci]) {
            const GpuModel::DrawPart::Group& grp = pd.draw.groups[g];
            reps.push_back({pd.lodIndices.data() + grp.first, std::size_t(grp.count), grp.error, int(g)});
        }
        return reps;
    };

    int height = 0;
    while ((1 << height) < std::max({grid.dims.x, grid.dims.y, grid.dims.z})) ++height;
    const double cellDiag = glm::length(grid.cellSize);

    // The octree, depth first from the root; a tile whose content is all full detail has no
    // children (they would draw the same).
    std::function<std::uint32_t(int, glm::ivec3)> makeTile = [&](int h, glm::ivec3 block) -> std::uint32_t {
        const std::uint32_t index = std::uint32_t(ts->tiles_.size());
        ts->tiles_.emplace_back();
        Tile tile;
        tile.height = h;
        const glm::ivec3 lo = block * (1 << h), hi = glm::min((block + 1) * (1 << h), grid.dims) - 1;
        const double budget = h == 0 ? 0.0 : kErrorPerSize * cellDiag * double(1 << h);
        std::set<std::pair<std::uint32_t, int>> usedGroups;
        Aabb box;
        float error = 0.0f;
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) {
                    for (const ClusterRef& ref : inCell[grid.indexOf({x, y, z})]) {
                        const std::vector<Rep> reps = repsOf(ref.part, ref.cluster);
                        const Rep* pick = &reps[0];
                        for (const Rep& r : reps) {
                            if (r.error > budget) break;
                            if (r.group >= 0) {
                                const auto& [glo, ghi] = groupBox[ref.part][std::size_t(r.group)];
                                if (glm::any(glm::lessThan(glo, lo)) || glm::any(glm::greaterThan(ghi, hi))) continue;
                            }
                            pick = &r;
                        }
                        if (pick->group >= 0 && !usedGroups.insert({ref.part, pick->group}).second) continue;
                        tile.pieces.push_back({ref.part, pick->indices, pick->count});
                        error = std::max(error, pick->error);
                        const auto& enu = ts->parts_[ref.part].enu;
                        for (std::size_t i = 0; i < pick->count; ++i) box.extend(glm::dvec3(enu[pick->indices[i]]));
                    }
                }
        tile.geometricError = error;
        if (h > 0 && error > 0.0f) {
            for (int dz = 0; dz < 2; ++dz)
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const glm::ivec3 child = block * 2 + glm::ivec3(dx, dy, dz);
                        const glm::ivec3 clo = child * (1 << (h - 1));
                        if (glm::any(glm::greaterThanEqual(clo, grid.dims))) continue;
                        const glm::ivec3 chi = glm::min((child + 1) * (1 << (h - 1)), grid.dims) - 1;
                        bool any = false;
                        for (int z = clo.z; z <= chi.z && !any; ++z)
                            for (int y = clo.y; y <= chi.y && !any; ++y)
                                for (int x = clo.x; x <= chi.x && !any; ++x)
                                    any = !inCell[grid.indexOf({x, y, z})].empty();
                        if (any) tile.children.push_back(makeTile(h - 1, child));
                    }
            for (std::uint32_t ch : tile.children) {
                const Tile& t = ts->tiles_[ch];
                box.extend(t.boxMin);
                box.extend(t.boxMax);
                tile.geometricError = std::max(tile.geometricError, t.geometricError * 1.0001 + 1e-6);
            }
        }
        tile.boxMin = box.min;
        tile.boxMax = box.max;
        ts->tiles_[index] = std::move(tile);
        return index;
    };
    makeTile(height, glm::ivec3(0));
    ts->buildMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return std::shared_ptr<const Tileset3d>(std::move(ts));
}

json Tileset3d::tilesetJson(const std::string& contentPrefix, const std::string& generator,
                            const std::string& contentQuery) const {
    std::function<json(std::uint32_t)> tileJson = [&](std::uint32_t n) {
        const Tile& t = tiles_[n];
        const glm::dvec3 mid = (t.boxMin + t.boxMax) * 0.5;
        // Half extents of at least 1 cm: a flat tile still has a volume.
        const glm::dvec3 half = glm::max((t.boxMax - t.boxMin) * 0.5, glm::dvec3(0.01));
        json j = json::object();
        j["boundingVolume"] = {{"box", {mid.x, mid.y, mid.z, half.x, 0.0, 0.0, 0.0, half.y, 0.0, 0.0, 0.0, half.z}}};
        j["geometricError"] = t.geometricError;
        if (!t.pieces.empty()) j["content"] = {{"uri", contentPrefix + std::to_string(n) + ".glb" + contentQuery}};
        if (!t.children.empty()) {
            json kids = json::array();
            for (std::uint32_t ch : t.children) kids.push_back(tileJson(ch));
            j["children"] = std::move(kids);
        }
        return j;
    };
    json root = tileJson(0);
    json transform = json::array();
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) transform.push_back(enuToEcef_[col][row]);
    json ordered = {{"transform", transform}};
    for (auto& [k, v] : root.items()) ordered[k] = v;
    ordered["refine"] = "REPLACE";
    const Tile& r = tiles_[0];
    return {{"asset", {{"version", "1.1"}, {"generator", generator}}},
            {"geometricError", std::max(glm::length(r.boxMax - r.boxMin), r.geometricError)},
            {"root", std::move(ordered)},
            {"extras",
             {{"geoslice",
               {{"model", name_},
                {"crs", crsId_},
                {"centre", {{"lon", centreLonLatH_.x}, {"lat", centreLonLatH_.y}, {"height", centreLonLatH_.z}}},
                {"frame", "east-north-up metres at the centre (WGS 84); model z taken as ellipsoidal height"},
                {"triangles", triangles_},
                {"tiles", tiles_.size()}}}}}};
}

Result<std::vector<std::uint8_t>> Tileset3d::tileGlb(std::size_t n) const {
    if (n >= tiles_.size())
        return makeError(ErrorCode::OutOfRange, "3D Tiles: tile " + std::to_string(n) +
                                                    " does not exist (the tileset has " +
                                                    std::to_string(tiles_.size()) + ")");
    const Tile& tile = tiles_[n];
    GlbBuilder glb(kGeneratorName);
    glb.doc()["extensionsUsed"] = {"EXT_mesh_features", "EXT_structural_metadata"};
    // Pieces by part: one primitive per part, unindexed, flat normals.
    std::map<std::uint32_t, std::vector<const Piece*>> byPart;
    for (const Piece& p : tile.pieces) byPart[p.part].push_back(&p);
    std::map<RecordId, std::size_t> materialOf;
    json materials = json::array();
    std::vector<float> pos, nrm, fid;
    for (const auto& [pi, pieces] : byPart) {
        const PartData& pd = parts_[pi];
        pos.clear(), nrm.clear(), fid.clear();
        for (const Piece* p : pieces)
            for (std::size_t i = 0; i + 2 < p->count; i += 3) {
                const glm::vec3 a = pd.enu[p->indices[i]], b = pd.enu[p->indices[i + 1]], c = pd.enu[p->indices[i + 2]];
                glm::dvec3 nn = glm::cross(glm::dvec3(b - a), glm::dvec3(c - a));
                const double len = glm::length(nn);
                nn = len > 0.0 ? nn / len : glm::dvec3(0.0, 0.0, 1.0);
                for (const glm::vec3& v : {a, b, c}) {
                    // ENU (z up) -> glTF (y up): (e, u, -n).
                    pos.insert(pos.end(), {v.x, v.z, -v.y});
                    nrm.insert(nrm.end(), {float(nn.x), float(nn.z), float(-nn.y)});
                    fid.push_back(float(pd.row));
                }
            }
        if (pos.empty()) continue;
        const std::size_t count = pos.size() / 3;
        const std::size_t position = glb.addPositions(pos.data(), count);
        const std::size_t normal =
            glb.addAccessor({{"bufferView", glb.addView(nrm.data(), nrm.size() * 4, kGltfArrayBuffer)},
                             {"componentType", kGltfFloat},
                             {"count", count},
                             {"type", "VEC3"}});
        const std::size_t feature =
            glb.addAccessor({{"bufferView", glb.addView(fid.data(), fid.size() * 4, kGltfArrayBuffer)},
                             {"componentType", kGltfFloat},
                             {"count", count},
                             {"type", "SCALAR"}});
        auto [it, fresh] = materialOf.try_emplace(pd.record, materials.size());
        if (fresh) {
            const AttributeRecord* rec = attributes_.find(pd.record);
            const Rgba8 col = rec ? rec->colour : Rgba8{};
            json mat = {
                {"name", rec && !rec->name.empty() ? rec->name : pd.name},
                {"pbrMetallicRoughness",
                 {{"baseColorFactor", {srgbToLinear(col.r), srgbToLinear(col.g), srgbToLinear(col.b), col.a / 255.0}},
                  {"metallicFactor", 0.0},
                  {"roughnessFactor", 0.9}}},
                {"doubleSided", true}};
            if (col.a < 255) mat["alphaMode"] = "BLEND";
            materials.push_back(std::move(mat));
        }
        json prim = {
            {"attributes", {{"POSITION", position}, {"NORMAL", normal}, {"_FEATURE_ID_0", feature}}},
            {"mode", kGltfTriangles},
            {"material", it->second},
            {"extensions",
             {{"EXT_mesh_features",
               {{"featureIds",
                 json::array(
                     {{{"featureCount", 1}, {"attribute", 0}, {"propertyTable", 0}, {"label", "record"}}})}}}}}};
        glb.addPart(pd.name, pd.kind, pd.record, std::move(prim));
    }
    json metadata = bake::addPropertyTable(glb, rows_, attributes_);
    json& doc = glb.finishDocument(name_ + " tile " + std::to_string(n),
                                   {{"tile", n}, {"height", tile.height}, {"geometricError", tile.geometricError}});
    doc["materials"] = std::move(materials);
    doc["extensions"]["EXT_structural_metadata"] = std::move(metadata);
    return glb.pack("3D Tiles tile " + std::to_string(n));
}

}  // namespace geoslice
