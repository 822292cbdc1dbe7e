// Geo3DML reading: surface and line geometry. Geo3DML's own TIN (GeoTin: Vertices/Vertex
// with IndexNo, Triangles/Triangle/VertexList), GML triangles (gml:TriangulatedSurface and
// gml:Tin patches of gml:Triangle rings, welded by position) and gml:LineString, with the
// srsDimension and declared-count checks they share. Part of the reader in
// model/io/geo3dml/geo3dml_reader.hpp.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "model/io/geo3dml/geo3dml_reader.hpp"

namespace geoslice::geo3dml {

std::optional<Error> Reader::checkSrsDimension(pugi::xml_node n) const {
    const pugi::xml_attribute dim = attributeNamed(n, "srsDimension");
    if (dim && trimSpace(dim.value()) != "3")
        return fail(n, "srsDimension=\"" + quoted(dim.value()) + "\"; only 3D coordinates (x y z) are supported");
    return std::nullopt;
}

std::optional<Error> Reader::checkDeclaredCount(pugi::xml_node n, std::string_view attr, std::size_t actual,
                                                std::string_view what) const {
    const pugi::xml_attribute a = attributeNamed(n, attr);
    if (!a) return std::nullopt;
    const std::optional<std::int64_t> declared = text::parseNumber<std::int64_t>(trimSpace(a.value()));
    if (!declared || *declared < 0) return fail(n, std::string(attr) + "=\"" + quoted(a.value()) + "\" is not a count");
    if (static_cast<std::uint64_t>(*declared) != actual)
        return fail(n, std::string(attr) + "=" + std::to_string(*declared) + " but it holds " + std::to_string(actual) +
                           " " + std::string(what));
    return std::nullopt;
}

std::optional<Error> Reader::readCoordinate(pugi::xml_node at, std::string_view token, double& value) const {
    const std::optional<double> parsed = text::parseXsDouble(token);
    if (!parsed) return fail(at, "'" + quoted(token) + "' is not a number");
    if (!std::isfinite(*parsed)) return fail(at, "coordinate '" + quoted(token) + "' is NaN or infinite");
    value = *parsed;
    return std::nullopt;
}

// gml:LineString: a posList (or gml:pos children) of 3D positions -> appended to `line` as
// a chain of segments. Borehole intervals and section boundary lines are written so.
std::optional<Error> Reader::appendLineString(pugi::xml_node ls, Polyline& line) const {
    if (auto err = checkSrsDimension(ls)) return err;
    std::vector<double> coords;
    std::optional<Error> error;
    const auto take = [&](pugi::xml_node at, std::string_view text) {
        forEachToken(text, [&](std::string_view token) {
            double value = 0.0;
            error = readCoordinate(at, token, value);
            if (!error) coords.push_back(value);
            return !error;
        });
    };
    if (const pugi::xml_node posList = childNamed(ls, "posList")) {
        if (auto err = checkSrsDimension(posList)) return err;
        take(posList, textOf(posList));
        if (error) return error;
        if (coords.size() % 3 != 0)
            return fail(posList, "the posList holds " + std::to_string(coords.size()) +
                                     " numbers, not a multiple of 3 (x y z per position)");
        if (auto err = checkDeclaredCount(posList, "count", coords.size() / 3, "positions")) return err;
    } else {
        for (pugi::xml_node pos = childNamed(ls, "pos"); pos && !error; pos = pos.next_sibling()) {
            if (!isNamed(pos, "pos")) continue;
            const std::size_t before = coords.size();
            take(pos, textOf(pos));
            if (!error && coords.size() - before != 3)
                return fail(pos, "a gml:pos has " + std::to_string(coords.size() - before) +
                                     " coordinates; expected 3 (x y z)");
        }
        if (error) return error;
    }
    const std::size_t n = coords.size() / 3;
    if (n < 2) return fail(ls, "a gml:LineString with " + std::to_string(n) + " positions; a line needs 2");
    if (line.points.size() + n >= std::numeric_limits<std::uint32_t>::max())
        return fail(ErrorCode::OutOfRange, ls, "more points than 32-bit indices can address");
    const auto base = static_cast<std::uint32_t>(line.points.size());
    for (std::size_t i = 0; i < n; ++i) line.points.emplace_back(coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]);
    for (std::uint32_t i = 0; i + 1 < n; ++i) line.segments.insert(line.segments.end(), {base + i, base + i + 1});
    return std::nullopt;
}

