// GOCAD TSurf ASCII loader (GOCAD "ASCII File Formats", TSurf objects).
//
// Output frame: world coordinates, x east, y north, z elevation up, metres. Depth-positive
// objects (ZPOSITIVE Depth) are negated and feet are converted on load.
//
// Choices, and why:
//  - One Part per `GOCAD TSurf ... END` object, holding every TFACE of that object. A
//    geologist sees a TSurf as one surface (one fault, one horizon); TFACEs are patches of
//    it that GOCAD stitches with ATOMs, and a closed shell is often made of several.
//  - ATOM / PATOM ids are aliases of the vertex they reference (same mesh index), so the
//    patches they stitch share vertices and a shell split into TFACEs can still be closed.
//  - Vertices no triangle uses are dropped: they would only widen the bounds and origin.
//  - A GOCAD_ORIGINAL_COORDINATE_SYSTEM block applies to the object it is in and to later
//    objects that have none of their own (some exporters write it once per file).
//  - model.crs is set only when the blocks name exactly one EPSG code that geoslice knows
//    (and no block names none); otherwise the model stays local. Either way each record
//    keeps its block's text in extra["gocad_coordinate_system"], as provenance.
//  - Objects of other GOCAD types (PLine, VSet, ...) after the first TSurf are skipped to
//    their END; the file itself must begin with `GOCAD TSurf`.
//  - Vertex ids are resolved when the object ends by sorting (id, index) pairs: O(n log n)
//    whatever ids an input picks, where a hash map could be driven quadratic; the usual
//    gap-free ids 1..n are looked up directly.
//  - Robustness: every line must be text (no control bytes); lines with unknown keywords
//    are skipped only when they are also well-formed UTF-8. Nothing is sized from a count
//    in the file; PVRTX columns are capped at kMaxPropertyColumns.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "model/loaders.hpp"
#include "model/text_scan.hpp"

namespace geoslice {
namespace {

// Columns of PVRTX properties per vertex (sum of ESIZES). Real files have a few dozen at
// most; the cap bounds the NaN padding that plain VRTX lines in such an object cost.
constexpr std::size_t kMaxPropertyColumns = 256;
constexpr double kFootM = 0.3048;                   // international foot, metres
constexpr double kUsSurveyFootM = 1200.0 / 3937.0;  // US survey foot, metres
constexpr std::uint32_t kUnresolved = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kMaxVertices = std::numeric_limits<std::uint32_t>::max() - 1;

using namespace geoslice::text;

enum class IdStatus { Ok, NotInteger, TooLarge };

IdStatus parseId(std::string_view tok, std::uint64_t& out) {
    if (tok.empty() || tok[0] < '0' || tok[0] > '9') return IdStatus::NotInteger;
    auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    if (ec == std::errc::result_out_of_range) return IdStatus::TooLarge;
    if (ec != std::errc() || end != tok.data() + tok.size()) return IdStatus::NotInteger;
    return IdStatus::Ok;
}

// Metres per unit of an AXIS_UNIT entry, or nullopt for a unit we do not convert.
std::optional<double> metresPerUnit(std::string_view unit) {
    std::string u = lower(unit);
    if (u == "m" || u == "meter" || u == "meters" || u == "metre" || u == "metres") return 1.0;
    if (u == "ft" || u == "feet" || u == "foot") return kFootM;
    if (u == "ft_us" || u == "us_ft" || u == "usft" || u == "ftus" || u == "us-ft" || u == "survey_ft")
        return kUsSurveyFootM;
    return std::nullopt;
}

std::string_view unquote(std::string_view s) {
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
    return s;
}

// The frame one object's numbers are in, from GOCAD_ORIGINAL_COORDINATE_SYSTEM.
struct CoordinateSystem {
    glm::dvec3 metresPerUnit{1.0};  // per axis
    bool depthPositive = false;     // ZPOSITIVE Depth: z grows downwards
    std::string text;               // the block's lines, for the record's extra
    std::optional<int> epsg;        // an "EPSG:nnnn" found in NAME or PROJECTION
};

struct VertexKey {
    std::uint64_t id = 0;
    std::uint32_t index = kUnresolved;  // mesh vertex; kUnresolved for an ATOM until resolved
    std::size_t line = 0;
};

struct Atom {
    std::uint64_t id = 0, ref = 0;
    std::size_t line = 0;
};

struct Triangle {
    std::uint64_t ids[3] = {0, 0, 0};
    std::size_t line = 0;
};

// One `GOCAD TSurf` object while it is being read. Coordinates are as written (file
// units, z sign as written) until finishObject() applies the coordinate system.
struct TsurfObject {
    std::size_t startLine = 0;
    std::string name;
    std::optional<Rgba8> solidColour, colour;
    std::string rawColour;  // kept when the colour text cannot be parsed
    std::string geologicalType, geologicalFeature, stratigraphicPosition;
    CoordinateSystem crs;
    bool hasOwnCrs = false;

