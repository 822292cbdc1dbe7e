// GOCAD TSolid and LightTSolid (.so): tetrahedra. TVOLUME name starts a region; VRTX /
// PVRTX / ATOM define vertices (ids shared by the whole object, ATOMs alias a vertex);
// TETRA a b c d [cell values] adds a cell to the current region (LightTSolid: one region,
// named after the object). After MODEL, SURFACE / TFACE / TRGL list the object's surfaces
// by vertex ids.
//
// Regions without TVOLUME (LightTSolid as RINGMesh and OpenGeode write it: one VRTX per
// position, SHAREDVRTX for the same position in another region): a "# CTETRA region ..."
// comment line after a TETRA names its region; without those, each MODEL_REGION name +-tface
// line seeds a region at the tetrahedron on that side (+: where the first TRGL of TFACE
// `tface`, (b-a)x(c-a), points) of that triangle, and the region is every tetrahedron
// reachable from the seed across faces that are not TRGLs of the model's surfaces.
//
// What it becomes: VolumeMesh -> regionBoundaries() -> one closed body per TVOLUME
// (model/mesh/volume_mesh.hpp), records named after the regions; the surfaces stay surfaces.
// Per-vertex properties (PVRTX columns) go to each body's Mesh properties; per-cell values
// (TETRA lines with values after the ids, named by TETRA_PROPERTIES when given) are kept as
// each region's volume-weighted mean and range in its record's extra["cell_properties"].
//
// Vertices are welded by exact position before the cells are built: exporters that write
// each TVOLUME's vertices again instead of ATOMs still give regions whose shared faces
// match.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "model/io/gocad/gocad_reader.hpp"
#include "model/mesh/volume_mesh.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

