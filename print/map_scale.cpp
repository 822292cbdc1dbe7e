#include "print/map_scale.hpp"

#include <cmath>

#include "print/round_numbers.hpp"
#include "view/view_limits.hpp"

namespace geoslice::print {

Status checkScale(double denominator) {
    if (!std::isfinite(denominator) || denominator < kMinScale || denominator > kMaxScale)
        return makeError(ErrorCode::OutOfRange, limitNumber(denominator) +
                                                    " is not a scale denominator within 1..100000000 (scale=5000 "
                                                    "means 1:5,000)");
    return {};
}

double roundScaleAtLeast(double denominator) {
    return niceAtLeast(std::max(denominator, kMinScale), {1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 7.5});
}

std::string formatScale(double denominator) {
    const double whole = std::round(denominator);
    const bool isWhole = std::abs(denominator - whole) < 1e-9 * denominator;
    return "1:" + formatGrouped(isWhole ? whole : denominator, isWhole ? 0 : 3, 1000.0);
}

}  // namespace geoslice::print