    // Property schema (PROPERTIES, ESIZES, NO_DATA_VALUES), fixed at the first vertex.
    std::vector<std::string> propertyNames;
    std::vector<std::size_t> esizes;
    std::vector<double> noData;
    std::size_t propertiesLine = 0, esizesLine = 0, noDataLine = 0;
    bool schemaFixed = false;
    std::vector<std::string> columnNames;
    std::vector<double> columnNoData;  // NaN: no no-data value for that column

    std::vector<glm::dvec3> positions;
    std::vector<float> properties;  // columnNames.size() per vertex
    std::vector<VertexKey> keys;
    std::vector<Atom> atoms;
    std::vector<Triangle> triangles;
};

class TsurfParser {
public:
    TsurfParser(std::string_view text, const std::string& source) : text_(text), source_(source) {}

    Result<Model> run();

private:
    bool nextLine(std::string_view& line);
    Error failAt(std::size_t line, const std::string& what) const;
    Error fail(const std::string& what) const { return failAt(lineNo_, what); }
    Status checkText(std::string_view line, bool utf8) const;

    Status readObjectLine(std::string_view keyword, Tokens& tokens, std::string_view line);
    Status readHeader(std::string_view afterKeyword);
    void headerEntry(std::string_view entry);
    Status readCoordinateSystem();
    Status skipBlock(std::size_t startLine, std::string_view what);
    Status skipObject(std::size_t startLine);
    Status fixSchema();
    Status readVertex(Tokens& tokens, bool withProperties);
    Status readAtom(Tokens& tokens, std::string_view keyword);
    Status readTriangle(Tokens& tokens);
    Status readNameList(Tokens& tokens, std::vector<std::string>& out);
    Status finishObject();

    std::string_view text_;
    const std::string& source_;
    std::size_t pos_ = 0;
    std::size_t lineNo_ = 0;    // 1-based number of the current line
    std::size_t lastLine_ = 0;  // number of the last line of the input
    bool endsWithNewline_ = true;
    bool inObject_ = false;

    Model model_;
    CoordinateSystem fileCrs_;  // last block seen, inherited by objects without one
    TsurfObject obj_;
    std::set<int> epsgCodes_;
    bool crsAmbiguous_ = false;
    std::size_t propertyValueBudget_ = 0;    // floats left for per-vertex properties
    std::vector<std::size_t> unnamedParts_;  // indices into model_.surfaces
};

bool TsurfParser::nextLine(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(pos_, end - pos_);
    pos_ = end < text_.size() ? end + 1 : text_.size();
    ++lineNo_;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return true;
}

Error TsurfParser::failAt(std::size_t line, const std::string& what) const {
    std::string msg = source_ + ": line " + std::to_string(line) + ": " + what;
    if (inObject_ && line == lastLine_ && !endsWithNewline_)
        msg += " (the input ends in this line, without END: truncated file?)";
    return makeError(ErrorCode::ParseError, std::move(msg));
}

Status TsurfParser::checkText(std::string_view line, bool utf8) const {
    std::size_t bad = findNonText(line, utf8);
    if (bad == std::string_view::npos) return {};
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned>(static_cast<unsigned char>(line[bad])));
    return fail(std::string("not text: byte ") + hex + " at column " + std::to_string(bad + 1) +
                (utf8 ? " (binary data, or not UTF-8)" : " (binary data?)"));
}

Result<Model> TsurfParser::run() {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);  // UTF-8 byte order mark
    endsWithNewline_ = text_.empty() || text_.back() == '\n';
    lastLine_ = static_cast<std::size_t>(std::count(text_.begin(), text_.end(), '\n')) + (endsWithNewline_ ? 0 : 1);
    // Honest PVRTX values cost at least two bytes of text each; only VRTX lines in an
    // object with properties add NaN padding, which this budget bounds.
    propertyValueBudget_ = text_.size() + (std::size_t(1) << 20);