namespace {

constexpr std::size_t kMaxCellColumns = 64;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kMaxRegions = 100000;

struct Tet {
    std::uint64_t ids[4] = {0, 0, 0, 0};
    std::int32_t region = 0;
    std::size_t line = 0;
};

struct SurfaceTri {
    std::uint64_t ids[3] = {0, 0, 0};
    std::size_t line = 0;
    std::size_t surface = 0;
    std::uint64_t tface = 0;  // the TFACE number it follows (0: none)
};

// MODEL_REGION name +n / -n.
struct ModelRegion {
    std::string name;
    bool positive = true;
    std::uint64_t tface = 0;
    std::size_t line = 0;
};

// What the lines of one TSolid object hold, as written.
struct TsolidText {
    PropertySchema schema;
    VertexIds ids;
    std::vector<glm::dvec3> positions;
    std::vector<Tet> tets;
    std::vector<std::string> regionNames;
    std::vector<std::string> cellNames;
    std::vector<float> cellValues;  // cellColumns per tet (when any)
    std::size_t cellColumns = 0;
    std::vector<std::string> surfaceNames;
    std::vector<SurfaceTri> surfaceTris;
    std::uint64_t currentTface = 0;
    bool sawTvolume = false;
    std::vector<std::string> ctetraNames;    // regions named by "# CTETRA" lines
    std::vector<std::int32_t> ctetraRegion;  // per tet: index into ctetraNames, -1 none
    std::vector<ModelRegion> modelRegions;
};

// A TETRA line: four vertex ids, then as many cell values as the first TETRA had. `unnamed`
// names the region of tetrahedra before any TVOLUME.
Status readTetra(const Lines& lines, Tokens& tokens, const std::string& unnamed, TsolidText& t) {
    Tet tet;
    tet.line = lines.lineNo();
    for (auto& id : tet.ids)
        if (Status s = readId(lines, tokens, "TETRA vertex id", id); !s) return s;
    if (t.regionNames.empty()) t.regionNames.push_back(unnamed);
    tet.region = static_cast<std::int32_t>(t.regionNames.size() - 1);
    std::string_view tok;
    std::size_t found = 0;
    const std::size_t before = t.cellValues.size();
    while (tokens.next(tok)) {
        std::optional<double> v = parseDouble(tok);
        if (!v) return lines.fail("TETRA cell value " + quoteToken(tok) + " is not a number");
        if (++found > kMaxCellColumns)
            return lines.fail("more than " + std::to_string(kMaxCellColumns) + " values on a TETRA line");
        const bool ok = std::isfinite(*v) && std::fabs(*v) <= std::numeric_limits<float>::max();
        t.cellValues.push_back(ok ? static_cast<float>(*v) : std::numeric_limits<float>::quiet_NaN());
    }
    if (t.tets.empty()) t.cellColumns = found;
    if (found != t.cellColumns) {
        t.cellValues.resize(before);
        return lines.fail("TETRA has " + std::to_string(found) + " cell values, the first TETRA had " +
                          std::to_string(t.cellColumns));
    }
    t.tets.push_back(tet);
    return {};
}

// The TSolid's own keywords (a KeywordReader for readObjectBody).
Status readTsolidKeyword(Context& cx, const ObjectInfo& info, Lines::Statement& st, TsolidText& t, bool& handled) {
    const Lines& lines = cx.lines;
    const std::string_view keyword = st.keyword;
    Tokens& tokens = st.tokens;
    const std::string& unnamed = info.name.empty() ? cx.model.name : info.name;
    if (keyword == "TVOLUME") {
        t.sawTvolume = true;
        t.regionNames.push_back(toUtf8(unquote(tokens.rest())));
        if (t.regionNames.back().empty()) t.regionNames.back() = "region_" + std::to_string(t.regionNames.size());
    } else if (keyword == "TETRA") {
        if (Status s = readTetra(lines, tokens, unnamed, t); !s) return s;
        t.ctetraRegion.push_back(-1);
    } else if (keyword == "CTETRA") {
        std::string_view name;
        if (t.tets.empty() || !tokens.next(name)) return {};  // a stray comment: nothing to name
        const std::string n = toUtf8(unquote(name));
        auto it = std::find(t.ctetraNames.begin(), t.ctetraNames.end(), n);
        if (it == t.ctetraNames.end()) {
            if (t.ctetraNames.size() >= kMaxRegions)
                return lines.fail("more than " + std::to_string(kMaxRegions) + " regions named by CTETRA lines");
            it = t.ctetraNames.insert(t.ctetraNames.end(), n);
        }
        t.ctetraRegion.back() = static_cast<std::int32_t>(it - t.ctetraNames.begin());
    } else if (keyword == "TFACE") {
        std::uint64_t n = 0;
        if (Status s = readId(lines, tokens, "TFACE number", n); !s) return s;
        t.currentTface = n;
    } else if (keyword == "MODEL_REGION") {
        ModelRegion r;
        r.line = lines.lineNo();
        std::string_view name, side;
        if (!tokens.next(name) || !tokens.next(side) || side.size() < 2 || (side[0] != '+' && side[0] != '-'))
            return lines.fail("MODEL_REGION needs a name and a signed TFACE number like +3 or -1");
        r.name = toUtf8(unquote(name));
        r.positive = side[0] == '+';
        Tokens number(side.substr(1));
        if (Status s = readId(lines, number, "MODEL_REGION TFACE number", r.tface); !s) return s;
        if (t.modelRegions.size() >= kMaxRegions)
            return lines.fail("more than " + std::to_string(kMaxRegions) + " MODEL_REGION lines");
        t.modelRegions.push_back(std::move(r));
    } else if (keyword == "TETRA_PROPERTIES" || keyword == "CELL_PROPERTIES") {
        t.cellNames.clear();
        std::string_view tok;
        while (tokens.next(tok) && t.cellNames.size() < kMaxCellColumns) t.cellNames.push_back(toUtf8(unquote(tok)));
    } else if (keyword == "SURFACE") {
        t.surfaceNames.push_back(toUtf8(unquote(tokens.rest())));
    } else if (keyword == "TRGL") {
        if (t.surfaceNames.empty()) t.surfaceNames.push_back(unnamed);
        SurfaceTri tri;
        tri.line = lines.lineNo();
        tri.surface = t.surfaceNames.size() - 1;
        tri.tface = t.currentTface;
        for (auto& id : tri.ids)
            if (Status s = readId(lines, tokens, "TRGL vertex id", id); !s) return s;
        t.surfaceTris.push_back(tri);
    } else {
        static constexpr std::string_view kIgnored[] = {"MODEL", "KEYVERTICES", "BSTONE", "BORDER"};
        handled = std::find(std::begin(kIgnored), std::end(kIgnored), keyword) != std::end(kIgnored);
    }
    return {};
}

// The tetrahedra in world coordinates, their vertices welded by exact position.
struct WeldedTets {
    VolumeMesh vm;
    std::vector<std::uint32_t> weld;  // vertex as read -> welded vertex
    std::vector<float> props;         // per welded vertex: the properties of the first of its group
    std::size_t columns = 0;
    std::vector<std::uint32_t> byPos;  // welded vertices sorted by position (when columns > 0)

