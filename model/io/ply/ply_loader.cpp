// PLY (Stanford polygon file) reader: ASCII, binary little-endian and binary big-endian.
//
// No PLY library is packaged in Debian 12 (apt-cache search finds none; tinyply, happly
// and rply are not packaged), and libassimp's PLY importer keeps only the face properties it
// knows (colours, material_index, texture coordinates), not a `region` or `label`, so this is
// a bounded reader written for geoslice.
//
// Frame: world coordinates, z up, metres, no axis swap (as OBJ and STL).
//
// What is read:
//  - element `vertex`: properties x, y, z of any scalar type (float, double or integer);
//  - element `face`: the list property `vertex_indices` (or `vertex_index`) with any
//    count and index types; polygons are fan-triangulated from their first corner;
//  - a face property naming the region: the first scalar face property called `region`,
//    `part`, `label`, `material_index`, `material`, `formation` or `domain` (any numeric
//    type; values must be whole numbers) splits the faces into parts named
//    "<property> <value>", e.g. "region 3"; without one, all faces are one part named after
//    the file stem;
//  - every other element and property (normals, colours, texture coordinates, edges,
//    materials) is skipped by its declared type.
// Each part's corners are welded exactly (model/io/weld.hpp): writers that repeat a vertex per
// face still give closed bodies; finishLoadedModel() makes closed parts bodies, open ones surfaces.
// Every element count and list length is checked against the bytes left before anything is
// allocated; errors name the file and the line (ASCII, header) or byte offset (binary).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "model/io/loaders.hpp"
#include "model/io/weld.hpp"
#include "model/text_scan.hpp"

namespace geoslice {
namespace {

using namespace geoslice::text;

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::optional<Type> typeNamed(std::string_view s) {
    if (s == "char" || s == "int8") return Type::Int8;
    if (s == "uchar" || s == "uint8") return Type::UInt8;
    if (s == "short" || s == "int16") return Type::Int16;
    if (s == "ushort" || s == "uint16") return Type::UInt16;
    if (s == "int" || s == "int32") return Type::Int32;
    if (s == "uint" || s == "uint32") return Type::UInt32;
    if (s == "float" || s == "float32") return Type::Float32;
    if (s == "double" || s == "float64") return Type::Float64;
    return std::nullopt;
}

std::size_t sizeOf(Type t) {
    switch (t) {
        case Type::Int8:
        case Type::UInt8:
            return 1;
        case Type::Int16:
        case Type::UInt16:
            return 2;
        case Type::Int32:
        case Type::UInt32:
        case Type::Float32:
            return 4;
        case Type::Float64:
            return 8;
    }
    return 8;
}

bool isInteger(Type t) { return t != Type::Float32 && t != Type::Float64; }

struct Property {
    std::string name;
    Type type = Type::Float32;
    bool list = false;
    Type countType = Type::UInt8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
    std::size_t line = 0;  // header line that declares it
};

enum class Format { Ascii, BinaryLittle, BinaryBig };

constexpr std::uint64_t kMaxPlyVertices = std::numeric_limits<std::uint32_t>::max() - 1;

constexpr std::string_view kRegionNames[] = {"region",   "part",      "label", "material_index",
                                             "material", "formation", "domain"};

class PlyReader {
public:
    PlyReader(std::string_view bytes, const std::string& source) : bytes_(bytes), source_(source) {}
    Result<Model> run();

private:
    Error failLine(std::size_t line, const std::string& what) const {
        return makeError(ErrorCode::ParseError, source_ + ": line " + std::to_string(line) + ": " + what);
    }
    Error failData(const std::string& what) const {
        if (format_ == Format::Ascii) return failLine(lineNo_, what);
        return makeError(ErrorCode::ParseError, source_ + ": byte offset " + std::to_string(pos_) + ": " + what);
    }
    Status readHeader();
    // One scalar value of type t from the body, as a double (integers are exact below 2^53).
    Status readValue(Type t, double& out);
    Status readAsciiToken(std::string_view& tok);
    Status skipElement(const Element& e);
    Status readVertices(const Element& e);
    Status readFaces(const Element& e);
    // Least bytes one instance of `e` takes in the body (ASCII: one digit and a separator
    // per value), for checking counts against the bytes left.
    std::uint64_t minBytes(const Element& e) const;
    Status checkCount(const Element& e) const;

