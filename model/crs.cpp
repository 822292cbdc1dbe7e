// CGCS2000 and its Gauss-Kruger projections through GeographicLib::TransverseMercator
// (Karney 2011, "Transverse Mercator with an accuracy of a few nanometers", J. Geodesy
// 85(8): Krüger's series to order 6, accurate to 5 nm within 3900 km of the central
// meridian). Every EPSG parameter below was checked against `projinfo EPSG:NNNN`
// (PROJ 9.1.1): +proj=tmerc +lat_0=0 +k=1 +y_0=0 on the CGCS2000 ellipsoid.
#include "model/crs.hpp"

#include <GeographicLib/Ellipsoid.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/TransverseMercator.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>

namespace geoslice {
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

constexpr int kGeographicEpsg = 4490;
constexpr int kGk6ZoneFirstEpsg = 4491;  // 6-degree, zones 13..23, zone in easting
constexpr int kGk6CmFirstEpsg = 4502;    // 6-degree, CM 75..135 E, FE 500 km
constexpr int kGk3ZoneFirstEpsg = 4513;  // 3-degree, zones 25..45, zone in easting
constexpr int kGk3CmFirstEpsg = 4534;    // 3-degree, CM 75..135 E, FE 500 km
constexpr int kGk3CmLastEpsg = 4554;
constexpr int kGk6Zones = 11;  // 13..23
constexpr int kGk3Zones = 21;  // 25..45
constexpr int kGk6FirstZone = 13;
constexpr int kGk3FirstZone = 25;
constexpr double kFalseEastingM = 500000.0;
constexpr double kZoneEastingM = 1e6;  // zone number * 1e6 m is added to the easting

const GeographicLib::TransverseMercator& projection() {
    // Thread-safe: a function-local static, and Forward/Reverse are const.
    static const GeographicLib::TransverseMercator tm(kSemiMajorM, kFlattening, kScaleK0);
    return tm;
}

double quarterMeridianM() {
    static const double q = GeographicLib::Ellipsoid(kSemiMajorM, kFlattening).QuarterMeridian();
    return q;
}

// Shortest round-trip decimal form of a double, for error messages.
std::string num(double v) {
    char buf[64];
    // Plain digits for coordinate-sized values (500000 rather than 5e+05).
    const bool plain = std::fabs(v) < 1e16 && (v == 0.0 || std::fabs(v) >= 1e-4);
    auto [end, ec] = plain ? std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed)
                           : std::to_chars(buf, buf + sizeof buf, v);
    if (ec != std::errc()) return "?";
    return std::string(buf, end);
}

std::string_view trim(std::string_view s) {
    const char* ws = " \t\r\n\f\v";
    const auto b = s.find_first_not_of(ws);
    if (b == std::string_view::npos) return {};
    const auto e = s.find_last_not_of(ws);
    return s.substr(b, e - b + 1);
}

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
        if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
        if (x != y) return false;
    }
    return true;
}

Error notProjected(const Crs& crs, const char* what) {
    return makeError(ErrorCode::InvalidArgument,
                     std::string(what) + " needs a Gauss-Kruger CRS, got " + crs.id());
}

}  // namespace

Result<Crs> Crs::fromEpsg(int code) {
    Crs c;
    c.epsg_ = code;
    if (code == kGeographicEpsg) {
        c.kind_ = Kind::Geographic;
        return c;
    }
    if (code >= kGk6ZoneFirstEpsg && code < kGk6ZoneFirstEpsg + kGk6Zones) {
        c.width_ = 6;
        c.zone_ = kGk6FirstZone + (code - kGk6ZoneFirstEpsg);
        c.zoneInEasting_ = true;
    } else if (code >= kGk6CmFirstEpsg && code < kGk6CmFirstEpsg + kGk6Zones) {
        c.width_ = 6;
        c.zone_ = kGk6FirstZone + (code - kGk6CmFirstEpsg);
    } else if (code >= kGk3ZoneFirstEpsg && code < kGk3ZoneFirstEpsg + kGk3Zones) {
        c.width_ = 3;
        c.zone_ = kGk3FirstZone + (code - kGk3ZoneFirstEpsg);
        c.zoneInEasting_ = true;
    } else if (code >= kGk3CmFirstEpsg && code <= kGk3CmLastEpsg) {
        c.width_ = 3;
        c.zone_ = kGk3FirstZone + (code - kGk3CmFirstEpsg);
    } else {
        return makeError(ErrorCode::Unsupported,
                         "EPSG:" + std::to_string(code) +
                             " is not a supported CRS (supported: EPSG:4490 CGCS2000 and its "
                             "Gauss-Kruger projections EPSG:4491-4554)");
    }
    c.kind_ = Kind::GaussKruger;
    // 6-degree zone n spans [6(n-1), 6n] E; 3-degree zone n is centred on 3n E.
    c.lon0_ = c.width_ == 6 ? c.zone_ * 6.0 - 3.0 : c.zone_ * 3.0;
    c.fe_ = kFalseEastingM + (c.zoneInEasting_ ? c.zone_ * kZoneEastingM : 0.0);
    return c;
}

