// What arrives with a request, parsed without HTTP: the query string as Params, JSON bodies
// (a section definition, a batch of pixel queries), tile addresses, the vector and image
// options, the pixel of a query. server/ hands these the decoded pieces of a request and
// turns their errors into statuses; every error names the parameter or field and the bad
// text. Pure functions, any thread. No HTTP or GL headers here.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/params.hpp"
#include "model/result.hpp"
#include "section/fill/vector_export.hpp"

namespace geoslice::api {

// Decoded query parameters, in the order given -> Params. A parameter given twice is an
// error (which one wins would otherwise depend on the parser), except `plane`, whose
// values are joined with ';' in the order given (a cut-out's planes, api/cut.hpp).
Result<Params> paramsFromQuery(const std::multimap<std::string, std::string>& query);

// A JSON object's fields -> Params: strings as they are, numbers in their shortest form,
// booleans as true/false, [n, ...] as "n,..." and [[n, ...], ...] (planes) as "n,...;n,...".
// `what` names the object in errors ("'view'", "the section definition").
Result<Params> paramsFromJson(const nlohmann::json& j, const std::string& what);

// The media type of a Content-Type header value: parameters dropped, lower case.
std::string mediaType(std::string_view contentType);
// application/json or any +json type (RFC 6839).
bool isJsonMediaType(std::string_view mediaType);

// `quality` (JPEG/WebP, 1..100); 0 when absent (the encoder's default).
Result<int> parseQuality(const Params& params);

// `space` of a GeoJSON section (section/fill/vector_export.hpp): "world" (WGS 84 lon/lat,
// RFC 7946; the default for a model with a CRS), "projected" (the model's CRS) or "plane"
// (section u/v metres; the default for a model without CRS). SVG ignores it.
Result<VectorFrame> parseVectorSpace(const Params& params, bool georeferenced);
// `space` of a DXF section: "plane" (default: the section as drawn, with hatches and labels)
// or "projected" (3D polylines in the model's CRS); section/fill/dxf_export.hpp.
Result<VectorFrame> parseDxfSpace(const Params& params);

// A tile's address as it appears in its path: z in 0..30, x and y within +-2^40 (the
// tile grid then says whether the tile exists). Error: NotFound.
struct TileAddress {
    int z = 0;
    long long x = 0, y = 0;
};
Result<TileAddress> parseTileAddress(std::string_view z, std::string_view x, std::string_view y);

// The pixel of GET /query: `px` and `py`, whole numbers within +-2^40 (the view says
// whether the pixel is inside it).
struct PixelXY {
    long long x = 0, y = 0;
};
Result<PixelXY> parseQueryPixel(const Params& params);

// POST /sections: the body is a JSON object of section parameters.
Result<Params> parseSectionBody(std::string_view body);

// POST /query: {"view": {view parameters}, "pixels": [[px, py], ...]}, at most
// kMaxBatchPixels pixels (view/view_limits.hpp). `view` is checked against `viewNames`;
// the pixels are read by parseBatchPixels once the view itself is known to be good, so a
// bad view is reported before a bad pixel.
struct QueryBatch {
    Params view;
    nlohmann::json pixels;  // an array, at most kMaxBatchPixels long
};
Result<QueryBatch> parseQueryBatch(std::string_view body, const std::vector<std::string_view>& viewNames);
Result<std::vector<PixelXY>> parseBatchPixels(const nlohmann::json& pixels);

}  // namespace geoslice::api