    model_.source = source_;
    model_.name = std::filesystem::path(source_).stem().string();
    bool sawObject = false;
    std::string_view line;
    while (nextLine(line)) {
        if (Status s = checkText(line, false); !s) return s.error();
        std::string_view t = trim(line);
        if (t.empty() || t.front() == '#') continue;
        Tokens tokens(t);
        std::string_view keyword;
        tokens.next(keyword);
        if (!inObject_) {
            if (keyword != "GOCAD") {
                if (!sawObject) return fail("not a GOCAD TSurf file: expected 'GOCAD TSurf 1', found " + quoteToken(t));
                return fail("expected 'GOCAD' to start the next object, found " + quoteToken(t));
            }
            std::string_view type;
            tokens.next(type);
            if (lower(type) != "tsurf") {
                if (!sawObject)
                    return fail("not a GOCAD TSurf file: the object type is " + quoteToken(type) +
                                ", this loader reads 'GOCAD TSurf'");
                if (Status s = skipObject(lineNo_); !s) return s.error();
                continue;
            }
            sawObject = true;
            inObject_ = true;
            obj_ = TsurfObject{};
            obj_.startLine = lineNo_;
            obj_.crs = fileCrs_;
            continue;
        }
        if (Status s = readObjectLine(keyword, tokens, t); !s) return s.error();
    }
    if (inObject_)
        return failAt(lastLine_, "missing END of the TSurf object that starts on line " +
                                     std::to_string(obj_.startLine) + " (truncated file?)");
    if (!sawObject) {
        if (text_.empty())
            return makeError(ErrorCode::ParseError, source_ + ": empty input (expected 'GOCAD TSurf 1')");
        return fail("empty input: only blank lines and comments, expected 'GOCAD TSurf 1'");
    }
    if (model_.surfaces.empty())
        return makeError(ErrorCode::ParseError, source_ + ": no triangles (TRGL) in any TSurf object");

    for (std::size_t i : unnamedParts_) {
        Part& p = model_.surfaces[i];
        p.name = model_.surfaces.size() == 1 ? model_.name : model_.name + "#" + std::to_string(i + 1);
        if (AttributeRecord* r = model_.attributes.find(p.record)) r->name = p.name;
    }
    if (epsgCodes_.size() == 1 && !crsAmbiguous_) {
        if (auto crs = Crs::fromEpsg(*epsgCodes_.begin())) model_.crs = crs.value();
    }

    finishLoadedModel(model_, /*classifyByClosure=*/true);
    // Records without a GEOLOGICAL_TYPE take the kind their part was classified as.
    for (auto* list : {&model_.bodies, &model_.surfaces}) {
        for (Part& p : *list) {
            AttributeRecord* r = model_.attributes.find(p.record);
            if (r && r->kind.empty()) r->kind = p.kind == PartKind::Body ? "body" : "surface";
        }
    }
    return std::move(model_);
}

