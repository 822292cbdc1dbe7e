// GET /v1/models/{id}/reserves over real HTTP on loopback, against analytic figures: a box
// orebody of known size, density and grade nested in a larger box host (no density), both
// centred on the same point, saved as a .glb in a models directory. Whole model: exact
// volumes, net = host minus ore, tonnage and metal; an axis plane through the common centre
// keeps exactly half of every figure; planes that miss the model keep all or nothing. The
// JSON equals `geoslice reserves --json` for the same file and plane (but "model", which
// names the file in the CLI and the id over HTTP); the CSV has the stated header and rows;
// bad parameters are 400 problems naming the parameter.
//
// Tolerance: relative 1e-12 on volumes and tonnages. The box corners are whole metres at
// Gauss-Kruger magnitudes (3.5e7), exactly representable after recentring, and the volume
// sums a dozen triangle products: only a few ulps of rounding, far below 1e-12.
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

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

const glm::dvec3 kLo(35500000.0, 3380000.0, -200.0), kHi = kLo + glm::dvec3(100.0, 60.0, 40.0);
const glm::dvec3 kMargin(50.0, 50.0, 30.0);
constexpr double kOre = 100.0 * 60.0 * 40.0;     // m^3
constexpr double kHost = 200.0 * 160.0 * 100.0;  // m^3, gross
constexpr double kDensity = 2.7, kGrade = 1.5;   // t/m^3, % Cu
// Relative (absolute below 1): box volumes, tonnages and metal from whole-metre corners at
// GK eastings, exact after recentring: a few double steps of the sums.
constexpr double kExactBoxRelTol = 1e-12;

void expectRel(double got, double want, const std::string& what) {
    EXPECT_NEAR(got, want, kExactBoxRelTol * std::max(1.0, std::abs(want))) << what;
}

class ServerReserves : public InProcessServer {
protected:
    static void SetUpTestSuite() {
        dir_ = freshTempDir("geoslice_reserves");
        Model m = test::modelOf({test::makePart("host", PartKind::Body, 1, test::boxMesh(kLo - kMargin, kHi + kMargin)),
                                 test::makePart("ore, main lens", PartKind::Body, 2, test::boxMesh(kLo, kHi))});
        AttributeRecord host;
        host.id = 1;
        host.name = "Host granite";
        host.lithology = "granite";
        m.attributes.put(host);
        AttributeRecord ore;
        ore.id = 2;
        ore.name = "Ore \"A\"";
        ore.lithology = "massive sulphide";
        ore.density = kDensity;
        ore.grade = kGrade;
        ore.gradeUnit = "% Cu";
        m.attributes.put(ore);
        ASSERT_TRUE(writeGlb(m, (dir_ / "box.glb").string()));
        ServerConfig c = loopbackConfig();
        c.modelsDir = dir_.string();
        startServer(c);
    }
    static void TearDownTestSuite() {
        stopServer();
        fs::remove_all(dir_);
    }
    // The fixture's getJson, and the answer is plain JSON.
    static json getJson(const std::string& path) {
        auto c = client();
        return test::getJson(c, path, 200, "application/json");
    }
    static void expectProblem(const std::string& path, int status, const std::string& needle) {
        auto r = get(path);
        ASSERT_TRUE(r) << path;
        EXPECT_EQ(r->status, status) << path << "\n" << r->body;
        EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
        const json j = json::parse(r->body, nullptr, false);
        ASSERT_TRUE(j.is_object()) << r->body;
        EXPECT_EQ(j["status"], status);
        EXPECT_NE(j["detail"].get<std::string>().find(needle), std::string::npos)
            << path << ": detail " << j["detail"] << " lacks " << needle;
    }
    static inline fs::path dir_;
};

