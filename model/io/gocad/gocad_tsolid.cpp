// GOCAD TSolid and LightTSolid (.so): tetrahedra. TVOLUME name starts a region; VRTX /
// PVRTX / ATOM define vertices (ids shared by the whole object, ATOMs alias a vertex);
// TETRA a b c d [cell values] adds a cell to the current region (LightTSolid: one region,
// named after the object). After MODEL, SURFACE / TFACE / TRGL list the object's surfaces
// by vertex ids; MODEL_REGION lines are not needed (the tetrahedra say which region is
// where) and are skipped.
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

struct Tet {
    std::uint64_t ids[4] = {0, 0, 0, 0};
    std::int32_t region = 0;
    std::size_t line = 0;
};

struct SurfaceTri {
    std::uint64_t ids[3] = {0, 0, 0};
    std::size_t line = 0;
    std::size_t surface = 0;
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
        t.regionNames.push_back(toUtf8(unquote(tokens.rest())));
        if (t.regionNames.back().empty()) t.regionNames.back() = "region_" + std::to_string(t.regionNames.size());
    } else if (keyword == "TETRA") {
        return readTetra(lines, tokens, unnamed, t);
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
        for (auto& id : tri.ids)
            if (Status s = readId(lines, tokens, "TRGL vertex id", id); !s) return s;
        t.surfaceTris.push_back(tri);
    } else {
        static constexpr std::string_view kIgnored[] = {"MODEL",  "TFACE",  "KEYVERTICES", "MODEL_REGION",
                                                        "BSTONE", "BORDER", "CTETRA"};
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
    auto shells = regionBoundaries(w.vm, t.regionNames.size());
    if (!shells) return lines.failAt(startLine, "TSolid: " + shells.error().message);
    addBodies(cx, t, w, shells.value());
    return addSurfaces(cx, startLine, t, w);
}

}  // namespace geoslice::gocad