    std::string_view bytes_;
    const std::string& source_;
    std::size_t pos_ = 0;
    std::size_t lineNo_ = 0;  // ASCII body: line of the last token read
    Format format_ = Format::Ascii;
    std::vector<Element> elements_;
    std::vector<glm::dvec3> positions_;
    bool haveVertices_ = false;
    // Per part: `indices` holds global vertex indices until run() welds each part's corners
    // exactly (some writers repeat a vertex per face, as STL does).
    std::vector<WeldedPart> parts_;
    std::map<std::int64_t, std::size_t> partByRegion_;
    std::string regionProperty_;
};

Status PlyReader::readHeader() {
    std::string_view line;
    std::size_t lineNo = 0;
    bool sawFormat = false;
    auto nextHeaderLine = [&]() -> bool {
        if (!text::nextLine(bytes_, pos_, line)) return false;
        ++lineNo;
        return true;
    };
    if (!nextHeaderLine() || trim(line) != "ply")
        return makeError(ErrorCode::ParseError, source_ + ": not PLY: the first line is not 'ply'");
    for (;;) {
        if (!nextHeaderLine()) return failLine(lineNo, "the file ends inside the header (no 'end_header')");
        if (std::size_t bad = findNonText(line, false); bad != std::string_view::npos)
            return failLine(lineNo, nonTextMessage(line, bad, false));
        Tokens tokens(trim(line));
        std::string_view kw;
        if (!tokens.next(kw)) continue;
        if (kw == "end_header") break;
        if (kw == "comment" || kw == "obj_info") continue;
        if (kw == "format") {
            std::string_view f, version;
            tokens.next(f);
            tokens.next(version);
            if (f == "ascii")
                format_ = Format::Ascii;
            else if (f == "binary_little_endian")
                format_ = Format::BinaryLittle;
            else if (f == "binary_big_endian")
                format_ = Format::BinaryBig;
            else
                return failLine(
                    lineNo, "unknown format " + quoteToken(f) + " (ascii, binary_little_endian or binary_big_endian)");
            if (version != "1.0") return failLine(lineNo, "PLY version " + quoteToken(version) + " (1.0 is read)");
            sawFormat = true;
        } else if (kw == "element") {
            std::string_view name, count;
            if (!tokens.next(name) || !tokens.next(count))
                return failLine(lineNo, "'element' needs a name and a count");
            std::uint64_t n = 0;
            if (parseUnsigned(count, n) != IntStatus::Ok)
                return failLine(lineNo, "element count " + quoteToken(count) + " is not a whole number");
            elements_.push_back(Element{std::string(name), n, {}, lineNo});
        } else if (kw == "property") {
            if (elements_.empty()) return failLine(lineNo, "'property' before any 'element'");
            Property p;
            std::string_view t;
            tokens.next(t);
            if (t == "list") {
                std::string_view ct, it;
                tokens.next(ct);
                tokens.next(it);
                auto c = typeNamed(ct), i = typeNamed(it);
                if (!c || !i) return failLine(lineNo, "unknown list types " + quoteToken(ct) + " " + quoteToken(it));
                if (!isInteger(*c)) return failLine(lineNo, "a list count type must be an integer type");
                p.list = true;
                p.countType = *c;
                p.type = *i;
            } else {
                auto ty = typeNamed(t);
                if (!ty) return failLine(lineNo, "unknown property type " + quoteToken(t));
                p.type = *ty;
            }
            std::string_view name;
            if (!tokens.next(name)) return failLine(lineNo, "'property' needs a name");
            p.name = std::string(name);
            elements_.back().properties.push_back(std::move(p));
        } else {
            return failLine(lineNo, "unknown header keyword " + quoteToken(kw));
        }
    }
    if (!sawFormat) return failLine(lineNo, "the header has no 'format' line");
    lineNo_ = lineNo + 1;  // the body starts on the next line
    return {};
}

std::uint64_t PlyReader::minBytes(const Element& e) const {
    std::uint64_t n = 0;
    for (const Property& p : e.properties) n += format_ == Format::Ascii ? 2 : sizeOf(p.list ? p.countType : p.type);
    return n;
}

Status PlyReader::checkCount(const Element& e) const {
    const std::uint64_t per = minBytes(e);
    const std::uint64_t left = bytes_.size() - pos_;
    if (per > 0 && e.count > left / per)
        return failData("element '" + e.name + "' (header line " + std::to_string(e.line) + ") declares " +
                        std::to_string(e.count) + " items of at least " + std::to_string(per) +
                        " bytes each, but only " + std::to_string(left) + " bytes are left");
    return {};
}

Status PlyReader::readAsciiToken(std::string_view& tok) {
    for (;;) {
        while (pos_ < bytes_.size() && isBlank(bytes_[pos_])) ++pos_;
        if (pos_ >= bytes_.size()) return failData("the file ends inside the data (more values were declared)");
        if (bytes_[pos_] == '\n') {
            ++pos_;
            ++lineNo_;
            continue;
        }
        break;
    }
    const std::size_t start = pos_;
    while (pos_ < bytes_.size() && !isSpace(bytes_[pos_])) ++pos_;
    tok = bytes_.substr(start, pos_ - start);
    return {};
}

Status PlyReader::readValue(Type t, double& out) {
    if (format_ == Format::Ascii) {
        std::string_view tok;
        if (Status s = readAsciiToken(tok); !s) return s;
        if (tok.size() > 64 || !std::all_of(tok.begin(), tok.end(), [](char c) { return c > ' ' && c < 127; }))
            return failData("a value is not text: " + quoteToken(tok.substr(0, 64)));
        if (isInteger(t)) {
            std::int64_t v = 0;
            if (parseInt(tok, v) != IntStatus::Ok) return failData("value " + quoteToken(tok) + " is not an integer");
            out = static_cast<double>(v);
        } else {
            auto v = parseDouble(tok);
            if (!v) return failData("value " + quoteToken(tok) + " is not a number");
            out = *v;
        }
        return {};
    }
    const std::size_t n = sizeOf(t);
    if (bytes_.size() - pos_ < n) return failData("the file ends inside the data (more values were declared)");
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + pos_, n);
    const bool swap = (format_ == Format::BinaryBig) == (std::endian::native == std::endian::little);
    if (swap) std::reverse(b, b + n);
    pos_ += n;
    switch (t) {
        case Type::Int8:
            out = static_cast<std::int8_t>(b[0]);
            break;
        case Type::UInt8:
            out = b[0];
            break;
        case Type::Int16: {
            std::int16_t v;
            std::memcpy(&v, b, 2);
            out = v;
            break;
        }
        case Type::UInt16: {
            std::uint16_t v;
            std::memcpy(&v, b, 2);
            out = v;
            break;
        }
        case Type::Int32: {
            std::int32_t v;
            std::memcpy(&v, b, 4);
            out = v;
            break;
        }
        case Type::UInt32: {
            std::uint32_t v;
            std::memcpy(&v, b, 4);
            out = v;
            break;
        }
        case Type::Float32: {
            float v;
            std::memcpy(&v, b, 4);
            out = v;
            break;
        }
        case Type::Float64: {
            double v;
            std::memcpy(&v, b, 8);
            out = v;
            break;
        }
    }
    return {};
}

Status PlyReader::skipElement(const Element& e) {
    if (Status s = checkCount(e); !s) return s;
    if (e.properties.empty()) return {};
    double v = 0.0;
    for (std::uint64_t i = 0; i < e.count; ++i) {
        for (const Property& p : e.properties) {
            if (Status s = readValue(p.list ? p.countType : p.type, v); !s) return s;
            if (!p.list) continue;
            if (v < 0) return failData("list '" + p.name + "' has a negative length");
            const std::uint64_t n = static_cast<std::uint64_t>(v);
            const std::uint64_t per = format_ == Format::Ascii ? 2 : sizeOf(p.type);
            if (n > (bytes_.size() - pos_) / per)
                return failData("list '" + p.name + "' of " + std::to_string(n) +
                                " items runs past the end of the file");
            if (format_ != Format::Ascii) {
                pos_ += static_cast<std::size_t>(n * per);
            } else {
                for (std::uint64_t k = 0; k < n; ++k)
                    if (Status s = readValue(p.type, v); !s) return s;
            }
        }
    }
    return {};
}

Status PlyReader::readVertices(const Element& e) {
    if (haveVertices_) return failData("a second 'vertex' element");
    int axis[3] = {-1, -1, -1};
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        for (int a = 0; a < 3; ++a)
            if (!p.list && p.name.size() == 1 && p.name[0] == "xyz"[a]) axis[a] = static_cast<int>(k);
    }
    for (int a = 0; a < 3; ++a)
        if (axis[a] < 0)
            return failLine(e.line, std::string("element 'vertex' has no scalar property '") + "xyz"[a] + "'");
    if (Status s = checkCount(e); !s) return s;
    if (e.count > kMaxPlyVertices)
        return failData("element 'vertex' declares " + std::to_string(e.count) + " vertices, over the limit of " +
                        std::to_string(kMaxPlyVertices));
    positions_.reserve(static_cast<std::size_t>(e.count));
    double v = 0.0;
    for (std::uint64_t i = 0; i < e.count; ++i) {
        glm::dvec3 p(0.0);
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
            const Property& prop = e.properties[k];
            if (Status s = readValue(prop.list ? prop.countType : prop.type, v); !s) return s;
            if (prop.list) {
                // A list on a vertex (rare): skipped by its length.
                if (v < 0) return failData("list '" + prop.name + "' has a negative length");
                const std::uint64_t n = static_cast<std::uint64_t>(v);
                const std::uint64_t per = format_ == Format::Ascii ? 2 : sizeOf(prop.type);
                if (n > (bytes_.size() - pos_) / per) return failData("list '" + prop.name + "' runs past the end");
                double ignored = 0.0;
                if (format_ != Format::Ascii)
                    pos_ += static_cast<std::size_t>(n * per);
                else
                    for (std::uint64_t j = 0; j < n; ++j)
                        if (Status s = readValue(prop.type, ignored); !s) return s;
                continue;
            }
            for (int a = 0; a < 3; ++a)
                if (static_cast<int>(k) == axis[a]) p[a] = v;
        }
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return failData("vertex " + std::to_string(i) + " has a non-finite coordinate");
        positions_.push_back(p);
    }
    haveVertices_ = true;
    return {};
}

