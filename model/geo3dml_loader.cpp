// Geo3DML loader. Geo3DML is the China Geological Survey's GML-based XML exchange format for
// 3D geological models (schema and examples: WuZixing/Geo3DML, v1.0).
//
// What is read:
//  - a Geo3DModel root, or a GeoModel root (as some Chinese tools write it; same content),
//    in any namespace (http or https URIs, or none);
//  - a Geo3DProject: its inlined models, and the model files it xi:includes, resolved
//    against the project file's folder (parseGeo3dml's baseDir). Includes that are absolute,
//    URLs, contain '..' or lead outside the folder through a link are refused, and missing
//    ones skipped, each with a warning naming it; included Geo3DMaps (styles) are not read;
//  - each GeoFeature under FeatureClasses/FeatureClass/GeoFeatureClass/Features/Feature whose
//    Geometry/Shape holds triangles: geo3dml:GeoTin (Vertices/Vertex "x y z" with IndexNo,
//    Triangles/Triangle/VertexList of three IndexNo values), or gml:TriangulatedSurface /
//    gml:Tin patches of gml:Triangle rings, also when wrapped (gml:Solid, Shell, MultiSurface);
//  - volumes, as cells -> regionBoundaries() (model/volume_mesh.hpp) -> a closed body:
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
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <variant>
#include <vector>

#include <iconv.h>

#include <pugixml.hpp>

#include "model/loaders.hpp"
#include "model/text_scan.hpp"
#include "model/volume_mesh.hpp"

