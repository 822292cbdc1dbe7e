#include "model/attributes.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "model/io/loaders.hpp"
#include "model/json_text.hpp"
#include "model/text_scan.hpp"

namespace geoslice {
namespace {

using text::trimSpace;

// A finite number, white space around it ignored; else nullopt.
std::optional<double> parseDouble(std::string_view s) {
    const std::optional<double> v = text::parseDouble(trimSpace(s));
    if (!v || !std::isfinite(*v)) return std::nullopt;
    return v;
}

std::optional<RecordId> parseId(std::string_view s) {
    std::uint64_t v = 0;
    if (text::parseUnsigned(trimSpace(s), v) != text::IntStatus::Ok || v == 0 || v > 0xFFFFFFFEull) return std::nullopt;
    return static_cast<RecordId>(v);
}

int hexDigit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// Appends key -> value to a JSON object without the linear key search of ordered_json's
// operator[] (which makes records with thousands of fields quadratic). The caller
// guarantees that the key is not there yet.
template <class V>
void appendField(nlohmann::ordered_json& object, const std::string& key, V&& value) {
    object.get_ref<nlohmann::ordered_json::object_t&>()
        .std::vector<std::pair<const std::string, nlohmann::ordered_json>>::emplace_back(
            key, nlohmann::ordered_json(std::forward<V>(value)));
}

}  // namespace

std::optional<Rgba8> parseColour(std::string_view text) {
    text = trimSpace(text);
    if (text.empty()) return std::nullopt;
    if (text.front() == '#') {
        text.remove_prefix(1);
        if (text.size() != 6 && text.size() != 8) return std::nullopt;
        std::uint8_t ch[4] = {0, 0, 0, 255};
        for (std::size_t i = 0; i < text.size() / 2; ++i) {
            int hi = hexDigit(text[2 * i]), lo = hexDigit(text[2 * i + 1]);
            if (hi < 0 || lo < 0) return std::nullopt;
            ch[i] = static_cast<std::uint8_t>(hi * 16 + lo);
        }
        return Rgba8{ch[0], ch[1], ch[2], ch[3]};
    }
    // Whitespace- or comma-separated numbers: all <= 1 means 0..1 floats (GOCAD), else 0..255.
    std::vector<double> v;
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && (text[i] == ' ' || text[i] == ',' || text[i] == '\t')) ++i;
        std::size_t j = i;
        while (j < text.size() && text[j] != ' ' && text[j] != ',' && text[j] != '\t') ++j;
        if (j > i) {
            auto d = parseDouble(text.substr(i, j - i));
            if (!d || *d < 0.0 || *d > 255.0) return std::nullopt;
            v.push_back(*d);
        }
        i = j;
    }
    if (v.size() != 3 && v.size() != 4) return std::nullopt;
    bool unit = true;
    for (double d : v) unit = unit && d <= 1.0;
    auto to8 = [&](double d) { return static_cast<std::uint8_t>(std::lround(unit ? d * 255.0 : d)); };
    return Rgba8{to8(v[0]), to8(v[1]), to8(v[2]), v.size() == 4 ? to8(v[3]) : std::uint8_t(255)};
}

std::string formatColour(Rgba8 c) {
    char buf[16];
    if (c.a == 255)
        std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    else
        std::snprintf(buf, sizeof buf, "#%02x%02x%02x%02x", c.r, c.g, c.b, c.a);
    return buf;
}

nlohmann::ordered_json AttributeRecord::toJson() const {
    nlohmann::ordered_json j;
    j["id"] = id;
    j["name"] = name;
    if (!kind.empty()) j["kind"] = kind;
    if (!lithology.empty()) j["lithology"] = lithology;
    if (!age.empty()) j["age"] = age;
    if (!era.empty()) j["era"] = era;
    j["colour"] = formatColour(colour);
    j["colour_source"] = colourSource.empty() ? "default" : colourSource;
    if (!nameSource.empty()) j["name_source"] = nameSource;
    if (density) j["density"] = *density;
    if (grade) j["grade"] = *grade;
    if (!gradeUnit.empty()) j["grade_unit"] = gradeUnit;
    // Extra fields follow; one named like a typed field above is shadowed by it.
    std::vector<std::string> typed;
    for (const auto& [k, v] : j.items()) typed.push_back(k);
    for (const auto& [k, v] : extra.items())
        if (std::find(typed.begin(), typed.end(), k) == typed.end()) appendField(j, k, v);
    return j;
}

