// Saved sections over real HTTP on loopback: a model with a <stem>.sections.json of two
// exploration lines, one whose sidecar names a line twice (served, the warning in /readyz and
// the list), and a sections directory shared by two servers (as by two replicas): a section
// saved on one is listed, opened and deleted on the other; saving it again is the same id;
// its query draws the section; its sheet carries the name in the title; hostile bodies and ids
// are clear problems.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "model/io/gltf/gltf_io.hpp"
#include "server/http_server.hpp"
#include "tests/server/server_fixture.hpp"
#include "tests/unit/test_meshes.hpp"

namespace geoslice::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

Model layers() {
    Model m =
        test::modelOf({test::makePart("upper", PartKind::Body, 1, test::boxMesh({0, 0, -100}, {1000, 2000, 0})),
                       test::makePart("lower", PartKind::Body, 2, test::boxMesh({0, 0, -200}, {1000, 2000, -100}))});
    for (RecordId r = 1; r <= 2; ++r) {
        AttributeRecord a;
        a.id = r;
        a.name = r == 1 ? "Upper" : "Lower";
        m.attributes.put(a);
    }
    return m;
}

class ServerSavedSections : public InProcessServer {
protected:
    static void SetUpTestSuite() {
        dir_ = freshTempDir("geoslice_saved_models");
        store_ = freshTempDir("geoslice_saved_store");
        const Model m = layers();
        ASSERT_TRUE(writeGlb(m, (dir_ / "mine.glb").string()));
        ASSERT_TRUE(writeGlb(m, (dir_ / "twice.glb").string()));
        std::ofstream(dir_ / "mine.sections.json")
            << R"({"sections": [{"number": "12", "vertices": [[500, 10], [500, 1990]], "vx": 2},
                                {"number": 14, "name": "十四号勘探线", "vertices": [[700, 10], [700, 1000], [800, 1990]]}]})";
        std::ofstream(dir_ / "twice.sections.json")
            << R"([{"number": "1", "vertices": [[100, 10], [100, 1990]]}, {"number": "1", "vertices": [[200, 10], [200, 1990]]}])";
        ServerConfig c = loopbackConfig();
        c.modelsDir = dir_.string();
        c.sectionsDir = store_.string();
        startServer(c);
    }
    static void TearDownTestSuite() {
        stopServer();
        fs::remove_all(dir_);
        fs::remove_all(store_);
    }
    static httplib::Result post(httplib::Client& c, const std::string& body) {
        return c.Post("/v1/models/mine/saved-sections", body, "application/json");
    }
    static inline fs::path dir_, store_;
};

TEST_F(ServerSavedSections, TheModelsLinesAreListedAndDrawn) {
    const json j = getJson("/v1/models/mine/saved-sections");
    EXPECT_EQ(j["saving"], true);
    ASSERT_EQ(j["sections"].size(), 2u) << j.dump();
    EXPECT_EQ(j["sections"][0]["name"], "Line 12");
    EXPECT_EQ(j["sections"][0]["source"], "model");
    EXPECT_EQ(j["sections"][0]["query"], "line=500,10,500,1990&vx=2");
    EXPECT_EQ(j["sections"][1]["name"], "十四号勘探线");
    EXPECT_EQ(j["sections"][1]["number"], "14");
    const json one = getJson("/v1/models/mine/saved-sections/" + j["sections"][1]["id"].get<std::string>());
    EXPECT_EQ(one, j["sections"][1]);
    // Each query draws its section; the sheet is titled by the name.
    for (const auto& s : j["sections"]) {
        auto r = get("/v1/models/mine/section.png?size=64x32&" + s["query"].get<std::string>());
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 200) << r->body;
    }
    auto svg = get("/v1/models/mine/section.svg?layout=print&" + j["sections"][1]["query"].get<std::string>() +
                   "&title=%E5%8D%81%E5%9B%9B%E5%8F%B7%E5%8B%98%E6%8E%A2%E7%BA%BF");
    ASSERT_TRUE(svg);
    EXPECT_EQ(svg->status, 200) << svg->body;
    EXPECT_NE(svg->body.find("十四号勘探线: Geological section"), std::string::npos);
}

