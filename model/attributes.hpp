// The attribute table: record id -> geology (name, lithology, age, colour, density, grade,
// and any extra fields, carried through untouched). Record id 0 means "no geology".
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/result.hpp"

namespace geoslice {

using RecordId = std::uint32_t;
constexpr RecordId kNoRecord = 0;

struct Rgba8 {
    std::uint8_t r = 160, g = 160, b = 160, a = 255;
    bool operator==(const Rgba8&) const = default;
};

// "#rrggbb", "#rrggbbaa", "r g b [a]" with 0..1 floats (GOCAD) or 0..255 ints.
std::optional<Rgba8> parseColour(std::string_view text);
std::string formatColour(Rgba8 c);  // "#rrggbb" or "#rrggbbaa" when a != 255

struct AttributeRecord {
    RecordId id = kNoRecord;
    std::string name;       // e.g. "Xujiahe Formation"
    std::string kind;       // "stratum", "orebody", "fault", "intrusion", "terrain", ...
    std::string lithology;  // e.g. "quartz sandstone"
    std::string age;        // e.g. "Late Triassic (T3x)"
    std::string era;        // e.g. "Mesozoic"
    Rgba8 colour;
    // Where colour and name came from, shown by `geoslice info` and the API's records:
    // "file (GOCAD *solid*color)", "sidecar", "table", "palette" (model/style/palette.hpp)...
    // An empty colourSource means nobody chose the colour: the default palette fills it in.
    std::string colourSource;
    std::string nameSource;
    std::optional<double> density;                                    // t/m^3
    std::optional<double> grade;                                      // in gradeUnit
    std::string gradeUnit;                                            // e.g. "% SiO2", "g/t Au"
    nlohmann::ordered_json extra = nlohmann::ordered_json::object();  // untouched fields

    // colour_source / name_source are written when known and read back by fromJson.
    nlohmann::ordered_json toJson() const;
};

class AttributeTable {
public:
    // Adds or replaces the record with r.id (r.id must not be 0).
    void put(AttributeRecord r);
    // Adds a record with the next free id and returns that id.
    RecordId add(AttributeRecord r);
    const AttributeRecord* find(RecordId id) const;
    AttributeRecord* find(RecordId id);
    // First record whose name equals `name` (exact, case-sensitive), or nullptr.
    const AttributeRecord* findByName(std::string_view name) const;
    RecordId nextId() const;
    std::size_t size() const { return records_.size(); }
    bool empty() const { return records_.empty(); }
    // Records in ascending id order.
    const std::map<RecordId, AttributeRecord>& records() const { return records_; }

    // The top-level "crs" string of a JSON sidecar ({"crs": "EPSG:2056", "records": [...]}),
    // as written; empty when none. Loaders apply it (model/io/loaders.cpp); CSV tables carry none.
    const std::string& declaredCrs() const { return declaredCrs_; }

    nlohmann::ordered_json toJson() const;  // {"records":[...]}
    // Accepts {"records":[...]}, {"crs": "...", "records": [...]}, {"crs": "..."} or a bare
    // array of objects. `source` names the input in errors.
    // Field order of `extra` follows the input document.
    static Result<AttributeTable> fromJson(const nlohmann::ordered_json& j, const std::string& source);
    static Result<AttributeTable> fromJson(const nlohmann::json& j, const std::string& source);
    // CSV with a header row; known columns: id,name,kind,lithology,age,era,colour|color,
    // density,grade,grade_unit. Other columns go to `extra` (numbers as numbers).
    static Result<AttributeTable> fromCsv(std::string_view text, const std::string& source);
    static Result<AttributeTable> load(const std::string& path);  // .json or .csv

private:
    std::map<RecordId, AttributeRecord> records_;
    std::string declaredCrs_;
};

}  // namespace geoslice
