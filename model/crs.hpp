// Coordinate reference systems: CGCS2000 (EPSG:4490) and its Gauss-Kruger projections,
// through GeographicLib (ellipsoid a = 6378137 m, 1/f = 298.257222101, k0 = 1).
//
//   EPSG:4513-4533  3-degree zones 25-45, zone number in the false easting (zone*1e6+500000 m)
//   EPSG:4534-4554  3-degree zones, central meridian 75..135 E, false easting 500000 m
//   EPSG:4491-4501  6-degree zones 13-23, zone number in the false easting
//   EPSG:4502-4512  6-degree zones, central meridian 75..135 E, false easting 500000 m
//
// Axis order: every geoslice API uses (easting, northing) for projected CRSs and
// (lon, lat) in degrees for geographic ones, whatever EPSG's own axis order is
// (EPSG lists northing first for these projected CRSs, and lat first for 4490).
#pragma once

#include <string>
#include <string_view>

#include <glm/glm.hpp>

#include "model/result.hpp"

namespace geoslice {

class Crs {
public:
    enum class Kind { Local, Geographic, GaussKruger };

    Crs() = default;                 // local: no georeference
    static Crs local() { return Crs(); }
    static Result<Crs> fromEpsg(int code);
    // "EPSG:4523", "epsg:4523", "4523", "local" or "" (local). Errors name the text.
    static Result<Crs> parse(std::string_view text);
    // The Gauss-Kruger zone CRS whose central meridian is nearest `lonDeg`.
    // zoneWidthDeg is 3 or 6; zoneInEasting selects 4513.. / 4491.. over 4534.. / 4502..
    static Result<Crs> gaussKrugerForLon(double lonDeg, int zoneWidthDeg, bool zoneInEasting);

    Kind kind() const { return kind_; }
    bool isLocal() const { return kind_ == Kind::Local; }
    bool isGeographic() const { return kind_ == Kind::Geographic; }
    bool isProjected() const { return kind_ == Kind::GaussKruger; }
    int epsg() const { return epsg_; }           // 0 when local
    std::string id() const;                      // "EPSG:4523" or "local"
    std::string name() const;                    // "CGCS2000 / 3-degree Gauss-Kruger zone 35"
    int zone() const { return zone_; }           // Gauss-Kruger zone number, 0 otherwise
    int zoneWidthDeg() const { return width_; }  // 3 or 6, 0 otherwise
    double centralMeridianDeg() const { return lon0_; }
    double falseEastingM() const { return fe_; }
    bool zoneInEasting() const { return zoneInEasting_; }

    // Projected CRS only. Degrees and metres; heights are ellipsoidal and pass through.
    // Errors: not projected, non-finite input, latitude beyond +-90.
    Result<glm::dvec2> toLonLat(double eastingM, double northingM) const;
    Result<glm::dvec2> fromLonLat(double lonDeg, double latDeg) const;

    bool operator==(const Crs& o) const { return epsg_ == o.epsg_; }

private:
    Kind kind_ = Kind::Local;
    int epsg_ = 0;
    int zone_ = 0;
    int width_ = 0;
    double lon0_ = 0.0;
    double fe_ = 0.0;
    bool zoneInEasting_ = false;
};

// Converts one point (x y z in the `from` CRS's API axis order) to `to`. Both CRSs must be
// CGCS2000-based (or both local with from == to); z passes through unchanged.
Result<glm::dvec3> convertPoint(const Crs& from, const Crs& to, const glm::dvec3& p);

}  // namespace geoslice
