// Surpac string (.str) and DTM (.dtm) readers, text forms.
//
// String file: a header record (name, date, purpose, styles), an axis record
// (`0, y1, x1, z1, y2, x2, z2`), then one record per point:
//     string_number, Y, X, Z[, d1, d2, ...]
// Y (northing) comes before X (easting). A record with string number 0 ends a segment of a
// string; `0, 0.000, 0.000, 0.000, END` ends the file. Strings are kept as lines: one
// Polyline per string number ("string 5"), its segments joined point to point (a closed
// segment repeats its first point last, so it closes by itself).
//
// DTM file: a header record (naming its string file), `0, 0.000, 0.000, 0.000, END`, then
// `OBJECT, n,` and `TRISOLATION, m, key=value,...` records, each followed by triangle records
//     triangle_id, p1, p2, p3, n1, n2, n3[, ...]
// where p1..p3 are point numbers: the 1-based sequence of the point records of the string
// file (records with a non-zero string number, in file order; separators and the header and
// axis records are not counted), and n1..n3 the neighbouring triangles (not used). `END`
// ends the file. Each trisolation is a part named "object n" (or "object n trisolation m"
// when the object has several), its points welded exactly; finishLoadedModel() makes a
// closed one a body and an open one a surface.
//
// Binary string and DTM files (Surpac can write both) are refused with an Unsupported error.
// Coordinates are world coordinates as written: x east, y north, z up, metres.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "model/io/loaders.hpp"
#include "model/io/weld.hpp"
#include "model/text_scan.hpp"

