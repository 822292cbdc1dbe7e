#include "api/context_layer.hpp"

#include <cmath>
#include <filesystem>
#include <optional>

#include "model/io/loaders.hpp"
#include "model/text_scan.hpp"

namespace geoslice::api {
namespace {

using J = nlohmann::ordered_json;

Error bad(const std::string& where, const std::string& what) {
    return makeError(ErrorCode::ParseError, where + ": " + what);
}

// The CRS text a GeoJSON `crs` member holds: {"type": "name", "properties": {"name": N}} or a
// bare string N ("urn:ogc:def:crs:EPSG::4523", "EPSG:4523", any text Crs::parse reads); empty
// when it holds none. OGC's CRS84 is WGS 84 lon/lat, RFC 7946's own.
std::string crsTextOf(const J& crs) {
    std::string name;
    if (crs.is_string())
        name = crs.get<std::string>();
    else if (crs.is_object() && crs.contains("properties") && crs["properties"].is_object() &&
             crs["properties"].contains("name") && crs["properties"]["name"].is_string())
        name = crs["properties"]["name"].get<std::string>();
    return name.find("CRS84") != std::string::npos ? "EPSG:4326" : name;
}

// Depth of nesting of positions each geometry type has (Point 0: a position itself).
std::optional<int> depthOf(const std::string& type) {
    if (type == "Point") return 0;
    if (type == "MultiPoint" || type == "LineString") return 1;
    if (type == "MultiLineString" || type == "Polygon") return 2;
    if (type == "MultiPolygon") return 3;
    return std::nullopt;
}

struct Converter {
    const CrsTransform* transform = nullptr;  // null: coordinates are the model's own
    std::size_t positions = 0;

    Status position(J& p, const std::string& where) {
        if (!p.is_array() || p.size() < 2 || p.size() > 3)
            return bad(where, "a position is not an array of 2 or 3 numbers");
        double v[3] = {0.0, 0.0, 0.0};
        for (std::size_t i = 0; i < p.size(); ++i) {
            if (!p[i].is_number()) return bad(where, "a coordinate is not a number");
            v[i] = p[i].get<double>();
            if (!std::isfinite(v[i])) return bad(where, "a coordinate is not finite");
        }
        if (++positions > kMaxContextPositions)
            return makeError(ErrorCode::OutOfRange,
                             where + ": more than " + std::to_string(kMaxContextPositions) + " positions");
        if (transform) {
            auto q = transform->apply({v[0], v[1], v[2]});
            if (!q)
                return bad(where, "(" + std::to_string(v[0]) + ", " + std::to_string(v[1]) +
                                      ") cannot be converted to the model's CRS: " + q.error().message);
            v[0] = q.value().x;
            v[1] = q.value().y;
        }
        // Millimetres are plenty for a plan, and keep the document small.
        p[0] = std::round(v[0] * 1000.0) / 1000.0;
        p[1] = std::round(v[1] * 1000.0) / 1000.0;
        return {};
    }
    Status walk(J& c, int depth, const std::string& where) {
        if (depth == 0) return position(c, where);
        if (!c.is_array()) return bad(where, "coordinates are not nested arrays as its type needs");
        for (J& x : c)
            if (auto s = walk(x, depth - 1, where); !s) return s;
        return {};
    }
};

}  // namespace

std::string contextSidecarFor(const std::string& modelPath) {
    std::filesystem::path p(modelPath);
    p.replace_extension(".context.geojson");
    std::error_code ec;
    return std::filesystem::is_regular_file(p, ec) ? p.string() : std::string();
}

Result<J> parseContextLayer(std::string_view text, const std::string& source, const Crs& modelCrs, const Aabb& bounds) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
    if (!text::isUtf8(text)) return bad(source, "not valid UTF-8");
    J doc = J::parse(text, nullptr, false);
    if (doc.is_discarded()) return bad(source, "not valid JSON");
    if (!doc.is_object() || doc.value("type", "") != "FeatureCollection" || !doc.contains("features") ||
        !doc["features"].is_array())
        return bad(source, "not a GeoJSON FeatureCollection (a \"type\": \"FeatureCollection\" with \"features\")");

