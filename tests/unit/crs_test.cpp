// Crs (model/crs/crs.hpp) against PROJ (cs2cs, projinfo from proj-bin) and `geoslice coords`.
//
// Frames and units: geographic points are (lon, lat) in degrees on CGCS2000; projected
// points are (easting, northing) in metres, easting including the false easting. That is
// geoslice's API axis order; cs2cs uses EPSG's order ("lat lon" in, "northing easting" out
// for these CRSs), so every exchange with cs2cs swaps the axes.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "model/crs/crs.hpp"
#include "tests/common/tolerances.hpp"

namespace geoslice {
namespace {

// Crs vs PROJ, projected metres. GeographicLib's TransverseMercator (Krüger series to
// order 6, Karney 2011) is accurate to about 5 nm within the zone, and PROJ's default
// tmerc (the Poder/Engsager extended algorithm) is of similar accuracy, so the two agree
// to nanometres; 1e-6 m (1 um) leaves room for cs2cs printing 10 decimals and still
// catches any parameter error (a wrong CM, false easting or flattening is metres off).
constexpr double kProjToleranceM = 1e-6;
// Crs vs PROJ, degrees: 1e-10 deg is 11 um on the ground, again far above both
// algorithms' error and far below any parameter mistake. cs2cs prints 12 decimals
// here so that its own rounding (5e-13 deg) stays out of the comparison.
constexpr double kProjToleranceDeg = 1e-10;
// Round trip through absolute coordinates, metres on the ground. The algorithmic error
// of the series pair is far below a nanometre; what remains is double rounding of the
// absolute projected coordinates: one unit in the last place is 7.5e-9 m for an easting
// of 35,600,000 m (zone number in the false easting) and 9.3e-10 m for a northing of
// 5,000,000 m, so a round trip cannot be held to 1e-9 m in every family. Measured
// maxima: 4.4e-9 m (EPSG:4523), 1.9e-9 m (FE 500 km families).
constexpr double kRoundTripToleranceM = 1e-8;
// Degrees to metres on the ground for error estimates (sphere of radius a; a few
// tenths of a percent is plenty for an error bound).
constexpr double kMetresPerDegree = 6378137.0 * std::numbers::pi / 180.0;
// Metres: two eastings of one absolute point that differ by a whole 35,000 km (zone prefix):
// exact up to the rounding of the absolute easting (ulp(3.5e7 m) = 7.5e-9 m).
constexpr double kAbsoluteEastingRoundingM = 1e-8;
// `geoslice coords` prints metres with 6 decimals: within half a micrometre.
constexpr double kPrinted6DecimalsM = 0.6e-6;
// `geoslice coords` prints degrees with 10 decimals: within half of 1e-10 degrees.
constexpr double kPrinted10DecimalsDeg = 0.6e-10;
// A defined unit factor (1200/3937 m per US survey foot): one double rounding.
constexpr double kUnitFactorTol = 1e-15;
// Degrees on a central meridian, where the projection is exact up to rounding.
constexpr double kOnCentralMeridianDeg = 1e-12;
// Metres on a central meridian (easting 500000 m), exact up to rounding.
constexpr double kOnCentralMeridianM = 1e-6;
// Degrees, a projection origin against projinfo's 13 decimals: 0.1 mm, far above the
// oblique Mercator's double error there and far below an axis swap (39 degrees).
constexpr double kProjectionOriginDeg = 1e-9;
// Metres back at that origin: 1e-13 degrees of rounding in lat_0/lon_0 is 0.01 mm.
constexpr double kProjectionOriginM = 1e-4;
using test::kSamePipelineDeg;  // degrees, against cs2cs running the same PROJ operation
// `coords` against cs2cs: metres printed with 6 decimals (5e-7 m) by us, 10 by cs2cs.
constexpr double kCoordsVsCs2csM = 1e-6;
// `coords` against cs2cs: degrees printed with 10 decimals by both: 0.1 mm.
constexpr double kCoordsVsCs2csDeg = 1e-9;

constexpr int kGeographic = 4490;

Crs crsOrDie(int code) {
    auto r = Crs::fromEpsg(code);
    GS_ASSERT(r.ok(), "test CRS must exist");
    return r.value();
}

// Absolute path of `name` on $PATH, or "" when not found.
std::string findOnPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::stringstream ss(path ? path : "/usr/local/bin:/usr/bin:/bin");
    std::string dir;
    while (std::getline(ss, dir, ':')) {
        if (dir.empty()) continue;
        const std::string candidate = dir + "/" + name;
        if (access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return "";
}

// A file under $TMPDIR (or /tmp) removed when this goes out of scope. mkstemp keeps
// tests that run in parallel processes apart.
class TempFile {
public:
    explicit TempFile(const std::string& contents) {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/geoslice_crs_test_XXXXXX";
        std::vector<char> buf(pattern.begin(), pattern.end());
        buf.push_back('\0');
        const int fd = mkstemp(buf.data());
        GS_ASSERT(fd >= 0, "mkstemp failed");
        close(fd);
        path_ = buf.data();
        std::ofstream(path_, std::ios::binary) << contents;
    }
    ~TempFile() { std::remove(path_.c_str()); }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

struct CommandResult {
    std::string out;  // stdout
    int exitCode = -1;
};

CommandResult runCommand(const std::string& command) {
    CommandResult r;
    FILE* p = popen(command.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
    const int status = pclose(p);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::vector<std::string> splitLines(const std::string& s) {
    std::vector<std::string> lines;
    std::stringstream ss(s);
    std::string line;
    while (std::getline(ss, line)) lines.push_back(line);
    return lines;
}

// Runs cs2cs from EPSG:`from` to EPSG:`to` on `input` (cs2cs axis order), fails the test
// when cs2cs is missing or fails, and returns its output lines.
std::vector<std::string> runCs2cs(int from, int to, const std::string& input, const char* format) {
    const std::string cs2cs = findOnPath("cs2cs");
    if (cs2cs.empty()) {
        ADD_FAILURE() << "cs2cs (PROJ) not found on PATH: run scripts/install-deps.sh (Debian package "
                         "proj-bin)";
        return {};
    }
    TempFile in(input);
    const auto r = runCommand(quote(cs2cs) + " -f " + format + " EPSG:" + std::to_string(from) +
                              " EPSG:" + std::to_string(to) + " < " + quote(in.path()) + " 2>&1");
    EXPECT_EQ(r.exitCode, 0) << "cs2cs EPSG:" << from << " EPSG:" << to << " failed:\n" << r.out;
    return splitLines(r.out);
}

// Runs cs2cs with `args` ("[-r] [-s] FROM TO") and -f %.10f on `input`; fails the test
// when cs2cs is missing or fails.
std::vector<std::string> runCs2csArgs(const std::string& args, const std::string& input) {
    const std::string cs2cs = findOnPath("cs2cs");
    if (cs2cs.empty()) {
        ADD_FAILURE() << "cs2cs (PROJ) not found on PATH: run scripts/install-deps.sh (proj-bin)";
        return {};
    }
    TempFile in(input);
    const auto r = runCommand(quote(cs2cs) + " -f %.10f " + args + " < " + quote(in.path()) + " 2>&1");
    EXPECT_EQ(r.exitCode, 0) << "cs2cs " << args << " failed:\n" << r.out;
    return splitLines(r.out);
}

// The CRSs compared with PROJ: both 3-degree families (incl. zone 35 = EPSG:4523 and
// CM 105E = EPSG:4544) and both 6-degree families, the first and last zone of each.
const std::vector<int> kComparedCodes = {4513, 4523, 4527, 4533, 4534, 4541, 4544,
                                         4554, 4491, 4496, 4501, 4502, 4507, 4512};

// Points over one zone, (lon, lat) degrees: the whole zone width, edges included, and
// China's latitudes.
std::vector<glm::dvec2> zonePoints(const Crs& crs) {
    const double w = crs.zoneWidthDeg();
    const double offsets[] = {-0.5, -0.37, -0.21, -0.04, 0.0, 0.13, 0.29, 0.43, 0.5};  // of the width
    const double lats[] = {3.9, 18.2, 25.0, 31.7, 40.3, 47.9, 53.5};
    std::vector<glm::dvec2> pts;
    for (double lat : lats)
        for (double f : offsets) pts.emplace_back(crs.centralMeridianDeg() + f * w, lat);
    return pts;
}

TEST(Crs, ForwardMatchesCs2cs) {
    int compared = 0;
    for (int code : kComparedCodes) {
        const Crs crs = crsOrDie(code);
        const auto pts = zonePoints(crs);
        std::string input;
        char line[128];
        for (const auto& p : pts) {
            std::snprintf(line, sizeof line, "%.15g %.15g\n", p.y, p.x);  // cs2cs: lat lon
            input += line;
        }
        const auto out = runCs2cs(kGeographic, code, input, "%.10f");
        ASSERT_EQ(out.size(), pts.size()) << "EPSG:" << code;
        for (size_t i = 0; i < pts.size(); ++i) {
            double north = 0.0, east = 0.0;  // cs2cs: northing easting
            ASSERT_EQ(std::sscanf(out[i].c_str(), "%lf %lf", &north, &east), 2) << out[i];
            const auto en = crs.fromLonLat(pts[i].x, pts[i].y);
            ASSERT_TRUE(en.ok()) << en.error().message;
            EXPECT_NEAR(en->x, east, kProjToleranceM) << "EPSG:" << code << " lon " << pts[i].x << " lat " << pts[i].y;
            EXPECT_NEAR(en->y, north, kProjToleranceM) << "EPSG:" << code << " lon " << pts[i].x << " lat " << pts[i].y;
            ++compared;
        }
    }
    EXPECT_GE(compared, 100);
}

TEST(Crs, InverseMatchesCs2cs) {
    int compared = 0;
    for (int code : kComparedCodes) {
        const Crs crs = crsOrDie(code);
        // Eastings across the zone (offsets from the central meridian, metres; a 3-degree
        // zone is about +-170 km wide at 20 N, a 6-degree one twice that), northings over China.
        const double scale = crs.zoneWidthDeg() / 3.0;
        const double xs[] = {-170e3, -123456.789, -60e3, -1.5, 0.0, 25e3, 98765.4321, 170e3};
        const double ys[] = {431234.5, 2012345.678, 2800000.0, 3456789.012, 4400000.0, 5300000.25, 5930000.0};
        std::vector<glm::dvec2> en;
        std::string input;
        char line[128];
        for (double y : ys) {
            for (double x : xs) {
                en.emplace_back(crs.falseEastingM() + x * scale, y);
                std::snprintf(line, sizeof line, "%.17g %.17g\n", en.back().y, en.back().x);  // N E
                input += line;
            }
        }
        const auto out = runCs2cs(code, kGeographic, input, "%.12f");
        ASSERT_EQ(out.size(), en.size()) << "EPSG:" << code;
        for (size_t i = 0; i < en.size(); ++i) {
            double lat = 0.0, lon = 0.0;  // cs2cs: lat lon
            ASSERT_EQ(std::sscanf(out[i].c_str(), "%lf %lf", &lat, &lon), 2) << out[i];
            const auto ll = crs.toLonLat(en[i].x, en[i].y);
            ASSERT_TRUE(ll.ok()) << ll.error().message;
            EXPECT_NEAR(ll->x, lon, kProjToleranceDeg) << "EPSG:" << code << " E " << en[i].x << " N " << en[i].y;
            EXPECT_NEAR(ll->y, lat, kProjToleranceDeg) << "EPSG:" << code << " E " << en[i].x << " N " << en[i].y;
            ++compared;
        }
    }
    EXPECT_GE(compared, 100);
}

TEST(Crs, ProjectedToProjectedMatchesCs2cs) {
    // Zone 35 with the zone number in the easting -> CM 108E without: through lon/lat.
    const Crs from = crsOrDie(4523), to = crsOrDie(4545);
    const std::vector<glm::dvec2> en = {{35500000.0, 3320113.5}, {35612345.678, 3900000.0}, {35401234.5, 2500000.0}};
    std::string input;
    char line[128];
    for (const auto& p : en) {
        std::snprintf(line, sizeof line, "%.17g %.17g\n", p.y, p.x);
        input += line;
    }
    const auto out = runCs2cs(4523, 4545, input, "%.10f");
    ASSERT_EQ(out.size(), en.size());
    for (size_t i = 0; i < en.size(); ++i) {
        double north = 0.0, east = 0.0;
        ASSERT_EQ(std::sscanf(out[i].c_str(), "%lf %lf", &north, &east), 2) << out[i];
        const auto q = convertPoint(from, to, glm::dvec3(en[i], 123.25));
        ASSERT_TRUE(q.ok()) << q.error().message;
        EXPECT_NEAR(q->x, east, kProjToleranceM);
        EXPECT_NEAR(q->y, north, kProjToleranceM);
        EXPECT_EQ(q->z, 123.25);  // heights pass through exactly
    }
}

TEST(Crs, EpsgTableParses) {
    for (int code = 4490; code <= 4554; ++code) {
        const std::string id = "EPSG:" + std::to_string(code);
        for (const std::string& text : {id, "epsg:" + std::to_string(code), std::to_string(code), "  " + id + "\t\n"}) {
            const auto c = Crs::parse(text);
            ASSERT_TRUE(c.ok()) << "\"" << text << "\": " << c.error().message;
            EXPECT_EQ(c->epsg(), code);
            EXPECT_EQ(c->id(), id);
        }
        const Crs c = crsOrDie(code);
        if (code == kGeographic) {
            EXPECT_TRUE(c.isGeographic());
            EXPECT_EQ(c.zone(), 0);
            continue;
        }
        EXPECT_TRUE(c.isProjected()) << id;
        // CM 75..135 E in every family; FE 500 km plus zone*1e6 m where the zone is in it.
        EXPECT_GE(c.centralMeridianDeg(), 75.0) << id;
        EXPECT_LE(c.centralMeridianDeg(), 135.0) << id;
        EXPECT_EQ(c.falseEastingM(), 500000.0 + (c.zoneInEasting() ? c.zone() * 1e6 : 0.0)) << id;
        const double zoneCm = c.zoneWidthDeg() == 3 ? c.zone() * 3.0 : c.zone() * 6.0 - 3.0;
        EXPECT_EQ(c.centralMeridianDeg(), zoneCm) << id;
    }
    for (int code : {0, -1, 1, 99999, 2147483647}) {
        const auto c = Crs::fromEpsg(code);
        ASSERT_FALSE(c.ok()) << code;
        EXPECT_NE(c.error().message.find(std::to_string(code)), std::string::npos) << c.error().message;
        const auto p = Crs::parse("EPSG:" + std::to_string(code));
        ASSERT_FALSE(p.ok()) << code;
        EXPECT_NE(p.error().message.find(std::to_string(code)), std::string::npos) << p.error().message;
    }
}

TEST(Crs, EpsgParametersOfSomeCodes) {
    struct Expected {
        int code;
        int zone;
        int width;
        double cmDeg;
        double feM;
        bool zoneInEasting;
        const char* name;
    };
    const Expected table[] = {
        {4491, 13, 6, 75.0, 13500000.0, true, "CGCS2000 / Gauss-Kruger zone 13"},
        {4501, 23, 6, 135.0, 23500000.0, true, "CGCS2000 / Gauss-Kruger zone 23"},
        {4502, 13, 6, 75.0, 500000.0, false, "CGCS2000 / Gauss-Kruger CM 75E"},
        {4507, 18, 6, 105.0, 500000.0, false, "CGCS2000 / Gauss-Kruger CM 105E"},
        {4512, 23, 6, 135.0, 500000.0, false, "CGCS2000 / Gauss-Kruger CM 135E"},
        {4513, 25, 3, 75.0, 25500000.0, true, "CGCS2000 / 3-degree Gauss-Kruger zone 25"},
        {4523, 35, 3, 105.0, 35500000.0, true, "CGCS2000 / 3-degree Gauss-Kruger zone 35"},
        {4533, 45, 3, 135.0, 45500000.0, true, "CGCS2000 / 3-degree Gauss-Kruger zone 45"},
        {4534, 25, 3, 75.0, 500000.0, false, "CGCS2000 / 3-degree Gauss-Kruger CM 75E"},
        {4544, 35, 3, 105.0, 500000.0, false, "CGCS2000 / 3-degree Gauss-Kruger CM 105E"},
        {4554, 45, 3, 135.0, 500000.0, false, "CGCS2000 / 3-degree Gauss-Kruger CM 135E"},
    };
    for (const auto& e : table) {
        const Crs c = crsOrDie(e.code);
        EXPECT_EQ(c.kind(), Crs::Kind::GaussKruger) << e.code;
        EXPECT_EQ(c.zone(), e.zone) << e.code;
        EXPECT_EQ(c.zoneWidthDeg(), e.width) << e.code;
        EXPECT_EQ(c.centralMeridianDeg(), e.cmDeg) << e.code;
        EXPECT_EQ(c.falseEastingM(), e.feM) << e.code;
        EXPECT_EQ(c.zoneInEasting(), e.zoneInEasting) << e.code;
        EXPECT_EQ(c.name(), e.name) << e.code;
    }
    EXPECT_EQ(crsOrDie(kGeographic).name(), "China Geodetic Coordinate System 2000");
}

TEST(Crs, EpsgTableMatchesProjinfo) {
    // Every code's name and PROJ definition as the installed EPSG database has them.
    const std::string projinfo = findOnPath("projinfo");
    ASSERT_FALSE(projinfo.empty()) << "projinfo (PROJ) not found on PATH: run scripts/install-deps.sh "
                                      "(Debian package proj-bin)";
    std::map<int, std::string> names;  // code -> name
    for (const auto& line : splitLines(runCommand(quote(projinfo) + " --list-crs --authority EPSG").out)) {
        int code = 0;
        char name[256] = {};
        if (std::sscanf(line.c_str(), "EPSG:%d \"%255[^\"]\"", &code, name) == 2 && code >= 4490 && code <= 4554)
            names[code] = name;
    }
    ASSERT_EQ(names.size(), 65u);
    for (const auto& [code, name] : names) EXPECT_EQ(crsOrDie(code).name(), name) << "EPSG:" << code;

    const auto defs =
        runCommand("for c in $(seq 4491 4554); do printf '%s ' $c; " + quote(projinfo) + " -o PROJ -q EPSG:$c; done");
    ASSERT_EQ(defs.exitCode, 0);
    int checked = 0;
    for (const auto& line : splitLines(defs.out)) {
        int code = 0;
        double lon0 = 0.0, x0 = 0.0, k = 0.0;
        char ellps[16] = {};
        ASSERT_EQ(std::sscanf(line.c_str(), "%d +proj=tmerc +lat_0=0 +lon_0=%lf +k=%lf +x_0=%lf +y_0=0 +ellps=%15s",
                              &code, &lon0, &k, &x0, ellps),
                  5)
            << line;
        // GRS80 in PROJ is a = 6378137 m, 1/f = 298.257222101, as CGCS2000.
        EXPECT_STREQ(ellps, "GRS80") << line;
        const Crs c = crsOrDie(code);
        EXPECT_EQ(c.centralMeridianDeg(), lon0) << line;
        EXPECT_EQ(c.falseEastingM(), x0) << line;
        EXPECT_EQ(k, 1.0) << line;
        ++checked;
    }
    EXPECT_EQ(checked, 64);
}

TEST(Crs, RoundTripOverZones) {
    const int codes[] = {4513, 4523, 4533, 4534, 4544, 4554, 4491, 4496, 4501, 4502, 4507, 4512};
    for (int code : codes) {
        const Crs c = crsOrDie(code);
        const double w = c.zoneWidthDeg();
        double worst = 0.0;
        for (int i = 0; i <= 40; ++i) {
            for (int j = 0; j <= 40; ++j) {
                const double lat = 60.0 * i / 40;  // equator to 60 N
                const double lon = c.centralMeridianDeg() - w / 2 + w * j / 40;
                const auto en = c.fromLonLat(lon, lat);
                ASSERT_TRUE(en.ok()) << en.error().message;
                const auto ll = c.toLonLat(en->x, en->y);
                ASSERT_TRUE(ll.ok()) << ll.error().message;
                const double err =
                    std::hypot((ll->y - lat) * kMetresPerDegree,
                               (ll->x - lon) * kMetresPerDegree * std::cos(lat * std::numbers::pi / 180.0));
                worst = std::max(worst, err);
                const auto en2 = c.fromLonLat(ll->x, ll->y);
                ASSERT_TRUE(en2.ok()) << en2.error().message;
                worst = std::max(worst, std::hypot(en2->x - en->x, en2->y - en->y));
            }
        }
        EXPECT_LT(worst, kRoundTripToleranceM) << "EPSG:" << code;
    }
}

TEST(Crs, ParseForms) {
    for (const char* text : {"", "local", "LOCAL", "  local ", " \t", "Default"}) {
        const auto c = Crs::parse(text);
        ASSERT_TRUE(c.ok()) << "\"" << text << "\"";
        EXPECT_TRUE(c->isLocal());
        EXPECT_EQ(c->epsg(), 0);
        EXPECT_EQ(c->id(), "local");
    }
    for (const char* text : {"EPSG:abc", "EPSG:", "EPSG:4523x", "EPSG:45 23", "4523.0", "EPSG:-4523",
                             "no such CRS name", "EPSG:99999999999999", "urn:ogc:def:crs:EPSG::x"}) {
        const auto c = Crs::parse(text);
        ASSERT_FALSE(c.ok()) << "\"" << text << "\"";
        EXPECT_NE(c.error().message.find(text), std::string::npos) << c.error().message;
    }
    const auto unknown = Crs::parse("EPSG:99999");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("99999"), std::string::npos) << unknown.error().message;
}

TEST(Crs, GaussKrugerForLon) {
    struct Case {
        double lon;
        int width;
        bool zoneInEasting;
        int epsg;
    };
    const Case cases[] = {
        {105.4, 3, true, 4523}, {105.4, 3, false, 4544}, {106.4, 3, false, 4544}, {106.6, 3, false, 4545},
        {75.0, 3, true, 4513},  {135.0, 3, false, 4554}, {105.4, 6, true, 4496},  {102.1, 6, false, 4507},
        {107.9, 6, true, 4496}, {73.6, 6, true, 4491},   {134.7, 6, false, 4512},
    };
    for (const auto& k : cases) {
        const auto c = Crs::gaussKrugerForLon(k.lon, k.width, k.zoneInEasting);
        ASSERT_TRUE(c.ok()) << k.lon << ": " << c.error().message;
        EXPECT_EQ(c->epsg(), k.epsg) << k.lon << " width " << k.width;
        EXPECT_LE(std::fabs(c->centralMeridianDeg() - k.lon), k.width / 2.0) << k.lon;
    }
    // Just outside 75..135 E (China's west tip is at 73.5 E): the edge zone, up to one
    // zone width from its central meridian.
    const auto west = Crs::gaussKrugerForLon(73.4, 3, true);
    ASSERT_TRUE(west.ok()) << west.error().message;
    EXPECT_EQ(west->epsg(), 4513);
    const auto east = Crs::gaussKrugerForLon(137.0, 3, false);
    ASSERT_TRUE(east.ok()) << east.error().message;
    EXPECT_EQ(east->epsg(), 4554);
    EXPECT_FALSE(Crs::gaussKrugerForLon(10.0, 3, true).ok());
    EXPECT_FALSE(Crs::gaussKrugerForLon(142.0, 6, true).ok());
    EXPECT_FALSE(Crs::gaussKrugerForLon(71.9, 3, false).ok());
    EXPECT_FALSE(Crs::gaussKrugerForLon(105.0, 4, true).ok());
    EXPECT_FALSE(Crs::gaussKrugerForLon(NAN, 3, true).ok());
}

TEST(Crs, ErrorPaths) {
    const Crs gk = crsOrDie(4523);
    const Crs geo = crsOrDie(kGeographic);
    const auto nanLon = gk.fromLonLat(NAN, 30.0);
    ASSERT_FALSE(nanLon.ok());
    EXPECT_NE(nanLon.error().message.find("nan"), std::string::npos) << nanLon.error().message;
    EXPECT_FALSE(gk.fromLonLat(105.0, INFINITY).ok());
    EXPECT_FALSE(gk.toLonLat(-INFINITY, 3e6).ok());
    EXPECT_FALSE(gk.toLonLat(35500000.0, NAN).ok());

    const auto lat95 = gk.fromLonLat(105.0, 95.0);
    ASSERT_FALSE(lat95.ok());
    EXPECT_EQ(lat95.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(lat95.error().message.find("95"), std::string::npos) << lat95.error().message;
    EXPECT_FALSE(convertPoint(geo, gk, {105.0, -95.0, 0.0}).ok());
    EXPECT_FALSE(convertPoint(geo, geo, {105.0, 95.0, 0.0}).ok());
    EXPECT_FALSE(convertPoint(geo, gk, {105.0, 30.0, NAN}).ok());

    // A longitude beyond the zone edge is still projected (up to 3900 km from the CM) ...
    EXPECT_TRUE(gk.fromLonLat(112.0, 30.0).ok());
    // ... but not beyond it, in either direction.
    const auto far = gk.fromLonLat(150.0, 10.0);
    ASSERT_FALSE(far.ok());
    EXPECT_EQ(far.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(far.error().message.find("150"), std::string::npos) << far.error().message;
    // An easting without the zone number (500000 m) is 35,000 km from the CM of zone 35.
    const auto noZone = gk.toLonLat(500000.0, 3e6);
    ASSERT_FALSE(noZone.ok());
    EXPECT_EQ(noZone.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(noZone.error().message.find("500000"), std::string::npos) << noZone.error().message;
    EXPECT_FALSE(gk.toLonLat(35500000.0 + 3.95e6, 3e6).ok());
    EXPECT_FALSE(gk.toLonLat(35500000.0, 1.1e7).ok());  // beyond the pole

    // Projection calls on a CRS that is not projected.
    EXPECT_FALSE(geo.fromLonLat(105.0, 30.0).ok());
    EXPECT_FALSE(Crs::local().toLonLat(0.0, 0.0).ok());

    // Local mixed with a real CRS names both.
    const auto mixed = convertPoint(Crs::local(), gk, {1.0, 2.0, 3.0});
    ASSERT_FALSE(mixed.ok());
    EXPECT_EQ(mixed.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(mixed.error().message.find("local"), std::string::npos) << mixed.error().message;
    EXPECT_NE(mixed.error().message.find("EPSG:4523"), std::string::npos) << mixed.error().message;
    EXPECT_FALSE(convertPoint(geo, Crs::local(), {105.0, 30.0, 0.0}).ok());
}

TEST(Crs, ConvertPointPaths) {
    const Crs gk3 = crsOrDie(4523), gk3cm = crsOrDie(4544), geo = crsOrDie(kGeographic);
    const glm::dvec3 ll(105.7, 31.2, -412.5);  // lon, lat degrees; ellipsoidal height metres
    // local -> local and geographic -> geographic: identity.
    const auto local = convertPoint(Crs::local(), Crs::local(), {1.5, -2.5, 3.5});
    ASSERT_TRUE(local.ok());
    EXPECT_EQ(local.value(), glm::dvec3(1.5, -2.5, 3.5));
    const auto same = convertPoint(geo, geo, ll);
    ASSERT_TRUE(same.ok());
    EXPECT_EQ(same.value(), ll);
    // Geographic -> projected equals fromLonLat; z passes through.
    const auto en = convertPoint(geo, gk3, ll);
    ASSERT_TRUE(en.ok()) << en.error().message;
    const auto direct = gk3.fromLonLat(ll.x, ll.y);
    ASSERT_TRUE(direct.ok());
    EXPECT_EQ(en->x, direct->x);
    EXPECT_EQ(en->y, direct->y);
    EXPECT_EQ(en->z, ll.z);
    // Zone 35 with and without the zone number: same CM, eastings differ by 35,000 km
    // exactly up to rounding of the absolute easting (ulp(3.5e7 m) = 7.5e-9 m).
    const auto cm = convertPoint(gk3, gk3cm, en.value());
    ASSERT_TRUE(cm.ok()) << cm.error().message;
    EXPECT_NEAR(cm->x, en->x - 35e6, kAbsoluteEastingRoundingM);
    EXPECT_NEAR(cm->y, en->y, kAbsoluteEastingRoundingM);
    // Projected -> geographic returns the point (tolerance: round trip, see above).
    const auto back = convertPoint(gk3cm, geo, cm.value());
    ASSERT_TRUE(back.ok());
    EXPECT_NEAR(back->x, ll.x, kRoundTripToleranceM / kMetresPerDegree);
    EXPECT_NEAR(back->y, ll.y, kRoundTripToleranceM / kMetresPerDegree);
    EXPECT_EQ(back->z, ll.z);
}

// ---- geoslice coords, end to end --------------------------------------------------------

CommandResult runCoords(const std::string& args, const std::string& input) {
    TempFile in(input);
    return runCommand(quote(GEOSLICE_BINARY) + " coords " + args + " < " + quote(in.path()) + " 2>/dev/null");
}

// stdout and stderr together.
CommandResult runCoordsWithStderr(const std::string& args, const std::string& input) {
    TempFile in(input);
    return runCommand(quote(GEOSLICE_BINARY) + " coords " + args + " < " + quote(in.path()) + " 2>&1");
}

TEST(CoordsCli, GeographicToGaussKruger) {
    const auto r = runCoords("--from EPSG:4490 --to EPSG:4523", "# lon lat h\n105.5 30.25 500\n\n104.1\t29.9\n");
    ASSERT_EQ(r.exitCode, 0) << r.out;
    const auto lines = splitLines(r.out);
    ASSERT_EQ(lines.size(), 4u) << r.out;
    EXPECT_EQ(lines[0], "# lon lat h");
    EXPECT_EQ(lines[2], "");
    const Crs gk = crsOrDie(4523);
    const glm::dvec2 in[] = {{105.5, 30.25}, {104.1, 29.9}};
    const std::string* outLines[] = {&lines[1], &lines[3]};
    for (int i = 0; i < 2; ++i) {
        double e = 0.0, n = 0.0, z = 0.0;
        const int fields = std::sscanf(outLines[i]->c_str(), "%lf %lf %lf", &e, &n, &z);
        ASSERT_EQ(fields, i == 0 ? 3 : 2) << *outLines[i];
        const auto en = gk.fromLonLat(in[i].x, in[i].y);
        ASSERT_TRUE(en.ok());
        // Printed with 6 decimals: within half a micrometre.
        EXPECT_NEAR(e, en->x, kPrinted6DecimalsM);
        EXPECT_NEAR(n, en->y, kPrinted6DecimalsM);
        if (i == 0) {
            EXPECT_EQ(z, 500.0);
        }
    }
}

TEST(CoordsCli, GaussKrugerToGeographicAndBadLine) {
    const auto r = runCoords("--from 4544 --to epsg:4490", "512345.678 3456789.012\nnot a point\n487000 3300000 12\n");
    EXPECT_EQ(r.exitCode, 1) << r.out;
    const auto lines = splitLines(r.out);
    ASSERT_EQ(lines.size(), 3u) << r.out;
    EXPECT_EQ(lines[1], "*\t*");
    const Crs gk = crsOrDie(4544);
    const glm::dvec2 in[] = {{512345.678, 3456789.012}, {487000.0, 3300000.0}};
    for (int i = 0; i < 2; ++i) {
        double lon = 0.0, lat = 0.0;
        ASSERT_GE(std::sscanf(lines[i * 2].c_str(), "%lf %lf", &lon, &lat), 2) << lines[i * 2];
        const auto ll = gk.toLonLat(in[i].x, in[i].y);
        ASSERT_TRUE(ll.ok());
        // Printed with 10 decimals: within half of 1e-10 degrees.
        EXPECT_NEAR(lon, ll->x, kPrinted10DecimalsDeg);
        EXPECT_NEAR(lat, ll->y, kPrinted10DecimalsDeg);
    }
}

TEST(CoordsCli, BadCrsIsUsageError) {
    EXPECT_EQ(runCoords("--from EPSG:abc --to EPSG:4490", "105 30\n").exitCode, 2);
    EXPECT_EQ(runCoords("--from EPSG:4490 --to EPSG:99999", "105 30\n").exitCode, 2);
    EXPECT_EQ(runCoords("--from local --to EPSG:4490", "105 30\n").exitCode, 2);
}

// ---- CRSs through PROJ ------------------------------------------------------------------

TEST(CrsProj, EpsgCrssBeyondCgcs2000) {
    const Crs lv95 = crsOrDie(2056);
    EXPECT_EQ(lv95.kind(), Crs::Kind::Projected);
    EXPECT_FALSE(lv95.isCgcs2000());
    EXPECT_EQ(lv95.name(), "CH1903+ / LV95");
    EXPECT_EQ(lv95.id(), "EPSG:2056");
    EXPECT_EQ(lv95.geographicId(), "EPSG:4150");
    EXPECT_EQ(lv95.unitName(), "metre");
    EXPECT_EQ(lv95.unitToMetre(), 1.0);
    ASSERT_TRUE(lv95.areaOfUse().has_value());
    EXPECT_TRUE(lv95.areaOfUse()->contains(7.5, 46.8));
    EXPECT_FALSE(lv95.areaOfUse()->contains(105.0, 30.0));
    EXPECT_TRUE(lv95.checkModelCrs().ok());

    const Crs nad27 = crsOrDie(26711);
    EXPECT_EQ(nad27.name(), "NAD27 / UTM zone 11N");
    EXPECT_EQ(nad27.geographicId(), "EPSG:4267");
    EXPECT_EQ(nad27.geographicName(), "NAD27");

    const Crs wgs84 = crsOrDie(4326);
    EXPECT_TRUE(wgs84.isGeographic());
    EXPECT_EQ(wgs84.geographicId(), "EPSG:4326");
    EXPECT_EQ(wgs84.unitName(), "degree");
    EXPECT_FALSE(wgs84.toLonLat(7.0, 46.0).ok());  // not projected

    // CGCS2000 keeps GeographicLib, with EPSG's metadata.
    const Crs gk = crsOrDie(4523);
    EXPECT_TRUE(gk.isGaussKruger());
    EXPECT_TRUE(gk.isCgcs2000());
    EXPECT_EQ(gk.geographicId(), "EPSG:4490");
    ASSERT_TRUE(gk.areaOfUse().has_value());
    EXPECT_TRUE(gk.areaOfUse()->contains(105.0, 30.0));

    // US survey feet: fine for conversions, refused for a model (its coordinates are metres).
    const Crs ftUs = crsOrDie(2227);
    EXPECT_NEAR(ftUs.unitToMetre(), 1200.0 / 3937.0, kUnitFactorTol);  // the definition of the US survey foot
    EXPECT_EQ(ftUs.unitName(), "US survey foot");
    const auto refused = ftUs.checkModelCrs();
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("US survey foot"), std::string::npos) << refused.error().message;
    EXPECT_NE(refused.error().message.find("EPSG:2227"), std::string::npos) << refused.error().message;

    // A compound CRS gives its horizontal part; geocentric and vertical CRSs are refused.
    EXPECT_EQ(crsOrDie(5972).epsg(), 25832);  // ETRS89 / UTM zone 32N + NN2000 height
    for (int code : {4978, 5703}) {
        const auto c = Crs::fromEpsg(code);
        ASSERT_FALSE(c.ok()) << code;
        EXPECT_EQ(c.error().code, ErrorCode::Unsupported);
        EXPECT_NE(c.error().message.find(code == 4978 ? "geocentric" : "vertical"), std::string::npos)
            << c.error().message;
    }
}

TEST(CrsProj, ParseNamesUrnsAndWkt) {
    const std::pair<const char*, int> named[] = {
        {"CH1903 / LV03", 21781},
        {"NAD27 / UTM zone 11N", 26711},
        {"GDA2020 / MGA zone 55", 7855},
        {"urn:ogc:def:crs:EPSG::2056", 2056},
        {"urn:ogc:def:crs:EPSG:9.8.15:2056", 2056},
        {"http://www.opengis.net/def/crs/EPSG/0/2056", 2056},
        {"CGCS2000 / 3-degree Gauss-Kruger zone 35", 4523},
        {"urn:ogc:def:crs:EPSG::4490", 4490},
        {"ETRS89 / UTM zone 32N", 25832},
    };
    for (const auto& [text, code] : named) {
        const auto c = Crs::parse(text);
        ASSERT_TRUE(c.ok()) << text << ": " << c.error().message;
        EXPECT_EQ(c->epsg(), code) << text;
        EXPECT_EQ(c->isGaussKruger(), code == 4523) << text;
    }
    // WKT as projinfo writes it (with its EPSG id) identifies the EPSG CRS.
    const std::string projinfo = findOnPath("projinfo");
    ASSERT_FALSE(projinfo.empty()) << "projinfo (PROJ) not found: run scripts/install-deps.sh (proj-bin)";
    for (const char* format : {"WKT2_2019", "WKT1_GDAL"}) {
        const auto wkt = runCommand(quote(projinfo) + " -q -o " + format + " EPSG:21781");
        ASSERT_EQ(wkt.exitCode, 0);
        const auto c = Crs::parse(wkt.out);
        ASSERT_TRUE(c.ok()) << format << ": " << c.error().message;
        EXPECT_EQ(c->epsg(), 21781) << format;
    }
    // A definition no EPSG CRS matches keeps its WKT as id, and parse(id()) gives it back.
    const auto custom =
        Crs::parse("+proj=tmerc +lat_0=0 +lon_0=9.5 +k=1 +x_0=100000 +y_0=0 +ellps=GRS80 +units=m +type=crs");
    ASSERT_TRUE(custom.ok()) << custom.error().message;
    EXPECT_EQ(custom->epsg(), 0);
    EXPECT_TRUE(custom->isProjected());
    EXPECT_NE(custom->id().find("PROJCRS"), std::string::npos) << custom->id();
    const auto again = Crs::parse(custom->id());
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_TRUE(again.value() == custom.value());
    const auto cm = custom->toLonLat(100000.0, 5e6);  // on the central meridian
    ASSERT_TRUE(cm.ok()) << cm.error().message;
    EXPECT_NEAR(cm->x, 9.5, kOnCentralMeridianDeg);  // exact on the central meridian up to rounding
    // Not CRSs: an operation, garbage.
    for (const char* text : {"+proj=utm +zone=32", "PROJCRS[", "EPSG:4978"}) {
        const auto c = Crs::parse(text);
        EXPECT_FALSE(c.ok()) << text;
    }
}

TEST(CrsProj, AxisOrderIsEastingNorthingAndLonLat) {
    // LV95's projection origin (Bern, x_0 = 2600000 m, y_0 = 1200000 m) is at its lat_0 and
    // lon_0, 46.9524055555556 N 7.43958333333333 E (projinfo EPSG:2056): lon comes first.
    // 1e-9 degrees (0.1 mm) is far above the double-precision error of the oblique
    // Mercator at its origin and far below an axis swap (39 degrees).
    const auto bern = crsOrDie(2056).toLonLat(2600000.0, 1200000.0);
    ASSERT_TRUE(bern.ok()) << bern.error().message;
    EXPECT_NEAR(bern->x, 7.43958333333333, kProjectionOriginDeg);
    EXPECT_NEAR(bern->y, 46.9524055555556, kProjectionOriginDeg);
    const auto back = crsOrDie(2056).fromLonLat(7.43958333333333, 46.9524055555556);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_NEAR(back->x, 2600000.0, kProjectionOriginM);  // 1e-13 degrees of rounding in lat_0/lon_0 is 0.01 mm
    EXPECT_NEAR(back->y, 1200000.0, kProjectionOriginM);
    // GDA2020 geographic (EPSG order lat, lon) -> MGA zone 55 (central meridian 147 E):
    // lon first in, easting first out; on the central meridian the easting is 500000 m.
    const auto mga = convertPoint(crsOrDie(7844), crsOrDie(7855), {147.0, -37.8, 12.5});
    ASSERT_TRUE(mga.ok()) << mga.error().message;
    EXPECT_NEAR(mga->x, 500000.0, kOnCentralMeridianM);  // the conversion is exact on the CM up to rounding
    EXPECT_GT(mga->y, 5.8e6);
    EXPECT_LT(mga->y, 5.82e6);
    EXPECT_EQ(mga->z, 12.5);  // 2D: heights pass through
}

TEST(CrsProj, NetworkIsOff) {
    ::setenv("PROJ_NETWORK", "ON", 1);
    EXPECT_FALSE(crsNetworkAccessEnabled());
    ::unsetenv("PROJ_NETWORK");
}

TEST(CrsProj, ErrorsNameTheProblem) {
    const Crs lv95 = crsOrDie(2056);
    const auto nan = lv95.toLonLat(NAN, 1200000.0);
    ASSERT_FALSE(nan.ok());
    EXPECT_NE(nan.error().message.find("EPSG:2056"), std::string::npos) << nan.error().message;
    EXPECT_FALSE(lv95.fromLonLat(7.0, 95.0).ok());
    EXPECT_FALSE(convertPoint(lv95, crsOrDie(4326), {2600000.0, INFINITY, 0.0}).ok());
    const auto unknown = Crs::parse("EPSG:99999");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("99999"), std::string::npos) << unknown.error().message;
    const auto name = Crs::parse("no such CRS name");
    ASSERT_FALSE(name.ok());
    EXPECT_NE(name.error().message.find("no such CRS name"), std::string::npos) << name.error().message;
    // Outside the area of use: converted, with a warning naming the CRS.
    std::string warning;
    const auto far = convertPoint(crsOrDie(4326), crsOrDie(26711), {-117.0, 10.0, 0.0}, &warning);
    ASSERT_TRUE(far.ok()) << far.error().message;
    EXPECT_NE(warning.find("outside the area of use of EPSG:26711"), std::string::npos) << warning;
    warning.clear();
    ASSERT_TRUE(convertPoint(crsOrDie(4326), crsOrDie(26711), {-117.0, 34.0, 0.0}, &warning).ok());
    EXPECT_EQ(warning, "");
}

// The transformation a model's query answers use to WGS 84 (CatalogModel::toWgs84).
TEST(CrsProj, Wgs84TransformForAnArea) {
    const Crs wgs84 = crsOrDie(4326);
    // SCEC faults (NAD27 / UTM 11N) around Los Angeles: a stated accuracy, and the same
    // operation cs2cs picks for points there, so the same numbers (1e-9 degrees: both
    // run the same PROJ pipeline; the margin covers cs2cs printing 10 decimals).
    const LonLatBox la{-118.6, 33.7, -117.6, 34.4};
    auto t = CrsTransform::forArea(crsOrDie(26711), wgs84, la);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_FALSE(t->isBallpark()) << t->operationName();
    EXPECT_GT(t->accuracyM(), 0.0) << t->operationName();
    std::printf("NAD27 / UTM 11N -> WGS 84 over Los Angeles: %s, %g m\n", t->operationName().c_str(), t->accuracyM());
    const std::vector<glm::dvec2> pts = {{380000.0, 3770000.0}, {420000.0, 3760000.0}, {400123.5, 3740000.25}};
    std::string input;
    // The same height as below: a Helmert shift through geocentric coordinates uses it
    // (100 m moves the longitude by 1.4e-8 degrees here) and PROJ restores it afterwards.
    for (const auto& p : pts) input += std::to_string(p.x) + " " + std::to_string(p.y) + " 100\n";
    const auto out = runCs2csArgs("-s EPSG:26711 EPSG:4326", input);
    ASSERT_EQ(out.size(), pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto g = t->apply({pts[i], 100.0});
        ASSERT_TRUE(g.ok()) << g.error().message;
        double lon = 0.0, lat = 0.0;
        ASSERT_EQ(std::sscanf(out[i].c_str(), "%lf %lf", &lon, &lat), 2) << out[i];
        EXPECT_NEAR(g->x, lon, kSamePipelineDeg) << t->operationName();
        EXPECT_NEAR(g->y, lat, kSamePipelineDeg) << t->operationName();
        EXPECT_EQ(g->z, 100.0);
    }
    // Swiss LV95: CH1903+ to WGS 84 (1), stated 1 m.
    auto swiss = CrsTransform::forArea(crsOrDie(2056), wgs84, {7.3, 46.8, 7.6, 47.0});
    ASSERT_TRUE(swiss.ok()) << swiss.error().message;
    EXPECT_FALSE(swiss->isBallpark());
    EXPECT_EQ(swiss->accuracyM(), 1.0) << swiss->operationName();
    // CGCS2000: PROJ's database has only a ballpark offset to WGS 84, which answers omit.
    auto china = CrsTransform::forArea(crsOrDie(4523), wgs84, {104.9, 30.5, 105.2, 30.7});
    ASSERT_TRUE(china.ok()) << china.error().message;
    EXPECT_TRUE(china->isBallpark()) << china->operationName();
}

// Many threads converting at once: PROJ contexts are per slot (model/crs/proj_pool.hpp), so
// every thread gets the single-threaded answer bit for bit.
TEST(CrsProj, ConcurrentConversionsAgree) {
    const Crs lv95 = crsOrDie(2056), nad27 = crsOrDie(26711), wgs84 = crsOrDie(4326);
    auto t = CrsTransform::forArea(nad27, wgs84, {-118.6, 33.7, -117.6, 34.4});
    ASSERT_TRUE(t.ok());
    constexpr int kPoints = 500;
    auto point = [](int i) { return glm::dvec2(2600000.0 + 37.5 * i, 1200000.0 - 11.25 * i); };
    auto utm = [](int i) { return glm::dvec3(380000.0 + 41.0 * i, 3740000.0 + 17.0 * i, 0.0); };
    std::vector<glm::dvec2> expectLl(kPoints);
    std::vector<glm::dvec3> expectWgs(kPoints);
    for (int i = 0; i < kPoints; ++i) {
        expectLl[i] = lv95.toLonLat(point(i).x, point(i).y).value();
        expectWgs[i] = t->apply(utm(i)).value();
    }
    std::vector<std::thread> threads;
    std::atomic<int> mismatches{0};
    for (int k = 0; k < 8; ++k) {
        threads.emplace_back([&] {
            for (int round = 0; round < 4; ++round)
                for (int i = 0; i < kPoints; ++i) {
                    const auto ll = lv95.toLonLat(point(i).x, point(i).y);
                    const auto g = t->apply(utm(i));
                    if (!ll.ok() || !g.ok() || ll.value() != expectLl[i] || g.value() != expectWgs[i]) ++mismatches;
                }
        });
    }
    for (auto& th : threads) th.join();
    EXPECT_EQ(mismatches.load(), 0);
}

// ---- geoslice coords against cs2cs --------------------------------------------------

struct CoordsCase {
    const char* from;
    const char* to;
    const char* cs2csFlags;  // -r / -s where EPSG's order is lat,lon or northing,easting
    bool toGeographic;
    std::vector<glm::dvec3> points;  // geoslice order
};

TEST(CoordsCli, MatchesCs2cs) {
    const std::vector<CoordsCase> cases = {
        // LV03 <-> LV95 (both easting, northing in EPSG too)
        {"EPSG:21781",
         "EPSG:2056",
         "",
         false,
         {{600000, 200000, 500}, {683000.5, 247000.25, 0}, {560000, 130000, 1200}}},
        {"EPSG:2056", "EPSG:21781", "", false, {{2600000, 1200000, 500}, {2750000.125, 1250000, 0}}},
        // NAD27 / UTM 11N (SCEC) <-> WGS 84 (lat, lon in EPSG)
        {"EPSG:26711",
         "EPSG:4326",
         "-s",
         true,
         {{380000, 3770000, 0}, {500000, 3800000, 100}, {420000, 3650000, -2000}}},
        {"EPSG:4326", "EPSG:26711", "-r", false, {{-118.3, 34.06, 0}, {-117.0, 33.5, 10}}},
        // GDA2020 / MGA zone 55 <-> GDA2020 geographic
        {"EPSG:7855", "EPSG:7844", "-s", true, {{320000, 5812000, 0}, {500000, 6000000, 50}, {710000, 5600000, 0}}},
        {"EPSG:7844", "EPSG:7855", "-r", false, {{144.96, -37.81, 0}, {147.5, -42.9, 0}}},
        // CGCS2000 Gauss-Kruger zone 35 <-> CGCS2000 (both in EPSG order lat/northing first)
        {"EPSG:4523", "EPSG:4490", "-r -s", true, {{35500000, 3388000, 0}, {35612345.678, 3900000, 10}}},
        {"EPSG:4490", "EPSG:4523", "-r -s", false, {{105.05, 30.62, 0}, {103.7, 36.1, 0}}},
        // A UTM zone pair on WGS 84
        {"EPSG:32632", "EPSG:32633", "", false, {{700000, 5300000, 0}, {650000.5, 5000000.5, 0}}},
        // US survey feet in and out (California zone 3)
        {"EPSG:2227", "EPSG:4269", "-s", true, {{6000000, 2100000, 0}, {6100000.5, 2000000, 0}}},
    };
    double worstM = 0.0, worstDeg = 0.0;
    int compared = 0;
    for (const auto& c : cases) {
        std::string input;
        char line[160];
        for (const auto& p : c.points) {
            std::snprintf(line, sizeof line, "%.10f %.10f %.6f\n", p.x, p.y, p.z);
            input += line;
        }
        const auto ours = runCoords(std::string("--from ") + c.from + " --to " + c.to, input);
        ASSERT_EQ(ours.exitCode, 0) << c.from << " -> " << c.to << ":\n" << ours.out;
        const auto theirs = runCs2csArgs(std::string(c.cs2csFlags) + " " + c.from + " " + c.to, input);
        const auto oursLines = splitLines(ours.out);
        ASSERT_EQ(oursLines.size(), c.points.size()) << ours.out;
        ASSERT_EQ(theirs.size(), c.points.size());
        for (std::size_t i = 0; i < c.points.size(); ++i) {
            double ax = 0, ay = 0, az = 0, bx = 0, by = 0, bz = 0;
            ASSERT_EQ(std::sscanf(oursLines[i].c_str(), "%lf %lf %lf", &ax, &ay, &az), 3) << oursLines[i];
            ASSERT_EQ(std::sscanf(theirs[i].c_str(), "%lf %lf %lf", &bx, &by, &bz), 3) << theirs[i];
            // Metres: we print 6 decimals (5e-7 m rounding), cs2cs 10: 1e-6 m holds both.
            // Degrees: we print 10 decimals, cs2cs 10: 1e-9 degrees (0.1 mm) holds both.
            const double tol = c.toGeographic ? kCoordsVsCs2csDeg : kCoordsVsCs2csM;
            EXPECT_NEAR(ax, bx, tol) << c.from << " -> " << c.to << " point " << i;
            EXPECT_NEAR(ay, by, tol) << c.from << " -> " << c.to << " point " << i;
            EXPECT_NEAR(az, bz, kCoordsVsCs2csM) << c.from << " -> " << c.to << " point " << i;
            const double d = std::max(std::fabs(ax - bx), std::fabs(ay - by));
            (c.toGeographic ? worstDeg : worstM) = std::max(c.toGeographic ? worstDeg : worstM, d);
            ++compared;
        }
    }
    std::printf("coords vs cs2cs: %d points, max difference %.3g m (projected), %.3g degrees (geographic)\n", compared,
                worstM, worstDeg);
    EXPECT_GE(compared, 20);
}

TEST(CoordsCli, WarningsAndBadInput) {
    // Outside NAD27 / UTM 11N's area of use: converted, warned, exit 0.
    const auto far = runCoordsWithStderr("--from EPSG:4326 --to EPSG:26711", "-117 10\n");
    EXPECT_EQ(far.exitCode, 0) << far.out;
    EXPECT_NE(far.out.find("outside the area of use of EPSG:26711"), std::string::npos) << far.out;
    // Non-finite numbers: "*\t*", exit 1, the line named.
    const auto bad = runCoordsWithStderr("--from EPSG:2056 --to EPSG:4326", "nan 1200000\n2600000 inf\n");
    EXPECT_EQ(bad.exitCode, 1) << bad.out;
    EXPECT_NE(bad.out.find("line 1"), std::string::npos) << bad.out;
    EXPECT_NE(bad.out.find("not finite"), std::string::npos) << bad.out;
    // A pair PROJ links only by a ballpark offset is said so before any output.
    const auto ballpark = runCoordsWithStderr("--from EPSG:4490 --to EPSG:4326", "105 30\n");
    EXPECT_EQ(ballpark.exitCode, 0) << ballpark.out;
    EXPECT_NE(ballpark.out.find("ballpark"), std::string::npos) << ballpark.out;
    // Unknown codes and names are usage errors.
    EXPECT_EQ(runCoords("--from EPSG:2056 --to EPSG:99999", "1 2\n").exitCode, 2);
    EXPECT_EQ(runCoords("--from 'no such CRS' --to EPSG:4326", "1 2\n").exitCode, 2);
}

}  // namespace
}  // namespace geoslice
