// What the GOCAD readers share: numbered lines, HEADER and coordinate-system blocks,
// vertex lines and property columns, vertex ids with ATOM aliases, binary sample files.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <system_error>

#include "model/gocad_reader.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

namespace {

// Columns of PVRTX properties per vertex (sum of ESIZES). Real files have a few dozen at
// most; the cap bounds the NaN padding that plain VRTX lines in such an object cost.
constexpr std::size_t kMaxPropertyColumns = 256;
constexpr double kFootM = 0.3048;                   // international foot, metres
constexpr double kUsSurveyFootM = 1200.0 / 3937.0;  // US survey foot, metres

bool isConstraintFlag(std::string_view tok) {
    // GOCAD writes constraint flags after a vertex's coordinates: CNXYZ, CNXY, CNZ, CNX...
    if (tok.size() < 3 || tok.substr(0, 2) != "CN") return false;
    for (char c : tok.substr(2))
        if (c != 'X' && c != 'Y' && c != 'Z' && c != 'T') return false;
    return true;
}

}  // namespace

Lines::Lines(std::string_view text, const std::string& source) : text_(text), source_(source) {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);  // UTF-8 byte order mark
    endsWithNewline_ = text_.empty() || text_.back() == '\n';
    lastLine_ = static_cast<std::size_t>(std::count(text_.begin(), text_.end(), '\n')) + (endsWithNewline_ ? 0 : 1);
}

bool Lines::next(std::string_view& line) {
    if (!text::nextLine(text_, pos_, line)) return false;
    ++lineNo_;
    return true;
}

std::string Lines::truncationHint() const {
    if (lineNo_ == lastLine_ && !endsWithNewline_) return " (the input ends in this line: truncated file?)";
    return "";
}

Error Lines::failAt(std::size_t line, const std::string& what, ErrorCode code) const {
    std::string msg = source_ + ": line " + std::to_string(line) + ": " + what;
    if (line == lastLine_ && !endsWithNewline_ && msg.find("truncated") == std::string::npos)
        msg += " (the input ends in this line, without END: truncated file?)";
    return makeError(code, std::move(msg));
}

bool Lines::nextStatement(Statement& out, Status& bad) {
    std::string_view line;
    while (next(line)) {
        if (Status s = checkText(line, false); !s) {
            bad = s;
            return false;
        }
        std::string_view t = text::trim(line);
        if (t.empty() || t.front() == '#') continue;
        out.line = line;
        out.text = t;
        out.tokens = text::Tokens(t);
        out.keyword = {};
        out.tokens.next(out.keyword);
        return true;
    }
    return false;
}

Status Lines::checkText(std::string_view line, bool utf8) const {
    std::size_t bad = findNonText(line, utf8);
    if (bad == std::string_view::npos) return {};
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned>(static_cast<unsigned char>(line[bad])));
    return fail(std::string("not text: byte ") + hex + " at column " + std::to_string(bad + 1) +
                (utf8 ? " (binary data, or not UTF-8)" : " (binary data?)"));
}

void Context::warn(std::size_t line, const std::string& what, const std::string& key) {
    if (!key.empty() && !warned.insert(key).second) return;
    warnings.push_back(lines.source() + ": line " + std::to_string(line) + ": " + what);
}

Status readId(const Lines& lines, Tokens& tokens, const std::string& what, std::uint64_t& out) {
    std::string_view tok;
    if (!tokens.next(tok)) return lines.fail(what + " is missing");
    switch (parseId(tok, out)) {
        case IdStatus::Ok:
            return {};
        case IdStatus::NotInteger:
            return lines.fail(what + " " + quoteToken(tok) + " is not a non-negative integer");
        case IdStatus::TooLarge:
            return lines.fail(what + " " + quoteToken(tok) + " is out of range");
    }
    return {};
}

std::string_view unquote(std::string_view s) {
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
    return s;
}

std::optional<double> metresPerUnit(std::string_view unit) {
    std::string u = lower(unit);
    if (u == "m" || u == "meter" || u == "meters" || u == "metre" || u == "metres") return 1.0;
    if (u == "km" || u == "kilometer" || u == "kilometers" || u == "kilometre" || u == "kilometres") return 1000.0;
    if (u == "ft" || u == "feet" || u == "foot") return kFootM;
    if (u == "ft_us" || u == "us_ft" || u == "usft" || u == "ftus" || u == "us-ft" || u == "survey_ft")
        return kUsSurveyFootM;
    return std::nullopt;
}

