// CGCS2000 and its Gauss-Kruger projections through GeographicLib::TransverseMercator
// (Karney 2011, "Transverse Mercator with an accuracy of a few nanometers", J. Geodesy
// 85(8): Krüger's series to order 6, accurate to 5 nm within 3900 km of the central
// meridian). Every EPSG parameter below was checked against `projinfo EPSG:NNNN`
// (PROJ 9.1.1): +proj=tmerc +lat_0=0 +k=1 +y_0=0 on the CGCS2000 ellipsoid.
#include "model/crs.hpp"

#include <proj.h>

#include <GeographicLib/Ellipsoid.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/TransverseMercator.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <numbers>
#include <string>
#include <system_error>
#include <vector>

#include "model/proj_pool.hpp"
#include "model/text_scan.hpp"

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

// C's isspace in the "C" locale: what CRS text (codes, WKT, PROJ strings) may be padded with.
std::string_view trim(std::string_view s) { return text::trim(s, " \t\r\n\f\v"); }

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

Error notProjected(const Crs& crs, const char* what) {
    return makeError(ErrorCode::InvalidArgument, std::string(what) + " needs a projected CRS, got " + crs.id());
}

std::string toLower(std::string_view s) {
    std::string out(s);
    for (char& ch : out)
        if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
    return out;
}

bool startsWithIgnoreCase(std::string_view s, std::string_view prefix) {
    return s.size() >= prefix.size() && equalsIgnoreCase(s.substr(0, prefix.size()), prefix);
}

// A positive decimal integer filling all of `digits`, or 0.
int parseCode(std::string_view digits) {
    int code = 0;
    const char* last = digits.data() + digits.size();
    auto [ptr, ec] = std::from_chars(digits.data(), last, code);
    if (digits.empty() || ec != std::errc() || ptr != last || code <= 0) return 0;
    return code;
}

bool allDigits(std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
}

// Releases a PJ or a PJ list at scope exit.
struct PjDeleter {
    void operator()(PJ* p) const { proj_destroy(p); }
};
using PjPtr = std::unique_ptr<PJ, PjDeleter>;
struct PjListDeleter {
    void operator()(PJ_OBJ_LIST* l) const { proj_list_destroy(l); }
};
using PjListPtr = std::unique_ptr<PJ_OBJ_LIST, PjListDeleter>;

std::string cstr(const char* s) { return s ? std::string(s) : std::string(); }

// "EPSG:n" when the object carries an EPSG id, else "".
std::string epsgIdOf(PJ* obj) {
    const std::string auth = cstr(proj_get_id_auth_name(obj, 0));
    const std::string code = cstr(proj_get_id_code(obj, 0));
    if (auth == "EPSG" && allDigits(code)) return "EPSG:" + code;
    return {};
}

std::string wktOf(PJ_CONTEXT* ctx, PJ* obj) {
    const char* const options[] = {"MULTILINE=NO", nullptr};
    return cstr(proj_as_wkt(ctx, obj, PJ_WKT2_2019, options));
}

const char* typeName(PJ_TYPE t) {
    switch (t) {
        case PJ_TYPE_GEOCENTRIC_CRS:
            return "a geocentric";
        case PJ_TYPE_VERTICAL_CRS:
            return "a vertical";
        case PJ_TYPE_ENGINEERING_CRS:
            return "an engineering";
        case PJ_TYPE_TEMPORAL_CRS:
            return "a temporal";
        default:
            return "not a geographic or projected";
    }
}

}  // namespace

// What PROJ said about a CRS, once, when the Crs was made. Immutable and shared by copies.
struct ProjCrsInfo {
    std::string def;  // text proj_create takes in any context: "EPSG:2056" or WKT
    std::uint32_t defId = 0;
    std::string name;
    std::string unitName;
    double unitToMetre = 1.0;
    std::string geoDef;  // the geographic CRS on the same datum
    std::uint32_t geoDefId = 0;
    std::string geoName;
    std::optional<LonLatBox> area;
};

struct CrsBuilder {
    // `obj` (owned) is the CRS PROJ made from `what`.
    static Result<Crs> fromObject(proj::Slot& slot, PjPtr obj, const std::string& what);
    static Result<Crs> fromEpsgCode(int code);
    static void setGaussKruger(Crs& c, int code);
};