Status TsurfParser::readObjectLine(std::string_view keyword, Tokens& tokens, std::string_view line) {
    if (keyword == "VRTX") return readVertex(tokens, false);
    if (keyword == "PVRTX") return readVertex(tokens, true);
    if (keyword == "TRGL") return readTriangle(tokens);
    if (keyword == "ATOM" || keyword == "PATOM") return readAtom(tokens, keyword);
    if (keyword == "TFACE") return {};  // a new patch of the same surface: one Part per object
    if (keyword == "END") {
        inObject_ = false;
        return finishObject();
    }
    if (keyword == "HEADER") return readHeader(tokens.rest());
    if (keyword.substr(0, 7) == "HEADER{") return readHeader(line.substr(6));
    if (keyword == "GOCAD_ORIGINAL_COORDINATE_SYSTEM") return readCoordinateSystem();
    if (keyword == "GEOLOGICAL_TYPE") {
        obj_.geologicalType = toUtf8(unquote(tokens.rest()));
        return {};
    }
    if (keyword == "GEOLOGICAL_FEATURE") {
        obj_.geologicalFeature = toUtf8(unquote(tokens.rest()));
        return {};
    }
    if (keyword == "STRATIGRAPHIC_POSITION") {
        obj_.stratigraphicPosition = toUtf8(tokens.rest());
        return {};
    }
    if (keyword == "PROPERTIES" || keyword == "PROPERTY_CLASSES") {
        // PROPERTIES names the columns; PROPERTY_CLASSES only when PROPERTIES is absent.
        if (obj_.schemaFixed) return fail(std::string(keyword) + " must come before the first vertex");
        if (keyword == "PROPERTY_CLASSES" && obj_.propertiesLine != 0 && !obj_.propertyNames.empty()) return {};
        obj_.propertiesLine = lineNo_;
        return readNameList(tokens, obj_.propertyNames);
    }
    if (keyword == "ESIZES") {
        if (obj_.schemaFixed) return fail("ESIZES must come before the first vertex");
        obj_.esizesLine = lineNo_;
        obj_.esizes.clear();
        std::string_view tok;
        while (tokens.next(tok)) {
            std::uint64_t n = 0;
            if (parseId(tok, n) != IdStatus::Ok || n == 0 || n > kMaxPropertyColumns)
                return fail("ESIZES entry " + quoteToken(tok) + " is not an integer from 1 to " +
                            std::to_string(kMaxPropertyColumns));
            obj_.esizes.push_back(static_cast<std::size_t>(n));
            if (obj_.esizes.size() > kMaxPropertyColumns)
                return fail("more than " + std::to_string(kMaxPropertyColumns) + " ESIZES entries");
        }
        return {};
    }
    if (keyword == "NO_DATA_VALUES") {
        if (obj_.schemaFixed) return fail("NO_DATA_VALUES must come before the first vertex");
        obj_.noDataLine = lineNo_;
        obj_.noData.clear();
        std::string_view tok;
        while (tokens.next(tok)) {
            std::optional<double> v = parseDouble(tok);
            if (!v) return fail("NO_DATA_VALUES entry " + quoteToken(tok) + " is not a number");
            obj_.noData.push_back(*v);
            if (obj_.noData.size() > kMaxPropertyColumns)
                return fail("more than " + std::to_string(kMaxPropertyColumns) + " NO_DATA_VALUES entries");
        }
        return {};
    }
    if (keyword == "GOCAD") {
        return fail("a new GOCAD object starts before END of the TSurf object that starts on line " +
                    std::to_string(obj_.startLine));
    }
    // Topology and display records we do not need: borders, stones, lines, property
    // class descriptions (their { } blocks are skipped below).
    static constexpr std::string_view kIgnored[] = {"BSTONE", "BORDER", "SEG", "ILINE", "PLINE", "VRTX_END"};
    bool known = std::find(std::begin(kIgnored), std::end(kIgnored), keyword) != std::end(kIgnored);
    // Unknown keywords are skipped (forward compatible), but only when the line is text.
    if (!known) {
        if (Status s = checkText(line, true); !s) return s;
    }
    if (line.back() == '{' || (line.find('{') != std::string_view::npos && line.find('}') == std::string_view::npos))
        return skipBlock(lineNo_, keyword);
    return {};
}

// HEADER { key:value ... }, over several lines or inline.
Status TsurfParser::readHeader(std::string_view afterKeyword) {
    std::size_t start = lineNo_;
    if (afterKeyword.empty() || afterKeyword.front() != '{') return fail("HEADER must be followed by '{'");
    std::string_view rest = afterKeyword.substr(1);
    if (std::size_t close = rest.find('}'); close != std::string_view::npos) {
        headerEntry(rest.substr(0, close));
        return {};
    }
    headerEntry(rest);
    std::string_view line;
    while (nextLine(line)) {
        if (Status s = checkText(line, false); !s) return s;
        if (std::size_t close = line.find('}'); close != std::string_view::npos) {
            headerEntry(line.substr(0, close));
            return {};
        }
        headerEntry(line);
    }
    return failAt(lastLine_, "the HEADER block that starts on line " + std::to_string(start) +
                                 " has no closing '}' (truncated file?)");
}

void TsurfParser::headerEntry(std::string_view entry) {
    entry = trim(entry);
    std::size_t colon = entry.find(':');
    if (colon == std::string_view::npos) return;
    std::string key = lower(trim(entry.substr(0, colon)));
    std::string_view value = trim(entry.substr(colon + 1));
    if (key == "name") {
        obj_.name = toUtf8(unquote(value));
    } else if (key == "*solid*color" || key == "color") {
        std::optional<Rgba8> c = parseColour(value);
        if (!c) {
            obj_.rawColour = toUtf8(value);
            return;
        }
        (key == "color" ? obj_.colour : obj_.solidColour) = *c;
    }
}