    // The welded vertex of vertex id `id`, named on line `atLine` by a `what` line.
    Result<std::uint32_t> vertexOf(const Lines& lines, std::size_t startLine, const VertexIds& ids, std::uint64_t id,
                                   std::size_t atLine, const char* what) const {
        const VertexIds::Key* k = ids.find(id);
        if (!k)
            return lines.failAt(atLine, std::string(what) + " refers to vertex id " + std::to_string(id) +
                                            ", which is not defined in the TSolid object that starts on line " +
                                            std::to_string(startLine));
        return weld[k->index];
    }
};

bool positionLess(const glm::dvec3& p, const glm::dvec3& q) {
    return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
}

Status weldTets(const Lines& lines, std::size_t startLine, const CoordinateSystem& crs, const TsolidText& t,
                WeldedTets& w) {
    std::vector<glm::dvec3> world(t.positions.size());
    for (std::size_t i = 0; i < t.positions.size(); ++i) world[i] = crs.toWorld(t.positions[i]);
    VolumeMesh& vm = w.vm;
    w.weld = weldExact(world, vm.positions);
    w.columns = t.schema.columnNames.size();
    const std::size_t columns = w.columns;
    if (columns > 0) {
        w.props.assign(vm.positions.size() * columns, std::numeric_limits<float>::quiet_NaN());
        std::vector<bool> set(vm.positions.size(), false);
        for (std::size_t v = 0; v < t.positions.size(); ++v) {
            if (set[w.weld[v]]) continue;
            set[w.weld[v]] = true;
            std::copy_n(t.schema.values.begin() + static_cast<std::ptrdiff_t>(v * columns), columns,
                        w.props.begin() + static_cast<std::ptrdiff_t>(w.weld[v] * columns));
        }
    }
    vm.cellTypes.reserve(t.tets.size());
    vm.cellOffsets.reserve(t.tets.size() + 1);
    vm.cellVertices.reserve(t.tets.size() * 4);
    vm.cellRegions.reserve(t.tets.size());
    vm.cellOffsets.push_back(0);
    for (const Tet& tet : t.tets) {
        for (std::uint64_t id : tet.ids) {
            auto v = w.vertexOf(lines, startLine, t.ids, id, tet.line, "TETRA");
            if (!v) return v.error();
            vm.cellVertices.push_back(v.value());
        }
        vm.cellTypes.push_back(VolumeMesh::CellType::Tetra);
        vm.cellOffsets.push_back(static_cast<std::uint32_t>(vm.cellVertices.size()));
        vm.cellRegions.push_back(tet.region);
    }
    w.byPos.resize(vm.positions.size());
    std::iota(w.byPos.begin(), w.byPos.end(), 0u);
    if (columns > 0)
        std::sort(w.byPos.begin(), w.byPos.end(),
                  [&](std::uint32_t a, std::uint32_t b) { return positionLess(vm.positions[a], vm.positions[b]); });
    return {};
}

using FaceKey = std::array<std::uint32_t, 3>;

FaceKey faceKey(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    FaceKey k{a, b, c};
    std::sort(k.begin(), k.end());
    return k;
}

// Regions of a TSolid without TVOLUME: from "# CTETRA" names, else grown from MODEL_REGION
// seeds (see the top of this file). Sets t.regionNames, each tet's region and the cells'.
Status assignRegions(Context& cx, std::size_t startLine, TsolidText& t, WeldedTets& w) {
    const Lines& lines = cx.lines;
    VolumeMesh& vm = w.vm;
    const std::size_t cells = t.tets.size();
    const bool named = std::any_of(t.ctetraRegion.begin(), t.ctetraRegion.end(), [](std::int32_t r) { return r >= 0; });
    if (t.sawTvolume || (!named && t.modelRegions.empty())) return {};
    std::vector<std::int32_t> region(cells, -1);
    std::vector<std::string> names;
    if (named) {
        names = t.ctetraNames;
        region = t.ctetraRegion;
    } else {
        // Faces of the tetrahedra, sorted, to find neighbours and the seeds' tetrahedra.
        std::vector<std::pair<FaceKey, std::uint32_t>> faces;
        faces.reserve(cells * 4);
        for (std::size_t c = 0; c < cells; ++c) {
            const std::uint32_t* v = &vm.cellVertices[c * 4];
            faces.push_back({faceKey(v[1], v[2], v[3]), std::uint32_t(c)});
            faces.push_back({faceKey(v[0], v[2], v[3]), std::uint32_t(c)});
            faces.push_back({faceKey(v[0], v[1], v[3]), std::uint32_t(c)});
            faces.push_back({faceKey(v[0], v[1], v[2]), std::uint32_t(c)});
        }
        std::sort(faces.begin(), faces.end());
        std::vector<FaceKey> walls;
        walls.reserve(t.surfaceTris.size());
        for (const SurfaceTri& tri : t.surfaceTris) {
            std::uint32_t v[3];
            for (int k = 0; k < 3; ++k) {
                auto r = w.vertexOf(lines, startLine, t.ids, tri.ids[k], tri.line, "TRGL");
                if (!r) return r.error();
                v[k] = r.value();
            }
            walls.push_back(faceKey(v[0], v[1], v[2]));
        }
        std::sort(walls.begin(), walls.end());
        auto isWall = [&](const FaceKey& k) { return std::binary_search(walls.begin(), walls.end(), k); };
        std::vector<std::array<std::uint32_t, 4>> next(cells, {kNone, kNone, kNone, kNone});
        std::vector<std::uint8_t> used(cells, 0);
        for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
            if (faces[i].first != faces[i + 1].first || isWall(faces[i].first)) continue;
            const std::uint32_t a = faces[i].second, b = faces[i + 1].second;
            if (used[a] < 4) next[a][used[a]++] = b;
            if (used[b] < 4) next[b][used[b]++] = a;
        }
        for (const ModelRegion& mr : t.modelRegions) {
            auto tri = std::find_if(t.surfaceTris.begin(), t.surfaceTris.end(),
                                    [&](const SurfaceTri& s) { return s.tface == mr.tface; });
            if (tri == t.surfaceTris.end())
                return lines.failAt(mr.line, "MODEL_REGION " + mr.name + " refers to TFACE " +
                                                 std::to_string(mr.tface) + ", which has no TRGL");
            std::uint32_t v[3];
            for (int k = 0; k < 3; ++k)
                v[k] = w.vertexOf(lines, startLine, t.ids, tri->ids[k], tri->line, "TRGL").value();
            const glm::dvec3 a = vm.positions[v[0]];
            const glm::dvec3 n = glm::cross(vm.positions[v[1]] - a, vm.positions[v[2]] - a);
            const FaceKey key = faceKey(v[0], v[1], v[2]);
            auto it = std::lower_bound(faces.begin(), faces.end(), std::make_pair(key, std::uint32_t(0)));
            std::uint32_t seed = kNone;
            for (; it != faces.end() && it->first == key; ++it) {
                const std::uint32_t* cv = &vm.cellVertices[std::size_t(it->second) * 4];
                std::uint32_t apex = cv[0];
                for (int k = 0; k < 4; ++k)
                    if (cv[k] != key[0] && cv[k] != key[1] && cv[k] != key[2]) apex = cv[k];
                const double side = glm::dot(n, vm.positions[apex] - a);
                if ((mr.positive && side > 0.0) || (!mr.positive && side < 0.0)) seed = it->second;
            }
            if (seed == kNone)
                return lines.failAt(mr.line, "MODEL_REGION " + mr.name + ": no tetrahedron lies on the " +
                                                 (mr.positive ? "+" : "-") + " side of the first TRGL of TFACE " +
                                                 std::to_string(mr.tface) + " (line " + std::to_string(tri->line) +
                                                 ")");
            if (region[seed] >= 0) {
                cx.warn(mr.line, "MODEL_REGION " + mr.name + " seeds a tetrahedron of region " +
                                     names[std::size_t(region[seed])] + ": read as that region");
                continue;
            }
            const auto r = static_cast<std::int32_t>(names.size());
            names.push_back(mr.name);
            std::vector<std::uint32_t> stack{seed};
            region[seed] = r;
            while (!stack.empty()) {
                const std::uint32_t c = stack.back();
                stack.pop_back();
                for (const std::uint32_t nb : next[c])
                    if (nb != kNone && region[nb] < 0) {
                        region[nb] = r;
                        stack.push_back(nb);
                    }
            }
        }
    }
    const std::size_t unassigned = static_cast<std::size_t>(std::count(region.begin(), region.end(), -1));
    if (unassigned > 0) {
        const std::string rest = "tetrahedra without a region";
        cx.warn(startLine, std::to_string(unassigned) + " of " + std::to_string(cells) +
                               " tetrahedra are in no region " +
                               (named ? "(no CTETRA line)" : "(no MODEL_REGION seed reaches them)") +
                               ": read as the region '" + rest + "'");
        for (auto& r : region)
            if (r < 0) r = static_cast<std::int32_t>(names.size());
        names.push_back(rest);
    }
    t.regionNames = std::move(names);
    for (std::size_t c = 0; c < cells; ++c) {
        t.tets[c].region = region[c];
        vm.cellRegions[c] = region[c];
    }
    return {};
}