namespace {

bool isGaussKrugerCode(int code) { return code >= kGk6ZoneFirstEpsg && code <= kGk3CmLastEpsg; }

// fromEpsg results, by code: each code asks the database once per process.
struct EpsgCache {
    std::mutex mutex;
    std::map<int, Crs> crs;
};
EpsgCache& epsgCache() {
    static EpsgCache* c = new EpsgCache;
    return *c;
}

}  // namespace

void CrsBuilder::setGaussKruger(Crs& c, int code) {
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
    } else {
        c.width_ = 3;
        c.zone_ = kGk3FirstZone + (code - kGk3CmFirstEpsg);
    }
    c.kind_ = Crs::Kind::GaussKruger;
    // 6-degree zone n spans [6(n-1), 6n] E; 3-degree zone n is centred on 3n E.
    c.lon0_ = c.width_ == 6 ? c.zone_ * 6.0 - 3.0 : c.zone_ * 3.0;
    c.fe_ = kFalseEastingM + (c.zoneInEasting_ ? c.zone_ * kZoneEastingM : 0.0);
}

Result<Crs> CrsBuilder::fromObject(proj::Slot& slot, PjPtr obj, const std::string& what) {
    PJ_CONTEXT* ctx = slot.ctx();
    PJ_TYPE type = proj_get_type(obj.get());
    if (type == PJ_TYPE_BOUND_CRS) {  // e.g. a PROJ string with +towgs84: keep the CRS itself
        obj.reset(proj_get_source_crs(ctx, obj.get()));
        if (!obj) return makeError(ErrorCode::Unsupported, what + ": a bound CRS without a source CRS");
        type = proj_get_type(obj.get());
    }
    if (type == PJ_TYPE_COMPOUND_CRS) {  // horizontal + vertical: the horizontal part
        obj.reset(proj_crs_get_sub_crs(ctx, obj.get(), 0));
        if (!obj) return makeError(ErrorCode::Unsupported, what + ": a compound CRS without a horizontal part");
        type = proj_get_type(obj.get());
    }
    const bool geographic = type == PJ_TYPE_GEOGRAPHIC_2D_CRS || type == PJ_TYPE_GEOGRAPHIC_3D_CRS;
    if (!geographic && type != PJ_TYPE_PROJECTED_CRS)
        return makeError(ErrorCode::Unsupported, what + " (" + cstr(proj_get_name(obj.get())) + ") is " +
                                                     typeName(type) +
                                                     " CRS; geoslice needs a geographic or projected CRS");
    std::string epsgId = epsgIdOf(obj.get());
    if (epsgId.empty()) {
        // A WKT or PROJ string without an id: the EPSG CRS it is equivalent to, if any.
        int* confidence = nullptr;
        PjListPtr matches(proj_identify(ctx, obj.get(), "EPSG", nullptr, &confidence));
        if (matches && proj_list_get_count(matches.get()) > 0 && confidence && confidence[0] == 100) {
            PjPtr best(proj_list_get(ctx, matches.get(), 0));
            if (best) epsgId = epsgIdOf(best.get());
        }
        proj_int_list_destroy(confidence);
    }
    const int code = epsgId.empty() ? 0 : parseCode(std::string_view(epsgId).substr(5));
    if (code != 0 && (code == kGeographicEpsg || isGaussKrugerCode(code))) return Crs::fromEpsg(code);

    auto info = std::make_shared<ProjCrsInfo>();
    info->def = code != 0 ? epsgId : wktOf(ctx, obj.get());
    if (info->def.empty()) return makeError(ErrorCode::Unsupported, what + ": PROJ cannot write this CRS as WKT");
    info->name = cstr(proj_get_name(obj.get()));

    // Axes: directions (no westing or southing) and the unit.
    PjPtr cs(proj_crs_get_coordinate_system(ctx, obj.get()));
    if (!cs || proj_cs_get_axis_count(ctx, cs.get()) < 2)
        return makeError(ErrorCode::Unsupported, what + " (" + info->name + "): no usable coordinate system");
    for (int i = 0; i < 2; ++i) {
        const char* direction = nullptr;
        const char* unit = nullptr;
        double factor = 0.0;
        if (!proj_cs_get_axis_info(ctx, cs.get(), i, nullptr, nullptr, &direction, &factor, &unit, nullptr, nullptr))
            return makeError(ErrorCode::Unsupported, what + " (" + info->name + "): cannot read its axes");
        const std::string dir = toLower(cstr(direction));
        if (dir == "west" || dir == "south")
            return makeError(ErrorCode::Unsupported, what + " (" + info->name + ") has an axis pointing " + dir +
                                                         "; geoslice's coordinates are easting/northing or lon/lat");
        if (i == 0) {
            info->unitName = cstr(unit);
            info->unitToMetre = factor;
        }
    }
    if (geographic) {
        // Radians per unit: only degrees keep the lon/lat-in-degrees contract.
        if (std::fabs(info->unitToMetre - std::numbers::pi / 180.0) > 1e-15)
            return makeError(ErrorCode::Unsupported, what + " (" + info->name + ") measures angles in " +
                                                         info->unitName +
                                                         "; geoslice's geographic coordinates are "
                                                         "degrees");
        info->unitName = "degree";
        info->unitToMetre = 0.0;
    }
    if (!(info->unitToMetre >= 0.0) || !std::isfinite(info->unitToMetre))
        return makeError(ErrorCode::Unsupported, what + " (" + info->name + "): unusable axis unit");

    PjPtr geo(geographic ? nullptr : proj_crs_get_geodetic_crs(ctx, obj.get()));
    PJ* g = geographic ? obj.get() : geo.get();
    if (!g) return makeError(ErrorCode::Unsupported, what + " (" + info->name + "): no geodetic CRS");
    if (geographic) {
        info->geoDef = info->def;
    } else {
        info->geoDef = epsgIdOf(g);
        if (info->geoDef.empty()) info->geoDef = wktOf(ctx, g);
    }
    info->geoName = cstr(proj_get_name(g));
    double w = 0, s = 0, e = 0, n = 0;
    if (proj_get_area_of_use(ctx, obj.get(), &w, &s, &e, &n, nullptr) && w > -1000.0 && s > -1000.0)
        info->area = LonLatBox{w, s, e, n};
    info->defId = proj::intern(info->def);
    info->geoDefId = proj::intern(info->geoDef);

    Crs c;
    c.kind_ = geographic ? Crs::Kind::Geographic : Crs::Kind::Projected;
    c.epsg_ = code;
    c.proj_ = std::move(info);
    return c;
}