Status readHeader(Lines& lines, std::string_view afterKeyword, std::map<std::string, std::string>& out) {
    const std::size_t start = lines.lineNo();
    afterKeyword = trim(afterKeyword);
    if (afterKeyword.empty() || afterKeyword.front() != '{') return lines.fail("HEADER must be followed by '{'");
    auto entry = [&](std::string_view e) {
        e = trim(e);
        std::size_t colon = e.find(':');
        if (colon == std::string_view::npos) return;
        out[lower(trim(e.substr(0, colon)))] = std::string(trim(e.substr(colon + 1)));
    };
    std::string_view rest = afterKeyword.substr(1);
    if (std::size_t close = rest.find('}'); close != std::string_view::npos) {
        entry(rest.substr(0, close));
        return {};
    }
    entry(rest);
    std::string_view line;
    while (lines.next(line)) {
        if (Status s = lines.checkText(line, false); !s) return s;
        if (std::size_t close = line.find('}'); close != std::string_view::npos) {
            entry(line.substr(0, close));
            return {};
        }
        entry(line);
    }
    return lines.failAt(lines.lastLine(), "the HEADER block that starts on line " + std::to_string(start) +
                                              " has no closing '}' (truncated file?)");
}

Status readCoordinateSystem(Context& cx, CoordinateSystem& out) {
    Lines& lines = cx.lines;
    const std::size_t start = lines.lineNo();
    CoordinateSystem cs;
    cs.declared = true;
    std::string_view line;
    while (lines.next(line)) {
        if (Status s = lines.checkText(line, true); !s) return s;
        std::string_view t = trim(line);
        if (t.empty() || t.front() == '#') continue;
        Tokens tokens(t);
        std::string_view keyword;
        tokens.next(keyword);
        if (keyword == "END_ORIGINAL_COORDINATE_SYSTEM") {
            out = cs;
            cx.fileCrs = cs;
            // The CRS this block declares: an explicit EPSG code, else its NAME ("Default": none).
            if (cs.epsg)
                cx.crsNames.insert("EPSG:" + std::to_string(*cs.epsg));
            else if (!cs.name.empty() && lower(cs.name) != "default")
                cx.crsNames.insert(cs.name);
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
                return lines.fail("ZPOSITIVE must be Elevation or Depth, found " + quoteToken(tokens.rest()));
        } else if (keyword == "AXIS_UNIT") {
            std::vector<double> scale;
            std::string_view tok;
            while (tokens.next(tok)) {
                std::optional<double> m = metresPerUnit(unquote(tok));
                if (!m)
                    return lines.failAt(lines.lineNo(),
                                        "AXIS_UNIT " + quoteToken(unquote(tok)) +
                                            " is not supported (m, km, ft, feet or US survey feet)",
                                        ErrorCode::Unsupported);
                if (scale.size() == 3) return lines.fail("AXIS_UNIT has more than three units");
                scale.push_back(*m);
            }
            if (scale.size() == 1)
                cs.metresPerUnit = glm::dvec3(scale[0]);
            else if (scale.size() == 3)
                cs.metresPerUnit = glm::dvec3(scale[0], scale[1], scale[2]);
            else
                return lines.fail("AXIS_UNIT needs one or three units");
            if (cs.metresPerUnit != glm::dvec3(1.0)) {
                char buf[96];
                std::snprintf(buf, sizeof buf, "%.10g %.10g %.10g", cs.metresPerUnit.x, cs.metresPerUnit.y,
                              cs.metresPerUnit.z);
                cx.warn(lines.lineNo(),
                        "AXIS_UNIT " + std::string(tokens.rest().empty() ? t.substr(10) : tokens.rest()) +
                            ": coordinates converted to metres (x " + buf + " m per unit)",
                        "axis_unit " + std::string(buf));
            }
        } else if (keyword == "NAME" || keyword == "PROJECTION") {
            std::string value = toUtf8(unquote(tokens.rest()));
            if (keyword == "NAME") cs.name = value;
            // An explicit "EPSG:nnnn" (or "EPSG nnnn") in NAME or PROJECTION.
            std::string v = lower(value);
            std::size_t at = v.find("epsg");
            if (at != std::string::npos) {
                std::size_t i = at + 4;
                while (i < v.size() && (v[i] == ':' || v[i] == ' ' || v[i] == '"')) ++i;
                std::size_t j = i;
                while (j < v.size() && j - i < 9 && v[j] >= '0' && v[j] <= '9') ++j;
                int code = 0;
                if (j > i && std::from_chars(v.data() + i, v.data() + j, code).ec == std::errc()) cs.epsg = code;
            }
        }
    }
    return lines.failAt(lines.lineNo(), "the GOCAD_ORIGINAL_COORDINATE_SYSTEM block that starts on line " +
                                            std::to_string(start) + " has no END_ORIGINAL_COORDINATE_SYSTEM" +
                                            (lines.atEnd() ? " (truncated file?)" : ""));
}

