// Geo3DML map styles: the display colours a project's Geo3DMap gives its layers' features.
//
// A Geo3DMap (included by a Geo3DProject like a model) holds Layers/Layer/Geo3DLayer, each
// naming a feature class (FeatureClass xlink:href="#<GeoFeatureClass gml:id>") and its
// Styles/Style/Geo3DStyle/FeatureStyle/se:FeatureTypeStyle/se:Rule list (OGC Symbology
// Encoding). What is read of a rule:
//  - its filter: none (every feature of the layer's class), or ogc:PropertyIsEqualTo of
//    PropertyName gml:id (one feature) or of a field name (features whose field of that name
//    has the Literal's text; also `name` / `gml:name` for the feature's name). Any other
//    filter is skipped with a warning naming the rule;
//  - its colour, from the first symbolizer (GeoSurfaceSymbolizer, GeoVolumeSymbolizer,
//    GeoLineSymbolizer...) that gives one, Front side first: Material/DiffuseColor (X3D-style
//    material), PBRMaterial/BaseColor, else a ParameterizedTexture's BorderColor when the texture
//    has no coordinates (an empty TexCoordList with WrapMode Border: the surface shows the border
//    colour everywhere; the image itself is not read). Colours are "r g b [a]", 0..1 each
//    (model/attributes.hpp parseColour).
// Rules apply in document order, a later match over an earlier one, after every model of the
// project is read; a style wins over a colour field of the feature's own (the map is how the
// project is meant to be shown) and loses to a sidecar, as every file colour does. Each
// coloured record's colourSource names the map. A rule that matches no feature is a warning.
#include <string>
#include <string_view>

#include <pugixml.hpp>

#include "model/io/geo3dml/geo3dml_reader.hpp"
#include "model/json_text.hpp"

