// A model's context layer: what a mine draws on its plan besides the geology (mining leases,
// workings, roads, faults drawn by hand), from the <stem>.context.geojson sidecar beside the
// model file, served in the model's CRS for the plan map (GET /v1/models/{id}/context.geojson).
//
// The file is GeoJSON (RFC 7946): a FeatureCollection of Point, MultiPoint, LineString,
// MultiLineString, Polygon and MultiPolygon features with any properties (`name` labels them
// on the plan). Coordinates are WGS 84 lon/lat as RFC 7946 says, unless the collection has the
// `crs` member GDAL and QGIS write for other CRSs ({"type": "name", "properties": {"name":
// "urn:ogc:def:crs:EPSG::4523"}}, also "EPSG:4523", any text Crs::parse reads): then they are
// in that CRS. Either way they are converted to the model's CRS through PROJ (one operation for the model's area, as
// the model's own conversions; a ballpark one, such as WGS 84 to CGCS2000 with no published shift, is used and said in
// `geoslice.note`). For a model without a CRS the coordinates are taken as the model's own and a `crs` member is an
// error.
//
// Limits: kMaxContextBytes of file, kMaxContextPositions positions. Errors name the file, the
// feature and what is wrong. Pure functions, any thread.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "model/crs/crs.hpp"
#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice::api {

constexpr std::size_t kMaxContextBytes = std::size_t(16) << 20;
constexpr std::size_t kMaxContextPositions = 1000000;

// The <stem>.context.geojson beside a model file, or "" when there is none.
std::string contextSidecarFor(const std::string& modelPath);

// `text` (named `source` in errors) as a FeatureCollection in the model's CRS: every feature
// kept with its properties, coordinates converted, a `geoslice` member saying the CRS, how the
// coordinates were read and any note. `bounds`: the model's world bounds (the area of the
// conversion).
Result<nlohmann::ordered_json> parseContextLayer(std::string_view text, const std::string& source, const Crs& modelCrs,
                                                 const Aabb& bounds);
// The sidecar at `path`, read and parsed.
Result<nlohmann::ordered_json> loadContextLayer(const std::string& path, const Crs& modelCrs, const Aabb& bounds);

}  // namespace geoslice::api