Status TsurfParser::readCoordinateSystem() {
    std::size_t start = lineNo_;
    CoordinateSystem cs;
    std::string_view line;
    while (nextLine(line)) {
        if (Status s = checkText(line, true); !s) return s;
        std::string_view t = trim(line);
        if (t.empty() || t.front() == '#') continue;
        Tokens tokens(t);
        std::string_view keyword;
        tokens.next(keyword);
        if (keyword == "END_ORIGINAL_COORDINATE_SYSTEM") {
            obj_.crs = cs;
            obj_.hasOwnCrs = true;
            fileCrs_ = cs;
            if (cs.epsg)
                epsgCodes_.insert(*cs.epsg);
            else
                crsAmbiguous_ = true;
            return {};
        }
        if (keyword == "END" || keyword == "GOCAD" || keyword == "VRTX" || keyword == "TRGL") break;
        if (!cs.text.empty()) cs.text += '\n';
        cs.text += t;
        if (keyword == "ZPOSITIVE") {
            std::string v = lower(tokens.rest());
            if (v == "depth")
                cs.depthPositive = true;
            else if (v == "elevation")
                cs.depthPositive = false;
            else
                return fail("ZPOSITIVE must be Elevation or Depth, found " + quoteToken(tokens.rest()));
        } else if (keyword == "AXIS_UNIT") {
            std::vector<double> scale;
            std::string_view tok;
            while (tokens.next(tok)) {
                std::optional<double> m = metresPerUnit(unquote(tok));
                if (!m)
                    return makeError(ErrorCode::Unsupported, source_ + ": line " + std::to_string(lineNo_) +
                                                                 ": AXIS_UNIT " + quoteToken(unquote(tok)) +
                                                                 " is not supported (metres or feet)");
                if (scale.size() == 3) return fail("AXIS_UNIT has more than three units");
                scale.push_back(*m);
            }
            if (scale.size() == 1)
                cs.metresPerUnit = glm::dvec3(scale[0]);
            else if (scale.size() == 3)
                cs.metresPerUnit = glm::dvec3(scale[0], scale[1], scale[2]);
            else
                return fail("AXIS_UNIT needs one or three units");
        } else if (keyword == "NAME" || keyword == "PROJECTION") {
            // Only an explicit "EPSG:nnnn" (or "EPSG nnnn") counts as a CRS we may use.
            std::string v = lower(tokens.rest());
            std::size_t at = v.find("epsg");
            if (at != std::string::npos) {
                std::size_t i = at + 4;
                while (i < v.size() && (v[i] == ':' || v[i] == ' ' || v[i] == '"')) ++i;
                std::size_t j = i;
                while (j < v.size() && j - i < 9 && v[j] >= '0' && v[j] <= '9') ++j;
                int code = 0;
                if (j > i && std::from_chars(v.data() + i, v.data() + j, code).ec == std::errc()) {
                    if (cs.epsg && *cs.epsg != code) {
                        crsAmbiguous_ = true;  // two codes in one block: ambiguous
                    }
                    cs.epsg = code;
                }
            }
        }
    }
    return failAt(lineNo_, "the GOCAD_ORIGINAL_COORDINATE_SYSTEM block that starts on line " + std::to_string(start) +
                               " has no END_ORIGINAL_COORDINATE_SYSTEM" +
                               (pos_ >= text_.size() ? " (truncated file?)" : ""));
}

// Skips a `KEYWORD ... {` block up to the line holding its '}'.
Status TsurfParser::skipBlock(std::size_t startLine, std::string_view what) {
    std::string_view line;
    std::string name(what.substr(0, 40));
    while (nextLine(line)) {
        if (Status s = checkText(line, true); !s) return s;
        if (line.find('}') != std::string_view::npos) return {};
    }
    return failAt(lastLine_, "the " + quoteToken(name) + " block that starts on line " + std::to_string(startLine) +
                                 " has no closing '}' (truncated file?)");
}

// Skips a GOCAD object of another type up to its END.
Status TsurfParser::skipObject(std::size_t startLine) {
    std::string_view line;
    while (nextLine(line)) {
        if (Status s = checkText(line, false); !s) return s;
        Tokens tokens(trim(line));
        std::string_view keyword;
        if (tokens.next(keyword) && keyword == "END") return {};
    }
    return failAt(lastLine_, "missing END of the GOCAD object that starts on line " + std::to_string(startLine) +
                                 " (truncated file?)");
}

