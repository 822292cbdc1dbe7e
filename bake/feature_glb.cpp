// writeFeatureGlb: the baked model as one glTF 2.0 binary for CesiumJS and other glTF tools,
// the package's mesh plus EXT_mesh_features (a feature-ID texture) and EXT_structural_metadata
// (one property-table row per record). encodeMesh (package_mesh.cpp) calls the pieces below.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <functional>
#include <optional>

#include "bake/feature_table.hpp"
#include "bake/package_internal.hpp"
#include "image/image_encode.hpp"
#include "model/json_text.hpp"

namespace geoslice::bake {
namespace package_detail {
namespace {

using json = nlohmann::ordered_json;

// The feature-ID texture of EXT_mesh_features: RGBA8 PNG whose 4 channels are the bytes of a
// little-endian uint32 property-table row (kNullFeature where no geology is).
constexpr std::uint32_t kNullFeature = 0xFFFFFFFFu;

Result<std::vector<std::uint8_t>> encodeFeaturePng(const BakedModel& baked, const std::vector<RecordId>& rows) {
    std::vector<std::uint32_t> texels(baked.texels.size());
    for (std::size_t i = 0; i < texels.size(); ++i) {
        const RecordId id = baked.texels[i];
        auto it = std::lower_bound(rows.begin(), rows.end(), id);
        const std::uint32_t row = id != kNoRecord && it != rows.end() && *it == id
                                      ? static_cast<std::uint32_t>(it - rows.begin())
                                      : kNullFeature;
        const std::uint8_t b[4] = {std::uint8_t(row), std::uint8_t(row >> 8), std::uint8_t(row >> 16),
                                   std::uint8_t(row >> 24)};
        std::memcpy(&texels[i], b, 4);
    }
    // Lossless RGBA: the channels are bytes of a row number, not colours (image/image_encode.hpp).
    EncodeOptions o;
    o.keepAlpha = true;
    o.pngLevel = 6;
    auto png = encodeImage(reinterpret_cast<const std::uint8_t*>(texels.data()), int(baked.width), int(baked.height),
                           ImageFormat::Png, o);
    if (!png) return makeError(png.error().code, "feature texture: " + png.error().message);
    return std::move(png.value());
}

}  // namespace

std::vector<RecordId> featureRows(const AttributeTable& table, const BakedModel& baked) {
    std::vector<RecordId> records;
    for (const BakedPart& part : baked.parts) records.push_back(part.record);
    return bake::featureRows(table, records);
}

json featureIdsExtension(std::size_t rowCount) {
    return {{"featureIds", json::array({{{"featureCount", rowCount},
                                         {"nullFeatureId", kNullFeature},
                                         {"label", "record"},
                                         {"texture", {{"index", 0}, {"texCoord", 0}, {"channels", {0, 1, 2, 3}}}},
                                         {"propertyTable", 0}}})}};
}

Status addFeatureTables(GlbBuilder& glb, const BakedModel& baked, const AttributeTable& table, FeatureExport& fx) {
    auto png = encodeFeaturePng(baked, fx.rows);
    if (!png) return png.error();
    fx.imageView = glb.addView(png->data(), png->size(), 0);
    fx.metadata = addPropertyTable(glb, fx.rows, table);
    return {};
}

void finishFeatureDocument(json& doc, const FeatureExport& fx) {
    doc["images"] = {{{"bufferView", fx.imageView}, {"mimeType", "image/png"}}};
    // Nearest sampling, clamped: ids must never be filtered.
    doc["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}};
    doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    doc["extensionsUsed"] = {"EXT_mesh_features", "EXT_structural_metadata"};
    doc["extensions"]["EXT_structural_metadata"] = fx.metadata;
}

}  // namespace package_detail

Status writeFeatureGlb(const Model& model, const BakedModel& baked, const std::string& path) {
    auto glb = package_detail::encodeMesh(model, baked, true, true);
    if (!glb) return glb.error();
    return package_detail::writeFile(std::filesystem::path(path), glb->data(), glb->size());
}

std::vector<RecordId> featureRows(const AttributeTable& table, std::span<const RecordId> partRecords) {
    std::vector<RecordId> rows;
    for (const auto& [id, rec] : table.records()) rows.push_back(id);
    for (RecordId r : partRecords)
        if (r != kNoRecord) rows.push_back(r);
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    return rows;
}

namespace {

bool isMetadataIdentifier(std::string_view s) {
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
    return std::all_of(s.begin(), s.end(),
                       [](char c) { return c == '_' || std::isalnum(static_cast<unsigned char>(c)); });
}

}  // namespace

nlohmann::ordered_json addPropertyTable(GlbBuilder& glb, const std::vector<RecordId>& rows,
                                        const AttributeTable& table) {
    using json = nlohmann::ordered_json;
    // Strings as UTF-8 values plus UINT32 offsets, numbers as FLOAT64 with -1 for "not
    // given"; 8-byte aligned views.
    json schemaProps = {{"id", {{"type", "SCALAR"}, {"componentType", "UINT32"}, {"required", true}}}};
    json tableProps = json::object();
    std::vector<std::uint32_t> ids(rows.begin(), rows.end());
    tableProps["id"] = {{"values", glb.addView(ids.data(), ids.size() * 4, 0, 8)}};
    auto addStrings = [&](const std::string& key, const std::function<std::string(const AttributeRecord&)>& get) {
        std::string values;
        std::vector<std::uint32_t> offsets{0};
        for (RecordId id : rows) {
            if (const AttributeRecord* r = table.find(id)) values += get(*r);
            offsets.push_back(static_cast<std::uint32_t>(values.size()));
        }
        schemaProps[key] = {{"type", "STRING"}};
        const std::size_t vv = glb.addView(values.data(), values.size(), 0, 8);
        const std::size_t ov = glb.addView(offsets.data(), offsets.size() * 4, 0, 8);
        tableProps[key] = {{"values", vv}, {"stringOffsets", ov}, {"stringOffsetType", "UINT32"}};
    };
    addStrings("name", [](const AttributeRecord& r) { return r.name; });
    addStrings("kind", [](const AttributeRecord& r) { return r.kind; });
    addStrings("lithology", [](const AttributeRecord& r) { return r.lithology; });
    addStrings("age", [](const AttributeRecord& r) { return r.age; });
    addStrings("era", [](const AttributeRecord& r) { return r.era; });
    addStrings("gradeUnit", [](const AttributeRecord& r) { return r.gradeUnit; });
    addStrings("colour", [](const AttributeRecord& r) { return formatColour(r.colour); });
    for (const char* key : {"density", "grade"}) {
        std::vector<double> v;
        for (RecordId id : rows) {
            const AttributeRecord* r = table.find(id);
            const std::optional<double> x = r ? (std::strcmp(key, "density") ? r->grade : r->density) : std::nullopt;
            v.push_back(x ? *x : -1.0);
        }
        schemaProps[key] = {{"type", "SCALAR"}, {"componentType", "FLOAT64"}, {"noData", -1.0}};
        tableProps[key] = {{"values", glb.addView(v.data(), v.size() * 8, 0, 8)}};
    }
    // The free-form fields, in order of first appearance.
    std::vector<std::string> extraKeys;
    for (RecordId id : rows)
        if (const AttributeRecord* r = table.find(id); r && r->extra.is_object())
            for (const auto& [k, v] : r->extra.items())
                if (std::find(extraKeys.begin(), extraKeys.end(), k) == extraKeys.end()) extraKeys.push_back(k);
    for (const std::string& key : extraKeys) {
        std::string name = key;
        if (!isMetadataIdentifier(name)) {
            for (char& c : name)
                if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
            name = "_" + name;
        }
        if (schemaProps.contains(name)) continue;
        addStrings(name, [&key](const AttributeRecord& r) {
            if (!r.extra.is_object() || !r.extra.contains(key)) return std::string();
            const auto& v = r.extra[key];
            return v.is_string() ? v.get<std::string>() : jsonText(v);
        });
    }
    return {
        {"schema", {{"id", "geoslice"}, {"classes", {{"geology", {{"properties", schemaProps}}}}}}},
        {"propertyTables", json::array({{{"class", "geology"}, {"count", rows.size()}, {"properties", tableProps}}})}};
}

}  // namespace geoslice::bake