Result<Crs> CrsBuilder::fromEpsgCode(int code) {
    const std::string what = "EPSG:" + std::to_string(code);
    proj::Lease slot;
    PjPtr obj(
        proj_create_from_database(slot->ctx(), "EPSG", std::to_string(code).c_str(), PJ_CATEGORY_CRS, 0, nullptr));
    if (!obj)
        return makeError(ErrorCode::Unsupported, what + " is not a CRS in PROJ's EPSG database (proj.db of PROJ " +
                                                     std::to_string(PROJ_VERSION_MAJOR) + "." +
                                                     std::to_string(PROJ_VERSION_MINOR) + ")");
    if (code != kGeographicEpsg && !isGaussKrugerCode(code)) return fromObject(*slot, std::move(obj), what);
    // CGCS2000: metadata from PROJ, arithmetic from GeographicLib.
    auto info = std::make_shared<ProjCrsInfo>();
    info->def = what;
    info->name = cstr(proj_get_name(obj.get()));
    info->geoDef = "EPSG:4490";
    info->geoName = code == kGeographicEpsg ? info->name : "China Geodetic Coordinate System 2000";
    info->unitName = code == kGeographicEpsg ? "degree" : "metre";
    info->unitToMetre = code == kGeographicEpsg ? 0.0 : 1.0;
    double w = 0, s = 0, e = 0, n = 0;
    if (proj_get_area_of_use(slot->ctx(), obj.get(), &w, &s, &e, &n, nullptr) && w > -1000.0 && s > -1000.0)
        info->area = LonLatBox{w, s, e, n};
    info->defId = proj::intern(info->def);
    info->geoDefId = proj::intern(info->geoDef);
    Crs c;
    c.epsg_ = code;
    if (code == kGeographicEpsg)
        c.kind_ = Crs::Kind::Geographic;
    else
        setGaussKruger(c, code);
    c.proj_ = std::move(info);
    return c;
}