Status skipBlock(Lines& lines, std::size_t startLine, std::string_view what) {
    std::string_view line;
    std::string name(what.substr(0, 40));
    while (lines.next(line)) {
        if (Status s = lines.checkText(line, true); !s) return s;
        if (line.find('}') != std::string_view::npos) return {};
    }
    return lines.failAt(lines.lastLine(), "the " + quoteToken(name) + " block that starts on line " +
                                              std::to_string(startLine) + " has no closing '}' (truncated file?)");
}

Status skipObject(Lines& lines, std::size_t startLine) {
    std::string_view line;
    while (lines.next(line)) {
        if (Status s = lines.checkText(line, false); !s) return s;
        Tokens tokens(trim(line));
        std::string_view keyword;
        if (tokens.next(keyword) && keyword == "END") return {};
    }
    return lines.failAt(lines.lastLine(), "missing END of the GOCAD object that starts on line " +
                                              std::to_string(startLine) + " (truncated file?)");
}

Status skipUnknown(Lines& lines, std::string_view keyword, std::string_view line) {
    if (Status s = lines.checkText(line, true); !s) return s;
    if (line.back() == '{' || (line.find('{') != std::string_view::npos && line.find('}') == std::string_view::npos))
        return skipBlock(lines, lines.lineNo(), keyword);
    return {};
}

void ObjectInfo::headerEntries(const std::map<std::string, std::string>& header) {
    for (const auto& [key, value] : header) {
        if (key == "name") {
            name = toUtf8(unquote(value));
        } else if (key == "*solid*color" || key == "color") {
            std::optional<Rgba8> c = parseColour(value);
            if (!c) {
                rawColour = toUtf8(value);
                continue;
            }
            (key == "color" ? colour : solidColour) = *c;
        }
    }
}

Status ObjectInfo::readCommon(Context& cx, std::string_view keyword, Tokens& tokens, std::string_view line,
                              bool& handled) {
    handled = true;
    if (keyword == "HEADER" || keyword.substr(0, 7) == "HEADER{") {
        std::map<std::string, std::string> header;
        std::string_view after = keyword == "HEADER" ? tokens.rest() : trim(line).substr(6);
        if (Status s = readHeader(cx.lines, after, header); !s) return s;
        headerEntries(header);
        return {};
    }
    if (keyword == "GOCAD_ORIGINAL_COORDINATE_SYSTEM") return readCoordinateSystem(cx, crs);
    if (keyword == "GEOLOGICAL_TYPE") {
        geologicalType = toUtf8(unquote(tokens.rest()));
        return {};
    }
    if (keyword == "GEOLOGICAL_FEATURE") {
        geologicalFeature = toUtf8(unquote(tokens.rest()));
        return {};
    }
    if (keyword == "STRATIGRAPHIC_POSITION") {
        stratigraphicPosition = toUtf8(tokens.rest());
        return {};
    }
    handled = false;
    return {};
}

