// Block models over real HTTP on loopback (issue 15 items 1-3): a box orebody nested in a
// box host at Gauss-Kruger magnitudes, saved as a .glb with a <stem>.blocks.json sidecar that
// names a CSV of 10 m cells (grade = 0.1 x i, density 2.5) clipped by the orebody. The server
// reads the sidecar; a coloured section image, its pixel query (the cell and its grade, as a
// point-in-box computation finds them), SVG pieces, the legend and grade-tonnage tables
// (exact volumes of the analytic box, JSON equal to `geoslice reserves --cutoffs --json`,
// CSV) are checked; bad parameters are 400 problems naming the parameter.
//
// Tolerance: relative 1e-12 on volumes and tonnages (a few ulps at 1e4..1e6 m³); the
// orebody's faces lie on grid planes and inside cells, both counted exactly.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <httplib.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "model/io/gltf/gltf_io.hpp"
#include "server/http_server.hpp"
#include "tests/common/run_command.hpp"
#include "tests/server/server_fixture.hpp"
#include "tests/unit/test_meshes.hpp"

namespace geoslice::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Grid: 12 x 10 x 6 cells of 10 m from kGrid; orebody [kGrid + (20, 15, 10), + (85, 70, 45)].
const glm::dvec3 kGrid(35500000.0, 3380000.0, -100.0);
const glm::dvec3 kOreLo = kGrid + glm::dvec3(20.0, 15.0, 10.0), kOreHi = kGrid + glm::dvec3(85.0, 70.0, 45.0);
constexpr double kDensity = 2.5;
// Relative: grade-tonnage sums of exact cell x box volumes against the closed form of
// whole-metre overlaps: a few double steps.
constexpr double kWholeCellsRelTol = 1e-12;
// g/t: a mean grade under 1.2 from those sums: a few double steps.
constexpr double kWholeCellsGradeTol = 1e-12;
// Relative: cut by a plane, cut points at eastings of 3.55e7 m carry ~1e-8 m of rounding.
constexpr double kPlaneCutRelTol = 1e-9;
// g/t: a mean grade under 1.2 from those cut volumes.
constexpr double kPlaneCutGradeTol = 1e-9;

double gradeOf(int i) { return 0.1 * i; }

double overlap(double a0, double a1, double b0, double b1) {
    return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
}

class ServerBlocks : public InProcessServer {
protected:
    static void SetUpTestSuite() {
        dir_ = freshTempDir("geoslice_blocks");
        Model m = test::modelOf(
            {test::makePart("host", PartKind::Body, 1, test::boxMesh(kGrid - 20.0, kGrid + glm::dvec3(140, 120, 80))),
             test::makePart("ore", PartKind::Body, 2, test::boxMesh(kOreLo, kOreHi))});
        AttributeRecord host, ore;
        host.id = 1;
        host.name = "host";
        ore.id = 2;
        ore.name = "ore";
        m.attributes.put(host);
        m.attributes.put(ore);
        ASSERT_TRUE(writeGlb(m, (dir_ / "box.glb").string()));
        std::ofstream csv(dir_ / "ore_blocks.csv");
        csv << "x,y,z,dx,dy,dz,grade [g/t Au],density\n";
        char line[256];
        for (int k = 0; k < 6; ++k)
            for (int j = 0; j < 10; ++j)
                for (int i = 0; i < 12; ++i) {
                    const glm::dvec3 c = kGrid + 10.0 * glm::dvec3(i + 0.5, j + 0.5, k + 0.5);
                    std::snprintf(line, sizeof line, "%.1f,%.1f,%.1f,10,10,10,%.17g,%g\n", c.x, c.y, c.z, gradeOf(i),
                                  kDensity);
                    csv << line;
                }
        csv.close();
        std::ofstream(dir_ / "box.blocks.json") << R"({"source": "ore_blocks.csv", "clip": ["ore"]})";
        ServerConfig c = loopbackConfig();
        c.modelsDir = dir_.string();
        startServer(c);
    }
    static void TearDownTestSuite() {
        stopServer();
        fs::remove_all(dir_);
    }
    static void expectProblem(const std::string& path, const std::string& needle) {
        auto r = get(path);
        ASSERT_TRUE(r) << path;
        EXPECT_GE(r->status, 400) << path;
        EXPECT_LT(r->status, 500) << path << "\n" << r->body;
        EXPECT_NE(r->body.find(needle), std::string::npos) << path << ": " << r->body;
    }
    static inline fs::path dir_;
};

