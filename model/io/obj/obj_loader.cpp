// Wavefront OBJ loader (polygonal geometry only).
//
// Frame: OBJ has no units or axis convention of its own. Geological exports (GOCAD/SKUA,
// Leapfrog, Micromine, Surpac) write world coordinates with z up, so OBJ is read as world
// coordinates: x east, y north, z elevation up, metres; no axis swap. A y-up model from a
// graphics tool will lie on its side and must be converted before loading.
//
// What is read:
//  - `v x y z [w]` (w, and the r g b of the vertex-colour extension, are ignored);
//  - `f` with `v`, `v/vt`, `v//vn`, `v/vt/vn` corners, negative (relative) indices;
//    polygons are fan-triangulated from their first corner (exact for convex polygons,
//    which is what exporters write);
//  - `o name` and `g name` start a new part: faces before any o/g go into a part named
//    after the file stem; faces under a `g` go into the part named after the group, also
//    inside an `o` (exporters such as Leapfrog write `o Name` then `g Name`: the part is
//    "Name", not "Name/Name"; OBJ group names are global, so the same group under two
//    objects is one part); faces under an `o` with no group (or after an empty `g`) go into
//    the part named after the object; a name seen again appends to its earlier part (OBJ
//    groups can be reopened);
//  - `mtllib` and `usemtl`: a part takes the diffuse colour (Kd) of the material most of its
//    faces use, from the .mtl files named by `mtllib` beside the OBJ (read with tinyobjloader,
//    Debian's libtinyobjloader; a file name with a folder part or '..' is not followed, and a
//    missing or unreadable .mtl is a model note, not an error). Opacity (d/Tr) is not used:
//    writers disagree on Tr (VTK writes Tr 1 for opaque). A sidecar colour still wins.
//  - texture coordinates, normals, smoothing groups, lines, points and free-form geometry are
//    ignored; unknown keywords are skipped if the line is text.
// Vertices are global to the file; each part gets its own compacted vertex array (in
// first-use order), and finishLoadedModel() classifies closed parts as bodies.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <tiny_obj_loader.h>

#include "model/io/loaders.hpp"
#include "model/text_scan.hpp"

namespace geoslice {
namespace {

constexpr std::size_t kMaxVertices = std::numeric_limits<std::uint32_t>::max() - 1;
constexpr std::uint32_t kUnset = std::numeric_limits<std::uint32_t>::max();

using namespace geoslice::text;

struct PartBuild {
    std::string name;
    std::vector<std::uint32_t> corners;               // global vertex indices, 3 per triangle
    std::map<std::string, std::size_t> faceMaterial;  // usemtl name -> faces
};

// A material of an .mtl file: its diffuse colour and the file it came from.
struct ObjMaterial {
    Rgba8 colour;
    std::string file;
};

// The materials of the .mtl files `names` (as `mtllib` gives them) in `baseDir`, read with
// tinyobjloader; what could not be read is said in `note`.
std::map<std::string, ObjMaterial> readMaterialLibraries(const std::vector<std::string>& names,
                                                         const std::string& baseDir, std::string& note) {
    std::map<std::string, ObjMaterial> out;
    for (const std::string& name : names) {
        const std::filesystem::path rel(name);
        if (rel.has_parent_path() || rel.is_absolute() || name == ".." || name == ".") {
            note += (note.empty() ? "" : "; ") + ("mtllib '" + name + "' names a folder: not followed");
            continue;
        }
        const std::filesystem::path path = std::filesystem::path(baseDir) / rel;
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            note += (note.empty() ? "" : "; ") + ("mtllib '" + name + "': cannot open " + path.string());
            continue;
        }
        std::map<std::string, int> index;
        std::vector<tinyobj::material_t> materials;
        std::string warning, error;
        tinyobj::LoadMtl(&index, &materials, &in, &warning, &error);
        for (const auto& [material, i] : index) {
            if (i < 0 || std::size_t(i) >= materials.size()) continue;
            const auto& d = materials[std::size_t(i)].diffuse;
            auto byte = [](double v) {
                return std::uint8_t(std::lround(std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 1.0) * 255.0));
            };
            out.try_emplace(material, ObjMaterial{Rgba8{byte(d[0]), byte(d[1]), byte(d[2]), 255}, name});
        }
    }
    return out;
}

