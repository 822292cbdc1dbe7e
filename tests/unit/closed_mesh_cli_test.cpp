// The inward cube of the bug report through the real executable: a closed 0..10 cube whose
// 12 triangles face inward (as many exporters write them) must load as one closed shell of
// 1000 m3, and `info`, `classify`, `section --areas` and `reserves` must answer as for the
// same cube wound outward; also at Gauss-Kruger coordinates, and for two cubes sharing an
// edge wound one each way.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/common/run_command.hpp"

// Relative: volumes and areas of cubes with integer corners are exact in double; the JSON
// prints them with 17 significant digits.
constexpr double kRelTol = 1e-9;

namespace {

using geoslice::test::CmdResult;
using geoslice::test::runCommand;
using geoslice::test::runGeoslice;
using nlohmann::json;

// The cube 0..10 (+ offset) as an OBJ, wound inward (the file of the report) or outward.
std::string cubeObj(bool inward, double ox = 0.0, double oy = 0.0, double oz = 0.0, int firstVertex = 1,
                    bool withVertices = true) {
    static const int kInward[12][3] = {{1, 7, 3}, {1, 5, 7}, {2, 8, 6}, {2, 4, 8}, {1, 6, 5}, {1, 2, 6},
                                       {3, 8, 4}, {3, 7, 8}, {1, 4, 2}, {1, 3, 4}, {5, 8, 7}, {5, 6, 8}};
    std::ostringstream s;
    s.precision(17);
    if (withVertices)
        for (int i = 0; i < 8; ++i)
            s << "v " << ox + ((i & 4) ? 10 : 0) << ' ' << oy + ((i & 2) ? 10 : 0) << ' ' << oz + ((i & 1) ? 10 : 0)
              << '\n';
    for (const auto& f : kInward) {
        const int a = f[0] + firstVertex - 1, b = f[1] + firstVertex - 1, c = f[2] + firstVertex - 1;
        s << "f " << a << ' ' << (inward ? b : c) << ' ' << (inward ? c : b) << '\n';
    }
    return s.str();
}

class ClosedMeshCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir = std::filesystem::temp_directory_path() / ("gs_closed_cli_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) {
        const std::string path = (dir / name).string();
        std::ofstream(path) << text;
        return path;
    }
    // `geoslice classify` of the points (one "x y z" per line): the answers, one per line.
    std::string classify(const std::string& model, const std::string& points) {
        const std::string in = write("points.txt", points);
        CmdResult r = runCommand(std::string(GEOSLICE_BINARY) + " classify " + model + " < " + in + " 2>/dev/null");
        EXPECT_EQ(r.exitCode, 0);
        return r.out;
    }
    std::filesystem::path dir;
};

void expectRel(double got, double want, const std::string& what) {
    EXPECT_NEAR(got, want, kRelTol * std::abs(want)) << what;
}

}  // namespace

TEST_F(ClosedMeshCli, InwardAndOutwardCubeAnswerAlike) {
    for (bool inward : {true, false}) {
        SCOPED_TRACE(inward ? "inward" : "outward");
        const std::string obj = write(inward ? "cube_in.obj" : "cube_out.obj", cubeObj(inward));

        CmdResult info = runGeoslice("info --json " + obj);
        ASSERT_EQ(info.exitCode, 0) << info.out;
        const json j = json::parse(info.out);
        ASSERT_EQ(j["bodies"].size(), 1u);
        const json& body = j["bodies"][0];
        EXPECT_TRUE(body["closed"].get<bool>());
        EXPECT_EQ(body["components"], 1);
        EXPECT_EQ(body["flipped"], inward);
        expectRel(body["volume_m3"].get<double>(), 1000.0, "info volume");
        for (const auto& issue : j["issues"]) {
            const std::string m = issue["message"];
            EXPECT_EQ(m.find("pinch"), std::string::npos) << m;  // the bug said "split at 0 edges and 2 vertices"
            EXPECT_NE(issue["severity"], "error") << m;
        }
        CmdResult text = runGeoslice("info " + obj);
        EXPECT_NE(text.out.find("closed  1000 m3"), std::string::npos) << text.out;

        // Inside, outside, and inside near each face and corner.
        EXPECT_EQ(classify(obj, "5 5 5\n15 5 5\n5 5 -1\n0.5 5 5\n9.5 9.5 9.5\n5 0.01 5\n"), "1\n0\n0\n1\n1\n1\n");

        CmdResult section = runGeoslice("section " + obj + " --plane 0,1,0,-5 --areas --size 16x16");
        ASSERT_EQ(section.exitCode, 0) << section.out;
        const json s = json::parse(section.out);
        ASSERT_EQ(s["bodies"].size(), 1u);
        expectRel(s["bodies"][0]["area_m2"].get<double>(), 100.0, "section area");
        EXPECT_EQ(s["bodies"][0]["polygons"], 1);
        EXPECT_EQ(s["bodies"][0]["open_chains"], 0);
        // A horizontal and an oblique plane through the centre: 100 m2 and 100 sqrt(2) m2.
        const json h = json::parse(runGeoslice("section " + obj + " --elevation 3 --areas --size 16x16").out);
        expectRel(h["bodies"][0]["area_m2"].get<double>(), 100.0, "horizontal section");
        const json o = json::parse(runGeoslice("section " + obj + " --plane 1,0,1,-10 --areas --size 16x16").out);
        expectRel(o["bodies"][0]["area_m2"].get<double>(), 100.0 * std::sqrt(2.0), "oblique section");

        CmdResult reserves = runGeoslice("reserves --json " + obj);
        ASSERT_EQ(reserves.exitCode, 0) << reserves.out;
        const json r = json::parse(reserves.out);
        ASSERT_EQ(r["bodies"].size(), 1u);
        expectRel(r["bodies"][0]["gross_volume_m3"].get<double>(), 1000.0, "reserves");
        expectRel(r["bodies"][0]["gross_volume_m3"].get<double>(), body["volume_m3"].get<double>(), "reserves = info");
        const json half = json::parse(runGeoslice("reserves --json --plane 0,1,0,-5 " + obj).out);
        expectRel(half["bodies"][0]["gross_volume_m3"].get<double>(), 500.0, "reserves of the kept half");
    }
}

