// Geo3DML reading: volumes -> cells of a VolumeMesh. GeoTetrahedronVolume, GeoCuboidVolume,
// GeoTriangularPrismVolume, GeoTruncatedRegularGrid (faces by vertex, cells by face) and
// gml:RectifiedGrid (the parallelepiped its limits span). Part of the reader in
// model/io/geo3dml/geo3dml_reader.hpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "model/io/geo3dml/geo3dml_reader.hpp"

namespace geoslice::geo3dml {
namespace {

// The 2k vertices of a prism-like cell (hexahedron: k = 4, wedge: k = 3) given by its
// k + 2 faces, in VTK order: a k-gon face, then for each of its vertices the vertex it is
// joined to by a side face. nullopt when the faces do not bound such a cell.
std::optional<std::vector<std::uint32_t>> prismFromFaces(const std::vector<std::vector<std::uint32_t>>& faces) {
    if (faces.size() != 5 && faces.size() != 6) return std::nullopt;
    const std::size_t k = faces.size() - 2;
    const std::vector<std::uint32_t>* bottom = nullptr;
    for (const auto& f : faces)
        if (f.size() == k) {
            bottom = &f;
            break;
        }
    if (!bottom) return std::nullopt;
    auto inBottom = [&](std::uint32_t v) { return std::find(bottom->begin(), bottom->end(), v) != bottom->end(); };
    std::vector<std::uint32_t> cell(*bottom);
    for (std::size_t i = 0; i < k; ++i) {
        const std::uint32_t b = (*bottom)[i];
        std::optional<std::uint32_t> partner;
        for (const auto& f : faces) {
            if (&f == bottom || f.size() != 4) continue;
            for (std::size_t j = 0; j < 4 && !partner; ++j) {
                if (f[j] != b) continue;
                for (const std::uint32_t n : {f[(j + 1) % 4], f[(j + 3) % 4]})
                    if (!inBottom(n)) partner = n;
            }
            if (partner) break;
        }
        if (!partner) return std::nullopt;
        cell.push_back(*partner);
    }
    std::vector<std::uint32_t> sorted(cell);
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return std::nullopt;
    return cell;
}

// Whole-number tokens of an index list (VertexList, FaceList, TopTriangle...); "" or what
// is wrong.
std::string readIndices(pugi::xml_node list, std::vector<std::uint64_t>& out) {
    out.clear();
    std::string problem;
    forEachToken(textOf(list), [&](std::string_view token) {
        const std::optional<std::int64_t> value = text::parseNumber<std::int64_t>(token);
        if (!value || *value < 0) {
            problem = "'" + quoted(token) + "' is not an index";
            return false;
        }
        out.push_back(static_cast<std::uint64_t>(*value));
        return out.size() <= 64;  // no cell has more
    });
    return problem;
}

// Exactly three tokens in the text of n, as whole numbers (T integral) or finite numbers
// (T = double), into out; false otherwise.
template <class T>
bool readThree(pugi::xml_node n, std::array<T, 3>& out) {
    std::size_t k = 0;
    forEachToken(textOf(n), [&](std::string_view t) {
        std::optional<T> v;
        if constexpr (std::is_floating_point_v<T>) {
            v = text::parseXsDouble(t);
            if (v && !std::isfinite(*v)) v.reset();
        } else {
            v = text::parseNumber<T>(t);
        }
        if (!v || k >= 3) return k = 4, false;
        out[k++] = *v;
        return true;
    });
    return k == 3;
}

}  // namespace

std::string Reader::appendVolume(pugi::xml_node volume, VolumeMesh& vm) const {
    const std::string_view kind = localName(volume.name());
    const std::string at = elementPath(volume);
    if (kind == "RectifiedGrid") {
        // The volume its lattice spans: one parallelepiped from the low to the high limits.
        std::array<std::int64_t, 3> low{}, high{};
        const pugi::xml_node env = childNamed(childNamed(volume, "limits"), "GridEnvelope");
        if (!readThree(childNamed(env, "low"), low) || !readThree(childNamed(env, "high"), high))
            return "its limits are not three low and three high whole numbers";
        std::array<double, 3> origin{};
        const pugi::xml_node originNode = childNamed(volume, "origin");
        pugi::xml_node point = childNamed(originNode, "Point");
        pugi::xml_node pos = point ? (childNamed(point, "pos") ? childNamed(point, "pos") : point) : originNode;
        if (!readThree(pos, origin)) return "its origin is not three finite numbers";
        std::vector<glm::dvec3> axes;
        for (pugi::xml_node o = childNamed(volume, "offsetVector"); o; o = o.next_sibling()) {
            if (!isNamed(o, "offsetVector")) continue;
            std::array<double, 3> v{};
            if (!readThree(o, v)) return "an offsetVector is not three finite numbers";
            axes.emplace_back(v[0], v[1], v[2]);
        }
        if (axes.size() != 3) return "it has " + std::to_string(axes.size()) + " offset vectors, not 3";
        for (int a = 0; a < 3; ++a)
            if (high[a] <= low[a]) return "its limits are empty along axis " + std::to_string(a + 1);
        const glm::dvec3 o(origin[0], origin[1], origin[2]);
        auto corner = [&](int i, int j, int k) {
            return o + double(i ? high[0] : low[0]) * axes[0] + double(j ? high[1] : low[1]) * axes[1] +
                   double(k ? high[2] : low[2]) * axes[2];
        };
        const auto base = static_cast<std::uint32_t>(vm.positions.size());
        for (const auto& c : {std::array{0, 0, 0}, std::array{1, 0, 0}, std::array{1, 1, 0}, std::array{0, 1, 0},
                              std::array{0, 0, 1}, std::array{1, 0, 1}, std::array{1, 1, 1}, std::array{0, 1, 1}})
            vm.positions.push_back(corner(c[0], c[1], c[2]));
        vm.addCell(VolumeMesh::CellType::Hexahedron,
                   {base, base + 1, base + 2, base + 3, base + 4, base + 5, base + 6, base + 7}, 0);
        return {};
    }

    VertexTable table;
    if (auto err = readVertices(volume, table)) return err->message.substr(source_.size() + 2);
    if (vm.positions.size() + table.positions.size() >= std::numeric_limits<std::uint32_t>::max())
        return "more vertices than 32-bit indices can address";
    const auto base = static_cast<std::uint32_t>(vm.positions.size());
    std::vector<std::uint64_t> ids;
    // Resolves IndexNo values into vm indices; "" or what is wrong.
    auto resolve = [&](const std::vector<std::uint64_t>& in, std::vector<std::uint32_t>& out) -> std::string {
        out.clear();
        for (const std::uint64_t id : in) {
            const auto p = table.find(id);
            if (!p)
                return "vertex index " + std::to_string(id) + " is not a Vertex of the volume (it has " +
                       std::to_string(table.positions.size()) + ")";
            out.push_back(base + *p);
        }
        return {};
    };
    std::vector<std::uint32_t> cell;
    std::vector<std::pair<VolumeMesh::CellType, std::vector<std::uint32_t>>> cells;
    auto cellList = [&](std::string_view wrapper, std::string_view item, VolumeMesh::CellType type,
                        std::size_t n) -> std::string {
        std::size_t index = 0;
        for (pugi::xml_node c = childNamed(childNamed(volume, wrapper), item); c; c = c.next_sibling(), ++index) {
            if (!isNamed(c, item)) continue;
            if (std::string p = readIndices(childNamed(c, "VertexList"), ids); !p.empty())
                return std::string(item) + " " + std::to_string(index) + ": " + p;
            if (ids.size() != n)
                return std::string(item) + " " + std::to_string(index) + " has " + std::to_string(ids.size()) +
                       " vertices, not " + std::to_string(n);
            if (std::string p = resolve(ids, cell); !p.empty())
                return std::string(item) + " " + std::to_string(index) + ": " + p;
            cells.emplace_back(type, cell);
        }
        return {};
    };
    std::string problem;
    if (kind == "GeoTetrahedronVolume") {
        problem = cellList("Tetrahedrons", "Tetrahedron", VolumeMesh::CellType::Tetra, 4);
    } else if (kind == "GeoCuboidVolume") {
        problem = cellList("Cuboids", "Cuboid", VolumeMesh::CellType::Hexahedron, 8);  // VTK hexahedron order
    } else if (kind == "GeoTriangularPrismVolume") {
        std::size_t index = 0;
        for (pugi::xml_node c = childNamed(childNamed(volume, "Prisms"), "Prism"); c && problem.empty();
             c = c.next_sibling(), ++index) {
            if (!isNamed(c, "Prism")) continue;
            std::vector<std::uint32_t> bottom, top;
            std::vector<std::uint64_t> b, t;
            problem = readIndices(childNamed(c, "BottomTriangle"), b);
            if (problem.empty()) problem = readIndices(childNamed(c, "TopTriangle"), t);
            if (problem.empty() && (b.size() != 3 || t.size() != 3)) problem = "top and bottom are not triangles";
            if (problem.empty()) problem = resolve(b, bottom);
            if (problem.empty()) problem = resolve(t, top);
            if (!problem.empty()) {
                problem = "Prism " + std::to_string(index) + ": " + problem;
                break;
            }
            // Wedge: the bottom triangle, then the top vertex above each of its vertices.
            cells.push_back({VolumeMesh::CellType::Wedge, {bottom[0], bottom[1], bottom[2], top[0], top[1], top[2]}});
        }
    } else {  // GeoTruncatedRegularGrid: Faces by vertex, Cells by face
        std::vector<std::vector<std::uint32_t>> faces;
        std::unordered_map<std::uint64_t, std::size_t> faceByIndexNo;
        std::size_t index = 0;
        for (pugi::xml_node f = childNamed(childNamed(volume, "Faces"), "Face"); f && problem.empty();
             f = f.next_sibling(), ++index) {
            if (!isNamed(f, "Face")) continue;
            problem = readIndices(childNamed(f, "VertexList"), ids);
            if (problem.empty() && ids.size() != 3 && ids.size() != 4)
                problem = "has " + std::to_string(ids.size()) + " vertices";
            if (problem.empty()) problem = resolve(ids, cell);
            if (!problem.empty()) {
                problem = "Face " + std::to_string(index) + ": " + problem;
                break;
            }
            std::uint64_t no = faces.size();
            if (auto parsed = text::parseNumber<std::int64_t>(trimSpace(attributeNamed(f, "IndexNo").value()));
                parsed && *parsed >= 0)
                no = std::uint64_t(*parsed);
            faceByIndexNo.emplace(no, faces.size());
            faces.push_back(cell);
        }
        index = 0;
        for (pugi::xml_node c = childNamed(childNamed(volume, "Cells"), "Cell"); c && problem.empty();
             c = c.next_sibling(), ++index) {
            if (!isNamed(c, "Cell")) continue;
            problem = readIndices(childNamed(c, "FaceList"), ids);
            std::vector<std::vector<std::uint32_t>> cellFaces;
            for (const std::uint64_t id : ids) {
                if (!problem.empty()) break;
                const auto it = faceByIndexNo.find(id);
                if (it == faceByIndexNo.end())
                    problem =
                        "face " + std::to_string(id) + " is not in Faces (it has " + std::to_string(faces.size()) + ")";
                else
                    cellFaces.push_back(faces[it->second]);
            }
            if (!problem.empty()) {
                problem = "Cell " + std::to_string(index) + ": " + problem;
                break;
            }
            const auto prism = prismFromFaces(cellFaces);
            if (!prism) {
                problem =
                    "Cell " + std::to_string(index) + ": its faces do not bound a hexahedron or a triangular prism";
                break;
            }
            cells.push_back(
                {prism->size() == 8 ? VolumeMesh::CellType::Hexahedron : VolumeMesh::CellType::Wedge, *prism});
        }
    }
    if (!problem.empty()) return problem + " (at " + at + ")";
    if (cells.empty()) return "it has no cells (at " + at + ")";
    vm.positions.insert(vm.positions.end(), table.positions.begin(), table.positions.end());
    for (const auto& [type, v] : cells) {
        vm.cellTypes.push_back(type);
        if (vm.cellOffsets.empty()) vm.cellOffsets.push_back(0);
        vm.cellVertices.insert(vm.cellVertices.end(), v.begin(), v.end());
        vm.cellOffsets.push_back(static_cast<std::uint32_t>(vm.cellVertices.size()));
        vm.cellRegions.push_back(0);
    }
    return {};
}

}  // namespace geoslice::geo3dml