namespace geoslice {
namespace {

using namespace geoslice::text;

// Comma-separated fields of one record, each trimmed.
std::vector<std::string_view> fields(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = line.find(',', start);
        out.push_back(
            trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    return out;
}

Error failAt(const std::string& source, std::size_t line, const std::string& what) {
    return makeError(ErrorCode::ParseError, source + ": line " + std::to_string(line) + ": " + what);
}

Status checkText(std::string_view text, const std::string& source, const char* what) {
    const std::size_t n = std::min<std::size_t>(text.size(), 4096);
    if (text.substr(0, n).find('\0') != std::string_view::npos)
        return makeError(ErrorCode::Unsupported,
                         source + ": a binary Surpac " + what + " file, which geoslice does not read: save it as text");
    return {};
}

struct StringPoint {
    std::int64_t string = 0;
    glm::dvec3 p{0.0};
    bool segmentStart = false;  // first point after a separator (or the axis record)
};

struct StringFile {
    std::vector<StringPoint> points;  // point records only, in file order (DTM point n = points[n-1])
};

Result<StringFile> readStringFile(std::string_view text, const std::string& source) {
    if (Status s = checkText(text, source, "string"); !s) return s.error();
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    StringFile out;
    std::size_t pos = 0, lineNo = 0;
    std::string_view line;
    bool ended = false, newSegment = true;
    while (text::nextLine(text, pos, line)) {
        ++lineNo;
        if (lineNo == 1) continue;  // the header record: free text
        if (std::size_t bad = findNonText(line, false); bad != std::string_view::npos)
            return failAt(source, lineNo, nonTextMessage(line, bad, false));
        if (trim(line).empty()) continue;
        const auto f = fields(line);
        if (lineNo == 2) {  // the axis record: checked for form only
            if (f.size() < 4 || f[0] != "0")
                return failAt(source, lineNo,
                              "not a Surpac string file: the axis record should be '0, y1, x1, z1, ...'");
            continue;
        }
        if (f.size() < 4)
            return failAt(source, lineNo,
                          "a record needs string number, Y, X, Z; found " + std::to_string(f.size()) + " field" +
                              (f.size() == 1 ? "" : "s"));
        std::int64_t string = 0;
        if (parseInt(f[0], string) != IntStatus::Ok || string < 0)
            return failAt(source, lineNo, "string number " + quoteToken(f[0]) + " is not a whole number");
        if (string == 0) {
            if (f.size() >= 5 && equalsNoCase(f[4], "END")) {
                ended = true;
                break;
            }
            newSegment = true;
            continue;
        }
        StringPoint sp;
        sp.string = string;
        const int order[3] = {1, 0, 2};  // Y, X, Z in the file
        for (int k = 0; k < 3; ++k) {
            if (f[static_cast<std::size_t>(k) + 1].empty())
                return failAt(
                    source, lineNo,
                    std::string("the ") + "YXZ"[k] + " field is empty (a record is string number, Y, X, Z, ...)");
            auto v = parseDouble(f[static_cast<std::size_t>(k) + 1]);
            if (!v)
                return failAt(source, lineNo,
                              "coordinate " + quoteToken(f[static_cast<std::size_t>(k) + 1]) + " is not a number");
            if (!std::isfinite(*v))
                return failAt(source, lineNo,
                              "coordinate " + quoteToken(f[static_cast<std::size_t>(k) + 1]) + " is not finite");
            sp.p[order[k]] = *v;
        }
        sp.segmentStart = newSegment || out.points.empty() || out.points.back().string != string;
        newSegment = false;
        if (out.points.size() >= std::numeric_limits<std::uint32_t>::max() - 1)
            return failAt(source, lineNo, "too many points");
        out.points.push_back(sp);
    }
    if (lineNo < 2) return makeError(ErrorCode::ParseError, source + ": not a Surpac string file (no axis record)");
    if (!ended)
        return makeError(ErrorCode::ParseError,
                         source + ": line " + std::to_string(lineNo) +
                             ": the file ends without its end record '0, 0.000, 0.000, 0.000, END'"
                             " (truncated?)");
    return out;
}

void addStrings(Model& model, const StringFile& sf) {
    std::map<std::int64_t, std::size_t> byString;
    for (const StringPoint& sp : sf.points) {
        auto [it, inserted] = byString.try_emplace(sp.string, model.lines.size());
        if (inserted) {
            model.lines.emplace_back();
            model.lines.back().name = "string " + std::to_string(sp.string);
        }
        Polyline& l = model.lines[it->second];
        const auto n = static_cast<std::uint32_t>(l.points.size());
        if (!sp.segmentStart && n > 0) {
            l.segments.push_back(n - 1);
            l.segments.push_back(n);
        }
        l.points.push_back(sp.p);
    }
    for (Polyline& l : model.lines) {
        AttributeRecord rec;
        rec.name = l.name;
        rec.kind = "line";
        l.record = model.attributes.add(std::move(rec));
    }
}

}  // namespace

Result<Model> parseSurpacString(std::string_view text, const std::string& source) {
    auto sf = readStringFile(text, source);
    if (!sf) return sf.error();
    if (sf->points.empty())
        return makeError(ErrorCode::ParseError, source + ": a string file with no points: nothing to load");
    Model model;
    model.source = source;
    model.name = std::filesystem::path(source).stem().string();
    addStrings(model, sf.value());
    finishLoadedModel(model, /*classifyByClosure=*/true);
    return model;
}

Result<Model> parseSurpacDtm(std::string_view dtm, const std::string& dtmSource, std::string_view str,
                             const std::string& strSource) {
    if (Status s = checkText(dtm, dtmSource, "DTM"); !s) return s.error();
    auto sf = readStringFile(str, strSource);
    if (!sf) return sf.error();
    const std::vector<StringPoint>& points = sf->points;
    if (dtm.substr(0, 3) == "\xEF\xBB\xBF") dtm.remove_prefix(3);

    std::vector<WeldedPart> parts;
    std::vector<std::pair<std::int64_t, std::int64_t>> keys;  // (object, trisolation) per part
    std::map<std::int64_t, int> trisolationsPerObject;
    std::int64_t object = -1;
    std::size_t current = std::string::npos;
    std::size_t pos = 0, lineNo = 0;
    std::string_view line;
    bool ended = false;
    while (text::nextLine(dtm, pos, line)) {
        ++lineNo;
        if (lineNo == 1) continue;  // header: the string file's name and options
        if (std::size_t bad = findNonText(line, false); bad != std::string_view::npos)
            return failAt(dtmSource, lineNo, nonTextMessage(line, bad, false));
        if (trim(line).empty()) continue;
        const auto f = fields(line);
        if (lineNo == 2) continue;  // "0, 0.000, 0.000, 0.000, END"
        if (equalsNoCase(f[0], "END")) {
            ended = true;
            break;
        }
        if (equalsNoCase(f[0], "OBJECT") || equalsNoCase(f[0], "TRISOLATION")) {
            std::int64_t n = 0;
            if (f.size() < 2 || parseInt(f[1], n) != IntStatus::Ok)
                return failAt(dtmSource, lineNo, std::string(f[0]) + " needs a number");
            if (equalsNoCase(f[0], "OBJECT")) {
                object = n;
                current = std::string::npos;
            } else {
                if (object < 0) return failAt(dtmSource, lineNo, "TRISOLATION before any OBJECT");
                current = parts.size();
                parts.emplace_back();
                keys.emplace_back(object, n);
                ++trisolationsPerObject[object];
            }
            continue;
        }
        if (current == std::string::npos)
            return failAt(dtmSource, lineNo, "a triangle record before any OBJECT and TRISOLATION");
        if (f.size() < 4)
            return failAt(dtmSource, lineNo,
                          "a triangle record needs id, p1, p2, p3; found " + std::to_string(f.size()) + " fields");
        glm::dvec3 c[3];
        for (int k = 0; k < 3; ++k) {
            std::int64_t id = 0;
            const std::string_view tok = f[static_cast<std::size_t>(k) + 1];
            if (parseInt(tok, id) != IntStatus::Ok)
                return failAt(dtmSource, lineNo, "point number " + quoteToken(tok) + " is not a whole number");
            if (id < 1 || static_cast<std::uint64_t>(id) > points.size())
                return failAt(dtmSource, lineNo,
                              "point number " + std::to_string(id) + " is out of range: " + strSource + " has " +
                                  std::to_string(points.size()) + " points");
            c[k] = points[static_cast<std::size_t>(id - 1)].p;
        }
        parts[current].addTriangle(c[0], c[1], c[2]);
        if (parts[current].indices.size() > std::numeric_limits<std::uint32_t>::max() - 3)
            return failAt(dtmSource, lineNo, "too many triangles");
    }
    if (!ended)
        return makeError(ErrorCode::ParseError, dtmSource + ": line " + std::to_string(lineNo) +
                                                    ": the file ends without its END record (truncated?)");
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const auto [o, t] = keys[i];
        parts[i].name =
            "object " + std::to_string(o) + (trisolationsPerObject[o] > 1 ? " trisolation " + std::to_string(t) : "");
    }
    Model model;
    model.source = dtmSource;
    model.name = std::filesystem::path(dtmSource).stem().string();
    addWeldedParts(model, parts);
    if (model.bodies.empty())
        return makeError(ErrorCode::ParseError, dtmSource + ": a DTM with no triangles: nothing to load");
    model.notes["surpac_string_file"] = strSource;
    finishLoadedModel(model, /*classifyByClosure=*/true);
    setRecordKinds(model);
    return model;
}

}  // namespace geoslice