// `scale` of every figure of the analytic model (1 = whole, 0.5 = half, 0 = nothing).
void expectFigures(const json& j, double scale, const std::string& what) {
    ASSERT_EQ(j["bodies"].size(), 2u) << j.dump();
    const json& host = j["bodies"][0];
    const json& ore = j["bodies"][1];
    EXPECT_EQ(host["body"], "host");
    EXPECT_EQ(host["record"], 1);
    EXPECT_EQ(host["record_name"], "Host granite");
    EXPECT_EQ(host["lithology"], "granite");
    expectRel(host["gross_volume_m3"].get<double>(), scale * kHost, what + " host gross");
    expectRel(host["net_volume_m3"].get<double>(), scale * (kHost - kOre), what + " host net");
    EXPECT_TRUE(host["density_t_per_m3"].is_null());
    EXPECT_TRUE(host["tonnage_t"].is_null());
    EXPECT_TRUE(host["metal"].is_null());
    EXPECT_EQ(ore["body"], "ore, main lens");
    EXPECT_EQ(ore["record_name"], "Ore \"A\"");
    EXPECT_EQ(ore["lithology"], "massive sulphide");
    expectRel(ore["gross_volume_m3"].get<double>(), scale * kOre, what + " ore gross");
    expectRel(ore["net_volume_m3"].get<double>(), scale * kOre, what + " ore net");
    EXPECT_EQ(ore["density_t_per_m3"].get<double>(), kDensity);
    expectRel(ore["tonnage_t"].get<double>(), scale * kOre * kDensity, what + " ore tonnage");
    EXPECT_EQ(ore["grade"].get<double>(), kGrade);
    EXPECT_EQ(ore["grade_unit"], "% Cu");
    expectRel(ore["metal"].get<double>(), scale * kOre * kDensity * kGrade / 100.0, what + " metal");
    EXPECT_EQ(ore["metal_unit"], "t");
    const json& t = j["totals"];
    EXPECT_EQ(t["bodies"], 2);
    expectRel(t["net_volume_m3"].get<double>(), scale * kHost, what + " total net");
    expectRel(t["tonnage_t"].get<double>(), scale * kOre * kDensity, what + " total tonnage");
    EXPECT_EQ(t["bodies_with_tonnage"], 1);
    ASSERT_EQ(t["metal"].size(), 1u);
    EXPECT_EQ(t["metal"][0]["unit"], "t");
    expectRel(t["metal"][0]["amount"].get<double>(), scale * kOre * kDensity * kGrade / 100.0, what + " total metal");
}

std::string num(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

TEST_F(ServerReserves, WholeModelIsExact) {
    const json j = getJson("/v1/models/box/reserves");
    EXPECT_EQ(j["model"], "box");
    EXPECT_TRUE(j["plane"].is_null());
    expectFigures(j, 1.0, "whole");
}

TEST_F(ServerReserves, AxisPlanesThroughTheCentreKeepExactlyHalf) {
    const glm::dvec3 c = 0.5 * (kLo + kHi);
    for (const std::string& plane : {"1,0,0," + num(-c.x), "-1,0,0," + num(c.x), "0,1,0," + num(-c.y),
                                     "0,0,-1," + num(c.z), "0,0,2," + num(-2.0 * c.z)}) {
        const json j = getJson("/v1/models/box/reserves?plane=" + plane);
        ASSERT_TRUE(j["plane"].is_array()) << plane;
        expectFigures(j, 0.5, "plane " + plane);
    }
}

TEST_F(ServerReserves, APlaneThatMissesTheModelKeepsAllOrNothing) {
    // Everything on the kept side: the whole model; everything on the other side: zeros (200).
    expectFigures(getJson("/v1/models/box/reserves?plane=0,0,1," + num(-(kLo.z - kMargin.z - 1000.0))), 1.0, "all");
    expectFigures(getJson("/v1/models/box/reserves?plane=0,0,1," + num(-(kHi.z + kMargin.z + 1000.0))), 0.0, "none");
}

TEST_F(ServerReserves, JsonEqualsTheCli) {
    const std::string glb = (dir_ / "box.glb").string();
    const std::string plane = "1,0,0," + num(-(kLo.x + 25.0));
    for (const std::string& p : {std::string(), plane}) {
        json cli =
            json::parse(test::runGeoslice("reserves '" + glb + "' --json" + (p.empty() ? "" : " --plane " + p)).out,
                        nullptr, false);
        ASSERT_TRUE(cli.is_object()) << p;
        json http = getJson("/v1/models/box/reserves" + (p.empty() ? "" : "?plane=" + p));
        EXPECT_EQ(cli["model"], glb);
        EXPECT_EQ(http["model"], "box");
        cli.erase("model");
        http.erase("model");
        EXPECT_EQ(cli, http) << "plane " << p;
    }
}

std::vector<std::vector<std::string>> parseCsv(const std::string& text) {
    // RFC 4180 subset: quoted fields with doubled quotes, '\n' line ends.
    std::vector<std::vector<std::string>> rows(1, std::vector<std::string>(1));
    bool quoted = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char ch = text[i];
        if (quoted) {
            if (ch == '"' && i + 1 < text.size() && text[i + 1] == '"') {
                rows.back().back() += '"';
                ++i;
            } else if (ch == '"') {
                quoted = false;
            } else {
                rows.back().back() += ch;
            }
        } else if (ch == '"') {
            quoted = true;
        } else if (ch == ',') {
            rows.back().emplace_back();
        } else if (ch == '\n') {
            rows.emplace_back(1);
        } else {
            rows.back().back() += ch;
        }
    }
    if (rows.back().size() == 1 && rows.back()[0].empty()) rows.pop_back();
    return rows;
}

