// Issue 15: `geoslice render --colour` (GL, cli/cmd_render.cpp) and HTTP colour= give the same
// coloured views, for a box block model (a CSV of 10 m cells clipped by a box orebody, by a
// <stem>.blocks.json sidecar) and an SGrid (tests/common/gocad_samples.hpp
// writeShearedSGridGroup), both served by a real SectionServer with a GL worker and read by
// the geoslice executable from the same files:
//   - perspective views, one plane and cut-outs of 2-3 planes (union and intersection): the
//     CLI's PNG and GET section.png?view=perspective are the same renderer on the same
//     context kind with the same request and colouring (workers/block_colouring.hpp), so
//     they must be identical pixel for pixel;
//   - profiles: `render --profile --cells` (GL) against the block cell of each pixel that
//     the exact engine's pixel query names (POST /query): two engines, so compared where
//     the exact 3x3 neighbourhood is one cell, and >= 99.9 % must agree (the rasteriser
//     samples triangle coverage, the exact engine polygon coverage);
//   - the refusals (no block model, unknown property, bad breaks, --cells without
//     --colour) carry the same messages as `geoslice section --colour`.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "image/image_encode.hpp"
#include "model/io/gltf/gltf_io.hpp"
#include "server/http_server.hpp"
#include "tests/common/buffer_agree.hpp"
#include "tests/common/gocad_samples.hpp"
#include "tests/common/run_command.hpp"
#include "tests/server/server_fixture.hpp"
#include "tests/unit/test_meshes.hpp"

namespace geoslice::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The box model: a 12 x 10 x 6 grid of 10 m cells from the origin (grade = 0.1 i), an
// orebody [20, 85] x [15, 70] x [10, 45] that clips it, in a host around the grid.
void writeBoxGroup(const fs::path& dir) {
    Model m = test::modelOf({test::makePart("host", PartKind::Body, 1, test::boxMesh({-20, -20, -20}, {140, 120, 80})),
                             test::makePart("ore", PartKind::Body, 2, test::boxMesh({20, 15, 10}, {85, 70, 45}))});
    for (RecordId id : {1u, 2u}) {
        AttributeRecord r;
        r.id = id;
        r.name = id == 1 ? "host" : "ore";
        m.attributes.put(r);
    }
    ASSERT_TRUE(writeGlb(m, (dir / "box.glb").string()));
    ASSERT_TRUE(writeGlb(m, (dir / "plain.glb").string()));  // the same without a block model
    std::ofstream csv(dir / "box_cells.csv");
    csv << "x,y,z,dx,dy,dz,grade [g/t Au]\n";
    for (int k = 0; k < 6; ++k)
        for (int j = 0; j < 10; ++j)
            for (int i = 0; i < 12; ++i)
                csv << 10 * i + 5 << "," << 10 * j + 5 << "," << 10 * k + 5 << ",10,10,10," << 0.1 * i << "\n";
    std::ofstream(dir / "box.blocks.json") << R"({"source": "box_cells.csv", "clip": ["ore"]})";
}

// geoslice with stderr kept (the refusals' messages).
test::CmdResult runWithStderr(const std::string& args) {
    return test::runCommand(std::string(GEOSLICE_BINARY) + " " + args + " 2>&1");
}

class RenderColour : public InProcessServer {
protected:
    static void SetUpTestSuite() {
        dir_ = freshTempDir("geoslice_render_colour");
        writeBoxGroup(dir_);
        if (HasFatalFailure()) return;
        test::writeShearedSGridGroup(dir_);
        ServerConfig c = loopbackConfig();
        c.modelsDir = dir_.string();
        c.gl = "auto";
        c.workers = 1;
        c.deadlineMs = 120000;
        startServer(c, 300);
    }
    static void TearDownTestSuite() {
        stopServer();
        fs::remove_all(dir_);
    }
    static inline fs::path dir_;
};

struct View {
    std::string model, file, eye, target, planes, cut;  // planes: a,b,c,d;a,b,c,d
};

// The perspective views: eyes on the removed side of every plane, so the cut faces (and the
// orebody's coloured caps) face them. The box model's planes miss its grid planes here; the
// profile test below has one on a grid plane.
std::vector<View> perspectiveViews() {
    std::vector<View> v;
    for (const char* cut : {"", "intersection", "union"}) {
        const std::string c = cut;
        v.push_back({"box", "box.glb", "-100,-150,150", "60,50,30",
                     c.empty() ? "0,1,0,-43" : "0,1,0,-43;1,0,0,-53" + std::string(c == "union" ? "" : ";0,0,-1,43"),
                     c});
        v.push_back({"mine", "mine.gp", "-40,-60,50", "15,15,7",
                     c.empty() ? "0,1,0,-12" : "0,1,0,-12;1,0,0,-15" + std::string(c == "union" ? "" : ";0,0,-1,9"),
                     c});
    }
    return v;
}