bool LonLatBox::contains(double lonDeg, double latDeg) const {
    if (latDeg < south || latDeg > north) return false;
    if (west <= east) return lonDeg >= west && lonDeg <= east;
    return lonDeg >= west || lonDeg <= east;  // crosses 180
}

Result<Crs> Crs::fromEpsg(int code) {
    if (code <= 0)
        return makeError(ErrorCode::InvalidArgument, "EPSG:" + std::to_string(code) + " is not an EPSG code");
    EpsgCache& cache = epsgCache();
    {
        std::lock_guard<std::mutex> lock(cache.mutex);
        if (auto it = cache.crs.find(code); it != cache.crs.end()) return it->second;
    }
    auto c = CrsBuilder::fromEpsgCode(code);
    if (!c) return c;
    std::lock_guard<std::mutex> lock(cache.mutex);
    cache.crs.emplace(code, c.value());
    return c;
}

Result<Crs> Crs::parse(std::string_view text) {
    const std::string_view t = trim(text);
    if (t.empty() || equalsIgnoreCase(t, "local") || equalsIgnoreCase(t, "default")) return Crs::local();
    const auto expected = [&](const std::string& why) {
        return makeError(ErrorCode::InvalidArgument,
                         "cannot parse CRS \"" + std::string(text) + "\": " + why +
                             " (expected \"EPSG:<code>\", \"<code>\", an OGC URN or URL, a CRS name PROJ knows such as "
                             "\"CH1903 / LV03\", WKT, \"local\" or empty)");
    };
    // EPSG codes directly, so that CGCS2000 ones stay with GeographicLib and errors are short.
    std::string_view digits;
    if (startsWithIgnoreCase(t, "epsg:"))
        digits = t.substr(5);
    else if (allDigits(t))
        digits = t;
    else if (startsWithIgnoreCase(t, "urn:ogc:def:crs:epsg:"))
        digits = t.substr(t.rfind(':') + 1);
    else if (startsWithIgnoreCase(t, "http://www.opengis.net/def/crs/epsg/") ||
             startsWithIgnoreCase(t, "https://www.opengis.net/def/crs/epsg/"))
        digits = t.substr(t.rfind('/') + 1);
    if (!digits.empty() || startsWithIgnoreCase(t, "epsg:")) {
        const int code = parseCode(trim(digits));
        if (code == 0) return expected("not an EPSG code");
        auto c = fromEpsg(code);
        if (!c) return makeError(c.error().code, "CRS \"" + std::string(text) + "\": " + c.error().message);
        return c;
    }
    if (t.size() > (1u << 20)) return expected("over 1 MiB of text");
    const std::string s(t);
    proj::Lease slot;
    PjPtr obj(proj_create(slot->ctx(), s.c_str()));
    if (!obj) return expected("PROJ: " + slot->lastError());
    if (!proj_is_crs(obj.get())) return expected("PROJ reads it as something other than a CRS");
    std::string what = "CRS \"" + s.substr(0, 80) + (s.size() > 80 ? "...\"" : "\"");
    return CrsBuilder::fromObject(*slot, std::move(obj), what);
}