class ObjParser {
public:
    ObjParser(std::string_view text, const std::string& source, const std::string& baseDir)
        : text_(text), source_(source), baseDir_(baseDir) {}
    Result<Model> run();

private:
    bool nextLine(std::string_view& line);
    Error fail(const std::string& what) const {
        return makeError(ErrorCode::ParseError, source_ + ": line " + std::to_string(lineNo_) + ": " + what);
    }
    Status checkText(std::string_view line, bool utf8) const;
    Status readVertex(Tokens& tokens);
    Status readFace(Tokens& tokens);
    Status readCorner(std::string_view tok, std::uint32_t& out);
    std::size_t currentPart();

    std::string_view text_;
    const std::string& source_;
    const std::string& baseDir_;  // where mtllib files are looked for; "" = not read
    std::string material_;        // the usemtl in force
    std::vector<std::string> materialLibraries_;
    std::size_t pos_ = 0;
    std::size_t lineNo_ = 0;  // 1-based number of the current line (the first of a continued line)
    std::size_t nextLineNo_ = 0;
    std::string joined_;  // a line continued with '\' at line ends

    std::string stem_;
    std::string object_, group_;
    std::size_t part_ = std::string::npos;  // into parts_, npos until the first face after o/g
    std::vector<glm::dvec3> positions_;     // world, metres
    std::vector<PartBuild> parts_;
    std::map<std::string, std::size_t> partByName_;
    std::vector<std::uint32_t> face_;  // corners of the face being read
};

// Returns the next logical line: a physical line, or several joined by a trailing '\'.
bool ObjParser::nextLine(std::string_view& line) {
    auto physical = [&](std::string_view& out) {
        if (!text::nextLine(text_, pos_, out)) return false;
        ++nextLineNo_;
        return true;
    };
    if (!physical(line)) return false;
    lineNo_ = nextLineNo_;
    if (line.empty() || line.back() != '\\') return true;
    joined_.assign(line.substr(0, line.size() - 1));
    std::string_view more;
    while (physical(more)) {
        bool continues = !more.empty() && more.back() == '\\';
        joined_ += ' ';
        joined_.append(continues ? more.substr(0, more.size() - 1) : more);
        if (!continues) break;
    }
    line = joined_;
    return true;
}

Status ObjParser::checkText(std::string_view line, bool utf8) const {
    std::size_t bad = findNonText(line, utf8);
    if (bad == std::string_view::npos) return {};
    return fail(nonTextMessage(line, bad, utf8));
}

