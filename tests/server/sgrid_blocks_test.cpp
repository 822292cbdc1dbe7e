// An SGrid block model over real HTTP on loopback (issue 15): the GOCAD group of
// tests/common/gocad_samples.hpp writeShearedSGridGroup (a closed TSurf orebody and a sheared
// SGrid with POINTS_FILE and cell PROP_FILEs, attached by a <stem>.blocks.json sidecar), whose
// layer volumes are the oracle for grade-tonnage and whose sheared lattice gives the pixel
// query's cell.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "server/http_server.hpp"
#include "tests/common/gocad_samples.hpp"
#include "tests/server/server_fixture.hpp"

namespace geoslice::server {
using test::writeShearedSGridGroup;
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Relative: sums of clipped tetrahedra at 10 m coordinates, a few double steps.
constexpr double kVolumeRelTol = 1e-9;

class ServerSGridBlocks : public InProcessServer {
protected:
    static void SetUpTestSuite() {
        dir_ = freshTempDir("geoslice_sgrid_blocks");
        writeShearedSGridGroup(dir_);
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

    // (GL perspective colouring of an SGrid: tests/gl/block_cells_test.cpp; this fixture serves
    // with --gl none.)
}

}  // namespace
}  // namespace geoslice::server