// Per-region statistics of the cell values: volume-weighted mean, min, max of each column.
struct CellStats {
    std::vector<double> volume, sum, weight, lo, hi;

    CellStats(const TsolidText& t, const VolumeMesh& vm) {
        const std::size_t regions = t.regionNames.size(), columns = t.cellColumns;
        volume.assign(regions, 0.0);
        sum.assign(regions * columns, 0.0);
        weight.assign(regions * columns, 0.0);
        lo.assign(regions * columns, std::numeric_limits<double>::infinity());
        hi.assign(regions * columns, -std::numeric_limits<double>::infinity());
        for (std::size_t c = 0; c < t.tets.size(); ++c) {
            const double v = std::fabs(cellVolume(vm, c));
            const auto r = static_cast<std::size_t>(t.tets[c].region);
            volume[r] += v;
            for (std::size_t k = 0; k < columns; ++k) {
                const float x = t.cellValues[c * columns + k];
                if (std::isnan(x)) continue;
                sum[r * columns + k] += v * x;
                weight[r * columns + k] += v;
                lo[r * columns + k] = std::min(lo[r * columns + k], double(x));
                hi[r * columns + k] = std::max(hi[r * columns + k], double(x));
            }
        }
    }

    // extra["cell_properties"] of region `r`.
    nlohmann::ordered_json json(const TsolidText& t, std::size_t r) const {
        nlohmann::ordered_json cp = nlohmann::ordered_json::object();
        for (std::size_t k = 0; k < t.cellColumns; ++k) {
            const std::string name = k < t.cellNames.size() ? t.cellNames[k] : "cell_property_" + std::to_string(k + 1);
            const std::size_t i = r * t.cellColumns + k;
            if (weight[i] > 0.0)
                cp[name] = {{"mean", sum[i] / weight[i]}, {"min", lo[i]}, {"max", hi[i]}};
            else
                cp[name] = nullptr;
        }
        return cp;
    }
};