void AttributeTable::put(AttributeRecord r) {
    GS_ASSERT(r.id != kNoRecord, "record id 0 is reserved for 'no geology'");
    records_[r.id] = std::move(r);
}

RecordId AttributeTable::add(AttributeRecord r) {
    r.id = nextId();
    RecordId id = r.id;
    put(std::move(r));
    return id;
}

const AttributeRecord* AttributeTable::find(RecordId id) const {
    auto it = records_.find(id);
    return it == records_.end() ? nullptr : &it->second;
}

AttributeRecord* AttributeTable::find(RecordId id) {
    auto it = records_.find(id);
    return it == records_.end() ? nullptr : &it->second;
}

const AttributeRecord* AttributeTable::findByName(std::string_view name) const {
    for (const auto& [id, r] : records_)
        if (r.name == name) return &r;
    return nullptr;
}

RecordId AttributeTable::nextId() const { return records_.empty() ? 1 : records_.rbegin()->first + 1; }

nlohmann::ordered_json AttributeTable::toJson() const {
    nlohmann::ordered_json arr = nlohmann::ordered_json::array();
    for (const auto& [id, r] : records_) arr.push_back(r.toJson());
    nlohmann::ordered_json j;
    j["records"] = std::move(arr);
    return j;
}

Result<AttributeTable> AttributeTable::fromJson(const nlohmann::json& j, const std::string& source) {
    return fromJson(nlohmann::ordered_json::parse(jsonText(j)), source);
}

Result<AttributeTable> AttributeTable::fromJson(const nlohmann::ordered_json& j, const std::string& source) {
    static const nlohmann::ordered_json kNoRecords = nlohmann::ordered_json::array();
    const nlohmann::ordered_json* arr = &j;
    std::string crs;
    if (j.is_object() && j.contains("crs")) {
        if (!j["crs"].is_string())
            return makeError(ErrorCode::ParseError, source + ": \"crs\" must be a string such as \"EPSG:2056\"");
        crs = j["crs"].get<std::string>();
        arr = &kNoRecords;
    }
    if (j.is_object() && j.contains("records")) arr = &j["records"];
    if (!arr->is_array())
        return makeError(ErrorCode::ParseError, source + ": expected an array of records or {\"records\": [...]}");
    AttributeTable table;
    table.declaredCrs_ = std::move(crs);
    std::size_t index = 0;
    for (const auto& o : *arr) {
        std::string where = source + ": record " + std::to_string(index++);
        if (!o.is_object()) return makeError(ErrorCode::ParseError, where + " is not an object");
        AttributeRecord r;
        auto idIt = o.find("id");
        if (idIt == o.end() || !idIt->is_number_unsigned() || idIt->get<std::uint64_t>() == 0 ||
            idIt->get<std::uint64_t>() > 0xFFFFFFFEull)
            return makeError(ErrorCode::ParseError, where + ": \"id\" must be an integer in 1..4294967294");
        r.id = idIt->get<RecordId>();
        if (table.find(r.id)) return makeError(ErrorCode::ParseError, where + ": duplicate id " + std::to_string(r.id));
        for (const auto& item : o.items()) {
            const std::string& key = item.key();
            const auto& value = item.value();
            auto str = [&](std::string& out) -> Status {
                if (!value.is_string())
                    return makeError(ErrorCode::ParseError, where + ": \"" + key + "\" must be a string");
                out = value.get<std::string>();
                return {};
            };
            auto num = [&](std::optional<double>& out) -> Status {
                if (value.is_null()) return {};
                if (!value.is_number() || !std::isfinite(value.get<double>()))
                    return makeError(ErrorCode::ParseError, where + ": \"" + key + "\" must be a finite number");
                out = value.get<double>();
                return {};
            };
            Status s;
            if (key == "id") continue;
            if (key == "name")
                s = str(r.name);
            else if (key == "kind")
                s = str(r.kind);
            else if (key == "lithology")
                s = str(r.lithology);
            else if (key == "age")
                s = str(r.age);
            else if (key == "era")
                s = str(r.era);
            else if (key == "grade_unit")
                s = str(r.gradeUnit);
            else if (key == "colour_source") {
                s = str(r.colourSource);
                if (r.colourSource == "default") r.colourSource.clear();  // nobody chose it
            } else if (key == "name_source")
                s = str(r.nameSource);
            else if (key == "density")
                s = num(r.density);
            else if (key == "grade")
                s = num(r.grade);
            else if (key == "colour" || key == "color") {
                std::optional<Rgba8> c = value.is_string() ? parseColour(value.get<std::string>()) : std::nullopt;
                if (!c)
                    return makeError(ErrorCode::ParseError,
                                     where + ": \"" + key + "\" is not a colour like \"#a0b0c0\"");
                r.colour = *c;
                if (r.colourSource.empty()) r.colourSource = "table";
            } else {
                appendField(r.extra, key, value);  // keys of a parsed object are unique
            }
            if (!s) return s.error();
        }
        table.put(std::move(r));
    }
    return table;
}