Result<Crs> Crs::parse(std::string_view text) {
    const std::string_view t = trim(text);
    if (t.empty() || equalsIgnoreCase(t, "local")) return Crs::local();
    std::string_view digits = t;
    if (t.size() >= 5 && equalsIgnoreCase(t.substr(0, 5), "epsg:")) digits = t.substr(5);
    int code = 0;
    const char* first = digits.data();
    const char* last = digits.data() + digits.size();
    auto [ptr, ec] = std::from_chars(first, last, code);
    if (digits.empty() || ec != std::errc() || ptr != last || code <= 0) {
        return makeError(ErrorCode::InvalidArgument,
                         "cannot parse CRS \"" + std::string(text) +
                             "\": expected \"EPSG:<code>\", \"<code>\", \"local\" or empty");
    }
    return fromEpsg(code);
}

Result<Crs> Crs::gaussKrugerForLon(double lonDeg, int zoneWidthDeg, bool zoneInEasting) {
    if (!std::isfinite(lonDeg)) {
        return makeError(ErrorCode::InvalidArgument, "Gauss-Kruger zone for longitude " +
                                                         num(lonDeg) + ": not a finite number");
    }
    if (zoneWidthDeg != 3 && zoneWidthDeg != 6) {
        return makeError(
            ErrorCode::InvalidArgument,
            "Gauss-Kruger zone width " + std::to_string(zoneWidthDeg) + " degrees: must be 3 or 6");
    }
    const double lon = std::remainder(lonDeg, 360.0);  // [-180, 180]
    int index = 0;  // 0-based within the EPSG family, counted from CM 75 E
    if (zoneWidthDeg == 3) {
        index = static_cast<int>(std::lround(lon / 3.0)) - kGk3FirstZone;
    } else {
        // Nearest central meridian 6n-3: zone n = floor(lon/6) + 1 (the zone containing it).
        index = static_cast<int>(std::floor(lon / 6.0)) + 1 - kGk6FirstZone;
    }
    // Points just west of 75 E or east of 135 E (China reaches 73.5 E) take the edge zone,
    // up to one zone width from its central meridian.
    const int count = zoneWidthDeg == 3 ? kGk3Zones : kGk6Zones;
    index = std::clamp(index, 0, count - 1);
    const double cm =
        zoneWidthDeg == 3 ? (kGk3FirstZone + index) * 3.0 : (kGk6FirstZone + index) * 6.0 - 3.0;
    if (std::fabs(lon - cm) > zoneWidthDeg) {
        return makeError(ErrorCode::OutOfRange,
                         "longitude " + num(lonDeg) + " degrees has no CGCS2000 " +
                             std::to_string(zoneWidthDeg) +
                             "-degree Gauss-Kruger zone (central meridians 75..135 E)");
    }
    int first = 0;
    if (zoneWidthDeg == 3)
        first = zoneInEasting ? kGk3ZoneFirstEpsg : kGk3CmFirstEpsg;
    else
        first = zoneInEasting ? kGk6ZoneFirstEpsg : kGk6CmFirstEpsg;
    return fromEpsg(first + index);
}

std::string Crs::id() const {
    if (kind_ == Kind::Local) return "local";
    return "EPSG:" + std::to_string(epsg_);
}

std::string Crs::name() const {
    switch (kind_) {
        case Kind::Local:
            return "local (no georeference)";
        case Kind::Geographic:
            return "China Geodetic Coordinate System 2000";
        case Kind::GaussKruger:
            break;
    }
    // EPSG's names, as `projinfo` prints them.
    std::string n = width_ == 3 ? "CGCS2000 / 3-degree Gauss-Kruger " : "CGCS2000 / Gauss-Kruger ";
    if (zoneInEasting_) return n + "zone " + std::to_string(zone_);
    return n + "CM " + std::to_string(static_cast<int>(lon0_)) + "E";
}

