// GOCAD reading: an object's HEADER block, its GOCAD_ORIGINAL_COORDINATE_SYSTEM block (axis
// units, depth-positive z, declared CRS), the common object keywords -> its attribute record,
// and skipping blocks and objects that are not read. Part of what the GOCAD readers share
// (model/io/gocad/gocad_reader.hpp).
#include <charconv>
#include <cstdio>
#include <system_error>

#include "model/io/gocad/gocad_reader.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

namespace {

constexpr double kFootM = 0.3048;                   // international foot, metres
constexpr double kUsSurveyFootM = 1200.0 / 3937.0;  // US survey foot, metres

}  // namespace

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
        } else if (key == "*solid*color" || key == "*surface*color" || key == "*line*color" || key == "color" ||
                   key == "*atoms*color") {
            std::optional<Rgba8> c = parseColour(value);
            if (!c) {
                rawColour = toUtf8(value);
                continue;
            }
            colours[key] = *c;
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
    // The object's own kind of colour first, then a plain `color`, then point markers'.
    for (const char* key : {"*solid*color", "*surface*color", "*line*color", "color", "*atoms*color"}) {
        if (auto it = colours.find(key); it != colours.end()) {
            rec.colour = it->second;
            rec.colourSource = std::string("file (GOCAD ") + key + ")";
            break;
        }
    }
    if (!name.empty()) rec.nameSource = "file (GOCAD name:)";
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
    if (!rawColour.empty() && colours.empty()) rec.extra["gocad_color"] = rawColour;
    return rec;
}

}  // namespace geoslice::gocad
