// Virtual boreholes: the intervals under a map point, from the model's rays. Any thread.
#pragma once

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "api/params.hpp"

namespace geoslice::api {

// A virtual borehole: `x`, `y` (world metres; or `lon`, `lat` degrees) -> the intervals
// with from/to depth below the collar and elevation, record and attributes, and the open
// surfaces crossed. Errors name the parameter; a point outside the model is OutOfRange;
// DeadlineExceeded when the model's rays are not built within `wait`.
Result<nlohmann::ordered_json> boreholeAt(const CatalogModel& model, const Params& params, const RayWait& wait = {});

}  // namespace geoslice::api