// Gives each shell vertex the properties of the welded vertex at its position.
void addShellProperties(const WeldedTets& w, const std::vector<std::string>& names, Mesh& mesh) {
    const std::size_t columns = w.columns;
    const VolumeMesh& vm = w.vm;
    mesh.propertyNames = names;
    mesh.propertyValues.reserve(mesh.positions.size() * columns);
    for (const glm::dvec3& p : mesh.positions) {
        auto it = std::lower_bound(w.byPos.begin(), w.byPos.end(), p, [&](std::uint32_t a, const glm::dvec3& q) {
            return positionLess(vm.positions[a], q);
        });
        GS_ASSERT(it != w.byPos.end() && vm.positions[*it] == p, "a shell vertex is a mesh vertex");
        mesh.propertyValues.insert(mesh.propertyValues.end(),
                                   w.props.begin() + static_cast<std::ptrdiff_t>(*it * columns),
                                   w.props.begin() + static_cast<std::ptrdiff_t>((*it + 1) * columns));
    }
}

// One body per region with tetrahedra: its boundary, properties and record.
void addBodies(Context& cx, const TsolidText& t, const WeldedTets& w, std::vector<Mesh>& shells) {
    const CellStats stats(t, w.vm);
    for (std::size_t r = 0; r < t.regionNames.size(); ++r) {
        Mesh& mesh = shells[r];
        if (mesh.indices.empty()) continue;
        if (w.columns > 0) addShellProperties(w, t.schema.columnNames, mesh);
        AttributeRecord rec;
        rec.name = t.regionNames[r];
        rec.kind = "body";
        rec.extra["tetrahedra_volume_m3"] = stats.volume[r];
        if (t.cellColumns > 0) rec.extra["cell_properties"] = stats.json(t, r);
        Part part;
        part.name = t.regionNames[r];
        part.kind = PartKind::Body;
        part.mesh = std::move(mesh);
        part.record = cx.model.attributes.add(std::move(rec));
        cx.model.bodies.push_back(std::move(part));
        cx.declaredVolumes = true;
    }
}

