// VTK XML UnstructuredGrid (.vtu) reading: the cells -> a model. Cell types (linear and
// quadratic tetrahedra, hexahedra, voxels, wedges, pyramids; lower-dimensional cells
// skipped), the formation array and record ids, one closed body per formation
// (regionBoundaries), cell arrays constant over a formation -> its record, point arrays ->
// per-vertex properties. Part of the reader in model/io/vtu/vtu_reader.hpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "model/io/vtu/vtu_reader.hpp"
#include "model/mesh/volume_mesh.hpp"

namespace geoslice::vtu {
namespace {

// Largest formation value used directly as a record id (ids stay readable, and far from
// the 32-bit limit of RecordId).
constexpr std::int64_t kMaxDirectRecordId = 1000000000;

// The .vtu's cells as a VolumeMesh (region indices filled by the caller).
struct CellCensus {
    std::size_t lowerDimensional = 0;  // types 1-9
    std::size_t quadratic = 0;         // types 24-27 taken as linear
};

}  // namespace

Result<Model> VtuReader::buildModel() {
    // Cells -> VolumeMesh cells; which cells are kept.
    VolumeMesh vm;
    vm.positions = std::move(points_);
    CellCensus census;
    std::vector<std::uint32_t> keptCells;  // input cell index of each VolumeMesh cell
    vm.cellOffsets.push_back(0);
    std::int64_t begin = 0;
    for (std::size_t c = 0; c < types_.size(); ++c) {
        const std::int64_t end = offsets_[c];
        const std::size_t n = static_cast<std::size_t>(end - begin);
        const std::int64_t* v = connectivity_.data() + begin;
        const int t = types_[c];
        auto bad = [&](std::size_t need) {
            return fail("cell " + std::to_string(c) + " of type " + std::to_string(t) + " has " + std::to_string(n) +
                        " vertices, not " + std::to_string(need));
        };
        VolumeMesh::CellType ct{};
        std::size_t corners = 0;
        const std::int64_t* order = nullptr;
        static const std::int64_t kVoxelToHex[8] = {0, 1, 3, 2, 4, 5, 7, 6};
        switch (t) {
            case 10:
                ct = VolumeMesh::CellType::Tetra, corners = 4;
                break;
            case 11:
                ct = VolumeMesh::CellType::Hexahedron, corners = 8, order = kVoxelToHex;
                break;
            case 12:
                ct = VolumeMesh::CellType::Hexahedron, corners = 8;
                break;
            case 13:
                ct = VolumeMesh::CellType::Wedge, corners = 6;
                break;
            case 14:
                ct = VolumeMesh::CellType::Pyramid, corners = 5;
                break;
            case 24:
                ct = VolumeMesh::CellType::Tetra, corners = 4;
                break;  // quadratic: 10 nodes
            case 25:
                ct = VolumeMesh::CellType::Hexahedron, corners = 8;
                break;  // 20
            case 26:
                ct = VolumeMesh::CellType::Wedge, corners = 6;
                break;  // 15
            case 27:
                ct = VolumeMesh::CellType::Pyramid, corners = 5;
                break;  // 13
            default:
                if (t >= 1 && t <= 9) {
                    ++census.lowerDimensional;
                    begin = end;
                    continue;
                }
                return fail("cell " + std::to_string(c) + " has VTK type " + std::to_string(t) +
                                (t == 42 ? " (polyhedron)" : "") +
                                ", which is not read (tetrahedra, hexahedra, voxels, wedges and pyramids are); "
                                "dropping it would change the volume",
                            ErrorCode::Unsupported);
        }
        static const std::size_t kQuadraticNodes[] = {10, 20, 15, 13};
        const std::size_t need = t >= 24 ? kQuadraticNodes[t - 24] : corners;
        if (n != need) return bad(need);
        if (t >= 24) ++census.quadratic;
        vm.cellTypes.push_back(ct);
        for (std::size_t k = 0; k < corners; ++k)
            vm.cellVertices.push_back(static_cast<std::uint32_t>(v[order ? order[k] : std::int64_t(k)]));
        if (vm.cellVertices.size() >= std::numeric_limits<std::uint32_t>::max())
            return fail("more cell vertices than 32-bit offsets can address");
        vm.cellOffsets.push_back(static_cast<std::uint32_t>(vm.cellVertices.size()));
        keptCells.push_back(static_cast<std::uint32_t>(c));
        begin = end;
    }
    if (begin != static_cast<std::int64_t>(connectivity_.size()))
        return fail("the cells' offsets end at " + std::to_string(begin) + " but connectivity has " +
                    std::to_string(connectivity_.size()) + " values");
    if (vm.cellTypes.empty())
        return fail("no volume cells (tetrahedra, hexahedra, wedges, pyramids) in " + std::to_string(types_.size()) +
                        " cells; a .vtu of surfaces or points is not a volume model",
                    ErrorCode::Unsupported);
    connectivity_ = {};
    offsets_ = {};

    // The formation array.
    const CellArray* region = nullptr;
    if (!options_.regionArray.empty()) {
        for (const auto& a : cellArrays_)
            if (a.name == options_.regionArray) region = &a;
        if (!region) {
            std::string names;
            for (const auto& a : cellArrays_)
                names += (names.empty() ? "" : ", ") + std::string("'") + printable(a.name) + "'";
            return fail("no cell-data array named '" + printable(options_.regionArray) + "' (the file has " +
                            (names.empty() ? std::string("none") : names) + ")",
                        ErrorCode::NotFound);
        }
        if (region->components != 1)
            return fail("cell-data array '" + printable(region->name) + "' has " + std::to_string(region->components) +
                            " components; a formation array has one",
                        ErrorCode::InvalidArgument);
    } else {
        for (const auto& a : cellArrays_)
            if (a.components == 1 && a.integerType) {
                region = &a;
                break;
            }
        if (!region)
            for (const auto& a : cellArrays_)
                if (a.components == 1 && std::all_of(a.values.begin(), a.values.end(), [](double x) {
                        return std::isfinite(x) && x == std::floor(x) && std::abs(x) < 9e15;
                    })) {
                    region = &a;
                    break;
                }
    }
    // Formation value of each kept cell -> region index (sorted by value).
    std::vector<std::int64_t> values;
    vm.cellRegions.resize(keptCells.size(), 0);
    std::vector<std::int64_t> cellValue(keptCells.size(), 0);
    if (region) {
        for (std::size_t i = 0; i < keptCells.size(); ++i) {
            const double x = region->values[keptCells[i]];
            if (!std::isfinite(x) || x != std::floor(x) || std::abs(x) >= 9e15)
                return fail("cell-data array '" + printable(region->name) + "': cell " + std::to_string(keptCells[i]) +
                            " has value " + std::to_string(x) + ", not a whole number naming a formation");
            cellValue[i] = static_cast<std::int64_t>(x);
        }
        values = cellValue;
        std::sort(values.begin(), values.end());
        values.erase(std::unique(values.begin(), values.end()), values.end());
        for (std::size_t i = 0; i < keptCells.size(); ++i)
            vm.cellRegions[i] = static_cast<std::int32_t>(std::lower_bound(values.begin(), values.end(), cellValue[i]) -
                                                          values.begin());
    } else {
        values = {1};
    }
    if (values.size() > 1000000)
        return fail("cell-data array '" + printable(region->name) + "' has " + std::to_string(values.size()) +
                        " distinct values; a formation array has few (choose another with --region-array)",
                    ErrorCode::InvalidArgument);

    auto boundaries = regionBoundaries(vm, values.size());
    if (!boundaries) return fail(boundaries.error().message, boundaries.error().code);

    Model model;
    model.source = source_;
    const bool direct = region && values.front() >= 1 && values.back() <= kMaxDirectRecordId;
    const std::string arrayName = region ? region->name : std::string("formation");
    model.notes["vtu_region_array"] = region ? region->name : std::string("(none: one formation)");
    if (region && !direct)
        model.notes["vtu_record_ids"] = "formation values are not all in [1, " + std::to_string(kMaxDirectRecordId) +
                                        "]: record ids are their ranks 1.." + std::to_string(values.size());
    if (census.lowerDimensional)
        model.notes["vtu_skipped_cells"] =
            std::to_string(census.lowerDimensional) + " point, line and face cells skipped";
    if (census.quadratic)
        model.notes["vtu_quadratic_cells"] =
            std::to_string(census.quadratic) + " quadratic cells taken as linear (mid-edge nodes ignored)";

    // Position -> input point, for point data on boundary vertices (regionBoundaries
    // renumbers each region's vertices; equal positions carry the first point's values).
    std::unordered_map<std::string_view, std::uint32_t> pointOf;
    std::vector<const CellArray*> pointFields;
    for (const auto& a : pointArrays_)
        if (a.values.size() == a.components * vm.positions.size()) pointFields.push_back(&a);
    if (!pointFields.empty()) {
        pointOf.reserve(vm.positions.size());
        for (std::size_t i = 0; i < vm.positions.size(); ++i)
            pointOf.emplace(std::string_view(reinterpret_cast<const char*>(&vm.positions[i]), sizeof(glm::dvec3)),
                            static_cast<std::uint32_t>(i));
    }

    for (std::size_t r = 0; r < values.size(); ++r) {
        Mesh& mesh = boundaries.value()[r];
        if (mesh.indices.empty()) continue;
        Part part;
        part.name = region ? arrayName + " " + std::to_string(values[r]) : std::string("cells");
        part.kind = PartKind::Body;
        part.kindDeclared = true;  // cells are a volume: a shell that cannot be closed is an error
        AttributeRecord rec;
        rec.id = direct ? static_cast<RecordId>(values[r]) : static_cast<RecordId>(r + 1);
        rec.name = part.name;
        rec.kind = "formation";
        if (region) rec.extra[region->name] = values[r];
        part.record = rec.id;
        model.attributes.put(std::move(rec));
        if (!pointFields.empty()) {
            for (const CellArray* a : pointFields)
                for (std::size_t k = 0; k < a->components; ++k)
                    mesh.propertyNames.push_back(a->components == 1 ? a->name
                                                                    : a->name + "[" + std::to_string(k) + "]");
            mesh.propertyValues.reserve(mesh.positions.size() * mesh.propertyNames.size());
            for (const glm::dvec3& p : mesh.positions) {
                auto it = pointOf.find(std::string_view(reinterpret_cast<const char*>(&p), sizeof(glm::dvec3)));
                const std::uint32_t src = it == pointOf.end() ? 0 : it->second;
                for (const CellArray* a : pointFields)
                    for (std::size_t k = 0; k < a->components; ++k)
                        mesh.propertyValues.push_back(static_cast<float>(a->values[src * a->components + k]));
            }
        }
        part.mesh = std::move(mesh);
        model.bodies.push_back(std::move(part));
    }
    // A body's formation index (into `values`), from its record id.
    auto formationOf = [&](const Part& part) {
        return direct ? static_cast<std::size_t>(
                            std::lower_bound(values.begin(), values.end(), std::int64_t(part.record)) - values.begin())
                      : static_cast<std::size_t>(part.record - 1);
    };
    // Cell arrays constant over a formation -> that formation's record.
    for (const auto& a : cellArrays_) {
        if (&a == region || a.components != 1) continue;
        std::vector<double> first(values.size(), std::numeric_limits<double>::quiet_NaN());
        std::vector<char> constant(values.size(), 1);
        for (std::size_t i = 0; i < keptCells.size(); ++i) {
            const std::size_t r = static_cast<std::size_t>(vm.cellRegions[i]);
            const double x = a.values[keptCells[i]];
            if (std::isnan(first[r]))
                first[r] = x;
            else if (first[r] != x)
                constant[r] = 0;
        }
        for (auto& part : model.bodies) {
            const std::size_t r = formationOf(part);
            if (!constant[r] || !std::isfinite(first[r])) continue;
            if (AttributeRecord* rec = model.attributes.find(part.record)) rec->extra[a.name] = first[r];
        }
    }
    // Formation names (the part's and the record's): a CellData string array constant over
    // every formation (arrays named like "name" or "formation" first), else a FieldData string
    // array indexed by the formation value (values 0..n-1 index it from 0, values 1..n from 1,
    // arrays named like "name" or "formation" first); a name two formations share keeps the
    // value beside it.
    if (region) {
        auto preferred = [](const std::string& name) {
            const std::string l = text::lower(name);
            return l.find("name") != std::string::npos || l.find("formation") != std::string::npos;
        };
        std::vector<std::string> names(values.size());
        std::string source;
        for (int pass = 0; pass < 2 && source.empty(); ++pass)
            for (const StringArray& a : cellStrings_) {
                if (preferred(a.name) != (pass == 0) || a.values.size() != types_.size()) continue;
                std::vector<std::string> first(values.size());
                std::vector<char> seen(values.size(), 0);
                bool constant = true;
                for (std::size_t i = 0; i < keptCells.size() && constant; ++i) {
                    const auto r = static_cast<std::size_t>(vm.cellRegions[i]);
                    const std::string& v = a.values[keptCells[i]];
                    if (!seen[r]) {
                        first[r] = v;
                        seen[r] = 1;
                    } else if (first[r] != v) {
                        constant = false;
                    }
                }
                if (!constant ||
                    std::any_of(first.begin(), first.end(), [](const std::string& s) { return trimSpace(s).empty(); }))
                    continue;
                names = std::move(first);
                source = "file (.vtu cell array '" + a.name + "')";
                break;
            }
        for (int pass = 0; pass < 2 && source.empty(); ++pass)
            for (const StringArray& a : fieldStrings_) {
                if (preferred(a.name) != (pass == 0)) continue;
                const auto n = static_cast<std::int64_t>(a.values.size());
                const std::int64_t base = values.front() >= 0 && values.back() < n    ? 0
                                          : values.front() >= 1 && values.back() <= n ? 1
                                                                                      : -1;
                if (base < 0) continue;
                for (std::size_t r = 0; r < values.size(); ++r)
                    names[r] = a.values[static_cast<std::size_t>(values[r] - base)];
                if (std::any_of(names.begin(), names.end(), [](const std::string& s) { return trimSpace(s).empty(); }))
                    continue;
                source = "file (.vtu field array '" + a.name + "', by " + region->name + (base ? " - 1" : "") + ")";
                break;
            }
        if (!source.empty()) {
            std::map<std::string, int> uses;
            for (const std::string& n : names) ++uses[std::string(trimSpace(n))];
            for (auto& part : model.bodies) {
                const std::size_t r = formationOf(part);
                if (r >= names.size()) continue;
                const std::string name(trimSpace(names[r]));
                part.name = uses[name] > 1 ? name + " (" + region->name + " " + std::to_string(values[r]) + ")" : name;
                if (AttributeRecord* rec = model.attributes.find(part.record)) {
                    rec->name = part.name;
                    rec->nameSource = source;
                }
            }
            model.notes["vtu_formation_names"] = source.substr(6, source.size() - 7);
        }
    }
    // A per-cell colour array (3 or 4 components, named like colour / color / rgb): a
    // formation takes the colour of its first cell (0..1 floats or 0..255).
    for (const auto& a : cellArrays_) {
        const std::string lowered = text::lower(a.name);
        if ((a.components != 3 && a.components != 4) ||
            (lowered.find("colo") == std::string::npos && lowered.find("rgb") == std::string::npos))
            continue;
        std::vector<std::size_t> firstCell(values.size(), keptCells.size());
        for (std::size_t i = 0; i < keptCells.size(); ++i) {
            const auto r = static_cast<std::size_t>(vm.cellRegions[i]);
            if (firstCell[r] == keptCells.size()) firstCell[r] = i;
        }
        for (auto& part : model.bodies) {
            const std::size_t r = formationOf(part);
            if (r >= firstCell.size() || firstCell[r] == keptCells.size()) continue;
            std::string text;
            for (std::size_t k = 0; k < a.components; ++k)
                text += std::to_string(a.values[keptCells[firstCell[r]] * a.components + k]) + " ";
            AttributeRecord* rec = model.attributes.find(part.record);
            if (!rec) continue;
            if (const std::optional<Rgba8> c = parseColour(text)) {
                rec->colour = *c;
                rec->colourSource = "file (.vtu cell array '" + a.name + "')";
            }
        }
        break;
    }
    finishLoadedModel(model, /*classifyByClosure=*/false);
    return model;
}

}  // namespace geoslice::vtu