Result<glm::dvec2> Crs::toLonLat(double eastingM, double northingM) const {
    if (!isProjected()) return notProjected(*this, "toLonLat");
    // Built only on failure: the success path allocates nothing.
    const auto where = [&] {
        return id() + " easting " + num(eastingM) + " m, northing " + num(northingM) + " m";
    };
    if (!std::isfinite(eastingM) || !std::isfinite(northingM)) {
        return makeError(ErrorCode::InvalidArgument, where() + ": not a finite number");
    }
    const double x = eastingM - fe_;
    if (std::fabs(x) > kMaxCentralMeridianDistanceM) {
        return makeError(ErrorCode::OutOfRange, where() + ": " + num(std::fabs(x) / 1e3) +
                                                    " km from the central meridian " + num(lon0_) +
                                                    " E (false easting " + num(fe_) +
                                                    " m), beyond the 3900 km limit");
    }
    if (std::fabs(northingM) > quarterMeridianM()) {
        return makeError(ErrorCode::OutOfRange,
                         where() + ": northing beyond the pole (quarter meridian " +
                             num(quarterMeridianM()) + " m)");
    }
    double lat = 0.0, lon = 0.0;
    projection().Reverse(lon0_, x, northingM, lat, lon);
    if (!std::isfinite(lat) || !std::isfinite(lon)) {
        return makeError(ErrorCode::Internal, where() + ": inverse projection failed");
    }
    return glm::dvec2(lon, lat);
}

Result<glm::dvec2> Crs::fromLonLat(double lonDeg, double latDeg) const {
    if (!isProjected()) return notProjected(*this, "fromLonLat");
    const auto where = [&] {
        return id() + " from lon " + num(lonDeg) + ", lat " + num(latDeg) + " degrees";
    };
    if (!std::isfinite(lonDeg) || !std::isfinite(latDeg)) {
        return makeError(ErrorCode::InvalidArgument, where() + ": not a finite number");
    }
    if (std::fabs(latDeg) > 90.0) {
        return makeError(ErrorCode::OutOfRange, where() + ": latitude beyond +-90 degrees");
    }
    const double dlon = GeographicLib::Math::AngDiff(lon0_, lonDeg);  // [-180, 180]
    if (std::fabs(dlon) > kMaxLonOffsetDeg) {
        return makeError(ErrorCode::OutOfRange, where() + ": " + num(std::fabs(dlon)) +
                                                    " degrees from the central meridian " +
                                                    num(lon0_) + " E");
    }
    double x = 0.0, y = 0.0;
    projection().Forward(lon0_, latDeg, lonDeg, x, y);
    if (!std::isfinite(x) || !std::isfinite(y) || std::fabs(x) > kMaxCentralMeridianDistanceM) {
        return makeError(ErrorCode::OutOfRange,
                         where() + ": more than 3900 km from the central meridian " + num(lon0_) +
                             " E, where the projection is not accurate");
    }
    return glm::dvec2(x + fe_, y);
}

Result<glm::dvec3> convertPoint(const Crs& from, const Crs& to, const glm::dvec3& p) {
    if (from.isLocal() || to.isLocal()) {
        if (from.isLocal() && to.isLocal()) return p;
        return makeError(ErrorCode::InvalidArgument, "cannot convert between " + from.id() +
                                                         " and " + to.id() +
                                                         ": a local CRS has no georeference");
    }
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        return makeError(ErrorCode::InvalidArgument, "convert " + from.id() + " -> " + to.id() +
                                                         ": point (" + num(p.x) + ", " + num(p.y) +
                                                         ", " + num(p.z) + ") is not finite");
    }
    if (from == to) {
        if (from.isGeographic() && std::fabs(p.y) > 90.0) {
            return makeError(ErrorCode::OutOfRange, "convert " + from.id() + " -> " + to.id() +
                                                        ": latitude " + num(p.y) +
                                                        " beyond +-90 degrees");
        }
        return p;
    }
    // Through geographic lon/lat (degrees); heights are ellipsoidal and unchanged.
    glm::dvec2 lonLat(p.x, p.y);
    if (from.isProjected()) {
        auto ll = from.toLonLat(p.x, p.y);
        if (!ll) return ll.error();
        lonLat = ll.value();
    } else if (std::fabs(p.y) > 90.0) {
        return makeError(ErrorCode::OutOfRange, "convert " + from.id() + " -> " + to.id() +
                                                    ": latitude " + num(p.y) +
                                                    " beyond +-90 degrees");
    }
    if (to.isGeographic()) return glm::dvec3(lonLat, p.z);
    auto en = to.fromLonLat(lonLat.x, lonLat.y);
    if (!en) {
        Error e = en.error();
        if (from.isProjected())
            e.message = "from " + from.id() + " (" + num(p.x) + ", " + num(p.y) + "): " + e.message;
        return e;
    }
    return glm::dvec3(en.value(), p.z);
}

}  // namespace geoslice
