#include "api/borehole.hpp"

#include <cmath>

#include "api/pixel_query.hpp"

namespace geoslice::api {

Result<nlohmann::ordered_json> boreholeAt(const CatalogModel& model, const Params& params, const RayWait& wait) {
    double x = 0.0, y = 0.0;
    if (param(params, "lon") || param(params, "lat")) {
        const auto lon = param(params, "lon"), lat = param(params, "lat");
        if (!lon || !lat) return makeError(ErrorCode::InvalidArgument, "borehole: give both 'lon' and 'lat'");
        auto lo = parseNumber("lon", *lon);
        if (!lo) return lo.error();
        auto la = parseNumber("lat", *lat);
        if (!la) return la.error();
        if (!model.model.crs.isProjected())
            return makeError(ErrorCode::InvalidArgument,
                             "borehole: lon/lat needs a model in a projected CRS; "
                             "this model is " +
                                 model.model.crs.id());
        auto xy = model.model.crs.fromLonLat(lo.value(), la.value());
        if (!xy) return xy.error();
        x = xy.value().x;
        y = xy.value().y;
    } else {
        const auto xs = param(params, "x"), ys = param(params, "y");
        if (!xs || !ys) return makeError(ErrorCode::InvalidArgument, "borehole: give 'x' and 'y' (or 'lon' and 'lat')");
        auto xv = parseNumber("x", *xs);
        if (!xv) return xv.error();
        auto yv = parseNumber("y", *ys);
        if (!yv) return yv.error();
        x = xv.value();
        y = yv.value();
    }
    auto rays = model.rays->wait(wait.deadline, wait.cancel);
    if (!rays) return rays.error();
    auto hole = rays.value().tracer->traceVertical(x, y);
    if (!hole) return hole.error();
    const Borehole& b = hole.value();
    nlohmann::ordered_json out;
    out["model"] = model.id;
    out["version"] = model.version;
    out.update(boreholeJson(model.model, b));
    // The collar in every coordinate system too, like every point the API reports.
    out["collarCoordinates"] =
        std::isnan(b.collarDepth) ? nlohmann::ordered_json(nullptr) : worldPointJson(model, b.collar);
    return out;
}

}  // namespace geoslice::api
