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

}  // namespace

Status readTsolid(Context& cx, std::size_t startLine) {
    Lines& lines = cx.lines;
    ObjectInfo info;
    info.crs = cx.fileCrs;
    PropertySchema schema;
    VertexIds ids;
    std::vector<glm::dvec3> positions;
    std::vector<Tet> tets;
    std::vector<std::string> regionNames;
    std::vector<std::string> cellNames;
    std::vector<float> cellValues;  // cellNames.size() per tet (when any)
    std::size_t cellColumns = 0;
    std::vector<std::string> surfaceNames;
    std::vector<SurfaceTri> surfaceTris;

    auto own = [&](Lines::Statement& st, bool& handled) -> Status {
        const std::string_view keyword = st.keyword;
        Tokens& tokens = st.tokens;
        if (keyword == "TVOLUME") {
            regionNames.push_back(toUtf8(unquote(tokens.rest())));
            if (regionNames.back().empty()) regionNames.back() = "region_" + std::to_string(regionNames.size());
        } else if (keyword == "TETRA") {
            Tet tet;
            tet.line = lines.lineNo();
            for (auto& id : tet.ids)
                if (Status s = readId(lines, tokens, "TETRA vertex id", id); !s) return s;
            if (regionNames.empty()) regionNames.push_back(info.name.empty() ? cx.model.name : info.name);
            tet.region = static_cast<std::int32_t>(regionNames.size() - 1);
            // Cell values after the four ids.
            std::string_view tok;
            std::size_t found = 0;
            const std::size_t before = cellValues.size();
            while (tokens.next(tok)) {
                std::optional<double> v = parseDouble(tok);
                if (!v) return lines.fail("TETRA cell value " + quoteToken(tok) + " is not a number");
                if (++found > kMaxCellColumns)
                    return lines.fail("more than " + std::to_string(kMaxCellColumns) + " values on a TETRA line");
                const bool ok = std::isfinite(*v) && std::fabs(*v) <= std::numeric_limits<float>::max();
                cellValues.push_back(ok ? static_cast<float>(*v) : std::numeric_limits<float>::quiet_NaN());
            }
            if (tets.empty()) cellColumns = found;
            if (found != cellColumns) {
                cellValues.resize(before);
                return lines.fail("TETRA has " + std::to_string(found) + " cell values, the first TETRA had " +
                                  std::to_string(cellColumns));
            }
            tets.push_back(tet);
        } else if (keyword == "TETRA_PROPERTIES" || keyword == "CELL_PROPERTIES") {
            cellNames.clear();
            std::string_view tok;
            while (tokens.next(tok) && cellNames.size() < kMaxCellColumns) cellNames.push_back(toUtf8(unquote(tok)));
        } else if (keyword == "SURFACE") {
            surfaceNames.push_back(toUtf8(unquote(tokens.rest())));
        } else if (keyword == "TRGL") {
            if (surfaceNames.empty()) surfaceNames.push_back(info.name.empty() ? cx.model.name : info.name);
            SurfaceTri tri;
            tri.line = lines.lineNo();
            tri.surface = surfaceNames.size() - 1;
            for (auto& id : tri.ids)
                if (Status s = readId(lines, tokens, "TRGL vertex id", id); !s) return s;
            surfaceTris.push_back(tri);
        } else {
            static constexpr std::string_view kIgnored[] = {"MODEL",  "TFACE",  "KEYVERTICES", "MODEL_REGION",
                                                            "BSTONE", "BORDER", "CTETRA"};
            handled = std::find(std::begin(kIgnored), std::end(kIgnored), keyword) != std::end(kIgnored);
        }
        return {};
    };
    const KeywordReader vertices = vertexKeywords(cx, "TSolid", schema, ids, positions);
    if (Status s = readObjectBody(cx, info, "TSolid object", startLine, own, vertices); !s) return s;
    if (Status s = ids.resolve(lines); !s) return s;
    if (tets.empty()) {
        cx.warn(startLine, "the TSolid object has no TETRA: no body");
        return {};
    }

    // World positions, welded by exact position; properties of the first of each group.
    std::vector<glm::dvec3> world(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) world[i] = info.crs.toWorld(positions[i]);
    VolumeMesh vm;
    const std::vector<std::uint32_t> weld = weldExact(world, vm.positions);
    const std::size_t columns = schema.columnNames.size();
    std::vector<float> weldedProps;
    if (columns > 0) {
        weldedProps.assign(vm.positions.size() * columns, std::numeric_limits<float>::quiet_NaN());
        std::vector<bool> set(vm.positions.size(), false);
        for (std::size_t v = 0; v < positions.size(); ++v) {
            if (set[weld[v]]) continue;
            set[weld[v]] = true;
            std::copy_n(schema.values.begin() + static_cast<std::ptrdiff_t>(v * columns), columns,
                        weldedProps.begin() + static_cast<std::ptrdiff_t>(weld[v] * columns));
        }
    }
    auto vertexOf = [&](std::uint64_t id, std::size_t atLine, const char* what) -> Result<std::uint32_t> {
        const VertexIds::Key* k = ids.find(id);
        if (!k)
            return lines.failAt(atLine, std::string(what) + " refers to vertex id " + std::to_string(id) +
                                            ", which is not defined in the TSolid object that starts on line " +
                                            std::to_string(startLine));
        return weld[k->index];
    };
    vm.cellTypes.reserve(tets.size());
    vm.cellOffsets.reserve(tets.size() + 1);
    vm.cellVertices.reserve(tets.size() * 4);
    vm.cellRegions.reserve(tets.size());
    vm.cellOffsets.push_back(0);
    for (const Tet& t : tets) {
        for (std::uint64_t id : t.ids) {
            auto v = vertexOf(id, t.line, "TETRA");
            if (!v) return v.error();
            vm.cellVertices.push_back(v.value());
        }
        vm.cellTypes.push_back(VolumeMesh::CellType::Tetra);
        vm.cellOffsets.push_back(static_cast<std::uint32_t>(vm.cellVertices.size()));
        vm.cellRegions.push_back(t.region);
    }
    auto shells = regionBoundaries(vm, regionNames.size());
    if (!shells) return lines.failAt(startLine, "TSolid: " + shells.error().message);

    // Per-region cell statistics: volume-weighted mean, min, max of each cell column.
    const std::size_t regions = regionNames.size();
    std::vector<double> volume(regions, 0.0);
    std::vector<double> sum(regions * cellColumns, 0.0), weight(regions * cellColumns, 0.0);
    std::vector<double> lo(regions * cellColumns, std::numeric_limits<double>::infinity());
    std::vector<double> hi(regions * cellColumns, -std::numeric_limits<double>::infinity());
    for (std::size_t c = 0; c < tets.size(); ++c) {
        const double v = std::fabs(cellVolume(vm, c));
        const auto r = static_cast<std::size_t>(tets[c].region);
        volume[r] += v;
        for (std::size_t k = 0; k < cellColumns; ++k) {
            const float x = cellValues[c * cellColumns + k];
            if (std::isnan(x)) continue;
            sum[r * cellColumns + k] += v * x;
            weight[r * cellColumns + k] += v;
            lo[r * cellColumns + k] = std::min(lo[r * cellColumns + k], double(x));
            hi[r * cellColumns + k] = std::max(hi[r * cellColumns + k], double(x));
        }
    }

    // Sorted welded positions, to find each shell vertex's properties.
    std::vector<std::uint32_t> byPos(vm.positions.size());
    std::iota(byPos.begin(), byPos.end(), 0u);
    auto less = [&](const glm::dvec3& p, const glm::dvec3& q) {
        return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
    };
    if (columns > 0)
        std::sort(byPos.begin(), byPos.end(),
                  [&](std::uint32_t a, std::uint32_t b) { return less(vm.positions[a], vm.positions[b]); });

    for (std::size_t r = 0; r < regions; ++r) {
        Mesh& mesh = shells.value()[r];
        if (mesh.indices.empty()) continue;
        if (columns > 0) {
            mesh.propertyNames = schema.columnNames;
            mesh.propertyValues.reserve(mesh.positions.size() * columns);
            for (const glm::dvec3& p : mesh.positions) {
                auto it = std::lower_bound(byPos.begin(), byPos.end(), p, [&](std::uint32_t a, const glm::dvec3& q) {
                    return less(vm.positions[a], q);
                });
                GS_ASSERT(it != byPos.end() && vm.positions[*it] == p, "a shell vertex is a mesh vertex");
                mesh.propertyValues.insert(mesh.propertyValues.end(),
                                           weldedProps.begin() + static_cast<std::ptrdiff_t>(*it * columns),
                                           weldedProps.begin() + static_cast<std::ptrdiff_t>((*it + 1) * columns));
            }
        }
        AttributeRecord rec;
        rec.name = regionNames[r];
        rec.kind = "body";
        rec.extra["tetrahedra_volume_m3"] = volume[r];
        if (cellColumns > 0) {
            nlohmann::ordered_json cp = nlohmann::ordered_json::object();
            for (std::size_t k = 0; k < cellColumns; ++k) {
                const std::string name = k < cellNames.size() ? cellNames[k] : "cell_property_" + std::to_string(k + 1);
                const std::size_t i = r * cellColumns + k;
                if (weight[i] > 0.0)
                    cp[name] = {{"mean", sum[i] / weight[i]}, {"min", lo[i]}, {"max", hi[i]}};
                else
                    cp[name] = nullptr;
            }
            rec.extra["cell_properties"] = std::move(cp);
        }
        Part part;
        part.name = regionNames[r];
        part.kind = PartKind::Body;
        part.mesh = std::move(mesh);
        part.record = cx.model.attributes.add(std::move(rec));
        cx.model.bodies.push_back(std::move(part));
        cx.declaredVolumes = true;
    }

    // The object's surfaces, by vertex ids.
    std::vector<std::vector<std::uint32_t>> surfaceIndices(surfaceNames.size());
    for (const SurfaceTri& t : surfaceTris)
        for (std::uint64_t id : t.ids) {
            auto v = vertexOf(id, t.line, "TRGL");
            if (!v) return v.error();
            surfaceIndices[t.surface].push_back(v.value());
        }
    std::vector<std::uint32_t> local(vm.positions.size(), std::numeric_limits<std::uint32_t>::max());
    for (std::size_t s = 0; s < surfaceNames.size(); ++s) {
        if (surfaceIndices[s].empty()) continue;
        Part part;
        part.name = surfaceNames[s].empty() ? "surface_" + std::to_string(s + 1) : surfaceNames[s];
        part.kind = PartKind::Surface;
        for (std::uint32_t v : surfaceIndices[s]) {
            if (local[v] == std::numeric_limits<std::uint32_t>::max()) {
                local[v] = static_cast<std::uint32_t>(part.mesh.positions.size());
                part.mesh.positions.push_back(vm.positions[v]);
            }
            part.mesh.indices.push_back(local[v]);
        }
        for (std::uint32_t v : surfaceIndices[s]) local[v] = std::numeric_limits<std::uint32_t>::max();
        AttributeRecord rec;
        rec.name = part.name;
        rec.kind = "surface";
        part.record = cx.model.attributes.add(std::move(rec));
        cx.model.surfaces.push_back(std::move(part));
    }
    return {};
}

}  // namespace geoslice::gocad