Status TsurfParser::readNameList(Tokens& tokens, std::vector<std::string>& out) {
    out.clear();
    std::string_view tok;
    while (tokens.next(tok)) {
        if (out.size() == kMaxPropertyColumns)
            return fail("more than " + std::to_string(kMaxPropertyColumns) + " properties");
        out.push_back(toUtf8(unquote(tok)));
    }
    return {};
}

// Fixes the property columns at the first vertex: PROPERTIES x ESIZES, with no-data values.
Status TsurfParser::fixSchema() {
    obj_.schemaFixed = true;
    const std::size_t n = obj_.propertyNames.size();
    if (n == 0) return {};
    std::vector<std::size_t> sizes = obj_.esizes;
    if (sizes.empty()) sizes.assign(n, 1);
    if (sizes.size() != n)
        return failAt(obj_.esizesLine, "ESIZES has " + std::to_string(sizes.size()) + " entries for " +
                                           std::to_string(n) + " PROPERTIES");
    if (!obj_.noData.empty() && obj_.noData.size() != n)
        return failAt(obj_.noDataLine, "NO_DATA_VALUES has " + std::to_string(obj_.noData.size()) + " entries for " +
                                           std::to_string(n) + " PROPERTIES");
    std::size_t total = 0;
    for (std::size_t s : sizes) total += s;  // each <= kMaxPropertyColumns, count <= kMaxPropertyColumns
    if (total > kMaxPropertyColumns)
        return failAt(obj_.esizesLine, "the properties have " + std::to_string(total) +
                                           " values per vertex, over the limit of " +
                                           std::to_string(kMaxPropertyColumns));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 0; k < n; ++k) {
        for (std::size_t e = 0; e < sizes[k]; ++e) {
            obj_.columnNames.push_back(sizes[k] == 1 ? obj_.propertyNames[k]
                                                     : obj_.propertyNames[k] + "[" + std::to_string(e) + "]");
            obj_.columnNoData.push_back(obj_.noData.empty() ? nan : obj_.noData[k]);
        }
    }
    return {};
}

Status TsurfParser::readVertex(Tokens& tokens, bool withProperties) {
    if (!obj_.schemaFixed) {
        if (Status s = fixSchema(); !s) return s;
    }
    const char* kw = withProperties ? "PVRTX" : "VRTX";
    std::string_view tok;
    if (!tokens.next(tok)) return fail(std::string(kw) + " needs an id and x y z");
    VertexKey key;
    switch (parseId(tok, key.id)) {
        case IdStatus::Ok:
            break;
        case IdStatus::NotInteger:
            return fail(std::string(kw) + " id " + quoteToken(tok) + " is not a non-negative integer");
        case IdStatus::TooLarge:
            return fail(std::string(kw) + " id " + quoteToken(tok) + " is out of range");
    }
    glm::dvec3 p(0.0);
    for (int a = 0; a < 3; ++a) {
        if (!tokens.next(tok))
            return fail(std::string(kw) + " " + std::to_string(key.id) + " needs x y z, found " + std::to_string(a) +
                        " coordinate" + (a == 1 ? "" : "s"));
        std::optional<double> v = parseDouble(tok);
        if (!v)
            return fail(std::string(kw) + " " + std::to_string(key.id) + ": coordinate " + quoteToken(tok) +
                        " is not a number");
        if (!std::isfinite(*v))
            return fail(std::string(kw) + " " + std::to_string(key.id) + ": coordinate " + quoteToken(tok) +
                        " is not a finite number");
        p[a] = *v;
    }
    if (obj_.positions.size() >= kMaxVertices) return fail("too many vertices in one TSurf object");

    // Properties: PVRTX carries one value per column; VRTX in an object with properties
    // gets NaN (no data). Without a PROPERTIES line, the first PVRTX names its columns.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (withProperties && obj_.columnNames.empty() && obj_.positions.empty()) {
        Tokens peek = tokens;
        std::string_view t;
        while (peek.next(t) && obj_.columnNames.size() < kMaxPropertyColumns) {
            obj_.columnNames.push_back("property_" + std::to_string(obj_.columnNames.size() + 1));
            obj_.columnNoData.push_back(nan);
        }
    }
    const std::size_t columns = obj_.columnNames.size();
    if (columns > 0) {
        if (propertyValueBudget_ < columns)
            return fail("too many property values for the size of the input (VRTX lines in an object with " +
                        std::to_string(columns) + " property columns)");
        propertyValueBudget_ -= columns;
        std::size_t found = 0;
        if (withProperties) {
            while (tokens.next(tok)) {
                if (found >= columns) {  // too many: count them for the message
                    ++found;
                    continue;
                }
                std::optional<double> v = parseDouble(tok);
                if (!v)
                    return fail("PVRTX " + std::to_string(key.id) + ": property value " + quoteToken(tok) +
                                " is not a number");
                double d = *v;
                if (d == obj_.columnNoData[found]) d = nan;
                if (std::isinf(d) || (std::isfinite(d) && std::fabs(d) > std::numeric_limits<float>::max()))
                    return fail("PVRTX " + std::to_string(key.id) + ": property value " + quoteToken(tok) +
                                " is outside the float range");
                obj_.properties.push_back(static_cast<float>(d));
                ++found;
            }
            if (found != columns)
                return fail("PVRTX " + std::to_string(key.id) + " has " + std::to_string(found) +
                            " property values, expected " + std::to_string(columns));
        } else {
            obj_.properties.insert(obj_.properties.end(), columns, std::numeric_limits<float>::quiet_NaN());
        }
    }
    key.index = static_cast<std::uint32_t>(obj_.positions.size());
    key.line = lineNo_;
    obj_.positions.push_back(p);
    obj_.keys.push_back(key);
    return {};
}

