// Geo3DML loader. Geo3DML is the China Geological Survey's GML-based XML exchange format for
// 3D geological models (schema and examples: WuZixing/Geo3DML, v1.0).
//
// What is read:
//  - a Geo3DModel root, or a GeoModel root (as some Chinese tools write it; same content),
//    in any namespace (http or https URIs, or none);
//  - a Geo3DProject: its inlined models, and the model files it xi:includes, resolved
//    against the project file's folder (parseGeo3dml's baseDir). Includes that are absolute,
//    URLs, contain '..' or lead outside the folder through a link are refused, and missing
//    ones skipped, each with a warning naming it; included Geo3DMaps give the colours of the
//    features their styles select (geo3dml_styles.cpp);
//  - each GeoFeature under FeatureClasses/FeatureClass/GeoFeatureClass/Features/Feature whose
//    Geometry/Shape holds triangles: geo3dml:GeoTin (Vertices/Vertex "x y z" with IndexNo,
//    Triangles/Triangle/VertexList of three IndexNo values), or gml:TriangulatedSurface /
//    gml:Tin patches of gml:Triangle rings, also when wrapped (gml:Solid, Shell, MultiSurface);
//  - volumes, as cells -> regionBoundaries() (model/mesh/volume_mesh.hpp) -> a closed body:
//    GeoTetrahedronVolume (Tetrahedrons/Tetrahedron/VertexList of 4), GeoCuboidVolume
//    (Cuboids/Cuboid/VertexList of 8, VTK hexahedron order), GeoTriangularPrismVolume
//    (Prisms/Prism Bottom/TopTriangle), GeoTruncatedRegularGrid (Faces/Face/VertexList,
//    Cells/Cell/FaceList of 6 quads or 2 triangles + 3 quads), and gml:RectifiedGrid (the
//    parallelepiped its limits and offset vectors span). A volume whose cells cannot be
//    built (indices of vertices or faces that are not in the file) is skipped with a
//    warning naming the feature (validation issue and the note "geo3dml_warnings").
//    All triangles of one feature form one Part; closed parts become bodies, open ones
//    surfaces (finishLoadedModel decides finally, by closure). A feature name already taken
//    by another model of a project gets " (<model name>)" appended;
//  - the feature's Fields -> one AttributeRecord per part (see buildRecord);
//  - Metadata/SpatialReferenceSystem/CoordinateReferenceSystem (Identifier "EPSG",
//    Parameter "4526") or a geometry's srsName -> Model::crs;
//  - Geo3DModel/Name (or Geo3DProject/Name) -> Model::name.
// Skipped without error: corner-point and other grids, points and lines (boreholes,
// sections) and coverages (ShapeProperty). A file with nothing to load is an Unsupported
// error that says what the file held.
//
// Elements and attributes are matched by local name, so namespace prefixes do not matter.
// Coordinates are taken as world x east, y north, z up, metres, in the file's order, except
// that a projected CGCS2000 file written northing first is detected and swapped
// (fixAxisOrder). Declared counts (posList count, VertexList ItemCount/Length) are only
// compared with what is present, never used to size anything.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <variant>
#include <vector>

#include <pugixml.hpp>

#include "model/io/geo3dml/geo3dml_reader.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/volume_mesh.hpp"

namespace geoslice {
namespace geo3dml {
namespace {

// True when every undirected edge is used by exactly two triangles (a closed 2-manifold).
bool isClosed(const Mesh& mesh) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(mesh.indices.size());
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
        for (std::size_t k = 0; k < 3; ++k) {
            std::uint32_t a = mesh.indices[t + k], b = mesh.indices[t + (k + 1) % 3];
            if (a > b) std::swap(a, b);
            edges.emplace_back(a, b);
        }
    if (edges.empty()) return false;
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i != 2) return false;
        i = j;
    }
    return true;
}

// Geo3DModel and GeoModel (the root some Chinese tools write) hold the same content.
bool isModelRoot(std::string_view local) { return local == "Geo3DModel" || local == "GeoModel"; }

}  // namespace