namespace geoslice {
namespace {

// Innermost elements shown in an error's element path; deeper paths start with ".../".
constexpr std::size_t kMaxPathElements = 12;
// Longest piece of input text quoted in an error message, in bytes.
constexpr std::size_t kMaxQuotedBytes = 40;
// Gauss-Kruger eastings lie within this distance of the false easting (metres): a 6-degree
// zone at 18 N (southern China) reaches about 318 km from its central meridian.
constexpr double kMaxOffsetFromFalseEastingM = 500000.0;
// Projected northings of CGCS2000 Gauss-Kruger coordinates (northern hemisphere), metres.
constexpr double kMaxNorthingM = 10002000.0;

// --- small string helpers ------------------------------------------------------------------

using text::isSpace;
using text::trimSpace;

char asciiLower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

std::string asciiLowerCopy(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = asciiLower(c);
    return out;
}

bool startsWithNoCase(std::string_view s, std::string_view prefix) {
    if (s.size() < prefix.size()) return false;
    for (std::size_t i = 0; i < prefix.size(); ++i)
        if (asciiLower(s[i]) != asciiLower(prefix[i])) return false;
    return true;
}

bool isDigits(std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool isValidUtf8(std::string_view s) {
    for (std::size_t i = 0; i < s.size();) {
        const std::size_t len = text::utf8Length(s, i);
        if (len == 0) return false;
        i += len;
    }
    return true;
}

// Input text made safe to put in a message (messages end up in JSON, which needs UTF-8):
// valid UTF-8 characters are kept, control characters and invalid bytes become \xNN, and
// the result is cut at about maxBytes.
std::string quoted(std::string_view s, std::size_t maxBytes = kMaxQuotedBytes) {
    std::string out;
    for (std::size_t i = 0; i < s.size();) {
        if (out.size() >= maxBytes) {
            out += "...";
            break;
        }
        const std::size_t len = text::utf8Length(s, i);
        const auto c = static_cast<unsigned char>(s[i]);
        if (len == 0 || c < 0x20 || c == 0x7F) {
            static constexpr char kHex[] = "0123456789abcdef";
            out += "\\x";
            out += kHex[c >> 4];
            out += kHex[c & 0xF];
            i += 1;
        } else {
            out.append(s.substr(i, len));
            i += len;
        }
    }
    return out;
}

// --- pugixml helpers, by local name ---------------------------------------------------------

std::string_view localName(const char* qualified) {
    std::string_view s(qualified);
    const std::size_t colon = s.rfind(':');
    return colon == std::string_view::npos ? s : s.substr(colon + 1);
}

bool isNamed(pugi::xml_node n, std::string_view local) {
    return n.type() == pugi::node_element && localName(n.name()) == local;
}

pugi::xml_node childNamed(pugi::xml_node n, std::string_view local) {
    for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
        if (isNamed(c, local)) return c;
    return {};
}

pugi::xml_node firstElementChild(pugi::xml_node n) {
    for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
        if (c.type() == pugi::node_element) return c;
    return {};
}

pugi::xml_attribute attributeNamed(pugi::xml_node n, std::string_view local) {
    for (pugi::xml_attribute a = n.first_attribute(); a; a = a.next_attribute())
        if (localName(a.name()) == local) return a;
    return {};
}

// Text content directly inside n (all PCDATA and CDATA children, in order), as decoded by
// pugixml (entities expanded, line ends normalised); not trimmed.
std::string textOf(pugi::xml_node n) {
    std::string s;
    for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
        if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) s += c.value();
    return s;
}

// Calls f(child) for each element child of `parent` named `wrapper` (using its children
// named `inner`) or named `inner` directly: Geo3DML wraps most lists twice
// (Features/Feature/GeoFeature), and some writers leave the middle level out.
template <class F>
void forEachWrapped(pugi::xml_node parent, std::string_view wrapper, std::string_view inner, F&& f) {
    for (pugi::xml_node c = parent.first_child(); c; c = c.next_sibling()) {
        if (isNamed(c, wrapper)) {
            for (pugi::xml_node d = c.first_child(); d; d = d.next_sibling())
                if (isNamed(d, inner)) f(d);
        } else if (isNamed(c, inner)) {
            f(c);
        }
    }
}

enum class Walk { Descend, Skip, Stop };

// Visits the element descendants of root in document order without recursion (inputs may
// nest arbitrarily deep). visit returns Descend, Skip (its subtree) or Stop.
template <class F>
void walkElements(pugi::xml_node root, F&& visit) {
    pugi::xml_node n = root.first_child();
    while (n) {
        Walk w = Walk::Skip;
        if (n.type() == pugi::node_element) {
            w = visit(n);
            if (w == Walk::Stop) return;
        }
        if (w == Walk::Descend && n.first_child()) {
            n = n.first_child();
            continue;
        }
        while (n != root && !n.next_sibling()) n = n.parent();
        if (n == root) return;
        n = n.next_sibling();
    }
}

// "/Geo3DModel/FeatureClasses/.../Triangle[7]/VertexList": local names, with a 1-based
// position among same-named siblings where there are several.
std::string elementPath(pugi::xml_node n) {
    std::vector<std::string> parts;
    bool truncated = false;
    for (; n && n.type() == pugi::node_element; n = n.parent()) {
        if (parts.size() == kMaxPathElements) {
            truncated = true;
            break;
        }
        const std::string_view name = localName(n.name());
        std::size_t position = 1, same = 1;
        for (pugi::xml_node s = n.previous_sibling(); s; s = s.previous_sibling())
            if (s.type() == pugi::node_element && localName(s.name()) == name) ++position, ++same;
        for (pugi::xml_node s = n.next_sibling(); s && same < 2; s = s.next_sibling())
            if (s.type() == pugi::node_element && localName(s.name()) == name) ++same;
        std::string part = quoted(name);
        if (same > 1) {
            part += '[';
            part += std::to_string(position);
            part += ']';
        }
        parts.push_back(std::move(part));
    }
    std::string path = truncated ? "..." : "";
    for (auto it = parts.rbegin(); it != parts.rend(); ++it) path += "/" + *it;
    return path;
}

// --- numbers ---------------------------------------------------------------------------------

// Splits on XML white space; calls f(token) for each; stops when f returns false.
template <class F>
void forEachToken(std::string_view text, F&& f) {
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && isSpace(text[i])) ++i;
        const std::size_t start = i;
        while (i < text.size() && !isSpace(text[i])) ++i;
        if (i > start && !f(text.substr(start, i - start))) return;
    }
}

// --- the reader ------------------------------------------------------------------------------

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
    std::optional<Error> readFeature(pugi::xml_node feature, std::string_view className, Model& model);
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
    std::size_t featuresWithoutGeometry_ = 0;
};