TEST_F(RenderColour, PerspectiveCliAndHttpGiveTheSameImage) {
    constexpr int kW = 96, kH = 72;
    auto c = client();
    for (const View& v : perspectiveViews()) {
        SCOPED_TRACE(v.model + " planes " + v.planes + " cut " + v.cut);
        std::string cliPlanes, httpPlanes;
        for (std::size_t at = 0; at <= v.planes.size();) {
            const std::size_t end = std::min(v.planes.find(';', at), v.planes.size());
            cliPlanes += " --plane " + v.planes.substr(at, end - at);
            at = end + 1;
        }
        for (char ch : v.planes) httpPlanes += ch == ';' ? std::string("%3B") : std::string(1, ch);
        const fs::path cliPng = dir_ / "cli.png", cells = dir_ / "cells.pgm", plainPng = dir_ / "plain.png";
        const std::string common = " --eye " + v.eye + " --target " + v.target + cliPlanes +
                                   (v.cut.empty() ? "" : " --cut " + v.cut) + " --size " + std::to_string(kW) + "x" +
                                   std::to_string(kH) + " --lod off";
        auto r = runWithStderr("render " + (dir_ / v.file).string() + common +
                               " --colour grade --breaks 1,2 --ramp viridis --cells " + cells.string() + " --out " +
                               cliPng.string());
        ASSERT_EQ(r.exitCode, 0) << r.out;
        auto plain = runWithStderr("render " + (dir_ / v.file).string() + common + " --out " + plainPng.string());
        ASSERT_EQ(plain.exitCode, 0) << plain.out;
        auto h =
            c.Get(("/v1/models/" + v.model + "/section.png?view=perspective&eye=" + v.eye + "&target=" + v.target +
                   "&plane=" + httpPlanes + (v.cut.empty() ? "" : "&cut=" + v.cut) + "&size=" + std::to_string(kW) +
                   "x" + std::to_string(kH) + "&colour=grade&breaks=1,2&ramp=viridis")
                      .c_str());
        ASSERT_TRUE(h);
        ASSERT_EQ(h->status, 200) << h->body;
        const fs::path httpPng = dir_ / "http.png";
        std::ofstream(httpPng, std::ios::binary) << h->body;
        auto a = readPngRgba(cliPng.string());
        auto b = readPngRgba(httpPng.string());
        auto p = readPngRgba(plainPng.string());
        ASSERT_TRUE(a.ok() && b.ok() && p.ok());
        ASSERT_EQ(a->width, kW);
        ASSERT_EQ(b->width, kW);
        ASSERT_EQ(a->height, kH);
        ASSERT_EQ(b->height, kH);
        std::size_t differ = 0, coloured = 0;
        for (std::size_t i = 0; i < a->rgba.size(); i += 4) {
            differ += std::memcmp(&a->rgba[i], &b->rgba[i], 4) != 0;
            coloured += std::memcmp(&a->rgba[i], &p->rgba[i], 4) != 0;
        }
        EXPECT_EQ(differ, 0u) << "pixels that differ between the CLI and HTTP images";
        // The orebody's caps cover a few hundred pixels of these views: the colouring must show.
        EXPECT_GT(coloured, 50u) << "pixels the colouring changed in the CLI image";
        int cellsW = 0, cellsH = 0;
        const std::vector<std::uint32_t> cellBuffer = test::readPgm16(cells, cellsW, cellsH);
        ASSERT_EQ(cellsW, kW);
        ASSERT_EQ(cellsH, kH);
        ASSERT_EQ(cellBuffer.size(), std::size_t(kW * kH));
        EXPECT_GT(std::count_if(cellBuffer.begin(), cellBuffer.end(), [](std::uint32_t x) { return x != 0; }), 50);
    }
}