// Parses text (GB18030 converted first when declared) into doc; sets converted_.
std::optional<Error> Reader::parseDocument(std::string_view text, pugi::xml_document& doc, std::string& storage) {
    converted_.clear();
    if (trimSpace(text).empty()) return fail({}, "empty input, not a Geo3DML document");
    pugi::xml_encoding encoding = pugi::encoding_auto;
    if (declaresGbEncoding(text)) {
        auto conv = gb18030ToUtf8(text);
        if (std::holds_alternative<std::size_t>(conv))
            return fail({}, "byte " + std::to_string(std::get<std::size_t>(conv)) +
                                ": not valid GB18030 text although the XML declaration says GB2312/GBK/GB18030");
        storage = std::move(std::get<std::string>(conv));
        text = storage;
        encoding = pugi::encoding_utf8;
        converted_ = " (of the text converted from GB18030 to UTF-8)";
    }
    const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size(), pugi::parse_default, encoding);
    if (!parsed) {
        std::string what = parsed.status == pugi::status_no_document_element
                               ? "not XML: no root element"
                               : std::string("not well-formed XML (truncated or malformed): ") + parsed.description();
        return fail({}, "byte " + std::to_string(parsed.offset) + converted_ + ": " + what);
    }
    const pugi::xml_node root = doc.document_element();
    for (pugi::xml_node n = root.next_sibling(); n; n = n.next_sibling())
        if (n.type() == pugi::node_element) return fail(n, "a second root element; XML allows one");
    return std::nullopt;
}

Result<Model> Reader::run(std::string_view text) {
    pugi::xml_document doc;
    std::string storage;
    if (auto err = parseDocument(text, doc, storage)) return std::move(*err);
    const pugi::xml_node root = doc.document_element();
    const std::string_view rootName = localName(root.name());
    Model model;
    model.source = source_;

    if (rootName == "Geo3DMap")
        return fail(ErrorCode::Unsupported, root,
                    "a Geo3DMap holds display styles for layers of a model, no geometry; load the "
                    "Geo3DModel file its layers refer to");
    if (isModelRoot(rootName)) {
        if (auto err = readModelElement(root, model)) return std::move(*err);
    } else if (rootName == "Geo3DProject") {
        if (auto err = readProject(root, model)) return std::move(*err);
    } else {
        return fail(root, "root element is <" + quoted(root.name()) +
                              ">, not Geo3DML (expected Geo3DModel, GeoModel or Geo3DProject)");
    }

    if (model.bodies.empty() && model.surfaces.empty() && model.lines.empty()) return nothingToLoad(root, model.name);

    applyCrs(model);
    applyStyles(model);
    finishLoadedModel(model, /*classifyByClosure=*/true);
    // Loader warnings (skipped volumes, missing or refused includes) as validation issues
    // and a model note; validate() runs again later keeps the note.
    std::string all;
    for (const auto& [part, message] : warnings_) {
        model.validation.issues.push_back({ValidationIssue::Severity::Warning, part, message});
        all += (all.empty() ? "" : "; ") + (part.empty() ? message : part + ": " + message);
    }
    if (!all.empty()) model.notes["geo3dml_warnings"] = all;
    return model;
}

// A Geo3DProject: models inlined, or xi:include'd from files beside the project (resolved
// against its folder; absolute paths, URLs and paths that leave the folder are refused,
// missing files are warnings). Included maps are read for their styles (readMap); nested
// projects are not read.
std::optional<Error> Reader::readProject(pugi::xml_node root, Model& model) {
    std::string projectName;
    if (auto err = readText(childNamed(root, "Name"), projectName)) return err;
    model.name = std::string(trimSpace(projectName));
    std::optional<Error> error;
    std::vector<std::string> hrefs;
    walkElements(root, [&](pugi::xml_node n) {
        const std::string_view name = localName(n.name());
        if (isModelRoot(name)) {
            error = readModelElement(n, model);
            return error ? Walk::Stop : Walk::Skip;
        }
        if (name == "include") {
            hrefs.emplace_back(attributeNamed(n, "href").value());
            includes_.push_back(quoted(hrefs.back(), 200));
            return Walk::Skip;
        }
        return Walk::Descend;
    });
    if (error) return error;
    for (const std::string& href : hrefs)
        if (auto err = readInclude(href, model)) return err;
    return std::nullopt;
}