Result<AttributeTable> AttributeTable::fromCsv(std::string_view text, const std::string& source) {
    std::size_t pos = 0;
    bool badQuote = false;
    if (text.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;  // UTF-8 byte order mark
    std::vector<std::string> header = text::csvRecord(text, pos, badQuote);
    if (badQuote) return makeError(ErrorCode::ParseError, source + ": line 1: unterminated quote");
    int idCol = -1;
    for (std::size_t c = 0; c < header.size(); ++c) {
        header[c] = std::string(trimSpace(header[c]));
        if (header[c] == "id") idCol = static_cast<int>(c);
    }
    if (idCol < 0) return makeError(ErrorCode::ParseError, source + ": line 1: the header has no \"id\" column");
    {
        std::vector<std::string> sorted = header;
        std::sort(sorted.begin(), sorted.end());
        for (std::size_t c = 1; c < sorted.size(); ++c)
            if (sorted[c] == sorted[c - 1])
                return makeError(ErrorCode::ParseError,
                                 source + ": line 1: column \"" + sorted[c] + "\" appears twice");
    }
    AttributeTable table;
    std::size_t line = 1;
    while (pos < text.size()) {
        ++line;
        std::vector<std::string> f = text::csvRecord(text, pos, badQuote);
        std::string where = source + ": line " + std::to_string(line);
        if (badQuote) return makeError(ErrorCode::ParseError, where + ": unterminated quote");
        if (f.size() == 1 && trimSpace(f[0]).empty()) continue;
        if (f.size() != header.size())
            return makeError(ErrorCode::ParseError, where + ": " + std::to_string(f.size()) + " fields, header has " +
                                                        std::to_string(header.size()));
        AttributeRecord r;
        auto id = parseId(f[static_cast<std::size_t>(idCol)]);
        if (!id)
            return makeError(ErrorCode::ParseError, where + ": id \"" + f[static_cast<std::size_t>(idCol)] +
                                                        "\" is not an integer in 1..4294967294");
        r.id = *id;
        if (table.find(r.id)) return makeError(ErrorCode::ParseError, where + ": duplicate id " + std::to_string(r.id));
        for (std::size_t c = 0; c < header.size(); ++c) {
            const std::string& key = header[c];
            std::string value(trimSpace(f[c]));
            if (static_cast<int>(c) == idCol) continue;
            if (key == "name")
                r.name = value;
            else if (key == "kind")
                r.kind = value;
            else if (key == "lithology")
                r.lithology = value;
            else if (key == "age")
                r.age = value;
            else if (key == "era")
                r.era = value;
            else if (key == "grade_unit")
                r.gradeUnit = value;
            else if (key == "density" || key == "grade") {
                if (value.empty()) continue;
                auto d = parseDouble(value);
                if (!d)
                    return makeError(ErrorCode::ParseError,
                                     where + ": " + key + " \"" + value + "\" is not a finite number");
                (key == "density" ? r.density : r.grade) = *d;
            } else if (key == "colour" || key == "color") {
                if (value.empty()) continue;
                auto col = parseColour(value);
                if (!col)
                    return makeError(ErrorCode::ParseError, where + ": colour \"" + value + "\" is not like #a0b0c0");
                r.colour = *col;
                r.colourSource = "table";
            } else if (auto d = parseDouble(value)) {
                appendField(r.extra, key, *d);  // header names are unique (checked above)
            } else {
                appendField(r.extra, key, value);
            }
        }
        table.put(std::move(r));
    }
    return table;
}

Result<AttributeTable> AttributeTable::load(const std::string& path) {
    // readFile: a FIFO or device named like a sidecar is refused, never opened to block.
    auto read = readFile(path, std::size_t(1) << 30);
    if (!read) return makeError(read.error().code, "attribute table " + read.error().message);
    const std::string text = std::move(read.value());
    bool json = path.size() >= 5 && path.substr(path.size() - 5) == ".json";
    if (!json) return fromCsv(text, path);
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) return makeError(ErrorCode::ParseError, path + ": not valid JSON");
    return fromJson(j, path);
}

}  // namespace geoslice