Status TsurfParser::readAtom(Tokens& tokens, std::string_view keyword) {
    std::string kw(keyword);
    Atom a;
    std::string_view tok;
    for (std::uint64_t* out : {&a.id, &a.ref}) {
        if (!tokens.next(tok)) return fail(kw + " needs an id and the id of the vertex it reuses");
        switch (parseId(tok, *out)) {
            case IdStatus::Ok:
                break;
            case IdStatus::NotInteger:
                return fail(kw + " id " + quoteToken(tok) + " is not a non-negative integer");
            case IdStatus::TooLarge:
                return fail(kw + " id " + quoteToken(tok) + " is out of range");
        }
    }
    a.line = lineNo_;
    obj_.atoms.push_back(a);
    obj_.keys.push_back(VertexKey{a.id, kUnresolved, lineNo_});
    return {};
}

Status TsurfParser::readTriangle(Tokens& tokens) {
    Triangle t;
    t.line = lineNo_;
    std::size_t n = 0;
    std::string_view tok;
    while (tokens.next(tok)) {
        if (n == 3) return fail("TRGL has more than 3 vertex ids");
        switch (parseId(tok, t.ids[n])) {
            case IdStatus::Ok:
                break;
            case IdStatus::NotInteger:
                return fail("TRGL vertex id " + quoteToken(tok) + " is not a non-negative integer");
            case IdStatus::TooLarge:
                return fail("TRGL vertex id " + quoteToken(tok) + " is out of range");
        }
        ++n;
    }
    if (n < 3) return fail("TRGL needs 3 vertex ids, found " + std::to_string(n));
    obj_.triangles.push_back(t);
    return {};
}