std::optional<Error> Reader::readInclude(std::string_view href, Model& model) {
    const std::string shownHref = "xi:include '" + quoted(href, 200) + "'";
    if (baseDir_.empty()) {
        warn("", shownHref + " not followed: the project was read from memory, not from a file");
        return std::nullopt;
    }
    namespace fs = std::filesystem;
    const std::string h(trimSpace(href));
    const fs::path rel(h);
    if (h.empty()) {
        warn("", "an xi:include without an href is skipped");
        return std::nullopt;
    }
    bool outside = rel.is_absolute() || rel.has_root_name() || rel.has_root_directory() ||
                   h.find(':') != std::string::npos || h.front() == '\\';
    for (const fs::path& part : rel)
        if (part == "..") outside = true;
    if (outside) {
        warn("",
             shownHref +
                 " refused: includes must name a file inside the project's folder (no absolute paths, URLs or '..')");
        return std::nullopt;
    }
    std::error_code ec;
    const fs::path base = fs::weakly_canonical(fs::path(baseDir_), ec);
    const fs::path target = fs::weakly_canonical(fs::path(baseDir_) / rel, ec);
    if (!fs::exists(target, ec)) {
        warn("", shownHref + " is missing (" + quoted((fs::path(baseDir_) / rel).string(), 300) + " does not exist)");
        return std::nullopt;
    }
    const auto [baseEnd, targetIt] = std::mismatch(base.begin(), base.end(), target.begin(), target.end());
    if (baseEnd != base.end()) {
        warn("", shownHref + " refused: it leads outside the project's folder (through a link)");
        return std::nullopt;
    }
    auto bytes = readFile(target.string(), std::size_t(1) << 30);
    if (!bytes) return bytes.error();
    // Read it as its own document, with messages naming it.
    const std::string projectSource = source_, projectConverted = converted_;
    source_ = target.string();
    pugi::xml_document doc;
    std::string storage;
    std::optional<Error> err = parseDocument(bytes.value(), doc, storage);
    if (!err) {
        const pugi::xml_node root = doc.document_element();
        const std::string_view name = localName(root.name());
        if (isModelRoot(name))
            err = readModelElement(root, model);
        else if (name == "Geo3DMap")
            readMap(root, std::string(href));
        else
            warn("", shownHref + " is a <" + quoted(root.name()) + ">, not a Geo3DModel: not read");
    }
    source_ = projectSource;
    converted_ = projectConverted;
    return err;
}

std::optional<Error> Reader::readText(pugi::xml_node n, std::string& out) const {
    out = textOf(n);
    if (!isValidUtf8(out)) return fail(n, "text is not valid UTF-8 (declare the file's real encoding)");
    return std::nullopt;
}

std::optional<Error> Reader::readModelElement(pugi::xml_node modelNode, Model& model) {
    {
        std::string name;
        if (auto err = readText(childNamed(modelNode, "Name"), name)) return err;
        currentModelName_ = std::string(trimSpace(name));
        if (model.name.empty()) model.name = currentModelName_;
    }
    if (modelType_.empty()) modelType_ = quoted(trimSpace(textOf(childNamed(modelNode, "Type"))));

    // Metadata/SpatialReferenceSystem/CoordinateReferenceSystem: <Identifier>EPSG</Identifier>
    // <Parameter>4526</Parameter> in the samples.
    const pugi::xml_node crsNode = childNamed(childNamed(childNamed(modelNode, "Metadata"), "SpatialReferenceSystem"),
                                              "CoordinateReferenceSystem");
    if (crsNode && declaredCrs_.empty()) {
        std::string identifier, parameter;
        if (auto err = readText(childNamed(crsNode, "Identifier"), identifier)) return err;
        if (auto err = readText(childNamed(crsNode, "Parameter"), parameter)) return err;
        const std::string_view id = trimSpace(identifier), param = trimSpace(parameter);
        if (isDigits(param) && (id.empty() || text::lower(id) == "epsg"))
            declaredCrs_ = "EPSG:" + std::string(param);
        else if (!id.empty())
            declaredCrs_ = std::string(id) + (param.empty() ? "" : ":" + std::string(param));
    }

    std::optional<Error> error;
    const pugi::xml_node classes = childNamed(modelNode, "FeatureClasses");
    forEachWrapped(classes, "FeatureClass", "GeoFeatureClass", [&](pugi::xml_node featureClass) {
        if (error) return;
        std::string className;
        if ((error = readText(childNamed(featureClass, "name"), className))) return;
        const std::string_view classId = trimSpace(attributeNamed(featureClass, "id").value());
        forEachWrapped(childNamed(featureClass, "Features"), "Feature", "GeoFeature", [&](pugi::xml_node feature) {
            if (!error) error = readFeature(feature, trimSpace(className), classId, model);
        });
    });
    return error;
}