TEST_F(ServerBlocks, TheSidecarIsLoadedAndDescribed) {
    const json j = getJson("/v1/models/box");
    ASSERT_TRUE(j.contains("blocks")) << j.dump();
    EXPECT_EQ(j["blocks"]["dims"], json({12, 10, 6}));
    EXPECT_EQ(j["blocks"]["clipBodies"], json({"ore"}));
    EXPECT_EQ(j["blocks"]["properties"][0]["unit"], "g/t Au");
}

TEST_F(ServerBlocks, GradeTonnageIsExactAndEqualsTheCli) {
    const std::string cutoffs = "0,0.35,0.75";
    const json j = getJson("/v1/models/box/reserves?cutoffs=" + cutoffs);
    ASSERT_TRUE(j.contains("grade_tonnage")) << j.dump();
    const json& gt = j["grade_tonnage"];
    EXPECT_EQ(gt["property"], "grade");
    ASSERT_EQ(gt["bodies"].size(), 1u);
    EXPECT_EQ(gt["bodies"][0]["body"], "ore");
    const double yz = (kOreHi.y - kOreLo.y) * (kOreHi.z - kOreLo.z);
    int row = 0;
    for (double cut : {0.0, 0.35, 0.75}) {
        double vol = 0.0, metal = 0.0;
        for (int i = 0; i < 12; ++i) {
            if (!(gradeOf(i) >= cut)) continue;
            const double v = overlap(kGrid.x + 10 * i, kGrid.x + 10 * (i + 1), kOreLo.x, kOreHi.x) * yz;
            vol += v;
            metal += v * kDensity * gradeOf(i);
        }
        const json& r = gt["bodies"][0]["rows"][row++];
        EXPECT_NEAR(r["volume_m3"].get<double>(), vol, kWholeCellsRelTol * vol) << cut;
        EXPECT_NEAR(r["tonnage_t"].get<double>(), vol * kDensity, kWholeCellsRelTol * vol * kDensity) << cut;
        EXPECT_NEAR(r["mean_grade"].get<double>(), metal / (vol * kDensity), kWholeCellsGradeTol) << cut;
        EXPECT_NEAR(r["metal"].get<double>(), metal, kWholeCellsRelTol * metal) << cut;
        EXPECT_EQ(r["metal_unit"], "g");
    }
    json cli =
        json::parse(test::runGeoslice("reserves '" + (dir_ / "box.glb").string() + "' --json --cutoffs " + cutoffs).out,
                    nullptr, false);
    ASSERT_TRUE(cli.is_object());
    EXPECT_EQ(cli["grade_tonnage"], gt);
    auto csv = get("/v1/models/box/reserves.csv?cutoffs=" + cutoffs);
    ASSERT_TRUE(csv);
    EXPECT_EQ(csv->status, 200);
    EXPECT_EQ(csv->body.substr(0, csv->body.find('\n')),
              "body,record,cutoff,cells,volume_m3,tonnage_t,mean_grade,grade_unit,metal,metal_unit");
    EXPECT_EQ(std::count(csv->body.begin(), csv->body.end(), '\n'), 4);
    expectProblem("/v1/models/box/reserves?cutoffs=1,0", "cutoffs");
    expectProblem("/v1/models/box/reserves?cutoffs=1&property=gold", "gold");
    expectProblem("/v1/models/box/reserves?property=grade", "'property'");
}

// Closed form of |[lo, hi] ∩ {n . p + d >= 0}| (no zero component in n): inclusion-exclusion
// of max(0, n . p + d)^3 / (6 n_x n_y n_z) over the corners, relative to lo.
double boxHalfSpace(glm::dvec3 lo, glm::dvec3 hi, glm::dvec3 n, double d) {
    const glm::dvec3 e = hi - lo;
    if (!(e.x > 0 && e.y > 0 && e.z > 0)) return 0.0;
    const double d0 = glm::dot(n, lo) + d;
    double v = 0.0;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner{(c & 1) ? e.x : 0.0, (c & 2) ? e.y : 0.0, (c & 4) ? e.z : 0.0};
        const double s = std::max(0.0, glm::dot(n, corner) + d0);
        v += ((!(c & 1) + !(c & 2) + !(c & 4)) % 2 ? -1.0 : 1.0) * s * s * s;
    }
    return v / (6.0 * n.x * n.y * n.z);
}