Status TsurfParser::finishObject() {
    TsurfObject& o = obj_;
    // Keys were appended in line order; a stable sort keeps that order among equal ids.
    auto byId = [](const VertexKey& a, const VertexKey& b) { return a.id < b.id; };
    if (!std::is_sorted(o.keys.begin(), o.keys.end(), byId)) std::stable_sort(o.keys.begin(), o.keys.end(), byId);
    const VertexKey* dup = nullptr;  // the duplicate with the smallest line, for a stable message
    for (std::size_t i = 1; i < o.keys.size(); ++i)
        if (o.keys[i].id == o.keys[i - 1].id && (!dup || o.keys[i].line < dup->line)) dup = &o.keys[i];
    if (dup) {
        auto first = std::lower_bound(o.keys.begin(), o.keys.end(), dup->id,
                                      [](const VertexKey& k, std::uint64_t id) { return k.id < id; });
        return failAt(dup->line, "duplicate vertex id " + std::to_string(dup->id) + " (already defined on line " +
                                     std::to_string(first->line) + ")");
    }
    // Ids are usually 1..n without gaps: then an id is its own offset (no search).
    const bool contiguous = !o.keys.empty() && o.keys.back().id - o.keys.front().id == o.keys.size() - 1;
    auto lookup = [&](std::uint64_t id) -> VertexKey* {
        if (contiguous) {
            const std::uint64_t offset = id - o.keys.front().id;  // wraps to huge when id < first
            return offset < o.keys.size() ? &o.keys[static_cast<std::size_t>(offset)] : nullptr;
        }
        auto it = std::lower_bound(o.keys.begin(), o.keys.end(), id,
                                   [](const VertexKey& k, std::uint64_t v) { return k.id < v; });
        return it != o.keys.end() && it->id == id ? &*it : nullptr;
    };
    // Atoms in file order: each reuses a vertex (or an atom) defined before it.
    for (const Atom& a : o.atoms) {
        VertexKey* ref = lookup(a.ref);
        if (!ref || ref->line >= a.line)
            return failAt(a.line, "ATOM " + std::to_string(a.id) + " refers to vertex id " + std::to_string(a.ref) +
                                      ", which is not defined before it");
        VertexKey* self = lookup(a.id);
        GS_ASSERT(self != nullptr, "every ATOM has its own key");
        self->index = ref->index;
    }
    if (o.triangles.empty()) return {};  // a TSurf without triangles adds nothing

    std::vector<std::uint32_t> indices;
    indices.reserve(o.triangles.size() * 3);
    for (const Triangle& t : o.triangles) {
        for (std::uint64_t id : t.ids) {
            const VertexKey* k = lookup(id);
            if (!k)
                return failAt(t.line, "TRGL refers to vertex id " + std::to_string(id) +
                                          ", which is not defined in the TSurf object that starts on line " +
                                          std::to_string(o.startLine));
            indices.push_back(k->index);
        }
    }

    // Keep the vertices that triangles use, in file order.
    std::vector<std::uint32_t> remap(o.positions.size(), kUnresolved);
    for (std::uint32_t i : indices) remap[i] = 0;
    Part part;
    Mesh& mesh = part.mesh;
    const std::size_t columns = o.columnNames.size();
    const CoordinateSystem& cs = o.crs;
    const glm::dvec3 scale = cs.metresPerUnit * glm::dvec3(1.0, 1.0, cs.depthPositive ? -1.0 : 1.0);
    for (std::size_t v = 0; v < o.positions.size(); ++v) {
        if (remap[v] == kUnresolved) continue;
        remap[v] = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.push_back(o.positions[v] * scale + glm::dvec3(0.0));  // + 0: depth 0 gives +0, not -0
        if (columns > 0)
            mesh.propertyValues.insert(mesh.propertyValues.end(),
                                       o.properties.begin() + static_cast<std::ptrdiff_t>(v * columns),
                                       o.properties.begin() + static_cast<std::ptrdiff_t>((v + 1) * columns));
    }
    for (std::uint32_t& i : indices) i = remap[i];
    mesh.indices = std::move(indices);
    mesh.propertyNames = o.columnNames;

    AttributeRecord rec;
    part.name = o.name;
    rec.name = o.name;
    rec.colour = o.solidColour ? *o.solidColour : o.colour ? *o.colour : Rgba8{};
    if (!o.geologicalType.empty()) {
        std::string t = lower(o.geologicalType);
        if (t == "fault")
            rec.kind = "fault";
        else if (t == "intrusive" || t == "intrusion")
            rec.kind = "intrusion";
        else if (t == "top" || t == "boundary" || t == "unconformity" || t == "erosion" || t == "ip" ||
                 t == "stratigraphic" || t == "horizon")
            rec.kind = "horizon";
        else
            rec.kind = t;
        rec.extra["geological_type"] = o.geologicalType;
    }
    if (!o.geologicalFeature.empty()) rec.extra["geological_feature"] = o.geologicalFeature;
    if (!o.stratigraphicPosition.empty()) rec.extra["stratigraphic_position"] = o.stratigraphicPosition;
    if (!o.crs.text.empty()) rec.extra["gocad_coordinate_system"] = toUtf8(o.crs.text);
    if (!o.rawColour.empty() && !o.solidColour && !o.colour) rec.extra["gocad_color"] = o.rawColour;
    part.record = model_.attributes.add(std::move(rec));
    part.kind = PartKind::Surface;
    if (part.name.empty()) unnamedParts_.push_back(model_.surfaces.size());
    model_.surfaces.push_back(std::move(part));
    obj_ = TsurfObject{};
    return {};
}

}  // namespace

Result<Model> parseTsurf(std::string_view text, const std::string& source) {
    TsurfParser parser(text, source);
    return parser.run();
}

}  // namespace geoslice
