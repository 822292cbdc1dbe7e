// Geo3DML reading, internal: the reader the files model/geo3dml_*.cpp implement together.
//   geo3dml_loader.cpp      documents, projects and includes, models, features -> parts;
//   geo3dml_geometry.cpp    GeoTin, gml:TriangulatedSurface / Tin, gml:LineString;
//   geo3dml_volumes.cpp     tetrahedra, cuboids, prisms, truncated grids, gml:RectifiedGrid;
//   geo3dml_attributes.cpp  a feature's Fields -> its attribute record;
//   geo3dml_crs.cpp         the declared CRS and the axis-order check;
//   geo3dml_styles.cpp      a project's Geo3DMap styles -> record colours;
//   geo3dml_xml.hpp/.cpp    XML and text helpers.
// What is read, and how: see model/io/geo3dml/geo3dml_loader.cpp. Not a public header.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include <pugixml.hpp>

#include "model/io/geo3dml/geo3dml_xml.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/volume_mesh.hpp"

namespace geoslice::geo3dml {

// What a file held that is not a TIN, for the "no triangles" message, in file order. Kept
// per kind of geometry (a bounded set), so that a file of many odd elements stays linear.
struct Census {
    struct Item {
        std::string_view noun;            // "tetrahedral volume"
        std::vector<std::string> locals;  // element names seen, at most kMaxNames
        std::size_t count = 0;
    };
    static constexpr std::size_t kMaxNames = 3;
    std::vector<Item> items;

    void add(std::string_view local) {
        const std::string_view noun = nounFor(local);
        auto it = std::find_if(items.begin(), items.end(), [&](const Item& item) { return item.noun == noun; });
        if (it == items.end()) it = items.insert(items.end(), Item{noun, {}, 0});
        ++it->count;
        const std::string name = quoted(local);
        if (it->locals.size() < kMaxNames && std::find(it->locals.begin(), it->locals.end(), name) == it->locals.end())
            it->locals.push_back(name);
    }

    // "1 regular grid (RectifiedGrid), 4 points (Point)"
    std::string describe() const {
        std::string out;
        for (const Item& item : items) {
            if (!out.empty()) out += ", ";
            out += std::to_string(item.count);
            out += ' ';
            out += item.noun;
            if (item.count > 1) out += 's';
            out += " (";
            for (std::size_t k = 0; k < item.locals.size(); ++k) {
                if (k > 0) out += ", ";
                out += item.locals[k];
            }
            out += ')';
        }
        return out;
    }

private:
    static std::string_view nounFor(std::string_view local) {
        static const std::pair<std::string_view, std::string_view> kNouns[] = {
            {"GeoTin", "empty TIN"},
            {"TriangulatedSurface", "empty triangulated surface"},
            {"Tin", "empty triangulated surface"},
            {"RectifiedGrid", "regular grid"},
            {"Grid", "grid"},
            {"GeoTetrahedronVolume", "tetrahedral volume"},
            {"GeoCuboidVolume", "cuboid volume"},
            {"GeoTriangularPrismVolume", "triangular prism volume"},
            {"GeoTruncatedRegularGrid", "truncated regular grid"},
            {"GeoCornerPointGrid", "corner-point grid"},
            {"GeoSGrid", "S-grid"},
            {"GeoPolyhedronVolume", "polyhedron volume"},
            {"GeoVolume", "volume"},
            {"Point", "point"},
            {"MultiPoint", "point set"},
            {"LineString", "line string"},
            {"Curve", "curve"},
            {"CompositeCurve", "curve"},
            {"MultiCurve", "curve set"},
            {"Polygon", "polygon"},
            {"Surface", "polygon surface"},
            {"MultiSurface", "polygon surface"},
            {"PolyhedralSurface", "polygon surface"},
            {"Solid", "solid"},
        };
        for (const auto& [name, noun] : kNouns)
            if (name == local) return noun;
        return "other geometry element";
    }
};

// A Vertices/Vertex list: positions in file order and how IndexNo values map to them.
struct VertexTable {
    std::vector<glm::dvec3> positions;
    bool identity = true;  // IndexNo == position for every vertex
    std::unordered_map<std::uint64_t, std::uint32_t> byIndexNo;
    std::optional<std::uint32_t> find(std::uint64_t indexNo) const {
        if (identity) {
            if (indexNo < positions.size()) return static_cast<std::uint32_t>(indexNo);
            return std::nullopt;
        }
        const auto it = byIndexNo.find(indexNo);
        if (it == byIndexNo.end()) return std::nullopt;
        return it->second;
    }
};

class Reader {
public:
    // baseDir: the folder of the file, for a project's xi:include; empty: includes are listed,
    // not followed (input from memory).
    Reader(const std::string& source, const std::string& baseDir) : source_(source), baseDir_(baseDir) {}

