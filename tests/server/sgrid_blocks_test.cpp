// An SGrid block model over real HTTP on loopback (issue 15): a GOCAD group written here as
// GOCAD writes it (a closed TSurf orebody and an SGrid with POINTS_FILE and cell PROP_FILEs),
// attached by a <stem>.blocks.json sidecar. The grid: 3 x 3 x 3 cells of 10 x 10 x 5 m,
// sheared x = 10 i + 2 k, so its k-layers stay horizontal slabs; grade = k + 0.5, density
// 2.5. The orebody [6, 24] x [2, 27] x [1, 13] lies inside it: layer k holds 18 x 25 x (its z
// overlap) m³ = 1800, 2250, 1350 (the oracle for grade-tonnage). The pixel query's cell is
// the sheared lattice's (floor of x - 2z/5 over 10, y / 10, z / 5).
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>
#include "tests/common/gocad_samples.hpp"

#include "server/http_server.hpp"
#include "tests/common/gocad_samples.hpp"
#include "tests/server/server_fixture.hpp"

namespace geoslice::server {
using test::bigEndianFloats;
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Relative: sums of clipped tetrahedra at 10 m coordinates, a few double steps.
constexpr double kVolumeRelTol = 1e-9;

class ServerSGridBlocks : public InProcessServer {
protected:
    static void SetUpTestSuite() {
        dir_ = freshTempDir("geoslice_sgrid_blocks");
        std::vector<float> xyz, grade, density;
        for (int k = 0; k < 4; ++k)
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) xyz.insert(xyz.end(), {float(10 * i + 2 * k), float(10 * j), float(5 * k)});
        for (int k = 0; k < 3; ++k)
            for (int n = 0; n < 9; ++n) {
                grade.push_back(float(k) + 0.5f);
                density.push_back(2.5f);
            }
        std::ofstream(dir_ / "sg_points@@", std::ios::binary) << bigEndianFloats(xyz);
        std::ofstream(dir_ / "sg_grade@@", std::ios::binary) << bigEndianFloats(grade);
        std::ofstream(dir_ / "sg_density@@", std::ios::binary) << bigEndianFloats(density);
        std::string ts = "GOCAD TSurf 1\nHEADER {\nname:ore\n}\nTFACE\n";
        const int lo[3] = {6, 2, 1}, hi[3] = {24, 27, 13};
        for (int c = 0; c < 8; ++c)
            ts += "VRTX " + std::to_string(c + 1) + " " + std::to_string(c & 1 ? hi[0] : lo[0]) + " " +
                  std::to_string(c & 2 ? hi[1] : lo[1]) + " " + std::to_string(c & 4 ? hi[2] : lo[2]) + "\n";
        for (const char* t : {"1 3 2", "2 3 4", "5 6 7", "6 8 7", "1 2 5", "2 6 5", "3 7 4", "4 7 8", "1 5 3", "3 5 7",
                              "2 4 6", "4 8 6"})
            ts += std::string("TRGL ") + t + "\n";
        ts += "END\n";
        std::ofstream(dir_ / "mine.gp")
            << "GOCAD HeterogeneousGroup 1\nHEADER {\nname:mine\n}\nBEGIN_MEMBERS\n"
            << ts
            << "GOCAD SGrid 1\nHEADER {\nname:sg\n}\nAXIS_N 4 4 4\nPROP_ALIGNMENT CELLS\nPOINTS_FILE sg_points@@\n"
               "PROPERTY 1 grade\nPROP_ESIZE 1 4\nPROP_FILE 1 sg_grade@@\n"
               "PROPERTY 2 density\nPROP_ESIZE 2 4\nPROP_FILE 2 sg_density@@\nEND\n"
            << "END_MEMBERS\nEND\n";
        std::ofstream(dir_ / "mine.blocks.json")
            << R"({"source": "grid:sg", "clip": ["ore"], "units": {"grade": "g/t Au"}})";
        ServerConfig c = loopbackConfig();
        c.modelsDir = dir_.string();
        startServer(c);
    }
    static void TearDownTestSuite() {
        stopServer();
        fs::remove_all(dir_);
    }
    static inline fs::path dir_;
};

TEST_F(ServerSGridBlocks, DescribedReservesSectionsAndQueries) {
    const json m = getJson("/v1/models/mine");
    ASSERT_TRUE(m.contains("blocks")) << m.dump();
    EXPECT_EQ(m["blocks"]["dims"], json({3, 3, 3}));
    EXPECT_EQ(m["blocks"]["cellShape"].get<std::string>().rfind("hexahedron", 0), 0u) << m.dump();

    const json r = getJson("/v1/models/mine/reserves?cutoffs=0,1,2");
    ASSERT_TRUE(r.contains("grade_tonnage")) << r.dump();
    const json& rows = r["grade_tonnage"]["bodies"][0]["rows"];
    ASSERT_EQ(rows.size(), 3u) << r.dump();
    const double volume[3] = {5400, 3600, 1350};
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(rows[k]["volume_m3"].get<double>(), volume[k], kVolumeRelTol * 5400) << rows[k].dump();
        EXPECT_NEAR(rows[k]["tonnage_t"].get<double>(), 2.5 * volume[k], 2.5 * kVolumeRelTol * 5400);
    }

    // y = 12 (plane 0,1,0,-12), 400 x 200 pixels: pixel (200, 100) lies at x 18.05, z 7.45
    // (the model's bounds framed with a 2 % margin): layer 1, x - 2z/5 = 15.07: cell (1, 1, 1).
    const json q = getJson("/v1/models/mine/query?plane=0,1,0,-12&size=400x200&px=200&py=100");
    ASSERT_TRUE(q.contains("block")) << q.dump();
    const double x = q["world"]["x"].get<double>(), z = q["world"]["z"].get<double>();
    const int k = int(z / 5), i = int((x - 0.4 * z) / 10);
    EXPECT_EQ(q["block"]["cell"], json({i, 1, k})) << q.dump();
    EXPECT_EQ(q["block"]["properties"]["grade"].get<double>(), k + 0.5);

    auto svg = get("/v1/models/mine/section.svg?plane=0,1,0,-12&size=400x200&colour=grade&breaks=1,2");
    ASSERT_TRUE(svg);
    EXPECT_EQ(svg->status, 200) << svg->body;
    std::size_t pieces = 0;
    for (std::size_t at = svg->body.find("data-cell="); at != std::string::npos;
         at = svg->body.find("data-cell=", at + 1))
        ++pieces;
    EXPECT_EQ(pieces, 8u) << "the orebody's cut meets 8 cells of the y = 12 slab: i 0..2 x k 0..2 less (2, 2)";
    auto png = get("/v1/models/mine/section.png?plane=0,1,0,-12&size=400x200&colour=grade");
    ASSERT_TRUE(png);
    EXPECT_EQ(png->status, 200) << png->body;

    // (GL perspective colouring of an SGrid is refused by name: tests/gl/block_texture_test.cpp;
    // this fixture serves with --gl none.)
}

}  // namespace
}  // namespace geoslice::server