TEST_F(ServerSavedSections, ABrokenSidecarIsNamedAndTheModelServed) {
    const json j = getJson("/v1/models/twice/saved-sections");
    EXPECT_TRUE(j["sections"].empty());
    ASSERT_EQ(j["warnings"].size(), 1u);
    EXPECT_NE(j["warnings"][0].get<std::string>().find("number '1' is given twice"), std::string::npos) << j.dump();
    const json ready = getJson("/readyz");
    EXPECT_NE(ready.dump().find("twice.sections.json"), std::string::npos) << ready.dump();
    auto r = get("/v1/models/twice/section.png?size=64x32&elevation=-50");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
}

TEST_F(ServerSavedSections, SavedOnOneReplicaOpenedAndDeletedOnAnother) {
    ServerConfig c = loopbackConfig();
    c.modelsDir = dir_.string();
    c.sectionsDir = store_.string();
    SectionServer other(c);
    auto port = other.start();
    ASSERT_TRUE(port) << port.error().message;
    ASSERT_TRUE(other.waitUntilLoaded());
    httplib::Client a("127.0.0.1", InProcessServer::port()), b("127.0.0.1", port.value());

    const std::string body = R"({"name": "Ramp decline", "line": "100,100,900,1900", "vx": 1.5})";
    auto first = post(a, body);
    ASSERT_TRUE(first);
    ASSERT_EQ(first->status, 201) << first->body;
    const json saved = json::parse(first->body);
    EXPECT_EQ(saved["source"], "saved");
    EXPECT_EQ(saved["query"], "line=100,100,900,1900&vx=1.5");
    EXPECT_EQ(first->get_header_value("Location"), "/v1/models/mine/saved-sections/" + saved["id"].get<std::string>());
    EXPECT_EQ(first->get_header_value("Cache-Control"), "no-store");
    // The same section saved on the other replica: one id, stored once, first `created` kept.
    auto again = post(b, body);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 200) << again->body;
    EXPECT_EQ(json::parse(again->body), saved);
    const json list = test::getJson(b, "/v1/models/mine/saved-sections");
    ASSERT_EQ(list["sections"].size(), 3u);
    EXPECT_EQ(list["sections"][2], saved);
    // Deleted on the other replica: gone from both.
    const std::string path = "/v1/models/mine/saved-sections/" + saved["id"].get<std::string>();
    auto del = b.Delete(path.c_str());
    ASSERT_TRUE(del);
    EXPECT_EQ(del->status, 204);
    auto gone = a.Get(path.c_str());
    ASSERT_TRUE(gone);
    EXPECT_EQ(gone->status, 404);
    // The model's own lines are not deleted through the API.
    const std::string own = "/v1/models/mine/saved-sections/" + list["sections"][0]["id"].get<std::string>();
    auto refused = a.Delete(own.c_str());
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 409);
    EXPECT_NE(refused->body.find("sections.json"), std::string::npos);
}

TEST_F(ServerSavedSections, HostileBodiesAndIdsAreClearProblems) {
    auto c = client();
    const std::pair<const char*, const char*> cases[] = {
        {"{", "not valid JSON"},
        {R"({"name": "far", "line": "5000,5000,6000,6000"})", "misses the model"},
        {R"({"name": "x", "line": "100,100,900,1900", "colour": "grade"})", "unknown field 'colour'"},
        {R"({"line": "100,100,900,1900"})", "needs a 'name' or a 'number'"},
        {R"({"name": "x", "line": "nan,1,2,3"})", "line"},
        {R"({"name": "x", "elevation": 1e308})", "elevation"},
        {R"({"name": "x\u0000y", "elevation": -50})", "control character"},
    };
    for (const auto& [body, needle] : cases) {
        auto r = post(c, body);
        ASSERT_TRUE(r) << body;
        EXPECT_EQ(r->status, 400) << body << " -> " << r->body;
        EXPECT_NE(r->body.find(needle), std::string::npos) << body << " -> " << r->body;
    }
    auto text = c.Post("/v1/models/mine/saved-sections", R"({"name": "x", "elevation": -50})", "text/plain");
    ASSERT_TRUE(text);
    EXPECT_EQ(text->status, 415);
    for (const char* id : {"..%2F..%2Fetc%2Fpasswd", "0123456789abcdef", "%FF", "x"}) {
        auto r = get(std::string("/v1/models/mine/saved-sections/") + id);
        ASSERT_TRUE(r) << id;
        EXPECT_TRUE(r->status == 404 || r->status == 400) << id << " " << r->status;
    }
    auto none = c.Post("/v1/models/nomodel/saved-sections", R"({"name": "x", "elevation": -50})", "application/json");
    ASSERT_TRUE(none);
    EXPECT_EQ(none->status, 404);
}

}  // namespace
}  // namespace geoslice::server