std::optional<Error> Reader::readFeature(pugi::xml_node feature, std::string_view className, std::string_view classId,
                                         Model& model) {
    const pugi::xml_node shape = childNamed(childNamed(feature, "Geometry"), "Shape");
    if (!shape) {
        ++featuresWithoutGeometry_;
        return std::nullopt;
    }
    std::string featureName;
    if (auto err = readText(childNamed(feature, "name"), featureName)) return err;
    featureName = std::string(trimSpace(featureName));
    if (featureName.empty()) featureName = quoted(attributeNamed(feature, "id").value(), 200);
    if (featureName.empty()) featureName = "feature " + std::to_string(model.bodies.size() + model.surfaces.size() + 1);

    Mesh mesh;
    Polyline line;
    VolumeMesh volume;
    std::vector<std::string> volumeProblems;
    std::optional<Error> error;
    walkElements(shape, [&](pugi::xml_node n) {
        if (srsName_.empty()) {
            if (const pugi::xml_attribute srs = attributeNamed(n, "srsName")) srsName_ = srs.value();
        }
        const std::string_view name = localName(n.name());
        if (name == "GeoTin") {
            error = appendGeoTin(n, mesh);
        } else if (name == "TriangulatedSurface" || name == "Tin") {
            error = appendGmlTriangles(n, mesh);
        } else if (name == "GeoTetrahedronVolume" || name == "GeoCuboidVolume" || name == "GeoTriangularPrismVolume" ||
                   name == "GeoTruncatedRegularGrid" || name == "RectifiedGrid") {
            std::string problem = appendVolume(n, volume);
            if (!problem.empty()) volumeProblems.push_back(std::string(name) + ": " + problem);
        } else if (name == "LineString") {
            error = appendLineString(n, line);
        } else if (name == "GeoVolume" || name == "GeoGrid") {
            return Walk::Descend;  // wrappers of the volume and grid elements above
        } else if (name.starts_with("Geo") || name == "Grid" || name == "Point") {
            return Walk::Skip;  // another Geo3DML volume / grid, or a point or line: nothing to triangulate
        } else {
            return Walk::Descend;  // gml:Solid, Shell, surfaceMember, MultiSurface... may wrap TINs
        }
        return error ? Walk::Stop : Walk::Skip;
    });
    if (error) return error;
    for (const std::string& problem : volumeProblems) warn(featureName, problem + "; this volume is skipped");

    const bool isVolume = volume.cellCount() > 0;
    if (isVolume) {
        auto shells = regionBoundaries(volume, 1);
        if (!shells) {
            warn(featureName, "its cells do not form a volume (" + shells.error().message + "); skipped");
        } else {
            const Mesh& b = shells.value()[0];
            const auto base = static_cast<std::uint32_t>(mesh.positions.size());
            mesh.positions.insert(mesh.positions.end(), b.positions.begin(), b.positions.end());
            for (const std::uint32_t i : b.indices) mesh.indices.push_back(base + i);
        }
    }

    if (mesh.indices.empty() && !line.segments.empty()) {
        // A line feature (borehole interval, section boundary): kept as a model line.
        Result<AttributeRecord> record = buildRecord(feature, featureName, className, false);
        if (!record) return record.error();
        line.name = featureName;
        line.record = model.attributes.add(std::move(record.value()));
        if (const std::string_view id = trimSpace(attributeNamed(feature, "id").value()); !id.empty())
            features_[std::string(id)] = {line.record, std::string(classId)};
        model.lines.push_back(std::move(line));
        return std::nullopt;
    }
    if (mesh.indices.empty()) {
        if (!volumeProblems.empty()) return std::nullopt;  // warned above
        const pugi::xml_node geometry = firstElementChild(shape);
        if (geometry) {
            census_.add(localName(geometry.name()));
            warn(featureName, "its geometry <" + std::string(localName(geometry.name())) +
                                  "> is not read (geoslice reads TINs, tetrahedral, cuboid, prism and truncated-grid "
                                  "volumes, gml:RectifiedGrid and line strings); the feature is skipped");
        } else
            ++featuresWithoutGeometry_;
        return std::nullopt;
    }

    // Feature names repeat across the models of a project (地层C in two models): the later
    // part gets its model's name appended.
    auto taken = [&](const std::string& n) {
        for (const auto* list : {&model.bodies, &model.surfaces})
            for (const Part& p : *list)
                if (p.name == n) return true;
        return false;
    };
    if (taken(featureName)) {
        std::string unique =
            featureName + " (" + (currentModelName_.empty() ? std::string("model") : currentModelName_) + ")";
        for (int k = 2; taken(unique); ++k) unique = featureName + " #" + std::to_string(k);
        featureName = unique;
    }

    // Provisional: finishLoadedModel classifies by closure again, after validation.
    const bool closed = isVolume || isClosed(mesh);
    Result<AttributeRecord> record = buildRecord(feature, featureName, className, closed);
    if (!record) return record.error();

    Part part;
    part.name = featureName;
    part.record = model.attributes.add(std::move(record.value()));
    if (const std::string_view id = trimSpace(attributeNamed(feature, "id").value()); !id.empty())
        features_[std::string(id)] = {part.record, std::string(classId)};
    part.mesh = std::move(mesh);
    part.kind = closed ? PartKind::Body : PartKind::Surface;
    part.kindDeclared = isVolume;  // a volume stays a body: an error if it cannot be closed, never a surface
    (closed ? model.bodies : model.surfaces).push_back(std::move(part));
    return std::nullopt;
}

