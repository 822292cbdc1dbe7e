// CRS internals shared by model/crs/crs.cpp (the Crs value: EPSG codes, parsing, PROJ
// identification), model/crs/gauss_kruger.cpp (CGCS2000 Gauss-Kruger through GeographicLib) and
// model/crs/crs_transform.cpp (conversions and PROJ operations). Not a public header.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <proj.h>

#include <glm/glm.hpp>

#include "model/crs/crs.hpp"
#include "model/result.hpp"

namespace geoslice {

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

namespace crs_detail {

// Shortest round-trip decimal form of a double, for error messages.
std::string num(double v);

// Releases a PJ or a PJ list at scope exit.
struct PjDeleter {
    void operator()(PJ* p) const { proj_destroy(p); }
};
using PjPtr = std::unique_ptr<PJ, PjDeleter>;
struct PjListDeleter {
    void operator()(PJ_OBJ_LIST* l) const { proj_list_destroy(l); }
};
using PjListPtr = std::unique_ptr<PJ_OBJ_LIST, PjListDeleter>;

inline std::string cstr(const char* s) { return s ? std::string(s) : std::string(); }

// "EPSG:2056", or the CRS's name when its id is long (WKT): for messages.
std::string shortId(const Crs& c);

// CGCS2000 Gauss-Kruger (model/crs/gauss_kruger.cpp): `c` is a GaussKruger Crs; (easting,
// northing) in metres <-> (lon, lat) in degrees. Errors: non-finite input, a point more
// than 3900 km from the central meridian or beyond the pole.
Result<glm::dvec2> gkToLonLat(const Crs& c, double eastingM, double northingM);
Result<glm::dvec2> gkFromLonLat(const Crs& c, double lonDeg, double latDeg);

}  // namespace crs_detail
}  // namespace geoslice
