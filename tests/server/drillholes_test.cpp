// Drillholes over real HTTP on loopback: horizontal strata saved as a .glb with a
// <stem>.drillholes.json sidecar (collar, survey, lithology CSV; a units map with one unit the
// model lacks) whose one hole, id "DH/1 ü" (a slash and a non-ASCII letter), is inclined at
// -60 degrees, so its contacts lie at (10 - z) / sin 60 along the hole. The check (JSON equal to
// `geoslice holes check --json`, CSV both ways), the strip log, and hostile requests: an unknown
// id, "../" in an id, an id of 1,000 bytes, invalid UTF-8, a model without drillholes (404) and
// one whose sidecar does not load (409).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <httplib.h>
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

// Metres: contacts at z = 0, -100, -200 stored as float32 local coordinates of whole metres
// (exact), crossed in double: far below a micrometre.
constexpr double kContactTolM = 1e-6;
const double kSin60 = std::sqrt(3.0) / 2.0;
double depthAt(double z) { return (10.0 - z) / kSin60; }

Model strata() {
    Model m = test::modelOf(
        {test::makePart("top", PartKind::Body, 1, test::boxMesh({-500, -500, -100}, {500, 500, 0})),
         test::makePart("middle", PartKind::Body, 2, test::boxMesh({-500, -500, -200}, {500, 500, -100})),
         test::makePart("bottom", PartKind::Body, 3, test::boxMesh({-500, -500, -300}, {500, 500, -200}))});
    const char* names[] = {"Sandstone", "Shale", "Granite"};
    for (RecordId r = 1; r <= 3; ++r) {
        AttributeRecord a;
        a.id = r;
        a.name = names[r - 1];
        m.attributes.put(a);
    }
    return m;
}

class ServerDrillholes : public InProcessServer {
protected:
    static void SetUpTestSuite() {
        dir_ = freshTempDir("geoslice_drillholes");
        const Model m = strata();
        ASSERT_TRUE(writeGlb(m, (dir_ / "strata.glb").string()));
        ASSERT_TRUE(writeGlb(m, (dir_ / "bare.glb").string()));
        ASSERT_TRUE(writeGlb(m, (dir_ / "broken.glb").string()));
        std::ofstream(dir_ / "collar.csv") << "HOLEID,EAST,NORTH,RL,DEPTH\n\"DH/1 ü\",0,0,10,400\n";
        std::ofstream(dir_ / "survey.csv") << "HOLEID,DEPTH,AZIMUTH,DIP\n\"DH/1 ü\",0,45,-60\n";
        char lith[512];
        // Overburden, then the three strata; the Shale/Granite contact logged 2 m deep.
        std::snprintf(lith, sizeof lith,
                      "HOLEID,FROM,TO,LITH\n\"DH/1 ü\",0,%.17g,OB\n\"DH/1 ü\",%.17g,%.17g,SST\n"
                      "\"DH/1 ü\",%.17g,%.17g,SH\n\"DH/1 ü\",%.17g,%.17g,GRN\n\"DH/1 ü\",%.17g,%.17g,BAS\n",
                      depthAt(0), depthAt(0), depthAt(-100), depthAt(-100), depthAt(-200) + 2.0, depthAt(-200) + 2.0,
                      depthAt(-300), depthAt(-300), depthAt(-300) + 5.0);
        std::ofstream(dir_ / "lithology.csv") << lith;
        std::ofstream(dir_ / "strata.drillholes.json")
            << R"({"collar": "collar.csv", "survey": "survey.csv", "intervals": ["lithology.csv"],
                  "units": {"column": "LITH", "map": {"SST": "Sandstone", "sh": "shale", "GRN": "3",
                                                      "BAS": "Basalt"}}})";
        std::ofstream(dir_ / "broken.drillholes.json") << R"({"collar": "missing.csv"})";
        ServerConfig c = loopbackConfig();
        c.modelsDir = dir_.string();
        startServer(c);
    }
    static void TearDownTestSuite() {
        stopServer();
        fs::remove_all(dir_);
    }
    static void expectProblem(const std::string& path, int status, const std::string& needle) {
        auto r = get(path);
        ASSERT_TRUE(r) << path;
        EXPECT_EQ(r->status, status) << path << "\n" << r->body;
        EXPECT_NE(r->body.find(needle), std::string::npos) << path << ": " << r->body;
    }
    static inline fs::path dir_;
};