// Geo3DML's own TIN: Vertices/Vertex ("x y z", attribute IndexNo) and Triangles/Triangle/
// VertexList (three IndexNo values; NeighborList is ignored). IndexNo is normally the
// vertex's position; when it is not, a map from IndexNo to position is built.
std::optional<Error> Reader::readVertices(pugi::xml_node owner, VertexTable& table) const {
    for (pugi::xml_node v = childNamed(childNamed(owner, "Vertices"), "Vertex"); v; v = v.next_sibling()) {
        if (!isNamed(v, "Vertex")) continue;
        if (auto err = checkSrsDimension(v)) return err;
        const std::size_t count = table.positions.size();
        if (count >= std::numeric_limits<std::uint32_t>::max())
            return fail(ErrorCode::OutOfRange, v, "more vertices than 32-bit indices can address");
        std::array<double, 3> xyz{};
        std::size_t n = 0;
        std::optional<Error> error;
        forEachToken(textOf(v), [&](std::string_view token) {
            double value = 0.0;
            error = readCoordinate(v, token, value);
            if (!error && n < 3) xyz[n] = value;
            ++n;
            return !error;
        });
        if (error) return error;
        if (n != 3) return fail(v, "a Vertex has " + std::to_string(n) + " coordinates; expected 3 (x y z)");

        std::uint64_t indexNo = count;
        if (const pugi::xml_attribute a = attributeNamed(v, "IndexNo")) {
            const std::optional<std::int64_t> parsed = text::parseNumber<std::int64_t>(trimSpace(a.value()));
            if (!parsed || *parsed < 0) return fail(v, "IndexNo=\"" + quoted(a.value()) + "\" is not a vertex index");
            indexNo = static_cast<std::uint64_t>(*parsed);
        }
        if (table.identity && indexNo != count) {
            table.identity = false;
            table.byIndexNo.reserve(count + 1);
            for (std::uint32_t k = 0; k < count; ++k) table.byIndexNo.emplace(k, k);
        }
        if (!table.identity && !table.byIndexNo.emplace(indexNo, static_cast<std::uint32_t>(count)).second)
            return fail(v, "IndexNo " + std::to_string(indexNo) + " is used by two vertices");
        table.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
    }
    return std::nullopt;
}

// Geo3DML's own TIN: Vertices/Vertex ("x y z", attribute IndexNo) and Triangles/Triangle/
// VertexList (three IndexNo values; NeighborList is ignored). IndexNo is normally the
// vertex's position; when it is not, a map from IndexNo to position is built.
std::optional<Error> Reader::appendGeoTin(pugi::xml_node tin, Mesh& mesh) const {
    if (auto err = checkSrsDimension(tin)) return err;
    VertexTable table;
    if (auto err = readVertices(tin, table)) return err;
    if (mesh.positions.size() + table.positions.size() >= std::numeric_limits<std::uint32_t>::max())
        return fail(ErrorCode::OutOfRange, tin, "more vertices than 32-bit indices can address");
    const std::size_t base = mesh.positions.size();
    const std::size_t count = table.positions.size();
    mesh.positions.insert(mesh.positions.end(), table.positions.begin(), table.positions.end());

    for (pugi::xml_node t = childNamed(childNamed(tin, "Triangles"), "Triangle"); t; t = t.next_sibling()) {
        if (!isNamed(t, "Triangle")) continue;
        const pugi::xml_node list = childNamed(t, "VertexList");
        if (!list) return fail(t, "a Triangle without a VertexList");
        std::array<std::uint64_t, 3> tri{};
        std::size_t n = 0;
        std::optional<Error> error;
        forEachToken(textOf(list), [&](std::string_view token) {
            const std::optional<std::int64_t> value = text::parseNumber<std::int64_t>(token);
            if (!value)
                error = fail(list, "'" + quoted(token) + "' is not a vertex index");
            else if (*value < 0)
                error = fail(list, "negative vertex index " + std::to_string(*value));
            else if (n < 3)
                tri[n] = static_cast<std::uint64_t>(*value);
            ++n;
            return !error;
        });
        if (error) return error;
        if (auto err = checkDeclaredCount(list, "ItemCount", n, "indices")) return err;
        if (auto err = checkDeclaredCount(list, "Length", n, "indices")) return err;
        if (n != 3) return fail(list, "a triangle with " + std::to_string(n) + " vertex indices; a TIN triangle has 3");
        for (const std::uint64_t indexNo : tri) {
            const std::optional<std::uint32_t> position = table.find(indexNo);
            if (!position)
                return fail(list, "vertex index " + std::to_string(indexNo) + " is out of range " +
                                      (table.identity ? "(the TIN has " + std::to_string(count) + " vertices)"
                                                      : std::string("(no Vertex of the TIN has that IndexNo)")));
            mesh.indices.push_back(static_cast<std::uint32_t>(base) + *position);
        }
    }
    return std::nullopt;
}