AttributeRecord ObjectInfo::record() const {
    AttributeRecord rec;
    rec.name = name;
    rec.colour = solidColour ? *solidColour : colour ? *colour : Rgba8{};
    if (!geologicalType.empty()) {
        std::string t = lower(geologicalType);
        if (t == "fault" || t == "normal_fault" || t == "reverse_fault")
            rec.kind = "fault";
        else if (t == "intrusive" || t == "intrusion")
            rec.kind = "intrusion";
        else if (t == "top" || t == "boundary" || t == "unconformity" || t == "erosion" || t == "ip" ||
                 t == "stratigraphic" || t == "horizon")
            rec.kind = "horizon";
        else
            rec.kind = t;
        rec.extra["geological_type"] = geologicalType;
    }
    if (!geologicalFeature.empty()) rec.extra["geological_feature"] = geologicalFeature;
    if (!stratigraphicPosition.empty()) rec.extra["stratigraphic_position"] = stratigraphicPosition;
    if (!crs.text.empty()) rec.extra["gocad_coordinate_system"] = toUtf8(crs.text);
    if (!rawColour.empty() && !solidColour && !colour) rec.extra["gocad_color"] = rawColour;
    return rec;
}

Status readVertexLine(Context& cx, Tokens& tokens, std::string_view keyword, VertexLine& out) {
    const std::string kw(keyword);
    std::string_view tok;
    if (!tokens.next(tok)) return cx.lines.fail(kw + " needs an id and x y z");
    switch (parseId(tok, out.id)) {
        case IdStatus::Ok:
            break;
        case IdStatus::NotInteger:
            return cx.lines.fail(kw + " id " + quoteToken(tok) + " is not a non-negative integer");
        case IdStatus::TooLarge:
            return cx.lines.fail(kw + " id " + quoteToken(tok) + " is out of range");
    }
    for (int a = 0; a < 3; ++a) {
        if (!tokens.next(tok))
            return cx.lines.fail(kw + " " + std::to_string(out.id) + " needs x y z, found " + std::to_string(a) +
                                 " coordinate" + (a == 1 ? "" : "s"));
        std::optional<double> v = parseDouble(tok);
        if (!v)
            return cx.lines.fail(kw + " " + std::to_string(out.id) + ": coordinate " + quoteToken(tok) +
                                 " is not a number");
        if (!std::isfinite(*v))
            return cx.lines.fail(kw + " " + std::to_string(out.id) + ": coordinate " + quoteToken(tok) +
                                 " is not a finite number");
        out.p[a] = *v;
    }
    Tokens peek = tokens;
    if (peek.next(tok) && isConstraintFlag(tok)) {
        tokens = peek;
        cx.warn(cx.lines.lineNo(),
                kw + " with GOCAD's constraint flag " + quoteToken(tok) + ": accepted, the flag is ignored", "cnxyz");
    }
    return {};
}

Status PropertySchema::readKeyword(const Lines& lines, std::string_view keyword, Tokens& tokens, bool& handled) {
    handled = true;
    if (keyword == "PROPERTIES" || keyword == "PROPERTY_CLASSES") {
        // PROPERTIES names the columns; PROPERTY_CLASSES only when PROPERTIES is absent.
        if (fixed) return lines.fail(std::string(keyword) + " must come before the first vertex");
        if (keyword == "PROPERTY_CLASSES" && propertiesLine != 0 && !names.empty()) return {};
        propertiesLine = lines.lineNo();
        names.clear();
        std::string_view tok;
        while (tokens.next(tok)) {
            if (names.size() == kMaxPropertyColumns)
                return lines.fail("more than " + std::to_string(kMaxPropertyColumns) + " properties");
            names.push_back(toUtf8(unquote(tok)));
        }
        return {};
    }
    if (keyword == "ESIZES") {
        if (fixed) return lines.fail("ESIZES must come before the first vertex");
        esizesLine = lines.lineNo();
        esizes.clear();
        std::string_view tok;
        while (tokens.next(tok)) {
            std::uint64_t n = 0;
            if (parseId(tok, n) != IdStatus::Ok || n == 0 || n > kMaxPropertyColumns)
                return lines.fail("ESIZES entry " + quoteToken(tok) + " is not an integer from 1 to " +
                                  std::to_string(kMaxPropertyColumns));
            esizes.push_back(static_cast<std::size_t>(n));
            if (esizes.size() > kMaxPropertyColumns)
                return lines.fail("more than " + std::to_string(kMaxPropertyColumns) + " ESIZES entries");
        }
        return {};
    }
    if (keyword == "NO_DATA_VALUES") {
        if (fixed) return lines.fail("NO_DATA_VALUES must come before the first vertex");
        noDataLine = lines.lineNo();
        noData.clear();
        std::string_view tok;
        while (tokens.next(tok)) {
            std::optional<double> v = parseDouble(tok);
            if (!v) return lines.fail("NO_DATA_VALUES entry " + quoteToken(tok) + " is not a number");
            noData.push_back(*v);
            if (noData.size() > kMaxPropertyColumns)
                return lines.fail("more than " + std::to_string(kMaxPropertyColumns) + " NO_DATA_VALUES entries");
        }
        return {};
    }
    handled = false;
    return {};
}

