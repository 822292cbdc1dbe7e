// CGCS2000 and its Gauss-Kruger projections through GeographicLib::TransverseMercator
// (Karney 2011, "Transverse Mercator with an accuracy of a few nanometers", J. Geodesy
// 85(8): Krüger's series to order 6, accurate to 5 nm within 3900 km of the central
// meridian). Every EPSG parameter below was checked against `projinfo EPSG:NNNN`
// (PROJ 9.1.1): +proj=tmerc +lat_0=0 +k=1 +y_0=0 on the CGCS2000 ellipsoid.
#include <cmath>
#include <string>

#include <GeographicLib/Ellipsoid.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/TransverseMercator.hpp>

#include "model/crs/crs_proj.hpp"

namespace geoslice::crs_detail {
namespace {

// CGCS2000 ellipsoid (EPSG:1024): semi-major axis in metres and flattening.
constexpr double kSemiMajorM = 6378137.0;
constexpr double kFlattening = 1.0 / 298.257222101;
// Gauss-Kruger scale on the central meridian.
constexpr double kScaleK0 = 1.0;
// Beyond this distance from the central meridian (metres, ground) the order-6 Krüger
// series is no longer guaranteed to 5 nm, so both directions refuse such points.
constexpr double kMaxCentralMeridianDistanceM = 3900e3;
// Longitude offsets from the central meridian beyond this (degrees) are the far side of
// the globe: never a Gauss-Kruger point.
constexpr double kMaxLonOffsetDeg = 90.0;

const GeographicLib::TransverseMercator& projection() {
    // Thread-safe: a function-local static, and Forward/Reverse are const.
    static const GeographicLib::TransverseMercator tm(kSemiMajorM, kFlattening, kScaleK0);
    return tm;
}

double quarterMeridianM() {
    static const double q = GeographicLib::Ellipsoid(kSemiMajorM, kFlattening).QuarterMeridian();
    return q;
}

}  // namespace

// GeographicLib's Gauss-Kruger formulas (Krüger series to order 6, Karney 2011).
Result<glm::dvec2> gkToLonLat(const Crs& c, double eastingM, double northingM) {
    // Built only on failure: the success path allocates nothing.
    const auto where = [&] { return c.id() + " easting " + num(eastingM) + " m, northing " + num(northingM) + " m"; };
    if (!std::isfinite(eastingM) || !std::isfinite(northingM)) {
        return makeError(ErrorCode::InvalidArgument, where() + ": not a finite number");
    }
    const double x = eastingM - c.falseEastingM();
    if (std::fabs(x) > kMaxCentralMeridianDistanceM) {
        return makeError(ErrorCode::OutOfRange, where() + ": " + num(std::fabs(x) / 1e3) +
                                                    " km from the central meridian " + num(c.centralMeridianDeg()) +
                                                    " E (false easting " + num(c.falseEastingM()) +
                                                    " m), beyond the 3900 km limit");
    }
    if (std::fabs(northingM) > quarterMeridianM()) {
        return makeError(ErrorCode::OutOfRange,
                         where() + ": northing beyond the pole (quarter meridian " + num(quarterMeridianM()) + " m)");
    }
    double lat = 0.0, lon = 0.0;
    projection().Reverse(c.centralMeridianDeg(), x, northingM, lat, lon);
    if (!std::isfinite(lat) || !std::isfinite(lon)) {
        return makeError(ErrorCode::Internal, where() + ": inverse projection failed");
    }
    return glm::dvec2(lon, lat);
}

Result<glm::dvec2> gkFromLonLat(const Crs& c, double lonDeg, double latDeg) {
    const auto where = [&] { return c.id() + " from lon " + num(lonDeg) + ", lat " + num(latDeg) + " degrees"; };
    if (!std::isfinite(lonDeg) || !std::isfinite(latDeg)) {
        return makeError(ErrorCode::InvalidArgument, where() + ": not a finite number");
    }
    if (std::fabs(latDeg) > 90.0) {
        return makeError(ErrorCode::OutOfRange, where() + ": latitude beyond +-90 degrees");
    }
    const double dlon = GeographicLib::Math::AngDiff(c.centralMeridianDeg(), lonDeg);  // [-180, 180]
    if (std::fabs(dlon) > kMaxLonOffsetDeg) {
        return makeError(ErrorCode::OutOfRange, where() + ": " + num(std::fabs(dlon)) +
                                                    " degrees from the central meridian " +
                                                    num(c.centralMeridianDeg()) + " E");
    }
    double x = 0.0, y = 0.0;
    projection().Forward(c.centralMeridianDeg(), latDeg, lonDeg, x, y);
    if (!std::isfinite(x) || !std::isfinite(y) || std::fabs(x) > kMaxCentralMeridianDistanceM) {
        return makeError(ErrorCode::OutOfRange, where() + ": more than 3900 km from the central meridian " +
                                                    num(c.centralMeridianDeg()) +
                                                    " E, where the projection is not accurate");
    }
    return glm::dvec2(x + c.falseEastingM(), y);
}

}  // namespace geoslice::crs_detail