Result<Model> ObjParser::run() {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);  // UTF-8 byte order mark
    stem_ = std::filesystem::path(source_).stem().string();
    if (stem_.empty()) stem_ = "obj";

    // Keywords we read past without using (attributes, free-form geometry, display).
    static constexpr std::string_view kIgnored[] = {
        "vt",   "vn",         "vp",        "l",     "p",     "s",      "cstype",   "deg",
        "bmat", "step",       "curv",      "curv2", "surf",  "parm",   "trim",     "hole",
        "scrv", "sp",         "end",       "con",   "mg",    "bevel",  "c_interp", "d_interp",
        "lod",  "shadow_obj", "trace_obj", "ctech", "stech", "maplib", "usemap"};

    std::string_view line;
    while (nextLine(line)) {
        if (Status s = checkText(line, false); !s) return s.error();
        std::string_view t = trim(line);
        if (t.empty() || t.front() == '#') continue;
        Tokens tokens(t, '#');
        std::string_view keyword;
        tokens.next(keyword);
        if (keyword == "v") {
            if (Status s = readVertex(tokens); !s) return s.error();
        } else if (keyword == "f" || keyword == "fo") {  // "fo" is the obsolete spelling of "f"
            if (Status s = readFace(tokens); !s) return s.error();
        } else if (keyword == "usemtl") {
            material_ = toUtf8(trim(t.substr(keyword.size())));
        } else if (keyword == "mtllib") {
            std::string_view file;
            while (tokens.next(file)) materialLibraries_.push_back(toUtf8(file));
        } else if (keyword == "o" || keyword == "g") {
            // The whole rest of the line is the name (names may hold spaces and '#').
            std::string name = toUtf8(trim(t.substr(keyword.size())));
            if (keyword == "o") {
                object_ = std::move(name);
                group_.clear();
            } else {
                group_ = std::move(name);
            }
            part_ = std::string::npos;
        } else if (std::find(std::begin(kIgnored), std::end(kIgnored), keyword) == std::end(kIgnored)) {
            if (Status s = checkText(line, true); !s) return s.error();
        }
    }

    if (parts_.empty())
        return makeError(ErrorCode::ParseError,
                         source_ + (text_.empty() ? ": empty input" : ": no faces ('f' lines)") + ": nothing to load");

    Model model;
    model.source = source_;
    model.name = stem_;
    std::string mtlNote;
    const std::map<std::string, ObjMaterial> materials =
        baseDir_.empty() || materialLibraries_.empty() ? std::map<std::string, ObjMaterial>()
                                                       : readMaterialLibraries(materialLibraries_, baseDir_, mtlNote);
    if (!mtlNote.empty()) model.notes["obj_materials"] = mtlNote;
    // Compact each part's vertices: stamp[v] says which part last took global vertex v.
    std::vector<std::uint32_t> stamp(positions_.size(), kUnset), local(positions_.size(), 0);
    for (std::size_t p = 0; p < parts_.size(); ++p) {
        PartBuild& b = parts_[p];
        Part part;
        part.name = b.name;
        part.kind = PartKind::Body;
        Mesh& mesh = part.mesh;
        mesh.indices.reserve(b.corners.size());
        for (std::uint32_t g : b.corners) {
            if (stamp[g] != p) {
                stamp[g] = static_cast<std::uint32_t>(p);
                local[g] = static_cast<std::uint32_t>(mesh.positions.size());
                mesh.positions.push_back(positions_[g]);
            }
            mesh.indices.push_back(local[g]);
        }
        std::vector<std::uint32_t>().swap(b.corners);
        // One record per part, made here rather than by finishLoadedModel(), whose
        // look-up by name costs O(records) per part: quadratic for files with many groups.
        AttributeRecord rec;
        rec.name = part.name;
        // The colour of the material most of the part's faces use.
        const auto most = std::max_element(b.faceMaterial.begin(), b.faceMaterial.end(),
                                           [](const auto& x, const auto& y) { return x.second < y.second; });
        if (most != b.faceMaterial.end())
            if (const auto m = materials.find(most->first); m != materials.end()) {
                rec.colour = m->second.colour;
                rec.colourSource = "file (OBJ material '" + m->first + "' Kd in " + m->second.file + ")";
            }
        part.record = model.attributes.add(std::move(rec));
        model.bodies.push_back(std::move(part));
    }
    finishLoadedModel(model, /*classifyByClosure=*/true);
    // The records' kind follows the classification, as finishLoadedModel() would set it.
    for (auto* list : {&model.bodies, &model.surfaces}) {
        for (Part& p : *list) {
            AttributeRecord* r = model.attributes.find(p.record);
            if (r && r->kind.empty()) r->kind = p.kind == PartKind::Body ? "body" : "surface";
        }
    }
    return model;
}