    Result<Model> run(std::string_view text);

private:
    // "<source>: byte 1234 in /Geo3DModel/...: what"
    Error fail(ErrorCode code, pugi::xml_node at, const std::string& what) const {
        std::string msg = source_ + ": ";
        if (at) {
            const std::ptrdiff_t offset = at.offset_debug();
            if (offset >= 0) msg += "byte " + std::to_string(offset) + converted_ + " in ";
            msg += elementPath(at) + ": ";
        }
        return makeError(code, msg + what);
    }
    Error fail(pugi::xml_node at, const std::string& what) const { return fail(ErrorCode::ParseError, at, what); }

    std::optional<Error> readModelElement(pugi::xml_node modelNode, Model& model);
    std::optional<Error> readFeature(pugi::xml_node feature, std::string_view className, std::string_view classId,
                                     Model& model);
    // An included Geo3DMap: its layers' colour rules into styleRules_ (geo3dml_styles.cpp).
    void readMap(pugi::xml_node map, const std::string& href);
    // The rules onto the records of the features they select, once every model is read.
    void applyStyles(Model& model);
    std::optional<Error> appendGeoTin(pugi::xml_node tin, Mesh& mesh) const;
    std::optional<Error> readVertices(pugi::xml_node owner, VertexTable& table) const;
    std::optional<Error> appendLineString(pugi::xml_node ls, Polyline& line) const;
    // A Geo3DML volume (tetrahedra, cuboids, prisms, truncated grid) or gml:RectifiedGrid
    // -> cells of vm. Returns what is wrong with it when it cannot be built (the feature is
    // then skipped with a warning), else an empty string.
    std::string appendVolume(pugi::xml_node volume, VolumeMesh& vm) const;
    std::optional<Error> readProject(pugi::xml_node root, Model& model);
    std::optional<Error> readInclude(std::string_view href, Model& model);
    void warn(const std::string& part, const std::string& message) { warnings_.push_back({part, message}); }
    std::optional<Error> appendGmlTriangles(pugi::xml_node surface, Mesh& mesh) const;
    std::optional<Error> checkSrsDimension(pugi::xml_node n) const;
    // One coordinate token of element `at`: a finite xs:double, else an error naming it.
    std::optional<Error> readCoordinate(pugi::xml_node at, std::string_view token, double& value) const;
    std::optional<Error> checkDeclaredCount(pugi::xml_node n, std::string_view attr, std::size_t actual,
                                            std::string_view what) const;
    std::optional<Error> readText(pugi::xml_node n, std::string& out) const;
    Result<AttributeRecord> buildRecord(pugi::xml_node feature, const std::string& featureName,
                                        std::string_view className, bool closed) const;
    void applyCrs(Model& model) const;
    Error nothingToLoad(pugi::xml_node root, const std::string& modelName) const;
    std::optional<Error> parseDocument(std::string_view text, pugi::xml_document& doc, std::string& storage);

    std::string source_;  // the file being read (an included file while it is read)
    std::string baseDir_;
    std::string converted_;  // " (after GB18030 -> UTF-8 conversion)" when it applies
    std::vector<std::pair<std::string, std::string>> warnings_;  // (part, message)
    std::string currentModelName_;  // of the Geo3DModel being read, to tell apart equal feature names
    std::string declaredCrs_;       // from Metadata, e.g. "EPSG:4526"
    std::string srsName_;           // first srsName on a geometry
    std::string modelType_;         // Geo3DModel/Type: 3DModel, Section, Drill, ...
    Census census_;
    std::vector<std::string> includes_;  // xi:include hrefs of a project
    // Features read, by gml:id: their record and their class's gml:id (for map styles).
    struct FeatureRef {
        RecordId record = kNoRecord;
        std::string classId;
    };
    std::unordered_map<std::string, FeatureRef> features_;
    struct StyleRule {
        std::string classId;            // the layer's feature class ("" = any)
        bool filtered = false;          // PropertyIsEqualTo(property, literal)
        std::string property, literal;  //
        Rgba8 colour;
        std::string from;     // "DiffuseColor", "BaseColor", ...
        std::string mapName;  // the Geo3DMap's Name
        std::string where;    // "map 'M', layer 'L', rule 2" for warnings
    };
    std::vector<StyleRule> styleRules_;
    std::size_t mapsRead_ = 0;
    std::size_t featuresWithoutGeometry_ = 0;
};

}  // namespace geoslice::geo3dml
