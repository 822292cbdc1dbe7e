// One lon/lat envelope of a model (model/crs/crs.hpp lonLatBoxOf): `geoslice info` and
// GET /v1/models/{id}'s lonlatBounds give the same box, and it is the envelope of the box's
// edges as PROJ's own cs2cs (proj-bin) computes it from 2,000 points an edge. On a Swiss
// model in LV03 (EPSG:21781) the two-corner box once used by the API cut ~100 m off.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "model/io/loaders.hpp"
#include "tests/common/run_command.hpp"

using namespace geoslice;

namespace {

struct Box {
    double west = 1e9, south = 1e9, east = -1e9, north = -1e9;
};

// cs2cs's envelope of the edges of [x0,x1] x [y0,y1] from EPSG:21781 to its own datum's
// lon/lat (CH1903, EPSG:4149; cs2cs prints EPSG:4149 in its axis order, latitude first).
Box cs2csEnvelope(double x0, double y0, double x1, double y1) {
    const std::filesystem::path in = std::filesystem::temp_directory_path() / "geoslice_lonlat_cs2cs.txt";
    {
        std::ofstream f(in);
        f.precision(17);
        const int n = 2000;
        for (int k = 0; k <= n; ++k) {
            const double t = double(k) / n;
            f << x0 + t * (x1 - x0) << " " << y0 << "\n" << x0 + t * (x1 - x0) << " " << y1 << "\n";
            f << x0 << " " << y0 + t * (y1 - y0) << "\n" << x1 << " " << y0 + t * (y1 - y0) << "\n";
        }
    }
    const test::CmdResult r = test::runCommand("cs2cs -f %.12f EPSG:21781 EPSG:4149 < " + in.string());
    std::filesystem::remove(in);
    EXPECT_EQ(r.exitCode, 0);
    Box b;
    std::istringstream lines(r.out);
    double lat = 0, lon = 0, h = 0;
    int count = 0;
    while (lines >> lat >> lon >> h) {
        b.west = std::min(b.west, lon);
        b.east = std::max(b.east, lon);
        b.south = std::min(b.south, lat);
        b.north = std::max(b.north, lat);
        ++count;
    }
    EXPECT_EQ(count, 4 * 2001);
    return b;
}

}  // namespace

TEST(LonLatEnvelope, InfoAndApiAgreeWithCs2cs) {
    if (test::runCommand("command -v cs2cs >/dev/null").exitCode != 0) GTEST_SKIP() << "cs2cs (proj-bin) not installed";
    // A 40 km x 30 km model near Bern in LV03: an OBJ box with a .crs sidecar.
    const double x0 = 580000, y0 = 180000, x1 = 620000, y1 = 210000;
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "geoslice_lonlat_test";
    std::filesystem::create_directories(dir);
    {
        std::ofstream obj(dir / "swiss.obj");
        obj.precision(17);
        for (int c = 0; c < 8; ++c)
            obj << "v " << ((c & 1) ? x1 : x0) << " " << ((c & 2) ? y1 : y0) << " " << ((c & 4) ? 900.0 : 400.0)
                << "\n";
        obj << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
        std::ofstream(dir / "swiss.crs") << "EPSG:21781\n";
    }
    const Box want = cs2csEnvelope(x0, y0, x1, y1);

    const test::CmdResult info = test::runGeoslice("info --json " + (dir / "swiss.obj").string());
    ASSERT_EQ(info.exitCode, 0) << info.out;
    const nlohmann::json j = nlohmann::json::parse(info.out, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << info.out;
    const nlohmann::json& first = j.is_array() ? j[0] : j;
    ASSERT_TRUE(first.contains("lonlat_bounds")) << info.out;
    const auto& ib = first["lonlat_bounds"];

    auto model = loadModel((dir / "swiss.obj").string());
    ASSERT_TRUE(model.ok()) << model.error().message;
    auto cm = api::catalogModelOf("swiss", std::move(model.value()), "v1", api::RayBuild::Deferred);
    ASSERT_TRUE(cm.ok()) << cm.error().message;
    const auto api = cm.value()->summary()["lonlatBounds"];
    ASSERT_TRUE(api.is_object());

    // The same numbers from both (one function), and cs2cs's envelope to 1e-7 degree (~1 cm):
    // densifying 64 steps an edge misses a curved edge's extreme by far less than that here.
    for (int k = 0; k < 2; ++k) {
        EXPECT_EQ(ib["min"][k].get<double>(), api["min"][k].get<double>());
        EXPECT_EQ(ib["max"][k].get<double>(), api["max"][k].get<double>());
    }
    EXPECT_NEAR(api["min"][0].get<double>(), want.west, 1e-7);
    EXPECT_NEAR(api["max"][0].get<double>(), want.east, 1e-7);
    EXPECT_NEAR(api["min"][1].get<double>(), want.south, 1e-7);
    EXPECT_NEAR(api["max"][1].get<double>(), want.north, 1e-7);

    // What two corners alone give: the box the API used to report, for the record.
    const Box sw = cs2csEnvelope(x0, y0, x0, y0), ne = cs2csEnvelope(x1, y1, x1, y1);
    const double cutWestM = (sw.west - want.west) * 111320.0 * std::cos(want.south * M_PI / 180.0);
    const double cutNorthM = (want.north - ne.north) * 111320.0;
    std::printf("lonlat envelope: two corners miss %.1f m on the west side and %.1f m on the north\n", cutWestM,
                cutNorthM);
    std::filesystem::remove_all(dir);
}
