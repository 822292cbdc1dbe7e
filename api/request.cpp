#include "api/request.hpp"

#include <cctype>
#include <cmath>

#include "model/json_text.hpp"
#include "view/view_limits.hpp"

namespace geoslice::api {

Result<Params> paramsFromQuery(const std::multimap<std::string, std::string>& query) {
    Params p;
    for (const auto& [k, v] : query) {
        auto [it, fresh] = p.emplace(k, v);
        if (!fresh && k == "plane")
            it->second += ";" + v;
        else if (!fresh)
            return makeError(ErrorCode::InvalidArgument, "parameter '" + k + "' is given more than once");
    }
    return p;
}

Result<Params> paramsFromJson(const nlohmann::json& j, const std::string& what) {
    if (!j.is_object()) return makeError(ErrorCode::InvalidArgument, what + " must be a JSON object");
    Params p;
    for (const auto& [k, v] : j.items()) {
        if (v.is_string())
            p[k] = v.get<std::string>();
        else if (v.is_number()) {
            const double d = v.get<double>();
            if (!std::isfinite(d)) return makeError(ErrorCode::InvalidArgument, what + ": '" + k + "' is not finite");
            p[k] = v.is_number_float() ? formatNumber(d) : jsonText(v);
        } else if (v.is_array()) {
            // [n, n, ...] -> "n,n,..."; [[n, ...], [n, ...]] (planes) -> "n,...;n,...".
            std::string s;
            for (std::size_t i = 0; i < v.size(); ++i) {
                const auto& x = v[i];
                const bool nested = x.is_array() && v[0].is_array();
                if (!x.is_number() && !nested)
                    return makeError(ErrorCode::InvalidArgument,
                                     what + ": '" + k + "' must be an array of numbers or of arrays of numbers");
                if (i) s += nested ? ';' : ',';
                if (!nested) {
                    s += formatNumber(x.get<double>());
                    continue;
                }
                for (std::size_t c = 0; c < x.size(); ++c) {
                    if (!x[c].is_number())
                        return makeError(ErrorCode::InvalidArgument,
                                         what + ": '" + k + "' must be an array of numbers or of arrays of numbers");
                    s += (c ? "," : "") + formatNumber(x[c].get<double>());
                }
            }
            p[k] = s;
        } else if (v.is_boolean()) {
            p[k] = v.get<bool>() ? "true" : "false";
        } else {
            return makeError(ErrorCode::InvalidArgument, what + ": '" + k + "' must be a string, number or array");
        }
    }
    return p;
}

std::string mediaType(std::string_view contentType) {
    std::string type(contentType.substr(0, contentType.find(';')));
    while (!type.empty() && type.back() == ' ') type.pop_back();
    for (char& c : type) c = char(std::tolower(static_cast<unsigned char>(c)));
    return type;
}

bool isJsonMediaType(std::string_view type) {
    return type == "application/json" || (type.size() > 5 && type.compare(type.size() - 5, 5, "+json") == 0);
}

Result<int> parseQuality(const Params& params) {
    if (const auto q = param(params, "quality")) {
        auto v = parseInteger("quality", *q, 1, 100);
        if (!v) return v.error();
        return int(v.value());
    }
    return 0;
}

Result<VectorFrame> parseVectorSpace(const Params& params, bool georeferenced) {
    const auto space = param(params, "space");
    if (!space) return georeferenced ? VectorFrame::LonLat : VectorFrame::Plane;
    if (*space == "world") return VectorFrame::LonLat;
    if (*space == "projected") return VectorFrame::Projected;
    if (*space == "plane") return VectorFrame::Plane;
    return makeError(ErrorCode::InvalidArgument,
                     "parameter 'space': '" + std::string(*space) + "' is not 'world', 'projected' or 'plane'");
}

Result<VectorFrame> parseDxfSpace(const Params& params) {
    const auto space = param(params, "space");
    if (!space || *space == "plane") return VectorFrame::Plane;
    if (*space == "projected") return VectorFrame::Projected;
    return makeError(ErrorCode::InvalidArgument, "parameter 'space': '" + std::string(*space) +
                                                     "' is not 'plane' or 'projected' (DXF has no lon/lat form)");
}

Result<TileAddress> parseTileAddress(std::string_view z, std::string_view x, std::string_view y) {
    auto zv = parseInteger("z", z, 0, 30);
    auto xv = parseInteger("x", x, -(1LL << 40), 1LL << 40);
    auto yv = parseInteger("y", y, -(1LL << 40), 1LL << 40);
    if (!zv || !xv || !yv) return makeError(ErrorCode::NotFound, "tile coordinates are out of range");
    return TileAddress{int(zv.value()), xv.value(), yv.value()};
}

Result<PixelXY> parseQueryPixel(const Params& params) {
    const auto px = param(params, "px");
    const auto py = param(params, "py");
    if (!px || !py) return makeError(ErrorCode::InvalidArgument, "query: give the pixel as 'px' and 'py'");
    auto x = parseInteger("px", *px, -(1LL << 40), 1LL << 40);
    if (!x) return x.error();
    auto y = parseInteger("py", *py, -(1LL << 40), 1LL << 40);
    if (!y) return y.error();
    return PixelXY{x.value(), y.value()};
}

Result<Params> parseSectionBody(std::string_view body) {
    const nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
    if (j.is_discarded()) return makeError(ErrorCode::ParseError, "the body is not valid JSON");
    return paramsFromJson(j, "the section definition");
}

Result<QueryBatch> parseQueryBatch(std::string_view body, const std::vector<std::string_view>& viewNames) {
    nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return makeError(ErrorCode::ParseError, "the body is not a JSON object");
    for (const auto& [k, v] : j.items())
        if (k != "view" && k != "pixels")
            return makeError(ErrorCode::InvalidArgument,
                             "unknown field '" + k.substr(0, 64) + "' in the body; known: view, pixels");
    if (!j.contains("view") || !j.contains("pixels") || !j["pixels"].is_array())
        return makeError(ErrorCode::InvalidArgument,
                         "the body needs 'view' (an object of view parameters) and 'pixels' ([[px, py], ...])");
    if (j["pixels"].size() > kMaxBatchPixels)
        return makeError(ErrorCode::OutOfRange, "field 'pixels': at most " + std::to_string(kMaxBatchPixels) +
                                                    " pixels per batch, got " + std::to_string(j["pixels"].size()));
    auto view = paramsFromJson(j["view"], "'view'");
    if (!view) return view.error();
    if (auto s = checkKnownParams(view.value(), viewNames); !s)
        return makeError(s.error().code, "field 'view': " + s.error().message);
    QueryBatch batch;
    batch.view = std::move(view.value());
    batch.pixels = std::move(j["pixels"]);
    return batch;
}

Result<std::vector<PixelXY>> parseBatchPixels(const nlohmann::json& pixels) {
    std::vector<PixelXY> out;
    out.reserve(pixels.size());
    for (const auto& p : pixels) {
        if (!p.is_array() || p.size() != 2 || !p[0].is_number_integer() || !p[1].is_number_integer())
            return makeError(ErrorCode::InvalidArgument, "field 'pixels': pixels[" + std::to_string(out.size()) +
                                                             "] is not [px, py] with whole numbers");
        out.push_back(PixelXY{p[0].get<long long>(), p[1].get<long long>()});
    }
    return out;
}

}  // namespace geoslice::api