Status PropertySchema::fix(const Lines& lines) {
    fixed = true;
    const std::size_t n = names.size();
    if (n == 0) return {};
    std::vector<std::size_t> sizes = esizes;
    if (sizes.empty()) sizes.assign(n, 1);
    if (sizes.size() != n)
        return lines.failAt(esizesLine, "ESIZES has " + std::to_string(sizes.size()) + " entries for " +
                                            std::to_string(n) + " PROPERTIES");
    if (!noData.empty() && noData.size() != n)
        return lines.failAt(noDataLine, "NO_DATA_VALUES has " + std::to_string(noData.size()) + " entries for " +
                                            std::to_string(n) + " PROPERTIES");
    std::size_t total = 0;
    for (std::size_t s : sizes) total += s;  // each <= kMaxPropertyColumns, count <= kMaxPropertyColumns
    if (total > kMaxPropertyColumns)
        return lines.failAt(esizesLine, "the properties have " + std::to_string(total) +
                                            " values per vertex, over the limit of " +
                                            std::to_string(kMaxPropertyColumns));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 0; k < n; ++k) {
        for (std::size_t e = 0; e < sizes[k]; ++e) {
            columnNames.push_back(sizes[k] == 1 ? names[k] : names[k] + "[" + std::to_string(e) + "]");
            columnNoData.push_back(noData.empty() ? nan : noData[k]);
        }
    }
    return {};
}

Status PropertySchema::appendVertex(Context& cx, Tokens& tokens, bool withProperties, std::uint64_t id) {
    const Lines& lines = cx.lines;
    if (!fixed) {
        if (Status s = fix(lines); !s) return s;
        // Without a PROPERTIES line, the first PVRTX names its columns.
        if (withProperties && columnNames.empty()) {
            Tokens peek = tokens;
            std::string_view t;
            while (peek.next(t) && columnNames.size() < kMaxPropertyColumns) {
                columnNames.push_back("property_" + std::to_string(columnNames.size() + 1));
                columnNoData.push_back(std::numeric_limits<double>::quiet_NaN());
            }
        }
    }
    const std::size_t columns = columnNames.size();
    if (columns == 0) return {};
    // Honest PVRTX values cost at least two bytes of text each; only VRTX lines in an
    // object with properties add NaN padding, which this budget bounds.
    if (cx.propertyValueBudget < columns)
        return lines.fail("too many property values for the size of the input (VRTX lines in an object with " +
                          std::to_string(columns) + " property columns)");
    cx.propertyValueBudget -= columns;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (!withProperties) {
        values.insert(values.end(), columns, std::numeric_limits<float>::quiet_NaN());
        return {};
    }
    std::size_t found = 0;
    std::string_view tok;
    while (tokens.next(tok)) {
        if (found >= columns) {  // too many: count them for the message
            ++found;
            continue;
        }
        std::optional<double> v = parseDouble(tok);
        if (!v)
            return lines.fail("PVRTX " + std::to_string(id) + ": property value " + quoteToken(tok) +
                              " is not a number");
        double d = *v;
        if (d == columnNoData[found]) d = nan;
        if (std::isinf(d) || (std::isfinite(d) && std::fabs(d) > std::numeric_limits<float>::max()))
            return lines.fail("PVRTX " + std::to_string(id) + ": property value " + quoteToken(tok) +
                              " is outside the float range");
        values.push_back(static_cast<float>(d));
        ++found;
    }
    if (found != columns) {
        values.resize(values.size() - std::min(values.size(), found));
        return lines.fail("PVRTX " + std::to_string(id) + " has " + std::to_string(found) +
                          " property values, expected " + std::to_string(columns));
    }
    return {};
}