    // Where the coordinates are, and the one operation that brings them to the model's CRS.
    std::optional<CrsTransform> transform;
    std::string read, note;
    if (modelCrs.isLocal()) {
        if (doc.contains("crs"))
            return bad(source, "a 'crs' member, but the model has no CRS: give the model's own coordinates");
        read = "the model's own coordinates (the model has no CRS)";
    } else {
        const std::string named = doc.contains("crs") ? crsTextOf(doc["crs"]) : "EPSG:4326";
        auto from = named.empty() ? Result<Crs>(makeError(ErrorCode::InvalidArgument, "no name")) : Crs::parse(named);
        if (!from || from.value().isLocal())
            return bad(source, "its 'crs' member names no CRS PROJ knows (e.g. urn:ogc:def:crs:EPSG::4523)" +
                                   (from ? std::string() : ": " + from.error().message));
        const std::string id = from.value().id();
        if (from.value() == modelCrs) {
            read = id + ", the model's CRS";
        } else {
            auto area = lonLatBoxOf(modelCrs, {bounds.min.x, bounds.min.y}, {bounds.max.x, bounds.max.y});
            if (!area) return bad(source, "the model's lon/lat extent: " + area.error().message);
            auto t = CrsTransform::forArea(from.value(), modelCrs, area.value());
            if (!t) return bad(source, "no PROJ operation from " + id + " to the model's CRS: " + t.error().message);
            transform = std::move(t.value());
            read = from.value().epsg() == 4326 ? "WGS 84 lon/lat (RFC 7946), converted to the model's CRS"
                                               : id + ", converted to the model's CRS";
            if (transform->isBallpark())
                note = "PROJ has only a ballpark operation (" + transform->operationName() + ": no datum shift) from " +
                       id + " to the model's CRS";
        }
    }

    Converter conv;
    conv.transform = transform ? &*transform : nullptr;
    J out;
    out["type"] = "FeatureCollection";
    J features = J::array();
    std::size_t i = 0;
    for (J& f : doc["features"]) {
        const std::string where = source + ": features[" + std::to_string(i++) + "]";
        if (!f.is_object() || f.value("type", "") != "Feature") return bad(where, "not a Feature");
        if (!f.contains("geometry") || f["geometry"].is_null()) continue;  // RFC 7946 3.2: unlocated
        J& g = f["geometry"];
        const std::string type = g.is_object() ? g.value("type", "") : "";
        const auto depth = depthOf(type);
        if (!depth)
            return bad(where, "geometry type '" + text::escapeText(type, 40) +
                                  "' (read: Point, MultiPoint, LineString, MultiLineString, Polygon, MultiPolygon)");
        if (!g.contains("coordinates")) return bad(where, "a geometry without coordinates");
        if (auto s = conv.walk(g["coordinates"], *depth, where); !s) return s.error();
        J kept;
        kept["type"] = "Feature";
        if (f.contains("id")) kept["id"] = f["id"];
        kept["geometry"] = {{"type", type}, {"coordinates", std::move(g["coordinates"])}};
        kept["properties"] = f.contains("properties") && f["properties"].is_object() ? f["properties"] : J::object();
        features.push_back(std::move(kept));
    }
    out["features"] = std::move(features);
    J meta;
    meta["space"] = "projected";
    meta["crs"] = modelCrs.isLocal() ? J() : J(modelCrs.id());
    meta["read"] = read;
    if (!note.empty()) meta["note"] = note;
    meta["positions"] = conv.positions;
    out["geoslice"] = std::move(meta);
    return out;
}

Result<J> loadContextLayer(const std::string& path, const Crs& modelCrs, const Aabb& bounds) {
    auto bytes = readFile(path, kMaxContextBytes);
    if (!bytes) return bytes.error();
    return parseContextLayer(bytes.value(), path, modelCrs, bounds);
}

}  // namespace geoslice::api
