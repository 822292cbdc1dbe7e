// `geoslice section` end to end: images, areas JSON, and errors for bad input.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "tests/common/run_command.hpp"

using geoslice::test::CmdResult;
using geoslice::test::runGeoslice;

TEST(SectionCli, ImagesAreasAndErrors) {
    const auto dir = std::filesystem::temp_directory_path() / ("gs_section_cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string glb = (dir / "m.glb").string();
    ASSERT_EQ(runGeoslice("generate --triangles 20000 --crs EPSG:4523 --out " + glb).exitCode, 0);
    auto info = nlohmann::json::parse(runGeoslice("info --json " + glb).out);
    const double ymid = 0.5 * (info["bounds"]["min"][1].get<double>() + info["bounds"]["max"][1].get<double>());

    const std::string ppm = (dir / "c.ppm").string(), pgm = (dir / "i.pgm").string();
    CmdResult r = runGeoslice("section " + glb + " --plane 0,1,0," + std::to_string(-ymid) + " --size 64x32 --out " +
                              ppm + " --out " + pgm + " --areas");
    ASSERT_EQ(r.exitCode, 0) << r.out;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["image"]["width"], 64);
    EXPECT_GE(j["bodies"].size(), 7u);
    double total = 0.0;
    for (const auto& b : j["bodies"]) {
        EXPECT_GT(b["area_m2"].get<double>(), 0.0);
        EXPECT_EQ(b["open_chains"], 0);
        total += b["area_m2"].get<double>();
    }
    EXPECT_GT(total, 1e6);  // a 6 km x ~2.5 km section
    EXPECT_EQ(j["traces"], 2);
    EXPECT_EQ(std::filesystem::file_size(ppm), std::string("P6\n64 32\n255\n").size() + 64 * 32 * 3);
    EXPECT_EQ(std::filesystem::file_size(pgm), std::string("P5\n64 32\n65535\n").size() + 64 * 32 * 2);

    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 900 --size 32x32").exitCode, 0);
    EXPECT_EQ(runGeoslice("section " + glb + " --plane nan,0,1,0").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --plane 0,0,0,1").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --plane 1,2,3").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 99999").exitCode, 1);  // misses the model
    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 900 --size 0x10").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 900 --size 100000x100000").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 900 --out x.jpg").exitCode, 2);
    EXPECT_NE(runGeoslice("section " + (dir / "missing.glb").string() + " --elevation 900").exitCode, 0);
    std::filesystem::remove_all(dir);
}