// The object's surfaces (SURFACE / TRGL), by vertex ids.
Status addSurfaces(Context& cx, std::size_t startLine, const TsolidText& t, const WeldedTets& w) {
    std::vector<std::vector<std::uint32_t>> surfaceIndices(t.surfaceNames.size());
    for (const SurfaceTri& tri : t.surfaceTris)
        for (std::uint64_t id : tri.ids) {
            auto v = w.vertexOf(cx.lines, startLine, t.ids, id, tri.line, "TRGL");
            if (!v) return v.error();
            surfaceIndices[tri.surface].push_back(v.value());
        }
    std::vector<std::uint32_t> local(w.vm.positions.size(), kNone);
    for (std::size_t s = 0; s < t.surfaceNames.size(); ++s) {
        if (surfaceIndices[s].empty()) continue;
        Part part;
        part.name = t.surfaceNames[s].empty() ? "surface_" + std::to_string(s + 1) : t.surfaceNames[s];
        part.kind = PartKind::Surface;
        for (std::uint32_t v : surfaceIndices[s]) {
            if (local[v] == kNone) {
                local[v] = static_cast<std::uint32_t>(part.mesh.positions.size());
                part.mesh.positions.push_back(w.vm.positions[v]);
            }
            part.mesh.indices.push_back(local[v]);
        }
        for (std::uint32_t v : surfaceIndices[s]) local[v] = kNone;
        AttributeRecord rec;
        rec.name = part.name;
        rec.kind = "surface";
        part.record = cx.model.attributes.add(std::move(rec));
        cx.model.surfaces.push_back(std::move(part));
    }
    return {};
}

}  // namespace

Status readTsolid(Context& cx, std::size_t startLine) {
    Lines& lines = cx.lines;
    ObjectInfo info;
    info.crs = cx.fileCrs;
    TsolidText t;
    auto own = [&](Lines::Statement& st, bool& handled) { return readTsolidKeyword(cx, info, st, t, handled); };
    const KeywordReader vertices = vertexKeywords(cx, "TSolid", t.schema, t.ids, t.positions);
    if (Status s = readObjectBody(cx, info, "TSolid object", startLine, own, vertices); !s) return s;
    if (Status s = t.ids.resolve(lines); !s) return s;
    if (t.tets.empty()) {
        cx.warn(startLine, "the TSolid object has no TETRA: no body");
        return {};
    }
    WeldedTets w;
    if (Status s = weldTets(lines, startLine, info.crs, t, w); !s) return s;
    if (Status s = assignRegions(cx, startLine, t, w); !s) return s;
    auto shells = regionBoundaries(w.vm, t.regionNames.size());
    if (!shells) return lines.failAt(startLine, "TSolid: " + shells.error().message);
    addBodies(cx, t, w, shells.value());
    return addSurfaces(cx, startLine, t, w);
}

}  // namespace geoslice::gocad