TEST_F(ServerBlocks, GradeTonnageOnTheKeptSideOfAPlane) {
    // An oblique plane through the orebody at Gauss-Kruger magnitudes: per cell the closed-form
    // volume of cell ∩ orebody ∩ half-space (computed relative to the grid's corner).
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.6, -0.5, 0.62));
    const double dLocal = -glm::dot(n, glm::dvec3(50.3, 41.7, 24.9));
    const double d = dLocal - glm::dot(n, kGrid);
    char plane[160];
    std::snprintf(plane, sizeof plane, "%.17g,%.17g,%.17g,%.17g", n.x, n.y, n.z, d);
    const json j = getJson(std::string("/v1/models/box/reserves?cutoffs=0,0.55&plane=") + plane);
    ASSERT_TRUE(j.contains("grade_tonnage")) << j.dump();
    const json& gt = j["grade_tonnage"];
    EXPECT_EQ(gt["plane"].size(), 4u);
    int row = 0;
    for (double cut : {0.0, 0.55}) {
        double vol = 0.0, metal = 0.0;
        for (int k = 0; k < 6; ++k)
            for (int jj = 0; jj < 10; ++jj)
                for (int i = 0; i < 12; ++i) {
                    if (!(gradeOf(i) >= cut)) continue;
                    const glm::dvec3 lo = 10.0 * glm::dvec3(i, jj, k);
                    const double v =
                        boxHalfSpace(glm::max(lo, kOreLo - kGrid), glm::min(lo + 10.0, kOreHi - kGrid), n, dLocal);
                    vol += v;
                    metal += v * kDensity * gradeOf(i);
                }
        const json& r = gt["bodies"][0]["rows"][row++];
        // Relative 1e-9: cut points at eastings of 3.55e7 m carry ~1e-8 m of rounding.
        EXPECT_NEAR(r["volume_m3"].get<double>(), vol, kPlaneCutRelTol * vol) << cut;
        EXPECT_NEAR(r["tonnage_t"].get<double>(), vol * kDensity, kPlaneCutRelTol * vol * kDensity) << cut;
        EXPECT_NEAR(r["mean_grade"].get<double>(), metal / (vol * kDensity), kPlaneCutGradeTol) << cut;
    }
    // The CLI gives the same table.
    json cli = json::parse(
        test::runGeoslice("reserves '" + (dir_ / "box.glb").string() + "' --json --cutoffs 0,0.55 --plane " + plane)
            .out,
        nullptr, false);
    ASSERT_TRUE(cli.is_object());
    EXPECT_EQ(cli["grade_tonnage"], gt);
    auto csv = get(std::string("/v1/models/box/reserves.csv?cutoffs=0,0.55&plane=") + plane);
    ASSERT_TRUE(csv);
    EXPECT_EQ(csv->status, 200);
    EXPECT_EQ(std::count(csv->body.begin(), csv->body.end(), '\n'), 3);
    expectProblem("/v1/models/box/reserves?cutoffs=0&plane=0,0,0,1", "plane");
}

TEST_F(ServerBlocks, PrintSheetsAreColouredWithTheRampInTheLegend) {
    const std::string view = "elevation=" + std::to_string(kGrid.z + 27.5) + "&colour=grade&breaks=0.5&date=2026-11-24";
    auto svg = get("/v1/models/box/section.svg?layout=print&paper=A4&" + view);
    ASSERT_TRUE(svg);
    ASSERT_EQ(svg->status, 200) << svg->body;
    // The ramp's title and class labels are text; the pieces carry their class as a title.
    for (const char* s : {"grade (g/t Au), viridis classes", "&lt; 0.5", "&gt;= 0.5", "<title>grade &gt;= 0.5</title>"})
        EXPECT_NE(svg->body.find(s), std::string::npos) << s;
    auto pdf = get("/v1/models/box/section.pdf?paper=A4&" + view);
    ASSERT_TRUE(pdf);
    ASSERT_EQ(pdf->status, 200) << pdf->body;
    EXPECT_EQ(pdf->body.rfind("%PDF-", 0), 0u);
    auto png = get("/v1/models/box/section.png?decorate=1&paper=A5&dpi=50&" + view);
    ASSERT_TRUE(png);
    EXPECT_EQ(png->status, 200) << png->body;
    expectProblem("/v1/models/box/section.pdf?elevation=0&colour=gold", "gold");
}

