// The Crs value (model/crs/crs.hpp): EPSG codes, CRS text, PROJ identification and the EPSG
// cache. CGCS2000 (EPSG:4490) and its Gauss-Kruger zones are recognised here and computed in
// model/crs/gauss_kruger.cpp (GeographicLib); conversions are model/crs/crs_transform.cpp. Every EPSG
// parameter below was checked against `projinfo EPSG:NNNN` (PROJ 9.1.1): +proj=tmerc
// +lat_0=0 +k=1 +y_0=0 on the CGCS2000 ellipsoid.
#include "model/crs/crs.hpp"

#include <proj.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <numbers>
#include <string>
#include <system_error>
#include <vector>

#include "model/crs/crs_proj.hpp"
#include "model/crs/proj_pool.hpp"
#include "model/text_scan.hpp"

namespace geoslice {

using crs_detail::cstr;
using crs_detail::num;
using crs_detail::PjListPtr;
using crs_detail::PjPtr;

namespace {

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

// C's isspace in the "C" locale: what CRS text (codes, WKT, PROJ strings) may be padded with.
std::string_view trim(std::string_view s) { return text::trim(s, " \t\r\n\f\v"); }

// A positive decimal integer filling all of `digits`, or 0.
int parseCode(std::string_view digits) {
    int code = 0;
    const char* last = digits.data() + digits.size();
    auto [ptr, ec] = std::from_chars(digits.data(), last, code);
    if (digits.empty() || ec != std::errc() || ptr != last || code <= 0) return 0;
    return code;
}

// "EPSG:n" when the object carries an EPSG id, else "".
std::string epsgIdOf(PJ* obj) {
    const std::string auth = cstr(proj_get_id_auth_name(obj, 0));
    const std::string code = cstr(proj_get_id_code(obj, 0));
    if (auth == "EPSG" && text::isDigits(code)) return "EPSG:" + code;
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
        const std::string dir = text::lower(cstr(direction));
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
    if (t.empty() || text::equalsNoCase(t, "local") || text::equalsNoCase(t, "default")) return Crs::local();
    const auto expected = [&](const std::string& why) {
        return makeError(ErrorCode::InvalidArgument,
                         "cannot parse CRS \"" + std::string(text) + "\": " + why +
                             " (expected \"EPSG:<code>\", \"<code>\", an OGC URN or URL, a CRS name PROJ knows such as "
                             "\"CH1903 / LV03\", WKT, \"local\" or empty)");
    };
    // EPSG codes directly, so that CGCS2000 ones stay with GeographicLib and errors are short.
    std::string_view digits;
    if (text::startsWithNoCase(t, "epsg:"))
        digits = t.substr(5);
    else if (text::isDigits(t))
        digits = t;
    else if (text::startsWithNoCase(t, "urn:ogc:def:crs:epsg:"))
        digits = t.substr(t.rfind(':') + 1);
    else if (text::startsWithNoCase(t, "http://www.opengis.net/def/crs/epsg/") ||
             text::startsWithNoCase(t, "https://www.opengis.net/def/crs/epsg/"))
        digits = t.substr(t.rfind('/') + 1);
    if (!digits.empty() || text::startsWithNoCase(t, "epsg:")) {
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

namespace crs_detail {

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

}  // namespace crs_detail

}  // namespace geoslice