namespace geoslice::geo3dml {
namespace {

// The colour a symbolizer gives, and where it came from ("DiffuseColor"...); nullopt: none.
std::optional<std::pair<Rgba8, std::string>> symbolizerColour(pugi::xml_node symbolizer) {
    for (const char* side : {"Front", "Back"}) {
        const pugi::xml_node s = childNamed(symbolizer, side);
        if (!s) continue;
        std::optional<std::pair<Rgba8, std::string>> found;
        // Material/DiffuseColor or PBRMaterial/BaseColor first; a border colour only if none.
        std::optional<std::pair<Rgba8, std::string>> border;
        walkElements(s, [&](pugi::xml_node n) {
            const std::string_view name = localName(n.name());
            if (name == "DiffuseColor" || name == "BaseColor") {
                if (auto c = parseColour(textOf(n))) {
                    found = std::make_pair(*c, std::string(name));
                    return Walk::Stop;
                }
            } else if (name == "ParameterizedTexture" && !border) {
                const pugi::xml_node coords = childNamed(n, "TexCoordList");
                const bool noCoords = !coords || (trimSpace(textOf(coords)).empty() && !firstElementChild(coords));
                if (noCoords)
                    if (auto c = parseColour(textOf(childNamed(n, "BorderColor"))))
                        border = std::make_pair(*c, std::string("BorderColor of a texture without coordinates"));
                return Walk::Skip;
            }
            return Walk::Descend;
        });
        if (found) return found;
        if (border) return border;
    }
    return std::nullopt;
}

// The text of a record's field `property` (a name in `extra`, or the record's name), for a
// PropertyIsEqualTo filter; nullopt when the record has no such field.
std::optional<std::string> fieldText(const AttributeRecord& rec, std::string_view property) {
    if (property == "name" || property == "gml:name") return rec.name;
    const auto it = rec.extra.find(std::string(property));
    if (it == rec.extra.end()) return std::nullopt;
    if (it->is_string()) return it->get<std::string>();
    return jsonText(*it);
}

}  // namespace

void Reader::readMap(pugi::xml_node map, const std::string& href) {
    std::string mapName(trimSpace(textOf(childNamed(map, "Name"))));
    if (mapName.empty() || !isValidUtf8(mapName)) mapName = quoted(href, 200);
    int layerNo = 0;
    forEachWrapped(childNamed(map, "Layers"), "Layer", "Geo3DLayer", [&](pugi::xml_node layer) {
        ++layerNo;
        std::string layerName(trimSpace(textOf(childNamed(layer, "name"))));
        if (layerName.empty() || !isValidUtf8(layerName)) layerName = "layer " + std::to_string(layerNo);
        const std::string where = "map '" + quoted(mapName, 200) + "', layer '" + quoted(layerName, 200) + "'";
        std::string classId(trimSpace(attributeNamed(childNamed(layer, "FeatureClass"), "href").value()));
        if (!classId.empty() && classId.front() == '#') classId.erase(0, 1);
        int ruleNo = 0;
        walkElements(childNamed(layer, "Styles"), [&](pugi::xml_node n) {
            if (localName(n.name()) != "Rule") return Walk::Descend;
            ++ruleNo;
            const std::string ruleWhere = where + ", rule " + std::to_string(ruleNo);
            StyleRule rule;
            rule.classId = classId;
            rule.where = ruleWhere;
            rule.mapName = mapName;
            if (const pugi::xml_node filter = childNamed(n, "Filter")) {
                const pugi::xml_node test = firstElementChild(filter);
                if (!test || localName(test.name()) != "PropertyIsEqualTo") {
                    warn("", ruleWhere + ": its filter <" + (test ? quoted(test.name(), 80) : std::string("empty")) +
                                 "> is not read (geoslice reads PropertyIsEqualTo); the rule is skipped");
                    return Walk::Skip;
                }
                rule.property = std::string(trimSpace(textOf(childNamed(test, "PropertyName"))));
                rule.literal = std::string(trimSpace(textOf(childNamed(test, "Literal"))));
                rule.filtered = true;
            }
            std::optional<std::pair<Rgba8, std::string>> colour;
            walkElements(n, [&](pugi::xml_node s) {
                const std::string_view name = localName(s.name());
                if (name.starts_with("Geo") && name.ends_with("Symbolizer")) {
                    colour = symbolizerColour(s);
                    return colour ? Walk::Stop : Walk::Skip;
                }
                return name == "Filter" ? Walk::Skip : Walk::Descend;
            });
            if (!colour) {
                warn("", ruleWhere +
                             ": no colour in its symbolizer (DiffuseColor, BaseColor, or the BorderColor "
                             "of a texture without coordinates); the rule is skipped");
                return Walk::Skip;
            }
            rule.colour = colour->first;
            rule.from = colour->second;
            styleRules_.push_back(std::move(rule));
            return Walk::Skip;
        });
    });
    ++mapsRead_;
}

void Reader::applyStyles(Model& model) {
    std::size_t coloured = 0;
    for (const StyleRule& rule : styleRules_) {
        std::size_t matched = 0;
        for (const auto& [id, feature] : features_) {
            if (!rule.classId.empty() && feature.classId != rule.classId) continue;
            AttributeRecord* rec = model.attributes.find(feature.record);
            if (!rec) continue;
            if (rule.filtered) {
                if (rule.property == "gml:id" || rule.property == "id") {
                    if (id != rule.literal) continue;
                } else {
                    const std::optional<std::string> v = fieldText(*rec, rule.property);
                    if (!v || std::string(trimSpace(*v)) != rule.literal) continue;
                }
            }
            if (rec->colourSource.empty() || !rec->colourSource.starts_with("file (Geo3DML map")) ++coloured;
            rec->colour = rule.colour;
            rec->colourSource = "file (Geo3DML map '" + quoted(rule.mapName, 200) + "' style, " + rule.from + ")";
            ++matched;
        }
        if (matched == 0)
            warn("", rule.where + (rule.filtered ? ": matches no feature (" + quoted(rule.property, 80) + " = '" +
                                                       quoted(rule.literal, 200) + "')"
                                                 : ": its feature class '" + quoted(rule.classId, 200) +
                                                       "' has no feature read"));
    }
    if (mapsRead_ > 0)
        model.notes["geo3dml_styles"] = std::to_string(mapsRead_) + (mapsRead_ == 1 ? " map, " : " maps, ") +
                                        std::to_string(styleRules_.size()) + " colour rules, " +
                                        std::to_string(coloured) + " features coloured";
}

}  // namespace geoslice::geo3dml