Status readVertex(Context& cx, const Lines& lines, Tokens& tokens, std::string_view keyword, std::string_view object,
                  PropertySchema& schema, VertexIds& ids, std::vector<glm::dvec3>& positions) {
    VertexLine v;
    if (Status s = readVertexLine(cx, tokens, keyword, v); !s) return s;
    if (positions.size() >= std::numeric_limits<std::uint32_t>::max() - 1)
        return lines.fail("too many vertices in one " + std::string(object) + " object");
    if (Status s = schema.appendVertex(cx, tokens, keyword == "PVRTX", v.id); !s) return s;
    ids.addVertex(v.id, static_cast<std::uint32_t>(positions.size()), lines.lineNo());
    positions.push_back(v.p);
    return {};
}

Status VertexIds::addAtom(const Lines& lines, Tokens& tokens, std::string_view keyword) {
    const std::string kw(keyword);
    Atom a;
    if (Status s = readId(lines, tokens, kw + " id", a.id); !s) return s;
    if (Status s = readId(lines, tokens, kw + " " + std::to_string(a.id) + ": the id of the vertex it reuses", a.ref);
        !s)
        return s;
    a.line = lines.lineNo();
    atoms.push_back(a);
    keys.push_back(Key{a.id, 0, a.line, true});
    return {};
}

Status VertexIds::resolve(const Lines& lines) {
    // Keys were appended in line order; a stable sort keeps that order among equal ids.
    auto byId = [](const Key& a, const Key& b) { return a.id < b.id; };
    if (!std::is_sorted(keys.begin(), keys.end(), byId)) std::stable_sort(keys.begin(), keys.end(), byId);
    const Key* dup = nullptr;  // the duplicate with the smallest line, for a stable message
    for (std::size_t i = 1; i < keys.size(); ++i)
        if (keys[i].id == keys[i - 1].id && (!dup || keys[i].line < dup->line)) dup = &keys[i];
    if (dup) {
        auto first = std::lower_bound(keys.begin(), keys.end(), dup->id,
                                      [](const Key& k, std::uint64_t id) { return k.id < id; });
        return lines.failAt(dup->line, "duplicate vertex id " + std::to_string(dup->id) + " (already defined on line " +
                                           std::to_string(first->line) + ")");
    }
    // Ids are usually 1..n without gaps: then an id is its own offset (no search).
    contiguous = !keys.empty() && keys.back().id - keys.front().id == keys.size() - 1;
    // Atoms in file order: each reuses a vertex (or an atom) defined before it.
    for (const Atom& a : atoms) {
        const Key* ref = find(a.ref);
        if (!ref || ref->line >= a.line)
            return lines.failAt(a.line, "ATOM " + std::to_string(a.id) + " refers to vertex id " +
                                            std::to_string(a.ref) + ", which is not defined before it");
        Key* self = const_cast<Key*>(find(a.id));
        GS_ASSERT(self != nullptr, "every ATOM has its own key");
        self->index = ref->index;
    }
    return {};
}

const VertexIds::Key* VertexIds::find(std::uint64_t id) const {
    if (contiguous) {
        const std::uint64_t offset = id - keys.front().id;  // wraps to huge when id < first
        return offset < keys.size() ? &keys[static_cast<std::size_t>(offset)] : nullptr;
    }
    auto it = std::lower_bound(keys.begin(), keys.end(), id, [](const Key& k, std::uint64_t v) { return k.id < v; });
    return it != keys.end() && it->id == id ? &*it : nullptr;
}

Result<std::string> dataFilePath(const Context& cx, std::string_view name, std::size_t line) {
    std::string file(unquote(trim(name)));
    if (file.empty()) return cx.lines.failAt(line, "the data file name is empty");
    if (cx.baseDir.empty())
        return cx.lines.failAt(line,
                               "data file " + quoteToken(file) +
                                   " cannot be read: the input is not a file on disk (load the header file by path)",
                               ErrorCode::Unsupported);
    std::filesystem::path p(file);
    if (p.is_relative()) p = std::filesystem::path(cx.baseDir) / p;
    return p.string();
}