TEST_F(ServerBlocks, ColouredImageQuerySvgAndLegend) {
    const std::string view = "elevation=" + std::to_string(kGrid.z + 27.5) + "&size=200x160&colour=grade&breaks=0.5";
    auto img = get("/v1/models/box/section.png?" + view);
    ASSERT_TRUE(img);
    EXPECT_EQ(img->status, 200) << img->body;
    EXPECT_EQ(img->get_header_value("Content-Type"), "image/png");
    // Every pixel of a row through the orebody: the query's cell is the one holding its
    // world point (point in box), with that cell's grade, inside the orebody; none outside.
    int inside = 0;
    for (int px = 0; px < 200; px += 7) {
        const json q = getJson("/v1/models/box/query?" + view + "&px=" + std::to_string(px) + "&py=80");
        const glm::dvec3 w{q["world"]["x"].get<double>(), q["world"]["y"].get<double>(), q["world"]["z"].get<double>()};
        const bool inOre = w.x >= kOreLo.x && w.x < kOreHi.x && w.y >= kOreLo.y && w.y < kOreHi.y;
        ASSERT_EQ(q["block"].is_object(), inOre) << q.dump();
        if (!inOre) continue;
        ++inside;
        const int i = int(std::floor((w.x - kGrid.x) / 10.0)), j = int(std::floor((w.y - kGrid.y) / 10.0));
        EXPECT_EQ(q["block"]["cell"], json({i, j, 2})) << q.dump();
        EXPECT_EQ(q["block"]["properties"]["grade"].get<double>(), gradeOf(i));
        EXPECT_EQ(q["block"]["units"]["grade"], "g/t Au");
    }
    EXPECT_GT(inside, 5);
    auto svg = get("/v1/models/box/section.svg?" + view);
    ASSERT_TRUE(svg);
    EXPECT_EQ(svg->status, 200);
    EXPECT_NE(svg->body.find("data-cell=\"2,2,2\""), std::string::npos);
    auto legend = get("/v1/models/box/legend.png?colour=grade&breaks=0.5&ramp=magma");
    ASSERT_TRUE(legend);
    EXPECT_EQ(legend->status, 200);
    expectProblem("/v1/models/box/section.png?elevation=-70&colour=gold", "'colour'");
    expectProblem("/v1/models/box/section.png?elevation=-70&colour=grade&ramp=jet", "'ramp'");
    expectProblem("/v1/models/box/legend.png?breaks=1", "colour");
}

TEST_F(ServerBlocks, ColouredTilesFromAStatelessSectionId) {
    httplib::Client c("127.0.0.1", server_->port());
    const std::string z = std::to_string(kGrid.z + 27.5);
    auto plain = c.Post("/v1/models/box/sections", R"({"elevation": )" + z + "}", "application/json");
    auto coloured = c.Post("/v1/models/box/sections",
                           R"({"elevation": )" + z + R"(, "colour": "grade", "breaks": "0.5"})", "application/json");
    ASSERT_TRUE(plain && coloured);
    ASSERT_EQ(coloured->status, 201) << coloured->body;
    const std::string a = json::parse(plain->body)["sid"], b = json::parse(coloured->body)["sid"];
    EXPECT_NE(a, b);  // the colouring is part of the section's identity (cache keys, ETags)
    auto ta = get("/v1/sections/" + a + "/tiles/0/0/0.png"), tb = get("/v1/sections/" + b + "/tiles/0/0/0.png");
    ASSERT_TRUE(ta && tb);
    EXPECT_EQ(ta->status, 200);
    EXPECT_EQ(tb->status, 200) << tb->body;
    EXPECT_NE(ta->body, tb->body);
}

}  // namespace
}  // namespace geoslice::server