// The same cube at a Gauss-Kruger easting and northing (zone number in the false easting).
TEST_F(ClosedMeshCli, InwardCubeAtGaussKrugerCoordinates) {
    const double ox = 35500000.0, oy = 3400000.0, oz = -500.0;
    const std::string obj = write("cube_gk.obj", cubeObj(true, ox, oy, oz));
    const json j = json::parse(runGeoslice("info --json " + obj).out);
    ASSERT_EQ(j["bodies"].size(), 1u);
    EXPECT_EQ(j["bodies"][0]["components"], 1);
    expectRel(j["bodies"][0]["volume_m3"].get<double>(), 1000.0, "info volume");
    EXPECT_EQ(classify(obj, "35500005 3400005 -495\n35500015 3400005 -495\n35500009.9 3400000.1 -490.1\n"),
              "1\n0\n1\n");
    const json s = json::parse(runGeoslice("section " + obj + " --plane 0,1,0,-3400005 --areas --size 16x16").out);
    ASSERT_EQ(s["bodies"].size(), 1u);
    expectRel(s["bodies"][0]["area_m2"].get<double>(), 100.0, "section area");
    const json r = json::parse(runGeoslice("reserves --json " + obj).out);
    expectRel(r["bodies"][0]["gross_volume_m3"].get<double>(), 1000.0, "reserves");
}

// Two cubes sharing the edge x = y = 10, one wound inward and one outward, in one object:
// two closed shells split at the edge, 2000 m3, two squares in a horizontal section.
TEST_F(ClosedMeshCli, CubesSharingAnEdgeWoundEachWay) {
    const std::string obj = write("twins.obj", cubeObj(true) + cubeObj(false, 10, 10, 0, 9));
    const json j = json::parse(runGeoslice("info --json " + obj).out);
    ASSERT_EQ(j["bodies"].size(), 1u);
    EXPECT_TRUE(j["bodies"][0]["closed"].get<bool>());
    EXPECT_EQ(j["bodies"][0]["components"], 2);
    expectRel(j["bodies"][0]["volume_m3"].get<double>(), 2000.0, "info volume");
    EXPECT_EQ(classify(obj, "5 5 5\n15 15 5\n15 5 5\n5 15 5\n"), "1\n1\n0\n0\n");
    const json s = json::parse(runGeoslice("section " + obj + " --elevation 5 --areas --size 16x16").out);
    ASSERT_EQ(s["bodies"].size(), 1u);
    expectRel(s["bodies"][0]["area_m2"].get<double>(), 200.0, "section area");
    EXPECT_EQ(s["bodies"][0]["polygons"], 2);  // two squares touching at a corner
    EXPECT_EQ(s["bodies"][0]["open_chains"], 0);
    const json r = json::parse(runGeoslice("reserves --json " + obj).out);
    expectRel(r["bodies"][0]["gross_volume_m3"].get<double>(), 2000.0, "reserves");
}