Result<std::vector<float>> readSampleFile(const std::string& path, const SampleFormat& format, std::size_t count,
                                          std::optional<double> noData, const std::string& what) {
    const std::size_t es = format.esize;
    const bool isFloat = format.etype == "IEEE";
    if (!((isFloat && (es == 4 || es == 8)) ||
          ((format.etype == "SIGNED_INT" || format.etype == "UNSIGNED_INT") && (es == 1 || es == 2 || es == 4))))
        return makeError(ErrorCode::Unsupported, what + ": element type " + format.etype + " of " + std::to_string(es) +
                                                     " bytes is not supported (IEEE 4 or 8, SIGNED_INT or "
                                                     "UNSIGNED_INT 1, 2 or 4)");
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) return makeError(ErrorCode::NotFound, what + ": cannot read " + path + " (" + ec.message() + ")");
    if (count > (std::numeric_limits<std::uint64_t>::max() - format.offset) / es)
        return makeError(ErrorCode::ParseError, what + ": " + std::to_string(count) + " samples is too many");
    const std::uint64_t need = format.offset + static_cast<std::uint64_t>(count) * es;
    if (size < need)
        return makeError(ErrorCode::ParseError, what + ": " + path + " has " + std::to_string(size) +
                                                    " bytes, the header needs " + std::to_string(need) + " (" +
                                                    std::to_string(count) + " samples of " + std::to_string(es) +
                                                    " bytes from offset " + std::to_string(format.offset) +
                                                    "): truncated file or wrong AXIS_N / PROP_ESIZE?");
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(ErrorCode::IoError, what + ": cannot open " + path);
    in.seekg(static_cast<std::streamoff>(format.offset));
    std::vector<float> out(count);
    std::vector<unsigned char> buf(std::size_t(1) << 16);
    std::size_t done = 0;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    while (done < count) {
        const std::size_t n = std::min(count - done, buf.size() / es);
        if (!in.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(n * es)))
            return makeError(ErrorCode::IoError, what + ": read failed in " + path);
        for (std::size_t i = 0; i < n; ++i) {
            unsigned char b[8];
            std::memcpy(b, buf.data() + i * es, es);
            if (format.littleEndian != (std::endian::native == std::endian::little)) std::reverse(b, b + es);
            double v = 0.0;
            if (isFloat && es == 4) {
                float f;
                std::memcpy(&f, b, 4);
                v = f;
            } else if (isFloat) {
                std::memcpy(&v, b, 8);
            } else if (format.etype == "SIGNED_INT") {
                if (es == 1) v = static_cast<std::int8_t>(b[0]);
                if (es == 2) {
                    std::int16_t x;
                    std::memcpy(&x, b, 2);
                    v = x;
                }
                if (es == 4) {
                    std::int32_t x;
                    std::memcpy(&x, b, 4);
                    v = x;
                }
            } else {
                if (es == 1) v = b[0];
                if (es == 2) {
                    std::uint16_t x;
                    std::memcpy(&x, b, 2);
                    v = x;
                }
                if (es == 4) {
                    std::uint32_t x;
                    std::memcpy(&x, b, 4);
                    v = x;
                }
            }
            if ((noData && v == *noData) || !std::isfinite(v) || std::fabs(v) > std::numeric_limits<float>::max())
                out[done + i] = nan;
            else
                out[done + i] = static_cast<float>(v);
        }
        done += n;
    }
    return out;
}

std::vector<std::uint32_t> weldExact(const std::vector<glm::dvec3>& positions, std::vector<glm::dvec3>& unique) {
    std::vector<std::uint32_t> order(positions.size());
    std::iota(order.begin(), order.end(), 0u);
    auto less = [&](std::uint32_t a, std::uint32_t b) {
        const glm::dvec3 &p = positions[a], &q = positions[b];
        if (p.x != q.x) return p.x < q.x;
        if (p.y != q.y) return p.y < q.y;
        if (p.z != q.z) return p.z < q.z;
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<std::uint32_t> first(positions.size());  // each position -> its group's smallest index
    for (std::size_t i = 0; i < order.size();) {
        std::size_t j = i;
        while (j < order.size() && positions[order[j]] == positions[order[i]]) first[order[j++]] = order[i];
        i = j;
    }
    std::vector<std::uint32_t> remap(positions.size(), std::numeric_limits<std::uint32_t>::max());
    unique.clear();
    for (std::size_t v = 0; v < positions.size(); ++v) {
        std::uint32_t f = first[v];
        if (remap[f] == std::numeric_limits<std::uint32_t>::max()) {
            remap[f] = static_cast<std::uint32_t>(unique.size());
            unique.push_back(positions[f]);
        }
        remap[v] = remap[f];
    }
    return remap;
}

}  // namespace geoslice::gocad
