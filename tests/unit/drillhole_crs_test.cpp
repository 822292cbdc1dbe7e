// Drillholes in another CRS than the model's (model/drillholes placeDrillholes): collars and
// desurveyed nodes converted as PROJ's cs2cs converts them (UTM 48N and CGCS2000 geographic
// to CGCS2000 / Gauss-Kruger zone 35), elevations kept, an inclined hole's direction turned
// with the grid so that its converted end is where the hole ends; a model without a CRS keeps
// the coordinates with a warning; a CRS PROJ does not know is refused, named.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "model/drillholes/drillholes.hpp"
#include "tests/common/run_command.hpp"

namespace geoslice {
namespace {

namespace fs = std::filesystem;

// cs2cs prints 10 decimals and runs the same PROJ operation: well under a millimetre.
constexpr double kSameOperationM = 1e-3;

struct Files {
    fs::path dir = fs::temp_directory_path() / ("geoslice_hole_crs_" + std::to_string(::getpid()));
    Files() {
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~Files() { fs::remove_all(dir); }
    void write(const std::string& name, const std::string& text) { std::ofstream(dir / name) << text; }
};

// x y in `from` (its API order: easting northing, or lon lat) -> EPSG:4523 easting northing.
std::pair<double, double> cs2cs(const char* from, double x, double y, bool geographic) {
    char cmd[256];
    // cs2cs takes and gives EPSG's axis order: lat lon for geographic, northing easting for 4523.
    std::snprintf(cmd, sizeof cmd, "echo '%.12f %.12f' | cs2cs -f %%.10f %s EPSG:4523", geographic ? y : x,
                  geographic ? x : y, from);
    std::istringstream in(test::runCommand(cmd).out);
    double n = 0.0, e = 0.0;
    in >> n >> e;
    return {e, n};
}

Aabb zone35Box() {
    Aabb b;
    b.min = {35500000.0, 3385000.0, -1000.0};
    b.max = {35510000.0, 3392000.0, 2000.0};
    return b;
}

TEST(DrillholeCrs, HolesInUtmAreConvertedAsCs2csConvertsThem) {
    // Two holes near 105.05E 30.62N in UTM 48N (EPSG:32648): DH1 vertical, DH2 at azimuth 45,
    // dip -60, 400 m long.
    const auto c1 = std::pair{576300.0, 3387800.0}, c2 = std::pair{577100.0, 3388400.0};
    Files f;
    char collar[256];
    std::snprintf(collar, sizeof collar, "hole,x,y,z,depth\nDH1,%.3f,%.3f,900,300\nDH2,%.3f,%.3f,950,400\n", c1.first,
                  c1.second, c2.first, c2.second);
    f.write("collar.csv", collar);
    f.write("survey.csv", "hole,depth,azimuth,dip\nDH2,0,45,-60\n");
    f.write("m.drillholes.json", R"({"crs": "EPSG:32648", "collar": "collar.csv", "survey": "survey.csv"})");
    auto db = loadDrillholes((f.dir / "m.drillholes.json").string());
    ASSERT_TRUE(db) << db.error().message;
    const DrillholeDatabase before = db.value();
    auto s = placeDrillholes(db.value(), Crs::fromEpsg(4523).value(), zone35Box());
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_NE(db.value().conversion.find("EPSG:32648"), std::string::npos) << db.value().conversion;
    for (std::size_t h = 0; h < 2; ++h) {
        const Drillhole& a = db.value().holes[h];
        const Drillhole& b = before.holes[h];
        const auto [e, n] = cs2cs("EPSG:32648", b.collar.x, b.collar.y, false);
        EXPECT_NEAR(a.collar.x, e, kSameOperationM) << a.id;
        EXPECT_NEAR(a.collar.y, n, kSameOperationM) << a.id;
        EXPECT_DOUBLE_EQ(a.collar.z, b.collar.z);
        ASSERT_EQ(a.path.position.size(), b.path.position.size());
        for (std::size_t i = 0; i < a.path.position.size(); ++i) {
            const auto [pe, pn] = cs2cs("EPSG:32648", b.path.position[i].x, b.path.position[i].y, false);
            EXPECT_NEAR(a.path.position[i].x, pe, kSameOperationM) << a.id << " node " << i;
            EXPECT_NEAR(a.path.position[i].y, pn, kSameOperationM) << a.id << " node " << i;
            EXPECT_DOUBLE_EQ(a.path.position[i].z, b.path.position[i].z);
        }
    }
    // The inclined hole: the converted direction leads to the converted end (a straight hole).
    const Drillhole& h = db.value().holes[1];
    const glm::dvec3 end = h.path.at(400.0);
    const auto [ee, en] =
        cs2cs("EPSG:32648", before.holes[1].path.at(400.0).x, before.holes[1].path.at(400.0).y, false);
    // 400 m along a direction turned at the collar: the grid scale change between the two
    // projections (about 4e-4 here) moves the end by some 0.1 m, far below a metre.
    EXPECT_NEAR(end.x, ee, 0.5);
    EXPECT_NEAR(end.y, en, 0.5);
}

TEST(DrillholeCrs, GeographicCollarsTheModelsOwnALocalModelAndAnUnknownCrs) {
    Files f;
    f.write("collar.csv", "hole,x,y,z,depth\nDH1,105.041,30.615,900,300\n");
    f.write("g.drillholes.json", R"({"crs": "EPSG:4490", "collar": "collar.csv"})");
    auto db = loadDrillholes((f.dir / "g.drillholes.json").string());
    ASSERT_TRUE(db) << db.error().message;
    auto s = placeDrillholes(db.value(), Crs::fromEpsg(4523).value(), zone35Box());
    ASSERT_TRUE(s) << s.error().message;
    const auto [e, n] = cs2cs("EPSG:4490", 105.041, 30.615, true);
    EXPECT_NEAR(db.value().holes[0].collar.x, e, kSameOperationM);
    EXPECT_NEAR(db.value().holes[0].collar.y, n, kSameOperationM);

    f.write("same.drillholes.json", R"({"crs": "EPSG:4523", "collar": "collar.csv"})");
    auto same = loadDrillholes((f.dir / "same.drillholes.json").string());
    ASSERT_TRUE(same);
    ASSERT_TRUE(placeDrillholes(same.value(), Crs::fromEpsg(4523).value(), zone35Box()));
    EXPECT_EQ(same.value().holes[0].collar.x, 105.041);  // the model's own: untouched
    EXPECT_TRUE(same.value().conversion.empty());

    auto local = loadDrillholes((f.dir / "g.drillholes.json").string());
    ASSERT_TRUE(local);
    ASSERT_TRUE(placeDrillholes(local.value(), Crs::local(), zone35Box()));
    ASSERT_FALSE(local.value().warnings.empty());
    EXPECT_NE(local.value().warnings.back().message.find("the model has no CRS"), std::string::npos);

    f.write("bad.drillholes.json", R"({"crs": "EPSG:999999", "collar": "collar.csv"})");
    auto bad = loadDrillholes((f.dir / "bad.drillholes.json").string());
    ASSERT_TRUE(bad);
    auto refused = placeDrillholes(bad.value(), Crs::fromEpsg(4523).value(), zone35Box());
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("EPSG:999999"), std::string::npos) << refused.error().message;
}

}  // namespace
}  // namespace geoslice