// Declared GB2312 / GBK / GB18030 (common in Chinese tools) is converted to UTF-8 here, as
// pugixml only knows the UTF and Latin-1 encodings. GB18030 is a superset of the other two.
bool declaresGbEncoding(std::string_view text) {
    if (!startsWithNoCase(text, "<?xml")) return false;
    const std::size_t end = text.find("?>");
    if (end == std::string_view::npos || end > 1024) return false;
    const std::string decl = asciiLowerCopy(text.substr(0, end));
    std::size_t at = decl.find("encoding");
    if (at == std::string::npos) return false;
    at = decl.find_first_of("\"'", at);
    if (at == std::string::npos) return false;
    const std::size_t close = decl.find(decl[at], at + 1);
    if (close == std::string::npos) return false;
    const std::string enc = decl.substr(at + 1, close - at - 1);
    return enc == "gb2312" || enc == "gbk" || enc == "gb18030" || enc == "cp936" || enc == "x-gbk" || enc == "euc-cn";
}

// GB18030 -> UTF-8 with iconv. On failure returns the byte offset where it stopped.
std::variant<std::string, std::size_t> gb18030ToUtf8(std::string_view in) {
    iconv_t cd = iconv_open("UTF-8", "GB18030");
    if (cd == reinterpret_cast<iconv_t>(-1)) return std::size_t(0);
    std::string out;
    out.resize(in.size() + in.size() / 2 + 16);  // GB18030 -> UTF-8 grows by at most 1.5x
    char* inPtr = const_cast<char*>(in.data());  // iconv's interface is not const-correct
    std::size_t inLeft = in.size();
    char* outPtr = out.data();
    std::size_t outLeft = out.size();
    const std::size_t r = iconv(cd, &inPtr, &inLeft, &outPtr, &outLeft);
    iconv_close(cd);
    if (r == static_cast<std::size_t>(-1) || inLeft != 0) return static_cast<std::size_t>(inPtr - in.data());
    out.resize(out.size() - outLeft);
    return out;
}

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

// Geo3DModel and GeoModel (the root some Chinese tools write) hold the same content.
bool isModelRoot(std::string_view local) { return local == "Geo3DModel" || local == "GeoModel"; }

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
// missing files are warnings). Included maps (styles) and nested projects are not read.
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
        else if (name == "Geo3DMap") {
            std::string& maps = model.notes["geo3dml_maps_not_read"];
            maps += (maps.empty() ? "" : ", ") + quoted(href, 200);
        } else
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
        if (isDigits(param) && (id.empty() || asciiLowerCopy(id) == "epsg"))
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
        forEachWrapped(childNamed(featureClass, "Features"), "Feature", "GeoFeature", [&](pugi::xml_node feature) {
            if (!error) error = readFeature(feature, trimSpace(className), model);
        });
    });
    return error;
}

std::optional<Error> Reader::readFeature(pugi::xml_node feature, std::string_view className, Model& model) {
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
        model.lines.push_back(std::move(line));
        return std::nullopt;
    }
    if (mesh.indices.empty()) {
        if (!volumeProblems.empty()) return std::nullopt;  // warned above
        const pugi::xml_node geometry = firstElementChild(shape);
        if (geometry)
            census_.add(localName(geometry.name()));
        else
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
    part.mesh = std::move(mesh);
    part.kind = closed ? PartKind::Body : PartKind::Surface;
    part.kindDeclared = isVolume;  // a volume stays a body: an error if it cannot be closed, never a surface
    (closed ? model.bodies : model.surfaces).push_back(std::move(part));
    return std::nullopt;
}

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

