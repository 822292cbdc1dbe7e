// Geo3DML reading: a feature's Fields -> its attribute record (name, kind, lithology, age,
// era, density, grade, colour, and every field verbatim in `extra`). Fields are recognised
// by their Name, Chinese or English. Part of the reader in model/io/geo3dml/geo3dml_reader.hpp.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/io/geo3dml/geo3dml_reader.hpp"

namespace geoslice::geo3dml {
namespace {

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
        const std::string lower = text::lower(s);
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

}  // namespace

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
                const std::string unit = text::lower(trimSpace(uom));
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
                if (const std::optional<Rgba8> c = parseColour(t)) {
                    rec.colour = *c;
                    rec.colourSource = "file (Geo3DML colour field)";
                }
                break;
            case FieldRole::None:
                break;
        }
    }
    extra.moveInto(rec.extra);
    return rec;
}

}  // namespace geoslice::geo3dml