Result<Crs> Crs::gaussKrugerForLon(double lonDeg, int zoneWidthDeg, bool zoneInEasting) {
    if (!std::isfinite(lonDeg)) {
        return makeError(ErrorCode::InvalidArgument,
                         "Gauss-Kruger zone for longitude " + num(lonDeg) + ": not a finite number");
    }
    if (zoneWidthDeg != 3 && zoneWidthDeg != 6) {
        return makeError(ErrorCode::InvalidArgument,
                         "Gauss-Kruger zone width " + std::to_string(zoneWidthDeg) + " degrees: must be 3 or 6");
    }
    const double lon = std::remainder(lonDeg, 360.0);  // [-180, 180]
    int index = 0;                                     // 0-based within the EPSG family, counted from CM 75 E
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
    const double cm = zoneWidthDeg == 3 ? (kGk3FirstZone + index) * 3.0 : (kGk6FirstZone + index) * 6.0 - 3.0;
    if (std::fabs(lon - cm) > zoneWidthDeg) {
        return makeError(ErrorCode::OutOfRange, "longitude " + num(lonDeg) + " degrees has no CGCS2000 " +
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
    if (epsg_ != 0) return "EPSG:" + std::to_string(epsg_);
    return proj_->def;
}

std::string Crs::name() const {
    if (kind_ == Kind::Local) return "local (no georeference)";
    return proj_->name;
}

std::string Crs::unitName() const { return proj_ ? proj_->unitName : std::string("metre"); }
double Crs::unitToMetre() const { return proj_ ? proj_->unitToMetre : 1.0; }
std::string Crs::geographicId() const { return proj_ ? proj_->geoDef : std::string(); }
std::string Crs::geographicName() const { return proj_ ? proj_->geoName : std::string(); }
std::optional<LonLatBox> Crs::areaOfUse() const { return proj_ ? proj_->area : std::nullopt; }

bool Crs::operator==(const Crs& o) const {
    if (kind_ != o.kind_ || epsg_ != o.epsg_) return false;
    if (epsg_ != 0 || kind_ == Kind::Local) return true;
    return proj_->def == o.proj_->def;
}

Status Crs::checkModelCrs() const {
    if (!isProjected() || std::fabs(unitToMetre() - 1.0) < 1e-12) return {};
    return makeError(ErrorCode::Unsupported,
                     id().substr(0, 120) + " (" + name() + ") measures in " + unitName() + " (" + num(unitToMetre()) +
                         " m); a geoslice model's coordinates are metres and geoslice does not rescale models: "
                         "give the model in a metre CRS (or --crs local)");
}

namespace {

const std::string& defOf(const Crs& c) { return c.projInfo()->def; }
std::uint32_t defIdOf(const Crs& c) { return c.projInfo()->defId; }

// proj_create_crs_to_crs(a, b), normalised to easting/northing and lon/lat order, cached
// in the slot.
PJ* crsToCrs(proj::Slot& slot, const std::string& a, std::uint32_t aId, const std::string& b, std::uint32_t bId) {
    return slot.get(proj::key(proj::ObjectKind::CrsToCrs, aId, bId), [&](PJ_CONTEXT* ctx) -> PJ* {
        PjPtr raw(proj_create_crs_to_crs(ctx, a.c_str(), b.c_str(), nullptr));
        if (!raw) return nullptr;
        return proj_normalize_for_visualization(ctx, raw.get());
    });
}

std::string shortId(const Crs& c) {
    std::string s = c.id();
    return s.size() > 60 ? c.name() : s;
}

Result<glm::dvec3> transformPoint(proj::Slot& slot, PJ* op, PJ_DIRECTION dir, const glm::dvec3& p,
                                  const std::function<std::string()>& where) {
    proj_errno_reset(op);
    const PJ_COORD r = proj_trans(op, dir, proj_coord(p.x, p.y, p.z, HUGE_VAL));
    if (!std::isfinite(r.xyz.x) || !std::isfinite(r.xyz.y) || std::fabs(r.xyz.x) >= HUGE_VAL / 2) {
        const int e = proj_errno(op);
        std::string why = e ? cstr(proj_context_errno_string(slot.ctx(), e)) : std::string("no result");
        proj_errno_reset(op);
        return makeError(ErrorCode::OutOfRange, where() + ": PROJ: " + why);
    }
    return glm::dvec3(r.xyz.x, r.xyz.y, r.xyz.z);
}

std::string pointText(const glm::dvec3& p) { return "(" + num(p.x) + ", " + num(p.y) + ")"; }

}  // namespace

Result<glm::dvec2> Crs::toLonLat(double easting, double northing) const {
    if (!isProjected()) return notProjected(*this, "toLonLat");
    if (kind_ == Kind::GaussKruger) return gkToLonLat(*this, easting, northing);
    const glm::dvec3 p(easting, northing, 0.0);
    if (!std::isfinite(easting) || !std::isfinite(northing))
        return makeError(ErrorCode::InvalidArgument, shortId(*this) + " " + pointText(p) + ": not a finite number");
    proj::Lease slot;
    PJ* op = crsToCrs(*slot, proj_->def, proj_->defId, proj_->geoDef, proj_->geoDefId);
    if (!op) return makeError(ErrorCode::Internal, shortId(*this) + " to lon/lat: PROJ: " + slot->lastError());
    auto r = transformPoint(*slot, op, PJ_FWD, p, [&] { return shortId(*this) + " " + pointText(p) + " to lon/lat"; });
    if (!r) return r.error();
    return glm::dvec2(r->x, r->y);
}

Result<glm::dvec2> Crs::fromLonLat(double lonDeg, double latDeg) const {
    if (!isProjected()) return notProjected(*this, "fromLonLat");
    if (kind_ == Kind::GaussKruger) return gkFromLonLat(*this, lonDeg, latDeg);
    const glm::dvec3 p(lonDeg, latDeg, 0.0);
    if (!std::isfinite(lonDeg) || !std::isfinite(latDeg))
        return makeError(ErrorCode::InvalidArgument,
                         shortId(*this) + " from lon/lat " + pointText(p) + ": not a finite number");
    if (std::fabs(latDeg) > 90.0)
        return makeError(ErrorCode::OutOfRange,
                         shortId(*this) + " from lon/lat " + pointText(p) + ": latitude beyond +-90 degrees");
    proj::Lease slot;
    PJ* op = crsToCrs(*slot, proj_->def, proj_->defId, proj_->geoDef, proj_->geoDefId);
    if (!op) return makeError(ErrorCode::Internal, shortId(*this) + " from lon/lat: PROJ: " + slot->lastError());
    auto r = transformPoint(*slot, op, PJ_INV, p, [&] { return shortId(*this) + " from lon/lat " + pointText(p); });
    if (!r) return r.error();
    return glm::dvec2(r->x, r->y);
}

namespace {

// The CGCS2000-only path (GeographicLib), unchanged from before PROJ was added.
Result<glm::dvec3> convertCgcs2000(const Crs& from, const Crs& to, const glm::dvec3& p) {
    if (from == to) {
        if (from.isGeographic() && std::fabs(p.y) > 90.0) {
            return makeError(ErrorCode::OutOfRange, "convert " + from.id() + " -> " + to.id() + ": latitude " +
                                                        num(p.y) + " beyond +-90 degrees");
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
        return makeError(ErrorCode::OutOfRange,
                         "convert " + from.id() + " -> " + to.id() + ": latitude " + num(p.y) + " beyond +-90 degrees");
    }
    if (to.isGeographic()) return glm::dvec3(lonLat, p.z);
    auto en = to.fromLonLat(lonLat.x, lonLat.y);
    if (!en) {
        Error e = en.error();
        if (from.isProjected()) e.message = "from " + from.id() + " (" + num(p.x) + ", " + num(p.y) + "): " + e.message;
        return e;
    }
    return glm::dvec3(en.value(), p.z);
}

std::string areaText(const LonLatBox& a) {
    return "lon " + num(a.west) + ".." + num(a.east) + ", lat " + num(a.south) + ".." + num(a.north);
}

// Where `p` (in `from`) lies outside either CRS's area of use: a sentence, else "".
std::string areaWarning(const Crs& from, const Crs& to, const glm::dvec3& p) {
    glm::dvec2 ll(p.x, p.y);
    if (from.isProjected()) {
        auto r = from.toLonLat(p.x, p.y);
        if (!r) return {};
        ll = r.value();
    }
    std::string out;
    for (const Crs* c : {&from, &to}) {
        const auto area = c->areaOfUse();
        if (!area || area->contains(ll.x, ll.y)) continue;
        if (c == &to && to == from) continue;
        if (!out.empty()) out += "; ";
        out += "lon/lat (" + num(ll.x) + ", " + num(ll.y) + ") lies outside the area of use of " + shortId(*c) + " (" +
               c->name() + ": " + areaText(*area) + ")";
    }
    return out;
}

}  // namespace

Result<glm::dvec3> convertPoint(const Crs& from, const Crs& to, const glm::dvec3& p, std::string* warning) {
    if (from.isLocal() || to.isLocal()) {
        if (from.isLocal() && to.isLocal()) return p;
        return makeError(ErrorCode::InvalidArgument, "cannot convert between " + shortId(from) + " and " + shortId(to) +
                                                         ": a local CRS has no georeference");
    }
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        return makeError(ErrorCode::InvalidArgument, "convert " + shortId(from) + " -> " + shortId(to) + ": point (" +
                                                         num(p.x) + ", " + num(p.y) + ", " + num(p.z) +
                                                         ") is not finite");
    }
    if (from.isGeographic() && std::fabs(p.y) > 90.0)
        return makeError(ErrorCode::OutOfRange, "convert " + shortId(from) + " -> " + shortId(to) + ": latitude " +
                                                    num(p.y) + " beyond +-90 degrees");
    Result<glm::dvec3> out = glm::dvec3(0.0);
    if (from.isCgcs2000() && to.isCgcs2000()) {
        out = convertCgcs2000(from, to, p);
    } else {
        proj::Lease slot;
        PJ* op = crsToCrs(*slot, defOf(from), defIdOf(from), defOf(to), defIdOf(to));
        if (!op)
            return makeError(ErrorCode::Unsupported, "no PROJ transformation from " + shortId(from) + " to " +
                                                         shortId(to) + ": " + slot->lastError());
        out = transformPoint(*slot, op, PJ_FWD, p,
                             [&] { return "convert " + shortId(from) + " -> " + shortId(to) + " " + pointText(p); });
    }
    if (warning) *warning = out ? areaWarning(from, to, p) : std::string();
    return out;
}

namespace {

struct FactoryDeleter {
    PJ_CONTEXT* ctx;
    void operator()(PJ_OPERATION_FACTORY_CONTEXT* f) const { proj_operation_factory_context_destroy(f); }
};

// PROJ's candidate operations from -> to (instantiable with the installed grids), best
// first, over `area` when given (strict containment) else over the CRSs' extents.
Result<std::vector<PjPtr>> candidateOperations(proj::Slot& slot, const Crs& from, const Crs& to,
                                               const std::optional<LonLatBox>& area) {
    PJ_CONTEXT* ctx = slot.ctx();
    PjPtr src(proj_create(ctx, defOf(from).c_str())), dst(proj_create(ctx, defOf(to).c_str()));
    if (!src || !dst) return makeError(ErrorCode::Internal, "PROJ: " + slot.lastError());
    std::unique_ptr<PJ_OPERATION_FACTORY_CONTEXT, FactoryDeleter> factory(
        proj_create_operation_factory_context(ctx, nullptr), FactoryDeleter{ctx});
    if (!factory) return makeError(ErrorCode::Internal, "PROJ: " + slot.lastError());
    if (area) {
        proj_operation_factory_context_set_area_of_interest(ctx, factory.get(), area->west, area->south, area->east,
                                                            area->north);
        proj_operation_factory_context_set_spatial_criterion(ctx, factory.get(),
                                                             PROJ_SPATIAL_CRITERION_STRICT_CONTAINMENT);
    } else {
        proj_operation_factory_context_set_spatial_criterion(ctx, factory.get(),
                                                             PROJ_SPATIAL_CRITERION_PARTIAL_INTERSECTION);
    }
    proj_operation_factory_context_set_grid_availability_use(ctx, factory.get(),
                                                             PROJ_GRID_AVAILABILITY_DISCARD_OPERATION_IF_MISSING_GRID);
    PjListPtr list(proj_create_operations(ctx, src.get(), dst.get(), factory.get()));
    std::vector<PjPtr> out;
    if (!list) return out;
    const int n = proj_list_get_count(list.get());
    for (int i = 0; i < n; ++i) {
        PjPtr op(proj_list_get(ctx, list.get(), i));
        if (op && proj_coordoperation_is_instantiable(ctx, op.get())) out.push_back(std::move(op));
    }
    return out;
}

// As proj_trans picks among proj_create_crs_to_crs's candidates for a point: the smallest
// stated accuracy wins, an unknown accuracy loses to any known one, ties keep PROJ's order.
std::size_t bestCandidate(proj::Slot& slot, const std::vector<PjPtr>& ops) {
    std::size_t best = 0;
    double bestAcc = -1.0;
    for (std::size_t i = 0; i < ops.size(); ++i) {
        const double acc = proj_coordoperation_get_accuracy(slot.ctx(), ops[i].get());
        if (acc >= 0.0 && (bestAcc < 0.0 || acc < bestAcc)) {
            best = i;
            bestAcc = acc;
        }
    }
    return best;
}

}  // namespace

Result<OperationSummary> summariseOperations(const Crs& from, const Crs& to) {
    OperationSummary s;
    if (from.isLocal() || to.isLocal())
        return makeError(ErrorCode::InvalidArgument, "no operations between a local CRS and another");
    s.identity = from.geographicId() == to.geographicId();
    proj::Lease slot;
    auto ops = candidateOperations(*slot, from, to, std::nullopt);
    if (!ops) return ops.error();
    if (ops->empty()) return s;
    const std::size_t best = bestCandidate(*slot, ops.value());
    s.bestName = cstr(proj_get_name(ops.value()[best].get()));
    s.bestAccuracyM = proj_coordoperation_get_accuracy(slot->ctx(), ops.value()[best].get());
    s.onlyBallpark = true;
    for (const auto& op : ops.value())
        if (!proj_coordoperation_has_ballpark_transformation(slot->ctx(), op.get())) s.onlyBallpark = false;
    if (s.identity) s.onlyBallpark = false;
    return s;
}

Result<CrsTransform> CrsTransform::forArea(const Crs& from, const Crs& to, const LonLatBox& area) {
    if (from.isLocal() || to.isLocal())
        return makeError(ErrorCode::InvalidArgument, "no transformation between a local CRS and another");
    proj::Lease slot;
    auto ops = candidateOperations(*slot, from, to, area);
    if (!ops) return ops.error();
    if (ops->empty())
        return makeError(ErrorCode::NotFound, "PROJ has no usable operation from " + shortId(from) + " to " +
                                                  shortId(to) + " over " + areaText(area));
    PJ* op = ops.value()[bestCandidate(*slot, ops.value())].get();
    CrsTransform t;
    t.from_ = from;
    t.to_ = to;
    t.name_ = cstr(proj_get_name(op));
    t.accuracyM_ = proj_coordoperation_get_accuracy(slot->ctx(), op);
    t.ballpark_ = proj_coordoperation_has_ballpark_transformation(slot->ctx(), op) != 0;
    PjPtr normalised(proj_normalize_for_visualization(slot->ctx(), op));
    if (!normalised) return makeError(ErrorCode::Internal, "PROJ: " + slot->lastError());
    t.pipeline_ = cstr(proj_as_proj_string(slot->ctx(), normalised.get(), PJ_PROJ_5, nullptr));
    if (t.pipeline_.empty()) t.pipeline_ = cstr(proj_as_projjson(slot->ctx(), normalised.get(), nullptr));
    if (t.pipeline_.empty()) return makeError(ErrorCode::Internal, "PROJ cannot write operation " + t.name_);
    t.pipelineId_ = proj::intern(t.pipeline_);
    return t;
}

Result<glm::dvec3> CrsTransform::apply(const glm::dvec3& p) const {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        return makeError(ErrorCode::InvalidArgument, name_ + ": point " + pointText(p) + " is not finite");
    proj::Lease slot;
    PJ* op = slot->get(proj::key(proj::ObjectKind::Pipeline, pipelineId_),
                       [&](PJ_CONTEXT* ctx) { return proj_create(ctx, pipeline_.c_str()); });
    if (!op) return makeError(ErrorCode::Internal, name_ + ": PROJ: " + slot->lastError());
    return transformPoint(*slot, op, PJ_FWD, p, [&] { return name_ + " " + pointText(p); });
}

bool crsNetworkAccessEnabled() { return proj::networkEnabled(); }

Result<LonLatBox> lonLatBoxOf(const Crs& crs, const glm::dvec2& min, const glm::dvec2& max) {
    if (crs.isLocal()) return makeError(ErrorCode::InvalidArgument, "a local CRS has no lon/lat");
    LonLatBox box{1e9, 1e9, -1e9, -1e9};
    for (double fx : {0.0, 0.5, 1.0}) {
        for (double fy : {0.0, 0.5, 1.0}) {
            const glm::dvec2 p = min + glm::dvec2(fx, fy) * (max - min);
            glm::dvec2 ll = p;
            if (crs.isProjected()) {
                auto r = crs.toLonLat(p.x, p.y);
                if (!r) return r.error();
                ll = r.value();
            }
            box.west = std::min(box.west, ll.x);
            box.east = std::max(box.east, ll.x);
            box.south = std::min(box.south, ll.y);
            box.north = std::max(box.north, ll.y);
        }
    }
    return box;
}

}  // namespace geoslice
