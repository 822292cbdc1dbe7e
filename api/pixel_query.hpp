// Pixel queries: what lies under a pixel of a profile view, tile or perspective view (from
// the view's cached ID buffer or the exact oracle), and the answer as JSON with the world point
// in every coordinate system of the model's CRS. Pixel frames as in api/view.hpp. Any thread.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/holes.hpp"
#include "api/request.hpp"
#include "api/view.hpp"

namespace geoslice::api {

// A pixel query: the record at the centre of pixel (px, py) of the plan's view, the world
// point, and its place in the section. From the cached ID buffer of the identical view
// when `cached` is given, otherwise from the exact oracle at the pixel centre; the two
// agree (tests/server). Errors: OutOfRange for a pixel outside the image.
struct QueryAnswer {
    long long px = 0, py = 0;
    RecordId record = kNoRecord;
    glm::dvec3 world{0.0};
    glm::dvec2 section{0.0};     // (u, v) plane metres, or (chainage, elevation) for a line
    double distanceAlong = 0.0;  // metres: from the image's left edge (plane), or chainage (line)
    bool line = false;
    bool perspective = false;  // world = the first visible point on the ray (NaN: none); distanceAlong = from the eye
    bool fromIdBuffer = false;
    // The block cell (blockCellAt), from the cells buffer when cached; perspective views: on a
    // cut face only (where the image colours by cell).
    std::size_t cell = BlockModel::kNoCell;
    // Profile views: the drawn drillhole within kHoleQueryPixels of the pixel centre, if any
    // (api/holes.hpp), answered next to the model's record ("drillhole").
    std::optional<HoleHit> hole;
};
// InvalidArgument naming the parameter ('plane', 'planes' or 'elevation') when the cut of a
// perspective view keeps no part of the model's bounds (api/cut.hpp).
Status checkPerspectiveCut(const CatalogModel& model, const ViewPlan& plan);
// The records of hide= / isolate= (ViewPlan::shown) are records of the model's bodies or
// surfaces; InvalidArgument naming the first that is not, and the model's records.
Status checkShownUnits(const CatalogModel& model, const ViewPlan& plan);
// The ray through a pixel of a perspective view: pixelRay of view/camera.hpp.
// A query that needs the model's rays (perspective, or no cached ID buffer) waits for them
// (CatalogModel::rays) as `wait` allows: DeadlineExceeded when they are not built in time.
Result<QueryAnswer> answerPixel(const CatalogModel& model, const ViewPlan& plan, long long px, long long py,
                                const ViewImage* cached, const RayWait& wait = {});
// The answer as JSON (appended to `out`): record and attributes, body, world point,
// distance along the section, CGCS2000 projected (easting, northing, zone) and geodetic
// (lon, lat, height) coordinates with their axis order named.
void writeQueryAnswer(const CatalogModel& model, const QueryAnswer& answer, std::string& out);
// answerPixel + writeQueryAnswer.
Result<std::string> queryPixel(const CatalogModel& model, const ViewPlan& plan, long long px, long long py,
                               const ViewImage* cached, const RayWait& wait = {});
// A batch of pixel queries as one JSON document {"results": [answer, ...]}, in the order
// given: the one writer of batch answers (the POST query route and `geoslice query`).
// Stops at the first pixel that fails, with an error naming it by `nameOf(i)`, or when the
// answer passes kMaxBatchAnswerBytes (OutOfRange naming `batchName`); `cancel` (may be
// null) is checked every 64 pixels.
Result<std::string> answerBatch(const CatalogModel& model, const ViewPlan& plan, const std::vector<PixelXY>& pixels,
                                const ViewImage* cached, const RayWait& wait, const std::atomic<bool>* cancel,
                                const std::string& batchName, const std::function<std::string(std::size_t)>& nameOf);

// The JSON of a world point: {x, y, z, crs, axes, projected: {...}, geodetic: {...},
// wgs84: {...} or wgs84Note} (README "Query answer coordinates").
nlohmann::ordered_json worldPointJson(const CatalogModel& model, const glm::dvec3& world);

}  // namespace geoslice::api