Status PlyReader::readFaces(const Element& e) {
    if (!haveVertices_)
        return failLine(e.line,
                        "element 'face' comes before element 'vertex' (faces index the vertices read before them)");
    int indices = -1, region = -1;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (p.list && indices < 0 && (p.name == "vertex_indices" || p.name == "vertex_index"))
            indices = static_cast<int>(k);
        if (!p.list && region < 0 &&
            std::find(std::begin(kRegionNames), std::end(kRegionNames), p.name) != std::end(kRegionNames))
            region = static_cast<int>(k);
    }
    if (indices < 0) return failLine(e.line, "element 'face' has no list property 'vertex_indices'");
    if (e.properties[static_cast<std::size_t>(indices)].type == Type::Float32 ||
        e.properties[static_cast<std::size_t>(indices)].type == Type::Float64)
        return failLine(e.line, "'vertex_indices' has a floating-point index type");
    if (region >= 0) regionProperty_ = e.properties[static_cast<std::size_t>(region)].name;
    if (Status s = checkCount(e); !s) return s;
    std::vector<std::uint32_t> corners;
    double v = 0.0;
    const std::string stem = [&] {
        std::string s = std::filesystem::path(source_).stem().string();
        return s.empty() ? std::string("ply") : s;
    }();
    for (std::uint64_t i = 0; i < e.count; ++i) {
        corners.clear();
        std::int64_t regionValue = 0;
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
            const Property& p = e.properties[k];
            if (Status s = readValue(p.list ? p.countType : p.type, v); !s) return s;
            if (!p.list) {
                if (static_cast<int>(k) == region) {
                    if (!std::isfinite(v) || v != std::floor(v) || std::fabs(v) > 9.0e15)
                        return failData("face " + std::to_string(i) + ": region property '" + p.name + "' value " +
                                        std::to_string(v) + " is not a whole number");
                    regionValue = static_cast<std::int64_t>(v);
                }
                continue;
            }
            if (v < 0) return failData("face " + std::to_string(i) + ": list '" + p.name + "' has a negative length");
            const std::uint64_t n = static_cast<std::uint64_t>(v);
            const std::uint64_t per = format_ == Format::Ascii ? 2 : sizeOf(p.type);
            if (n > (bytes_.size() - pos_) / per)
                return failData("face " + std::to_string(i) + ": list '" + p.name + "' of " + std::to_string(n) +
                                " items runs past the end of the file");
            const bool isIndices = static_cast<int>(k) == indices;
            for (std::uint64_t j = 0; j < n; ++j) {
                double idx = 0.0;
                if (Status s = readValue(p.type, idx); !s) return s;
                if (!isIndices) continue;
                if (idx < 0 || idx >= static_cast<double>(positions_.size()))
                    return failData("face " + std::to_string(i) + ": vertex index " +
                                    std::to_string(static_cast<std::int64_t>(idx)) + " is out of range (" +
                                    std::to_string(positions_.size()) + " vertices)");
                corners.push_back(static_cast<std::uint32_t>(idx));
            }
            if (isIndices && n < 3)
                return failData("face " + std::to_string(i) + " has " + std::to_string(n) + " vertices (3 at least)");
        }
        auto [it, inserted] = partByRegion_.try_emplace(region >= 0 ? regionValue : 0, parts_.size());
        if (inserted) {
            parts_.emplace_back();
            parts_.back().name = region >= 0 ? regionProperty_ + " " + std::to_string(regionValue) : stem;
        }
        WeldedPart& part = parts_[it->second];
        for (std::size_t c = 1; c + 1 < corners.size(); ++c) {
            part.indices.push_back(corners[0]);
            part.indices.push_back(corners[c]);
            part.indices.push_back(corners[c + 1]);
        }
        if (part.indices.size() > std::numeric_limits<std::uint32_t>::max() - 3)
            return failData("too many triangles in one part");
    }
    return {};
}

