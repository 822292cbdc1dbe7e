// The coordinates in query answers (api/view.cpp writeWorldPoint via worldPointJson): for a
// model in a PROJ CRS (LV95), lon/lat on its own datum and WGS 84 equal cs2cs's; for a
// CGCS2000 model, no WGS 84 (PROJ has only a ballpark) but a note; for a local model, a note.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "api/catalog.hpp"
#include "api/pixel_query.hpp"
#include "api/view.hpp"
#include "tests/common/tolerances.hpp"

namespace geoslice {
namespace {

namespace fs = std::filesystem;
using test::kSamePipelineDeg;  // degrees, against cs2cs running the same PROJ operation

class TempDir {
public:
    TempDir() {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/geoslice_query_coords_XXXXXX";
        GS_ASSERT(mkdtemp(pattern.data()) != nullptr, "mkdtemp failed");
        path_ = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    std::string file(const std::string& name, const std::string& contents) const {
        const std::string p = (fs::path(path_) / name).string();
        std::ofstream(p, std::ios::binary) << contents;
        return p;
    }

private:
    std::string path_;
};

// A closed, outward tetrahedron with one corner at (x, y, 500), 100 m edges.
std::string tetra(double x, double y) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "o Rock\nv %.3f %.3f 500\nv %.3f %.3f 500\nv %.3f %.3f 500\nv %.3f %.3f 600\n"
                  "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
                  x, y, x + 100, y, x, y + 100, x, y);
    return buf;
}

// cs2cs -f %.10f ARGS on one line of input: the first two numbers it prints.
glm::dvec2 cs2cs(const std::string& args, const std::string& line) {
    const std::string cmd = "echo '" + line + "' | cs2cs -f %.10f " + args;
    FILE* p = popen(cmd.c_str(), "r");
    GS_ASSERT(p != nullptr, "popen failed");
    double a = NAN, b = NAN;
    const int n = std::fscanf(p, "%lf %lf", &a, &b);
    pclose(p);
    EXPECT_EQ(n, 2) << cmd << " (is proj-bin installed? scripts/install-deps.sh)";
    return {a, b};
}

TEST(QueryCoords, Lv95ModelGivesOwnDatumAndWgs84) {
    TempDir dir;
    const std::string obj = dir.file("bern.obj", tetra(2600000.0, 1200000.0));
    dir.file("bern.crs", "EPSG:2056\n");
    auto m = api::loadCatalogModel("bern", obj);
    ASSERT_TRUE(m.ok()) << m.error().message;
    const auto& model = *m.value();
    ASSERT_NE(model.toWgs84, nullptr) << model.wgs84Note;
    const auto summary = model.summary();
    EXPECT_EQ(summary["crs"]["id"], "EPSG:2056");
    EXPECT_EQ(summary["crs"]["geographic"]["id"], "EPSG:4150");
    EXPECT_EQ(summary["crs"]["wgs84"]["accuracyM"].get<double>(), 1.0);  // CH1903+ to WGS 84 (1)

    const glm::dvec3 p(2600010.5, 1200020.25, 550.0);
    const auto w = api::worldPointJson(model, p);
    EXPECT_EQ(w["projected"]["easting"].get<double>(), p.x);
    EXPECT_FALSE(w["projected"].contains("zone"));
    // Own datum: CH1903+ (EPSG:4150), lon first; cs2cs (EPSG order lat, lon; -s swaps).
    // 1e-9 degrees: both are PROJ's same conversion, cs2cs prints 10 decimals.
    EXPECT_EQ(w["geodetic"]["crs"], "EPSG:4150");
    const glm::dvec2 own = cs2cs("-s EPSG:2056 EPSG:4150", "2600010.5 1200020.25");
    EXPECT_NEAR(w["geodetic"]["lon"].get<double>(), own.x, kSamePipelineDeg);
    EXPECT_NEAR(w["geodetic"]["lat"].get<double>(), own.y, kSamePipelineDeg);
    // WGS 84 through the operation chosen for the model, the one cs2cs uses here too.
    ASSERT_TRUE(w.contains("wgs84")) << w.dump();
    // With the same height: the Helmert shift through geocentric coordinates uses it.
    const glm::dvec2 wgs = cs2cs("-s EPSG:2056 EPSG:4326", "2600010.5 1200020.25 550");
    EXPECT_NEAR(w["wgs84"]["lon"].get<double>(), wgs.x, kSamePipelineDeg);
    EXPECT_NEAR(w["wgs84"]["lat"].get<double>(), wgs.y, kSamePipelineDeg);
    EXPECT_EQ(w["wgs84"]["accuracyM"].get<double>(), 1.0);
    EXPECT_EQ(w["wgs84"]["height"].get<double>(), 550.0);
}

TEST(QueryCoords, Cgcs2000ModelOmitsBallparkWgs84) {
    TempDir dir;
    const std::string obj = dir.file("mine.obj", tetra(35504000.0, 3388000.0));
    dir.file("mine.attributes.json", R"({"crs": "EPSG:4523"})");
    auto m = api::loadCatalogModel("mine", obj);
    ASSERT_TRUE(m.ok()) << m.error().message;
    const auto w = api::worldPointJson(*m.value(), {35504010.0, 3388010.0, 520.0});
    EXPECT_EQ(w["projected"]["zone"], 35);
    EXPECT_EQ(w["geodetic"]["crs"], "EPSG:4490");
    EXPECT_FALSE(w.contains("wgs84")) << w.dump();
    EXPECT_NE(w["wgs84Note"].get<std::string>().find("ballpark"), std::string::npos) << w.dump();
}

TEST(QueryCoords, LocalModelSaysSo) {
    TempDir dir;
    auto m = api::loadCatalogModel("plain", dir.file("plain.obj", tetra(0.0, 0.0)));
    ASSERT_TRUE(m.ok()) << m.error().message;
    const auto w = api::worldPointJson(*m.value(), {10.0, 10.0, 520.0});
    EXPECT_EQ(w["crs"], "local");
    EXPECT_TRUE(w.contains("projectedNote"));
    EXPECT_FALSE(w.contains("geodetic"));
    EXPECT_FALSE(w.contains("wgs84"));
    EXPECT_FALSE(w.contains("wgs84Note"));
}

}  // namespace
}  // namespace geoslice