// gml:LineString: a posList (or gml:pos children) of 3D positions -> appended to `line` as
// a chain of segments. Borehole intervals and section boundary lines are written so.
std::optional<Error> Reader::appendLineString(pugi::xml_node ls, Polyline& line) const {
    if (auto err = checkSrsDimension(ls)) return err;
    std::vector<double> coords;
    std::optional<Error> error;
    const auto take = [&](pugi::xml_node at, std::string_view text) {
        forEachToken(text, [&](std::string_view token) {
            const std::optional<double> value = text::parseXsDouble(token);
            if (!value)
                error = fail(at, "'" + quoted(token) + "' is not a number");
            else if (!std::isfinite(*value))
                error = fail(at, "coordinate '" + quoted(token) + "' is NaN or infinite");
            else
                coords.push_back(*value);
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
            const std::optional<double> value = text::parseXsDouble(token);
            if (!value)
                error = fail(v, "'" + quoted(token) + "' is not a number");
            else if (!std::isfinite(*value))
                error = fail(v, "coordinate '" + quoted(token) + "' is NaN or infinite");
            else if (n < 3)
                xyz[n] = *value;
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

std::string Reader::appendVolume(pugi::xml_node volume, VolumeMesh& vm) const {
    const std::string_view kind = localName(volume.name());
    const std::string at = elementPath(volume);
    if (kind == "RectifiedGrid") {
        // The volume its lattice spans: one parallelepiped from the low to the high limits.
        std::array<std::int64_t, 3> low{}, high{};
        std::size_t nl = 0, nh = 0;
        const pugi::xml_node env = childNamed(childNamed(volume, "limits"), "GridEnvelope");
        forEachToken(textOf(childNamed(env, "low")), [&](std::string_view t) {
            auto v = text::parseNumber<std::int64_t>(t);
            if (!v || nl >= 3) return nl = 4, false;
            low[nl++] = *v;
            return true;
        });
        forEachToken(textOf(childNamed(env, "high")), [&](std::string_view t) {
            auto v = text::parseNumber<std::int64_t>(t);
            if (!v || nh >= 3) return nh = 4, false;
            high[nh++] = *v;
            return true;
        });
        if (nl != 3 || nh != 3) return "its limits are not three low and three high whole numbers";
        std::array<double, 3> origin{};
        std::size_t no = 0;
        const pugi::xml_node originNode = childNamed(volume, "origin");
        pugi::xml_node point = childNamed(originNode, "Point");
        pugi::xml_node pos = point ? (childNamed(point, "pos") ? childNamed(point, "pos") : point) : originNode;
        forEachToken(textOf(pos), [&](std::string_view t) {
            auto v = text::parseXsDouble(t);
            if (!v || !std::isfinite(*v) || no >= 3) return no = 4, false;
            origin[no++] = *v;
            return true;
        });
        if (no != 3) return "its origin is not three finite numbers";
        std::vector<glm::dvec3> axes;
        for (pugi::xml_node o = childNamed(volume, "offsetVector"); o; o = o.next_sibling()) {
            if (!isNamed(o, "offsetVector")) continue;
            std::array<double, 3> v{};
            std::size_t n = 0;
            forEachToken(textOf(o), [&](std::string_view t) {
                auto d = text::parseXsDouble(t);
                if (!d || !std::isfinite(*d) || n >= 3) return n = 4, false;
                v[n++] = *d;
                return true;
            });
            if (n != 3) return "an offsetVector is not three finite numbers";
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
                const std::optional<double> value = text::parseXsDouble(token);
                if (!value)
                    error = fail(at, "'" + quoted(token) + "' is not a number");
                else if (!std::isfinite(*value))
                    error = fail(at, "coordinate '" + quoted(token) + "' is NaN or infinite");
                else if (n < coords.size())
                    coords[n] = *value;
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

// Field names, tokenised for matching English names: lower case, split at anything that is
// not a letter or digit and at camelCase boundaries ("rockAge" -> rock, age).
std::vector<std::string> nameTokens(std::string_view name) {
    std::vector<std::string> tokens;
    std::string current;
    char previous = 0;
    for (const char c : name) {
        const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
        const bool upperAfterLower = c >= 'A' && c <= 'Z' && previous >= 'a' && previous <= 'z';
        if (!alnum || upperAfterLower) {
            if (!current.empty()) tokens.push_back(std::move(current));
            current.clear();
        }
        if (alnum) current += asciiLower(c);
        previous = c;
    }
    if (!current.empty()) tokens.push_back(std::move(current));
    return tokens;
}

bool hasToken(const std::vector<std::string>& tokens, std::string_view t) {
    return std::find(tokens.begin(), tokens.end(), t) != tokens.end();
}

bool contains(std::string_view s, std::string_view part) { return s.find(part) != std::string_view::npos; }

enum class FieldRole { None, Name, Lithology, Age, Era, Density, Grade, Colour };

// What a Fields/Field is, from its Name (Chinese or English).
FieldRole fieldRole(std::string_view name) {
    const std::vector<std::string> t = nameTokens(name);
    const bool stratumWord = hasToken(t, "stratigraphic") || hasToken(t, "stratigraphical") || hasToken(t, "stratum") ||
                             hasToken(t, "formation") || hasToken(t, "strata");
    if (contains(name, "地层名") || name == "地层" || contains(name, "组名") ||
        (stratumWord && (t.size() == 1 || hasToken(t, "name"))))
        return FieldRole::Name;
    if (contains(name, "岩性") || contains(name, "岩石名称") || hasToken(t, "lithology") || hasToken(t, "lith"))
        return FieldRole::Lithology;
    if (contains(name, "时代") || contains(name, "年代") || hasToken(t, "age")) return FieldRole::Age;
    if (name == "代" || hasToken(t, "era")) return FieldRole::Era;
    if (contains(name, "密度") || hasToken(t, "density")) return FieldRole::Density;
    if (contains(name, "品位") || hasToken(t, "grade")) return FieldRole::Grade;
    if (contains(name, "颜色") || hasToken(t, "colour") || hasToken(t, "color")) return FieldRole::Colour;
    return FieldRole::None;
}

// record.kind from the feature class or feature name; "" when neither says.
std::string kindFromNames(std::string_view className, std::string_view featureName) {
    for (const std::string_view s : {className, featureName}) {
        const std::string lower = asciiLowerCopy(s);
        if (contains(s, "断层") || contains(lower, "fault")) return "fault";
        if (contains(s, "矿体") || contains(lower, "orebody") || contains(lower, "ore body") ||
            contains(lower, "ore_body"))
            return "orebody";
        if (contains(s, "岩体") || contains(lower, "intrusi")) return "intrusion";
        if (contains(s, "地形") || contains(s, "地表") || contains(lower, "terrain") || contains(lower, "topograph"))
            return "terrain";
        if (contains(s, "地层") || contains(lower, "strat") || contains(lower, "formation")) return "stratum";
    }
    return "";
}

// Builds a record's `extra` in file order. ordered_json finds keys by linear search, so
// inserting n fields one by one costs O(n^2); a feature with very many fields must not hang
// the loader. Keys are made unique here (a repeated field name becomes "name#2", "name#3"...)
// and appended to the underlying vector of ordered_json's object directly.
class ExtraBuilder {
public:
    void put(const std::string& key, nlohmann::ordered_json value) {
        std::string k = key;
        if (!used_.insert(k).second) {
            std::size_t& n = nextSuffix_[key];
            if (n < 2) n = 2;
            do k = key + "#" + std::to_string(n++);
            while (!used_.insert(k).second);
        }
        entries_.emplace_back(std::move(k), std::move(value));
    }
    bool contains(const std::string& key) const { return used_.count(key) != 0; }

    void moveInto(nlohmann::ordered_json& extra) {
        if (!extra.is_object()) extra = nlohmann::ordered_json::object();
        auto& object = extra.get_ref<nlohmann::ordered_json::object_t&>();
        GS_ASSERT(object.empty(), "ExtraBuilder::moveInto expects an empty object");
        object.reserve(entries_.size());
        for (auto& [k, v] : entries_) object.emplace_back(std::move(k), std::move(v));
        entries_.clear();
        used_.clear();
    }

private:
    std::vector<std::pair<std::string, nlohmann::ordered_json>> entries_;
    std::unordered_set<std::string> used_;
    std::unordered_map<std::string, std::size_t> nextSuffix_;
};

// One record per feature:
//  - name: the stratigraphic-name field (地层名称, stratigraphic_name...) when it has a value,
//    else the feature's gml:name; kind from the feature class / feature name;
//  - lithology (岩性, lithology), age (时代, 年代, age), era, density (密度, density; t/m3,
//    g/cm3 or kg/m3), grade (品位, grade; unit from swe:uom), colour (颜色, colour);
//  - extra: "gml:id", "gml:name", "geo3dml:featureClass", then every field in file order with
//    its value as written (text verbatim; swe:Quantity / swe:Count values as numbers when
//    they are finite numbers; absent values as null) and "<field>:uom" for units. Keys with
//    a ':' are the loader's (Field Name is an NCName, which cannot contain ':').
Result<AttributeRecord> Reader::buildRecord(pugi::xml_node feature, const std::string& featureName,
                                            std::string_view className, bool closed) const {
    AttributeRecord rec;
    rec.name = featureName;
    rec.kind = kindFromNames(className, featureName);
    if (rec.kind.empty()) rec.kind = closed ? "body" : "surface";
    ExtraBuilder extra;
    if (const pugi::xml_attribute id = attributeNamed(feature, "id")) {
        if (!isValidUtf8(id.value())) return fail(feature, "gml:id is not valid UTF-8");
        extra.put("gml:id", id.value());
    }
    extra.put("gml:name", featureName);
    if (!className.empty()) extra.put("geo3dml:featureClass", std::string(className));

    bool nameFromField = false;
    const pugi::xml_node fields = childNamed(feature, "Fields");
    std::size_t ordinal = 0;
    for (pugi::xml_node field = fields.first_child(); field; field = field.next_sibling()) {
        if (!isNamed(field, "Field")) continue;
        ++ordinal;
        std::string key = attributeNamed(field, "Name").value();
        if (!isValidUtf8(key)) return fail(field, "the field's Name is not valid UTF-8");
        if (key.empty()) key = "field" + std::to_string(ordinal);

        // One swe data component (Text, Quantity, Count, Category, Boolean...) with a value.
        const pugi::xml_node component = firstElementChild(field);
        const std::string_view componentName = component ? localName(component.name()) : std::string_view();
        const pugi::xml_node valueNode = childNamed(component, "value");
        const std::string uom = attributeNamed(childNamed(component, "uom"), "code").value();
        if (!isValidUtf8(uom)) return fail(field, "the field's uom is not valid UTF-8");

        nlohmann::ordered_json value;  // null when the field has no value element
        std::string text;
        if (valueNode) {
            if (auto err = readText(valueNode, text)) return std::move(*err);
            value = text;
            const std::string_view t = trimSpace(text);
            if (componentName == "Quantity" || componentName == "Count") {
                if (const std::optional<std::int64_t> i = text::parseNumber<std::int64_t>(t);
                    i && componentName == "Count")
                    value = *i;
                else if (const std::optional<double> d = text::parseXsDouble(t); d && std::isfinite(*d))
                    value = *d;
            } else if (componentName == "Boolean") {
                if (t == "true" || t == "1")
                    value = true;
                else if (t == "false" || t == "0")
                    value = false;
            }
        }
        extra.put(key, std::move(value));
        if (!uom.empty()) extra.put(key + ":uom", uom);

        const std::string_view t = trimSpace(text);
        if (t.empty()) continue;
        switch (fieldRole(key)) {
            case FieldRole::Name:
                if (!nameFromField) rec.name = std::string(t), nameFromField = true;
                break;
            case FieldRole::Lithology:
                if (rec.lithology.empty()) rec.lithology = std::string(t);
                break;
            case FieldRole::Age:
                if (rec.age.empty()) rec.age = std::string(t);
                break;
            case FieldRole::Era:
                if (rec.era.empty()) rec.era = std::string(t);
                break;
            case FieldRole::Density: {
                const std::optional<double> d = text::parseXsDouble(t);
                const std::string unit = asciiLowerCopy(trimSpace(uom));
                double scale = 0.0;  // to t/m3; 0 = unknown unit, not mapped
                if (unit.empty() || unit == "t/m3" || unit == "g/cm3" || unit == "t/m^3" || unit == "g/cm^3")
                    scale = 1.0;
                else if (unit == "kg/m3" || unit == "kg/m^3")
                    scale = 0.001;
                if (d && std::isfinite(*d) && scale > 0.0 && !rec.density) rec.density = *d * scale;
                break;
            }
            case FieldRole::Grade: {
                const std::optional<double> d = text::parseXsDouble(t);
                if (d && std::isfinite(*d) && !rec.grade) {
                    rec.grade = *d;
                    rec.gradeUnit = std::string(trimSpace(uom));
                }
                break;
            }
            case FieldRole::Colour:
                if (const std::optional<Rgba8> c = parseColour(t)) rec.colour = *c;
                break;
            case FieldRole::None:
                break;
        }
    }
    extra.moveInto(rec.extra);
    return rec;
}

// "EPSG:4526", "urn:ogc:def:crs:EPSG::4526", "urn:ogc:def:crs:EPSG:6.6:4526",
// "http://www.opengis.net/def/crs/EPSG/0/4526" -> "EPSG:4526"; anything else unchanged.
std::string normaliseCrsText(std::string_view text) {
    text = trimSpace(text);
    const std::string lower = asciiLowerCopy(text);
    std::size_t codeStart = std::string::npos;
    if (lower.starts_with("urn:ogc:def:crs:epsg:"))
        codeStart = lower.rfind(':') + 1;
    else if (lower.starts_with("http") && contains(lower, "/def/crs/epsg/"))
        codeStart = lower.rfind('/') + 1;
    else if (lower.starts_with("epsg:"))
        codeStart = 5;
    if (codeStart != std::string::npos && isDigits(text.substr(codeStart)))
        return "EPSG:" + std::string(text.substr(codeStart));
    return std::string(text);
}

// Declared CRS -> model.crs. A CRS geoslice does not support leaves the model local, with the
// declared text in the model's notes ("declared_crs", "declared_crs_note"), so it is
// not lost. For a projected CRS the coordinates are checked against it (fixAxisOrder inside).
void Reader::applyCrs(Model& model) const {
    const std::string declared = declaredCrs_.empty() ? srsName_ : declaredCrs_;
    if (trimSpace(declared).empty()) return;
    const auto note = [&](const char* key, const std::string& value) { model.notes.emplace(key, quoted(value, 400)); };
    const Result<Crs> crs = Crs::parse(normaliseCrsText(declared));
    if (!crs) {
        note("declared_crs", declared);
        note("declared_crs_note",
             "not a CRS geoslice supports (" + crs.error().message + "); the model is kept in local coordinates");
        return;
    }
    model.crs = crs.value();
    // The fit check below knows Gauss-Kruger false eastings only; PROJ CRSs are taken as declared.
    if (!model.crs.isGaussKruger()) return;

    // Gauss-Kruger: easting = false easting +- a few hundred km, northing 0..10,002 km. Chinese
    // surveying writes X = northing first; EPSG's axis order for these CRSs is northing first
    // too, while geoslice's world frame is x = easting. Swap when only the swapped order fits.
    Aabb box;
    for (const auto* parts : {&model.bodies, &model.surfaces})
        for (const Part& p : *parts)
            for (const glm::dvec3& q : p.mesh.positions) box.extend(q);
    if (!box.valid()) return;
    const double fe = model.crs.falseEastingM();
    const auto eastingFits = [&](double lo, double hi) {
        return lo >= fe - kMaxOffsetFromFalseEastingM && hi <= fe + kMaxOffsetFromFalseEastingM;
    };
    const auto northingFits = [&](double lo, double hi) { return lo >= 0.0 && hi <= kMaxNorthingM; };
    const bool asWritten = eastingFits(box.min.x, box.max.x) && northingFits(box.min.y, box.max.y);
    const bool swapped = eastingFits(box.min.y, box.max.y) && northingFits(box.min.x, box.max.x);
    if (asWritten) return;
    if (swapped) {
        for (auto* parts : {&model.bodies, &model.surfaces})
            for (Part& p : *parts) {
                for (glm::dvec3& q : p.mesh.positions) std::swap(q.x, q.y);
                // Swapping two axes mirrors the mesh; swapping two corners keeps outward normals.
                for (std::size_t t = 0; t + 2 < p.mesh.indices.size(); t += 3)
                    std::swap(p.mesh.indices[t + 1], p.mesh.indices[t + 2]);
            }
        note("axis_order", "coordinates were written northing first (X = north); swapped to x = east, y = north");
        return;
    }
    const auto metres = [](double v) {  // whole metres; any finite double, however large
        char buf[64];
        std::snprintf(buf, sizeof buf, std::fabs(v) < 1e15 ? "%.0f" : "%.6g", v);
        return std::string(buf);
    };
    const auto range = [&](double lo, double hi) { return metres(std::floor(lo)) + ".." + metres(std::ceil(hi)); };
    note("crs_warning", "coordinates (x " + range(box.min.x, box.max.x) + " m, y " + range(box.min.y, box.max.y) +
                            " m) do not fit " + model.crs.id() + " (eastings near " + metres(fe) +
                            " m): the declared CRS may not apply");
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
        ". geoslice reads Geo3DML TIN surfaces (GeoTin, gml:TriangulatedSurface); grids, volumes, "
        "boreholes and section lines are skipped";
    return makeError(ErrorCode::Unsupported, msg);
}

}  // namespace

Result<Model> parseGeo3dml(std::string_view text, const std::string& source, const std::string& baseDir) {
    Reader reader(source, baseDir);
    return reader.run(text);
}

}  // namespace geoslice
