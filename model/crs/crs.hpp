// Coordinate reference systems, through two backends:
//
//  - CGCS2000 (EPSG:4490) and its Gauss-Kruger projections, through GeographicLib
//    (ellipsoid a = 6378137 m, 1/f = 298.257222101, k0 = 1):
//      EPSG:4513-4533  3-degree zones 25-45, zone number in the false easting (zone*1e6+500000 m)
//      EPSG:4534-4554  3-degree zones, central meridian 75..135 E, false easting 500000 m
//      EPSG:4491-4501  6-degree zones 13-23, zone number in the false easting
//      EPSG:4502-4512  6-degree zones, central meridian 75..135 E, false easting 500000 m
//  - every other geographic or projected CRS in PROJ's EPSG database (LV03/LV95, UTM on
//    any datum, NAD27, GDA2020 MGA, ...), and CRSs given as WKT or by name, through PROJ
//    (libproj 9.1) with its local proj.db and grids only: network access is off in every
//    PROJ context geoslice makes (model/crs/proj_pool.hpp).
//
// Axis order: every geoslice API uses (easting, northing) for projected CRSs and
// (lon, lat) in degrees for geographic ones, whatever EPSG's own axis order is (EPSG lists
// northing first for the CGCS2000 Gauss-Kruger CRSs and lat first for 4490 and 4326; PROJ
// objects are normalised with proj_normalize_for_visualization). CRSs whose axes point
// west or south are refused.
//
// Units: projected coordinates are in the CRS's own linear unit (metres for almost all;
// feet for some, unitToMetre() says), so `geoslice coords` works like cs2cs for any CRS.
// A model's world coordinates are metres: checkModelCrs() refuses a CRS in other units for
// a model (geoslice does not rescale models).
//
// Thread-safety: a Crs is an immutable value, cheap to copy, usable from any thread.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <glm/glm.hpp>

#include "model/result.hpp"

namespace geoslice {

// An area in degrees of longitude and latitude. west > east when it crosses 180 degrees.
struct LonLatBox {
    double west = 0.0, south = 0.0, east = 0.0, north = 0.0;
    bool contains(double lonDeg, double latDeg) const;
};

struct ProjCrsInfo;  // model/crs/crs.cpp: what PROJ said about a CRS

class Crs {
public:
    // GaussKruger: CGCS2000 zones through GeographicLib. Projected: any other projected CRS,
    // through PROJ. Geographic: 4490 through GeographicLib, any other through PROJ.
    enum class Kind { Local, Geographic, GaussKruger, Projected };

    Crs() = default;  // local: no georeference
    static Crs local() { return Crs(); }
    // Any geographic (2D or 3D) or projected CRS of PROJ's EPSG database; compound CRSs
    // give their horizontal part. Errors name the code.
    static Result<Crs> fromEpsg(int code);
    // "EPSG:4523", "epsg:4523", "4523", "urn:ogc:def:crs:EPSG::2056",
    // "http://www.opengis.net/def/crs/EPSG/0/2056", a name PROJ knows ("CH1903 / LV03",
    // "NAD27 / UTM zone 11N"), WKT or PROJJSON; "local", "Default" (GOCAD's word for none)
    // or "" give local. A definition matching an EPSG CRS exactly becomes that EPSG CRS.
    // Errors name the text and say what PROJ said.
    static Result<Crs> parse(std::string_view text);
    // The Gauss-Kruger zone CRS whose central meridian is nearest `lonDeg`.
    // zoneWidthDeg is 3 or 6; zoneInEasting selects 4513.. / 4491.. over 4534.. / 4502..
    static Result<Crs> gaussKrugerForLon(double lonDeg, int zoneWidthDeg, bool zoneInEasting);

    Kind kind() const { return kind_; }
    bool isLocal() const { return kind_ == Kind::Local; }
    bool isGeographic() const { return kind_ == Kind::Geographic; }
    bool isProjected() const { return kind_ == Kind::GaussKruger || kind_ == Kind::Projected; }
    bool isGaussKruger() const { return kind_ == Kind::GaussKruger; }
    // True for CGCS2000 and its Gauss-Kruger zones (GeographicLib), false for PROJ CRSs.
    bool isCgcs2000() const { return epsg_ >= 4490 && epsg_ <= 4554; }
    int epsg() const { return epsg_; }  // 0 when local or when no EPSG code matches
    // "EPSG:2056", "local", or the WKT of a CRS no EPSG code matches; parse(id()) gives
    // this CRS back.
    std::string id() const;
    std::string name() const;  // EPSG's name: "CH1903+ / LV95", "CGCS2000 / 3-degree Gauss-Kruger zone 35"

    // Gauss-Kruger only (0 / false otherwise).
    int zone() const { return zone_; }
    int zoneWidthDeg() const { return width_; }  // 3 or 6
    double centralMeridianDeg() const { return lon0_; }
    double falseEastingM() const { return fe_; }
    bool zoneInEasting() const { return zoneInEasting_; }