TEST_F(ServerDrillholes, CheckFindsTheShiftedContactAndWarnsOfTheMissingUnit) {
    const json j = getJson("/v1/models/strata/drillholes/check");
    ASSERT_EQ(j["holes"].size(), 1u) << j.dump();
    const json& h = j["holes"][0];
    EXPECT_EQ(h["hole"], "DH/1 ü");
    // Logged: SST 100/sin60, SH 100/sin60 + 2, GRN 100/sin60 - 2, BAS 5 (lacking): 2 + 5 disagree.
    const double logged = 3.0 * 100.0 / kSin60 + 5.0;
    EXPECT_NEAR(h["logged_m"].get<double>(), logged, kContactTolM);
    EXPECT_NEAR(h["agreed_m"].get<double>(), logged - 7.0, kContactTolM);
    EXPECT_NEAR(h["unmatched_m"].get<double>(), depthAt(0), kContactTolM);  // OB names no unit
    ASSERT_EQ(h["contacts"].size(), 3u);
    EXPECT_NEAR(h["contacts"][0]["distance_m"].get<double>(), 0.0, kContactTolM);
    EXPECT_NEAR(h["contacts"][1]["distance_m"].get<double>(), -2.0, kContactTolM);
    EXPECT_TRUE(h["contacts"][2]["distance_m"].is_null());  // Granite -> Basalt: not in the model
    bool warned = false;
    for (const auto& w : j["warnings"]) warned = warned || w.get<std::string>().find("'Basalt'") != std::string::npos;
    EXPECT_TRUE(warned) << j["warnings"].dump();
    // The CLI's document is the same (but for how the model and the sidecar are named).
    const auto cli = test::runGeoslice("holes check '" + (dir_ / "strata.glb").string() + "' --json");
    ASSERT_EQ(cli.exitCode, 0) << cli.out;
    const json c = json::parse(cli.out);
    EXPECT_EQ(c["holes"], j["holes"]);
    EXPECT_EQ(c["units"], j["units"]);
    EXPECT_EQ(c["summary"], j["summary"]);
}

TEST_F(ServerDrillholes, CheckAsCsv) {
    auto r = get("/v1/models/strata/drillholes/check.csv");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->body.substr(0, r->body.find('\n')), "hole,unit,in_model,logged_m,agreed_m,share");
    EXPECT_NE(r->body.find("DH/1 ü,Basalt,false,5"), std::string::npos) << r->body;
    r = get("/v1/models/strata/drillholes/check?format=csv&rows=contacts");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->body.substr(0, r->body.find('\n')),
              "hole,depth_m,code_above,code_below,unit_above,unit_below,model_depth_m,distance_m");
    expectProblem("/v1/models/strata/drillholes/check.csv?format=json", 400, "format");
    expectProblem("/v1/models/strata/drillholes/check?rows=contacts", 400, "rows");
    expectProblem("/v1/models/strata/drillholes/check?colour=red", 400, "colour");
}

