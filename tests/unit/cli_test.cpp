// End-to-end tests of the geoslice executable: generate, info, classify.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "tests/common/run_command.hpp"

namespace {

using geoslice::test::CmdResult;

CmdResult run(const std::string& args, const std::string& input = "") {
    std::string cmd = std::string(GEOSLICE_BINARY) + " " + args + " 2>/dev/null";
    std::string inFile;
    if (!input.empty()) {
        inFile = (std::filesystem::temp_directory_path() / ("gs_cli_in_" + std::to_string(::getpid()))).string();
        std::ofstream(inFile) << input;
        cmd += " < " + inFile;
    }
    CmdResult r = geoslice::test::runCommand(cmd);
    if (!inFile.empty()) std::filesystem::remove(inFile);
    return r;
}

class CliTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir = std::filesystem::temp_directory_path() / ("gs_cli_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }
    std::filesystem::path dir;
};

}  // namespace

TEST_F(CliTest, GenerateInfoClassify) {
    const std::string glb = (dir / "demo.glb").string();
    CmdResult g = run("generate --triangles 20000 --seed 3 --crs EPSG:4523 --at 105.1,30.6 --out " + glb);
    ASSERT_EQ(g.exitCode, 0) << g.out;
    EXPECT_TRUE(std::filesystem::exists(dir / "demo.attributes.json"));

    CmdResult info = run("info --json " + glb);
    ASSERT_EQ(info.exitCode, 0) << info.out;
    auto j = nlohmann::json::parse(info.out);
    EXPECT_EQ(j["crs"]["id"], "EPSG:4523");
    EXPECT_TRUE(j["ok"].get<bool>());
    ASSERT_EQ(j["bounds"]["min"].size(), 3u);
    const double xmin = j["bounds"]["min"][0].get<double>(), xmax = j["bounds"]["max"][0].get<double>();
    EXPECT_GT(xmin, 35'000'000.0);
    EXPECT_GT(j["lonlat_bounds"]["max"][0].get<double>(), 105.1);
    EXPECT_LT(j["lonlat_bounds"]["min"][0].get<double>(), 105.1);
    EXPECT_GE(j["bodies"].size(), 22u);

    // A point well above the terrain, one in the lowest stratum, and a bad line.
    const double cx = 0.5 * (xmin + xmax),
                 cy = 0.5 * (j["bounds"]["min"][1].get<double>() + j["bounds"]["max"][1].get<double>());
    const double zmin = j["bounds"]["min"][2].get<double>();
    char pts[256];
    std::snprintf(pts, sizeof pts, "%.3f %.3f 5000\n%.3f %.3f %.3f\nnot a point\n", cx, cy, cx, cy, zmin + 5.0);
    CmdResult c = run("classify " + glb, pts);
    EXPECT_EQ(c.exitCode, 1);  // the bad line
    EXPECT_EQ(c.out, "0\n1\n*\n");
}

TEST_F(CliTest, InfoFailsOnBrokenFiles) {
    const std::string bad = (dir / "broken.glb").string();
    std::ofstream(bad) << "glTF this is not a GLB";
    CmdResult r = run("info " + bad);
    EXPECT_NE(r.exitCode, 0);
    CmdResult missing = run("info " + (dir / "missing.obj").string());
    EXPECT_NE(missing.exitCode, 0);
    CmdResult usage = run("generate --triangles 10 --out " + (dir / "x.glb").string());
    EXPECT_NE(usage.exitCode, 0);
    CmdResult noSub = run("");
    EXPECT_NE(noSub.exitCode, 0);
}