    // Projected: the axes' unit ("metre", "US survey foot") and metres per unit. Geographic:
    // "degree" and 0. Local: "metre" and 1.
    std::string unitName() const;
    double unitToMetre() const;
    // The geographic CRS on this CRS's own datum (EPSG:4490 for CGCS2000, EPSG:4267 for
    // NAD27 / UTM zone 11N, the CRS itself when geographic): id and name. Empty when local.
    std::string geographicId() const;
    std::string geographicName() const;
    // EPSG's area of use, when known (CGCS2000 zones: their zone's longitude band over China).
    std::optional<LonLatBox> areaOfUse() const;

    // Projected only: (easting, northing) in the CRS's units <-> (lon, lat) in degrees on the
    // CRS's own datum (a conversion, exact to the projection's formulas). Errors: not
    // projected, non-finite input, a point the projection cannot take.
    Result<glm::dvec2> toLonLat(double easting, double northing) const;
    Result<glm::dvec2> fromLonLat(double lonDeg, double latDeg) const;

    // Ok when a model's world coordinates (metres) can be in this CRS: local, geographic,
    // or projected in metres. A CRS in feet is refused with a message naming its unit.
    Status checkModelCrs() const;

    bool operator==(const Crs& o) const;
    bool operator!=(const Crs& o) const { return !(*this == o); }

    const ProjCrsInfo* projInfo() const { return proj_.get(); }  // null for local and CGCS2000

private:
    friend struct CrsBuilder;  // model/crs/crs.cpp
    Kind kind_ = Kind::Local;
    int epsg_ = 0;
    int zone_ = 0;
    int width_ = 0;
    double lon0_ = 0.0;
    double fe_ = 0.0;
    bool zoneInEasting_ = false;
    std::shared_ptr<const ProjCrsInfo> proj_;
};

// Converts one point (x y z in `from`'s API axis order and units) to `to`, as cs2cs does:
// CGCS2000 to CGCS2000 through GeographicLib, any other pair through PROJ's
// proj_create_crs_to_crs (the operation chosen per point by area of use, as cs2cs does;
// a 2D pair passes z through unchanged). Both local with from == to: unchanged.
// When `warning` is given it receives a note when the point lies outside the area of use
// of either CRS (the point is still converted).
Result<glm::dvec3> convertPoint(const Crs& from, const Crs& to, const glm::dvec3& p, std::string* warning = nullptr);

// What PROJ offers between two CRSs over their common area: the best accuracy of its
// candidate operations (metres, -1 unknown), whether only ballpark operations exist, and
// the best operation's name. For `geoslice coords` to warn once before converting.
struct OperationSummary {
    std::string bestName;
    double bestAccuracyM = -1.0;
    bool onlyBallpark = false;
    bool identity = false;  // same datum: a conversion, exact
};
Result<OperationSummary> summariseOperations(const Crs& from, const Crs& to);

// One transformation from `from` to `to`, chosen once for an area: the first operation PROJ
// ranks best whose area of use contains `area` (lon/lat on `from`'s datum) and whose grids
// are installed. Using one operation for a whole model keeps every answer a pure function
// of the model (no switch between operations at an area boundary inside it).
// Thread-safe: apply() may run on any number of threads at once.
class CrsTransform {
public:
    static Result<CrsTransform> forArea(const Crs& from, const Crs& to, const LonLatBox& area);

    // (x, y, z) in from's API axis order and units -> to's. z passes through for 2D CRSs.
    Result<glm::dvec3> apply(const glm::dvec3& p) const;
    const std::string& operationName() const { return name_; }
    // PROJ's stated accuracy in metres; < 0 when it states none.
    double accuracyM() const { return accuracyM_; }
    // A "ballpark" operation (datum shift ignored or guessed): not to be presented as a
    // transformation result.
    bool isBallpark() const { return ballpark_; }
    const Crs& source() const { return from_; }
    const Crs& target() const { return to_; }

private:
    Crs from_, to_;
    std::string name_;
    std::string pipeline_;  // PROJ string of the normalised operation, rebuilt per context
    unsigned pipelineId_ = 0;
    double accuracyM_ = -1.0;
    bool ballpark_ = false;
};

// Whether the PROJ contexts geoslice makes may use the network (always false: only the
// local proj.db and grids are used, whatever PROJ_NETWORK says). For tests.
bool crsNetworkAccessEnabled();

// The lon/lat box of a projected or geographic extent [min, max] (API axis order, the
// CRS's units): the envelope of its four edges, each sampled at kLonLatEdgeSteps points and
// converted to the CRS's own datum. The one lon/lat envelope of a model (`geoslice info`,
// GET /v1/models/{id} lonlatBounds, the WGS 84 transform's area).
constexpr int kLonLatEdgeSteps = 64;
Result<LonLatBox> lonLatBoxOf(const Crs& crs, const glm::dvec2& min, const glm::dvec2& max);

}  // namespace geoslice