Error Reader::nothingToLoad(pugi::xml_node root, const std::string& modelName) const {
    std::string what = localName(root.name()) == "Geo3DProject" ? "the Geo3DProject" : "the Geo3DModel";
    if (!modelName.empty()) what += " '" + quoted(modelName, 200) + "'";
    if (!modelType_.empty() && localName(root.name()) == "Geo3DModel") what += " (Type " + modelType_ + ")";
    std::string held = census_.describe();
    if (featuresWithoutGeometry_ > 0) {
        if (!held.empty()) held += ", ";
        held += std::to_string(featuresWithoutGeometry_);
        held += featuresWithoutGeometry_ == 1 ? " feature without geometry" : " features without geometry";
    }
    std::string msg = source_ + ": no TIN triangles to load: " + what;
    if (!held.empty())
        msg += " contains only " + held;
    else
        msg += " contains no feature geometry";
    if (!includes_.empty() && baseDir_.empty()) {
        msg += "; its models are in separate files (xi:include";
        for (const std::string& href : includes_) msg += " " + href;
        msg += "): load those";
    }
    msg +=
        ". geoslice reads Geo3DML TIN surfaces (GeoTin, gml:TriangulatedSurface), volumes (GeoTetrahedronVolume, "
        "GeoCuboidVolume, GeoTriangularPrismVolume, GeoTruncatedRegularGrid, gml:RectifiedGrid) and line strings "
        "(borehole intervals, section lines)";
    return makeError(ErrorCode::Unsupported, msg);
}

}  // namespace geo3dml

Result<Model> parseGeo3dml(std::string_view text, const std::string& source, const std::string& baseDir) {
    geo3dml::Reader reader(source, baseDir);
    return reader.run(text);
}

}  // namespace geoslice