// The GL profile's cell buffer against the exact engine's block cell of every pixel.
TEST_F(RenderColour, ProfileCellsAgreeWithTheExactPixelQuery) {
    constexpr int kW = 80, kH = 60;  // 4800 pixels: one batch query (at most 5000)
    auto c = client();
    for (const View& v :
         {View{"box", "box.glb", "", "", "0,1,0,-43", ""}, View{"mine", "mine.gp", "", "", "0,1,0,-12", ""},
          // On a grid plane (between the layers j = 3 and 4): the face goes to the cell cellAt
          // names in both engines (section/blocks/block_section.cpp cellPolygons).
          View{"box", "box.glb", "", "", "0,1,0,-40", ""}}) {
        SCOPED_TRACE(v.model);
        const fs::path cells = dir_ / "profile_cells.pgm";
        auto r = runWithStderr("render " + (dir_ / v.file).string() + " --profile --plane " + v.planes + " --size " +
                               std::to_string(kW) + "x" + std::to_string(kH) + " --colour grade --cells " +
                               cells.string() + " --out " + (dir_ / "profile.png").string());
        ASSERT_EQ(r.exitCode, 0) << r.out;
        int w = 0, h = 0;
        const std::vector<std::uint32_t> gl = test::readPgm16(cells, w, h);
        ASSERT_EQ(w, kW);
        ASSERT_EQ(h, kH);
        ASSERT_EQ(gl.size(), std::size_t(kW * kH));
        auto dims = getJson("/v1/models/" + v.model)["blocks"]["dims"];
        ASSERT_EQ(dims.size(), 3u);
        const json view = {{"plane", v.planes}, {"size", std::to_string(kW) + "x" + std::to_string(kH)}};
        json pixels = json::array();
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) pixels.push_back({x, y});
        auto q = c.Post(("/v1/models/" + v.model + "/query").c_str(), json{{"view", view}, {"pixels", pixels}}.dump(),
                        "application/json");
        ASSERT_TRUE(q);
        ASSERT_EQ(q->status, 200) << q->body.substr(0, 500);
        const json results = json::parse(q->body)["results"];
        ASSERT_EQ(results.size(), std::size_t(kW * kH));
        std::vector<std::uint32_t> exact(results.size(), 0);
        for (std::size_t i = 0; i < results.size(); ++i)
            if (results[i].contains("block") && results[i]["block"].is_object()) {
                const json& ijk = results[i]["block"]["cell"];
                exact[i] = 1 + ijk[0].get<std::uint32_t>() +
                           dims[0].get<std::uint32_t>() * (ijk[1].get<std::uint32_t>() +
                                                           dims[1].get<std::uint32_t>() * ijk[2].get<std::uint32_t>());
            }
        const auto [compared, agree] = test::agreeWhereUniform(exact, gl, kW, kH, true);
        std::printf("[ render --cells ] %s: %zu/%zu interior pixels agree\n", v.model.c_str(), agree, compared);
        // The orebody's section covers about a third of these frames.
        EXPECT_GE(compared, 1000u);
        EXPECT_GE(double(agree), 0.999 * double(compared));
        EXPECT_GT(std::count_if(exact.begin(), exact.end(), [](std::uint32_t x) { return x != 0; }), 300);
    }
}

// The refusals: exit 2 with the message `geoslice section --colour` gives for the same flags.
TEST_F(RenderColour, RefusalsNameTheProblemAsSectionDoes) {
    struct Case {
        std::string file, flags, needle;
    };
    const std::vector<Case> cases = {
        {"plain.glb", "--colour grade", "has no block model"},
        {"box.glb", "--colour nope", "nope"},
        {"mine.gp", "--colour grade --breaks 2,1", "increase"},
        {"box.glb", "--colour grade --ramp rainbow", "rainbow"},
    };
    for (const Case& k : cases) {
        SCOPED_TRACE(k.file + " " + k.flags);
        auto r = runWithStderr("render " + (dir_ / k.file).string() + " --plane 0,1,0,-12 --size 32x32 " + k.flags +
                               " --out " + (dir_ / "refused.png").string());
        auto s = runWithStderr("section " + (dir_ / k.file).string() + " --plane 0,1,0,-12 --size 32x32 " + k.flags +
                               " --out " + (dir_ / "refused.png").string());
        EXPECT_EQ(r.exitCode, 2) << r.out;
        EXPECT_EQ(s.exitCode, 2) << s.out;
        const std::size_t at = r.out.find("geoslice render: --colour: ");
        ASSERT_NE(at, std::string::npos) << r.out;
        const std::string message = r.out.substr(at + std::strlen("geoslice render: "));
        EXPECT_NE(message.find(k.needle), std::string::npos) << message;
        EXPECT_NE(s.out.find("geoslice section: " + message), std::string::npos) << s.out << "\nvs\n" << r.out;
    }
    auto r = runWithStderr("render " + (dir_ / "box.glb").string() + " --plane 0,1,0,-12 --cells " +
                           (dir_ / "c.pgm").string() + " --out " + (dir_ / "refused.png").string());
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.out.find("--cells: needs --colour"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace geoslice::server