Result<Model> PlyReader::run() {
    if (Status s = readHeader(); !s) return s.error();
    bool sawFaces = false;
    for (const Element& e : elements_) {
        Status s;
        if (e.name == "vertex") {
            s = readVertices(e);
        } else if (e.name == "face" && !sawFaces) {
            s = readFaces(e);
            sawFaces = true;
        } else {
            s = skipElement(e);
        }
        if (!s) return s.error();
    }
    if (!sawFaces) return makeError(ErrorCode::ParseError, source_ + ": PLY with no 'face' element: nothing to load");
    Model model;
    model.source = source_;
    model.name = std::filesystem::path(source_).stem().string();
    for (WeldedPart& b : parts_) {
        std::vector<std::uint32_t> global = std::move(b.indices);
        b.indices.clear();
        b.indices.reserve(global.size());
        for (std::uint32_t g : global) b.indices.push_back(b.welder.add(positions_[g]));
    }
    std::vector<glm::dvec3>().swap(positions_);
    addWeldedParts(model, parts_);
    if (model.bodies.empty()) return makeError(ErrorCode::ParseError, source_ + ": PLY with no faces: nothing to load");
    if (!regionProperty_.empty()) model.notes["ply_region_property"] = regionProperty_;
    finishLoadedModel(model, /*classifyByClosure=*/true);
    setRecordKinds(model);
    return model;
}

}  // namespace

Result<Model> parsePly(std::string_view bytes, const std::string& source) { return PlyReader(bytes, source).run(); }

}  // namespace geoslice