Status ObjParser::readVertex(Tokens& tokens) {
    glm::dvec3 p(0.0);
    std::string_view tok;
    for (int a = 0; a < 3; ++a) {
        if (!tokens.next(tok))
            return fail("'v' needs x y z, found " + std::to_string(a) + " coordinate" + (a == 1 ? "" : "s"));
        std::optional<double> v = parseDouble(tok);
        if (!v) return fail("vertex coordinate " + quoteToken(tok) + " is not a number");
        if (!std::isfinite(*v)) return fail("vertex coordinate " + quoteToken(tok) + " is not a finite number");
        p[a] = *v;
    }
    // Optional w, or r g b of the vertex-colour extension: checked, not used.
    while (tokens.next(tok))
        if (!parseDouble(tok)) return fail("vertex value " + quoteToken(tok) + " is not a number");
    if (positions_.size() >= kMaxVertices) return fail("too many vertices");
    positions_.push_back(p);
    return {};
}

// One face corner: "v", "v/vt", "v//vn" or "v/vt/vn"; returns the 0-based vertex index.
Status ObjParser::readCorner(std::string_view tok, std::uint32_t& out) {
    std::size_t slash = tok.find('/');
    std::string_view vtok = tok.substr(0, slash);
    std::int64_t v = 0;
    IntStatus st = parseInt(vtok, v);
    if (st == IntStatus::NotInteger) return fail("face corner " + quoteToken(tok) + ": vertex index is not an integer");
    const auto count = static_cast<std::int64_t>(positions_.size());
    if (st == IntStatus::TooLarge || v == 0 || v > count || v < -count) {
        if (v == 0 && st == IntStatus::Ok)
            return fail("face corner " + quoteToken(tok) + ": vertex index 0 (OBJ counts from 1)");
        return fail("face corner " + quoteToken(tok) + ": vertex index out of range (" + std::to_string(count) +
                    " vertices defined before this line)");
    }
    if (slash != std::string_view::npos) {
        // Texture and normal indices are not used, only checked for form.
        std::string_view rest = tok.substr(slash + 1);
        std::size_t slash2 = rest.find('/');
        std::string_view vt = rest.substr(0, slash2);
        std::string_view vn = slash2 == std::string_view::npos ? std::string_view() : rest.substr(slash2 + 1);
        bool ok = slash2 == std::string_view::npos ? !vt.empty() : !vn.empty();
        std::int64_t ignored = 0;
        if (ok && !vt.empty()) ok = parseInt(vt, ignored) == IntStatus::Ok && ignored != 0;
        if (ok && !vn.empty()) ok = parseInt(vn, ignored) == IntStatus::Ok && ignored != 0;
        if (!ok) return fail("face corner " + quoteToken(tok) + " is not v, v/vt, v//vn or v/vt/vn");
    }
    out = static_cast<std::uint32_t>(v > 0 ? v - 1 : count + v);
    return {};
}

std::size_t ObjParser::currentPart() {
    if (part_ != std::string::npos) return part_;
    // The group names the part; then the object; then the file (see the rules at the top).
    std::string name = !group_.empty() ? group_ : !object_.empty() ? object_ : stem_;
    auto [it, inserted] = partByName_.try_emplace(name, parts_.size());
    if (inserted) parts_.push_back(PartBuild{std::move(name), {}, {}});
    part_ = it->second;
    return part_;
}

Status ObjParser::readFace(Tokens& tokens) {
    face_.clear();
    std::string_view tok;
    while (tokens.next(tok)) {
        std::uint32_t v = 0;
        if (Status s = readCorner(tok, v); !s) return s;
        face_.push_back(v);
    }
    if (face_.size() < 3) return fail("a face needs at least 3 vertices, found " + std::to_string(face_.size()));
    PartBuild& part = parts_[currentPart()];
    if (!material_.empty()) ++part.faceMaterial[material_];
    std::vector<std::uint32_t>& corners = part.corners;
    for (std::size_t i = 1; i + 1 < face_.size(); ++i) {
        corners.push_back(face_[0]);
        corners.push_back(face_[i]);
        corners.push_back(face_[i + 1]);
    }
    return {};
}

}  // namespace

Result<Model> parseObj(std::string_view text, const std::string& source, const std::string& baseDir) {
    ObjParser parser(text, source, baseDir);
    return parser.run();
}

}  // namespace geoslice