TEST_F(ServerDrillholes, StripLogOfAHoleWithASlashInItsId) {
    const json j = getJson("/v1/models/strata/drillholes/DH%2F1%20%C3%BC/log");
    EXPECT_EQ(j["hole"], "DH/1 ü");
    ASSERT_EQ(j["tables"].size(), 1u);
    EXPECT_EQ(j["tables"][0]["code_column"], "LITH");
    ASSERT_EQ(j["tables"][0]["intervals"].size(), 5u);
    EXPECT_TRUE(j["tables"][0]["intervals"][0]["unit"].is_null());  // OB
    EXPECT_EQ(j["tables"][0]["intervals"][2]["unit"], "Shale");
    EXPECT_EQ(j["tables"][0]["intervals"][4]["unit_in_model"], false);  // Basalt
    const json& model = j["model"]["intervals"];
    ASSERT_EQ(model.size(), 3u);
    const char* units[] = {"Sandstone", "Shale", "Granite"};
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(model[i]["unit"], units[i]);
        EXPECT_NEAR(model[i]["from_m"].get<double>(), depthAt(-100.0 * double(i)), kContactTolM);
        EXPECT_NEAR(model[i]["to_m"].get<double>(), depthAt(-100.0 * double(i + 1)), kContactTolM);
    }
    EXPECT_EQ(j["stations"].size(), 1u);
}

// The holes for a map: the inclined hole's trace ends at the collar plus 400 m along azimuth
// 45, dip -60 (one station: a straight hole), to the millimetre the route rounds to.
TEST_F(ServerDrillholes, HolesForAMap) {
    const json j = getJson("/v1/models/strata/drillholes");
    ASSERT_EQ(j["holes"].size(), 1u) << j.dump();
    const json& h = j["holes"][0];
    EXPECT_EQ(h["id"], "DH/1 ü");
    EXPECT_EQ(h["collar"], json::array({0.0, 0.0, 10.0}));
    EXPECT_DOUBLE_EQ(h["depth"].get<double>(), 400.0);
    EXPECT_NEAR(h["azimuth"].get<double>(), 45.0, 1e-3);
    EXPECT_NEAR(h["dip"].get<double>(), -60.0, 1e-3);
    const json& end = h["trace"].back();
    const double across = 400.0 * 0.5 / std::sqrt(2.0);
    EXPECT_NEAR(end[0].get<double>(), across, 0.5e-3);
    EXPECT_NEAR(end[1].get<double>(), across, 0.5e-3);
    EXPECT_NEAR(end[2].get<double>(), 10.0 - 400.0 * kSin60, 0.5e-3);
    ASSERT_EQ(j["columns"].size(), 1u);
    EXPECT_EQ(j["columns"][0]["column"], "LITH");
    EXPECT_EQ(j["columns"][0]["kind"], "text");
    expectProblem("/v1/models/bare/drillholes", 404, "has no drillholes");
    expectProblem("/v1/models/broken/drillholes", 409, "did not load");
    expectProblem("/v1/models/strata/drillholes?x=1", 400, "'x'");
}

// Without --sections-dir the model's own sections are listed and saving says what to do.
TEST_F(ServerDrillholes, SavingIsOffWithoutASectionsDirectory) {
    const json j = getJson("/v1/models/strata/saved-sections");
    EXPECT_EQ(j["saving"], false);
    EXPECT_TRUE(j["sections"].empty());
    auto r =
        client().Post("/v1/models/strata/saved-sections", R"({"name": "a", "elevation": -50})", "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 501);
    EXPECT_NE(r->body.find("--sections-dir"), std::string::npos) << r->body;
}

TEST_F(ServerDrillholes, HostileRequestsAreClearProblems) {
    expectProblem("/v1/models/strata/drillholes/nope/log", 404, "no drillhole 'nope'");
    expectProblem("/v1/models/strata/drillholes/..%2F..%2Fetc%2Fpasswd/log", 404, "no drillhole '../../etc/passwd'");
    expectProblem("/v1/models/strata/drillholes/" + std::string(1000, 'x') + "/log", 404, "1000 bytes");
    expectProblem("/v1/models/strata/drillholes/%FF%FE/log", 400, "UTF-8");
    expectProblem("/v1/models/bare/drillholes/check", 404, "has no drillholes");
    expectProblem("/v1/models/bare/drillholes/DH1/log", 404, "has no drillholes");
    expectProblem("/v1/models/broken/drillholes/check", 409, "did not load");
    expectProblem("/v1/models/nomodel/drillholes/check", 404, "nomodel");
}

}  // namespace
}  // namespace geoslice::server