// gml:TriangulatedSurface / gml:Tin: patches of gml:Triangle, each an exterior LinearRing of
// four positions (the last repeats the first) in a posList or in four gml:pos. Vertices with
// identical coordinates are welded so that shared edges connect.
std::optional<Error> Reader::appendGmlTriangles(pugi::xml_node surface, Mesh& mesh) const {
    if (auto err = checkSrsDimension(surface)) return err;
    std::map<std::array<double, 3>, std::uint32_t> welded;
    std::optional<Error> error;
    walkElements(surface, [&](pugi::xml_node tri) {
        if (!isNamed(tri, "Triangle")) return Walk::Descend;
        const pugi::xml_node ring = childNamed(childNamed(tri, "exterior"), "LinearRing");
        if (!ring) {
            error = fail(tri, "a gml:Triangle without exterior/LinearRing");
            return Walk::Stop;
        }
        std::array<double, 12> coords{};  // up to 4 positions; more is an error below
        std::size_t n = 0;
        const auto take = [&](pugi::xml_node at, std::string_view text) {
            forEachToken(text, [&](std::string_view token) {
                double value = 0.0;
                error = readCoordinate(at, token, value);
                if (!error && n < coords.size()) coords[n] = value;
                ++n;
                return !error;
            });
        };
        pugi::xml_node at = ring;
        if (const pugi::xml_node posList = childNamed(ring, "posList")) {
            at = posList;
            if ((error = checkSrsDimension(posList))) return Walk::Stop;
            take(posList, textOf(posList));
            if (error) return Walk::Stop;
            if (n % 3 != 0) {
                error = fail(posList, "the posList holds " + std::to_string(n) +
                                          " numbers, not a multiple of 3 (x y z per position)");
                return Walk::Stop;
            }
            if ((error = checkDeclaredCount(posList, "count", n / 3, "positions"))) return Walk::Stop;
        } else {
            for (pugi::xml_node pos = childNamed(ring, "pos"); pos && !error; pos = pos.next_sibling()) {
                if (!isNamed(pos, "pos")) continue;
                const std::size_t before = n;
                take(pos, textOf(pos));
                if (!error && n - before != 3)
                    error =
                        fail(pos, "a gml:pos has " + std::to_string(n - before) + " coordinates; expected 3 (x y z)");
            }
            if (error) return Walk::Stop;
        }
        const std::size_t points = n / 3;
        const bool closedRing = points == 4 && std::equal(coords.begin(), coords.begin() + 3, coords.begin() + 9);
        if (points != 3 && !closedRing) {
            error = fail(at, "a gml:Triangle ring has " + std::to_string(points) + " positions" +
                                 (points == 4 ? " and does not end where it starts" : "") +
                                 "; expected 4 with the last repeating the first");
            return Walk::Stop;
        }
        for (std::size_t k = 0; k < 3; ++k) {
            const std::array<double, 3> p{coords[3 * k], coords[3 * k + 1], coords[3 * k + 2]};
            auto [it, inserted] = welded.emplace(p, static_cast<std::uint32_t>(mesh.positions.size()));
            if (inserted) {
                if (mesh.positions.size() >= std::numeric_limits<std::uint32_t>::max()) {
                    error = fail(ErrorCode::OutOfRange, tri, "more vertices than 32-bit indices can address");
                    return Walk::Stop;
                }
                mesh.positions.emplace_back(p[0], p[1], p[2]);
            }
            mesh.indices.push_back(it->second);
        }
        return Walk::Skip;
    });
    return error;
}

}  // namespace geoslice::geo3dml