TEST_F(ServerReserves, CsvHasTheHeaderBodiesAndTotals) {
    const glm::dvec3 c = 0.5 * (kLo + kHi);
    for (const std::string& path : {"/v1/models/box/reserves.csv?plane=1,0,0," + num(-c.x),
                                    "/v1/models/box/reserves?format=csv&plane=1,0,0," + num(-c.x)}) {
        auto r = get(path);
        ASSERT_TRUE(r);
        ASSERT_EQ(r->status, 200) << r->body;
        EXPECT_EQ(r->get_header_value("Content-Type").rfind("text/csv", 0), 0u);
        const auto rows = parseCsv(r->body);
        ASSERT_EQ(rows.size(), 4u) << r->body;
        EXPECT_EQ(rows[0], (std::vector<std::string>{"body", "record", "record_name", "lithology", "gross_volume_m3",
                                                     "net_volume_m3", "density_t_per_m3", "tonnage_t", "grade",
                                                     "grade_unit", "metal", "metal_unit"}));
        for (const auto& row : rows) ASSERT_EQ(row.size(), 12u) << r->body;
        EXPECT_EQ(rows[1][0], "host");
        EXPECT_EQ(rows[1][3], "granite");
        expectRel(std::stod(rows[1][5]), 0.5 * (kHost - kOre), "csv host net");
        EXPECT_EQ(rows[1][7], "");  // no density: no tonnage
        EXPECT_EQ(rows[2][0], "ore, main lens");
        EXPECT_EQ(rows[2][1], "2");
        EXPECT_EQ(rows[2][2], "Ore \"A\"");
        expectRel(std::stod(rows[2][4]), 0.5 * kOre, "csv ore gross");
        expectRel(std::stod(rows[2][7]), 0.5 * kOre * kDensity, "csv ore tonnage");
        EXPECT_EQ(rows[2][9], "% Cu");
        expectRel(std::stod(rows[2][10]), 0.5 * kOre * kDensity * kGrade / 100.0, "csv metal");
        EXPECT_EQ(rows[2][11], "t");
        EXPECT_EQ(rows[3][0], "(total)");
        expectRel(std::stod(rows[3][5]), 0.5 * kHost, "csv total net");
        expectRel(std::stod(rows[3][7]), 0.5 * kOre * kDensity, "csv total tonnage");
        EXPECT_EQ(rows[3][11], "t");
    }
}

TEST_F(ServerReserves, BadParametersAreProblemsNamingThem) {
    expectProblem("/v1/models/box/reserves?plane=1,2,3", 400, "'plane'");
    expectProblem("/v1/models/box/reserves?plane=0,0,0,1", 400, "'plane'");
    expectProblem("/v1/models/box/reserves?plane=a,b,c,d", 400, "'plane'");
    expectProblem("/v1/models/box/reserves?plane=nan,0,1,0", 400, "'plane'");
    expectProblem("/v1/models/box/reserves?plane=0,0,1,1e300", 400, "'plane'");
    expectProblem("/v1/models/box/reserves?plane=0,0,1,0&plane=1,0,0,0", 400, "'plane'");
    expectProblem("/v1/models/box/reserves?format=xml", 400, "'format'");
    expectProblem("/v1/models/box/reserves.csv?format=json", 400, "'format'");
    expectProblem("/v1/models/box/reserves?plan=0,0,1,0", 400, "plan");
    expectProblem("/v1/models/nosuch/reserves", 404, "nosuch");
}

TEST_F(ServerReserves, RepeatsAreCachedWithAnETag) {
    auto a = get("/v1/models/box/reserves?plane=0,1,0,-3380010");
    auto b = get("/v1/models/box/reserves?plane=0,2,0,-6760020");  // the same plane, scaled
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->status, 200);
    EXPECT_FALSE(a->get_header_value("ETag").empty());
    EXPECT_EQ(a->get_header_value("ETag"), b->get_header_value("ETag"));
    EXPECT_EQ(a->body, b->body);
}

}  // namespace
}  // namespace geoslice::server
