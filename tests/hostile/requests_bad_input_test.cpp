// Issue 11 item 9: the real server (a child process) against a matrix of bad inputs.
// Every one must be a 4xx problem+json whose detail names the parameter, with the server
// alive and /healthz fast afterwards; headers of the operational routes.
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/common/serve_process.hpp"

namespace geoslice::test {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// The demo model's east-west section through its centre (northing 3388846 m).
const std::string kPlane = "plane=0,1,0,-3388846";
const std::string kLine = "line=35502500,3388000,35504500,3389000";
const std::string kSection = "/v1/models/demo/section.png?";

class Hostile : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        server_ = ServeProcess::start({"--gl", "none", "--demo-triangles", "20000", "--workers", "2"}).release();
        ASSERT_NE(server_, nullptr);
        ASSERT_TRUE(server_->waitReady()) << server_->log();
    }
    static void TearDownTestSuite() {
        delete server_;
        server_ = nullptr;
    }
    static ServeProcess* server_;
};
ServeProcess* Hostile::server_ = nullptr;

struct Case {
    std::string method;  // GET or POST
    std::string path;
    int status;          // expected 4xx
    std::string needle;  // the problem detail must contain it (the parameter's name)
    std::string body = "";
    std::string contentType = "application/json";
};

// Sends a case; checks the status, the problem+json shape and the needle; returns ms.
double check(const ServeProcess& s, const Case& c, int& failures) {
    auto cl = s.client(30);
    const auto t0 = Clock::now();
    auto r = c.method == "GET" ? cl.Get(c.path.c_str()) : cl.Post(c.path.c_str(), c.body, c.contentType.c_str());
    const double ms = msSince(t0);
    const std::string what = c.method + " " + c.path.substr(0, 200);
    if (!r) {
        ADD_FAILURE() << what << ": no answer (" << httplib::to_string(r.error()) << ")";
        ++failures;
        return ms;
    }
    bool ok = r->status == c.status;
    EXPECT_EQ(r->status, c.status) << what << "\n" << r->body;
    if (r->status >= 400) {
        EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json") << what;
        const json j = json::parse(r->body, nullptr, false);
        const std::string detail = j.is_object() && j.contains("detail") ? j["detail"].get<std::string>() : "";
        const bool named = detail.find(c.needle) != std::string::npos;
        EXPECT_TRUE(named) << what << ": detail '" << detail << "' does not name '" << c.needle << "'";
        ok = ok && named;
    }
    if (!ok) ++failures;
    return ms;
}

std::vector<Case> badInputMatrix() {
    std::vector<Case> m;
    auto get = [&](std::string path, int status, std::string needle) {
        m.push_back(Case{"GET", std::move(path), status, std::move(needle)});
    };
    const std::string p = kSection + kPlane + "&size=256x128";
    // frame
    for (const char* f : {"0,1e-300,0,1e-300", "0,1e-100,0,1e-100", "-100,100,1e-7,2e-7", "1,0,0,1", "0,1,1,1",
                          "nan,1,0,1", "inf,1,0,1", "0,1e309,0,1", "-1e300,1e300,-1,1", "0,1,0", "0,1,0,1,5", "a,b,c,d",
                          "", "0,1e-6,0,1", "1e7,1.00000000001e7,0,1", "-1e9,1e9,0,1", "0x1,2,3,4"})
        get(p + "&frame=" + f, 400, "frame");
    // size
    for (const char* s : {"0x10", "10x0", "-5x5", "8193x1", "1x8193", "abc", "10", "10x", "x10", "1e3x1e3",
                          "99999999999999999999x1", "256x128x3", "%20"})
        get(kSection + kPlane + "&size=" + s, 400, "size");
    // plane
    for (const char* pl : {"0,0,0,1", "0,1,0", "0,1,0,nan", "0,1,0,inf", "0,1,0,1e309", "0,1,0,-1e300", ",,,", "x",
                           "0,1,0,1,2", "1e-320,0,0,1e10"})
        get(kSection + std::string("plane=") + pl, 400, "plane");
    get(kSection + "plane=1e308,1e308,1e308,1", 400, "parameter 'plane'");  // a valid plane that misses the model
    get(kSection + kPlane + "&" + kLine, 400, "geometry");
    get(kSection + "size=64x64", 400, "geometry");
    // elevation
    for (const char* z : {"nan", "1e300", "abc", ""}) get(kSection + std::string("elevation=") + z, 400, "elevation");
    // line
    {
        std::string many = "line=";
        for (int i = 0; i < 300; ++i) many += std::string(i ? "," : "") + std::to_string(35502500 + i) + ",3388000";
        get(kSection + many, 400, "line");
    }
    for (const char* l : {"1,2", "1,2,3", "35502500,3388000,35502500,3388000", "1e300,0,0,0", "a,b,c,d", "1,2,,4"})
        get(kSection + std::string("line=") + l, 400, "line");
    get(kSection + kLine + "&coords=mars", 400, "coords");
    get(kSection + "line=500,100,501,100&coords=lonlat", 400, "line");
    // vx, bg, view, camera
    for (const char* v : {"0", "1000", "nan", "x", "0.01"}) get(p + "&vx=" + v, 400, "vx");
    for (const char* b : {"zzz", "#12", "#1234567", "rgb(1,2,3)"}) get(p + "&bg=" + b, 400, "bg");
    get(p + "&view=orthographic", 400, "view");
    get(kSection + kLine + "&view=perspective", 422, "view");
    const std::string persp = kSection + kPlane + "&size=128x128&view=perspective";
    get(persp + "&eye=35504000,3387000,1500", 400, "target");
    get(persp + "&eye=35504000,3387000,1500&target=35504000,3387000,1500", 400, "eye");
    get(persp + "&eye=35504000,3387000,1500&target=35504000,3388846,0&up=0,0,0", 400, "up");
    get(persp + "&eye=35504000,3387000,1500&target=35504000,3387000,0", 400, "up");  // up parallel to view
    get(persp + "&eye=1e300,3387000,1500&target=35504000,3388846,0", 400, "eye");
    get(persp + "&eye=35504000,3387000,1500&target=35504000,nan,0", 400, "target");
    for (const char* f : {"0", "180", "nan", "0.5"})
        get(persp + "&eye=35504000,3387000,1500&target=35504000,3388846,0&fov=" + f, 400, "fov");
    // cut-outs (api/cut.hpp): more than six planes, bad numbers, zero normals, duplicates, no
    // or a bad combine mode, both spellings, a profile of several planes, everything removed
    {
        const std::string cut = kSection + "size=128x128&view=perspective&";
        const std::string a = "-1,0,0,35504794", b = "0,1,0,-3388846";
        std::string seven = "planes=" + a + ";" + b;
        for (int i = 0; i < 5; ++i) seven += ";0,0,1," + std::to_string(-100 * i);
        get(cut + seven + "&cut=intersection", 400, "parameter 'planes': 7 planes given, at most 6");
        std::string repeated;
        for (int i = 0; i < 7; ++i) repeated += "&plane=0,0,1," + std::to_string(-100 * i);
        get(cut + repeated.substr(1) + "&cut=union", 400, "parameter 'plane': 7 planes");
        get(cut + "planes=" + a + ";0,1,0,nan&cut=union", 400, "parameter 'planes': plane 2");
        get(cut + "planes=" + a + ";0,1,0,inf&cut=union", 400, "parameter 'planes': plane 2");
        get(cut + "planes=" + a + ";0,0,0,5&cut=union", 400, "parameter 'planes': plane 2");
        get(cut + "planes=" + a + ";1e-320,0,0,1&cut=union", 400, "parameter 'planes': plane 2");
        get(cut + "planes=" + a + ";-2,0,0,71009588&cut=union", 400, "are the same plane");
        get(cut + "plane=" + a + "&plane=" + a + "&cut=union", 400, "are the same plane");
        get(cut + "planes=" + a + ";" + b, 400, "parameter 'cut'");
        get(cut + "planes=" + a + ";" + b + "&cut=xor", 400, "parameter 'cut'");
        get(cut + "planes=" + a + ";;" + b + "&cut=union", 400, "parameter 'planes': plane 2");
        get(cut + "planes=" + a + ";" + b + ";&cut=union", 400, "parameter 'planes': plane 3");
        get(cut + "plane=" + a + "&planes=" + b + "&cut=union", 400, "not both");
        get(kSection + "planes=" + a + ";" + b + "&cut=union", 400, "perspective views only");
        get(kSection + "elevation=500&cut=union", 400, "parameter 'cut'");
        get(cut + "planes=1,0,0,-35600000;0,1,0,-3400000;0,0,1,-9000&cut=intersection", 400,
            "parameter 'planes': the cut removes the whole model");
        get(cut + "planes=1,0,0,-35600000;0,1,0,-3388846&cut=union", 400, "removes the whole model");
        get(cut + "plane=0,0,1,-9000", 400, "parameter 'plane': the cut removes the whole model");
        get("/v1/models/demo/query?size=64x64&view=perspective&px=1&py=1&planes=" + a + ";" + b +
                "&cut=union&cut=union",
            400, "cut");
        get("/v1/models/demo/query?size=64x64&view=perspective&px=1&py=1&plane=0,0,1,-9000", 400,
            "removes the whole model");
    }
    // quality, unknown and repeated parameters
    for (const char* q : {"0", "101", "abc"}) get(p + "&quality=" + q, 400, "quality");
    get(p + "&foo=1", 400, "foo");
    get(p + "&siz=10x10", 400, "siz");
    get(kSection + "planee=0,1,0,-3388846", 400, "planee");
    get(p + "&plane=0,1,0,-3388000", 400, "plane");
    get("/v1/models/demo/section.geojson?" + kPlane + "&space=mars", 400, "space");
    get("/v1/models/demo/section.geojson?" + kPlane + "&frame=0,1e-300,0,1e-300", 400, "frame");
    get("/v1/models/demo/section.svg?" + kPlane + "&size=0x0", 400, "size");
    // formats and models
    get("/v1/models/demo/section.gif?" + kPlane, 404, "gif");
    get("/v1/models/nope/section.png?" + kPlane, 404, "nope");
    get("/v1/models/..%2F..%2Fetc/section.png?" + kPlane, 404, "model");
    // pixel queries
    const std::string q = "/v1/models/demo/query?" + kPlane + "&size=256x128";
    get(q, 400, "px");
    get(q + "&px=3", 400, "py");
    for (const char* px : {"-1", "256", "abc", "1e3", "99999999999999999999"})
        get(q + "&px=" + px + "&py=3", 400, "px");
    get(q + "&px=3&py=3&foo=2", 400, "foo");
    // boreholes
    const std::string bh = "/v1/models/demo/borehole?";
    get(bh + "x=35504000", 400, "y");
    get(bh + "x=nan&y=3388846", 400, "x");
    get(bh + "x=35504000&y=abc", 400, "y");
    get(bh + "lon=105", 400, "lat");
    get(bh + "x=35504000&y=3388846&depth=3", 400, "depth");
    // tiles and section ids
    get("/v1/sections/AAAA/tiles/0/0/0.png", 400, "section id");
    get("/v1/sections/!!!/tiles/0/0/0.png", 404, "no route");
    get("/v1/sections/" + std::string(20000, 'A') + "/tiles/0/0/0.png", 400, "section id");
    // A sid that decodes to two planes, and one with an unknown key (base64url of the text).
    get("/v1/sections/bW9kZWw9ZGVtbyZwbGFuZT0wLDEsMCwtMzM4ODg0NiZwbGFuZT0xLDAsMCwtMzU1MDQ1MDA/tiles/0/0/0.png", 400,
        "plane");
    get("/v1/sections/bW9kZWw9ZGVtbyZwbGFuZT0wLDEsMCwtMzM4ODg0NiZmb289MQ/tiles/0/0/0.png", 400, "foo");
    // POST bodies
    const std::string post = "/v1/models/demo/query";
    m.push_back(Case{"POST", post, 415, "Content-Type", R"({"view":{"plane":"0,1,0,-3388846"},"pixels":[[1,1]]})",
                     "text/plain"});
    m.push_back(Case{"POST", post, 400, "JSON", "{not json", "application/json"});
    m.push_back(Case{"POST", post, 400, "pixels", R"({"view":{"plane":"0,1,0,-3388846"}})", "application/json"});
    m.push_back(Case{"POST", post, 400, "pixels",
                     R"({"view":{"plane":"0,1,0,-3388846","size":"64x64"},"pixels":[[1,1],[1]]})", "application/json"});
    m.push_back(Case{"POST", post, 400, "frame",
                     R"({"view":{"plane":"0,1,0,-3388846","frame":[0,1e-300,0,1e-300]},"pixels":[[1,1]]})",
                     "application/json"});
    m.push_back(Case{"POST", post, 400, "foo", R"({"view":{"plane":"0,1,0,-3388846"},"pixels":[[1,1]],"foo":1})",
                     "application/json"});
    m.push_back(Case{"POST", "/v1/models/demo/sections", 400, "plane", R"({"plane":[0,0,0,1]})", "application/json"});
    m.push_back(Case{"POST", "/v1/models/demo/sections", 400, "planes",
                     R"({"planes":[[0,1,0,-3388846],[1,0,0,-35504794]],"cut":"union"})", "application/json"});
    m.push_back(Case{"POST", post, 400, "same plane",
                     R"({"view":{"planes":[[0,1,0,-3388846],[0,1,0,-3388846]],"cut":"union","view":"perspective"},)"
                     R"("pixels":[[1,1]]})",
                     "application/json"});
    m.push_back(Case{"POST", post, 400, "planes",
                     R"({"view":{"planes":[[0,1,0,-3388846],[1,0,"x",0]],"cut":"union","view":"perspective"},)"
                     R"("pixels":[[1,1]]})",
                     "application/json"});
    m.push_back(Case{"POST", "/v1/models/demo/sections", 400, "foo", R"({"plane":[0,1,0,-3388846],"foo":1})",
                     "application/json"});
    m.push_back(Case{"POST", "/v1/models/demo/sections", 415, "Content-Type", R"({"plane":[0,1,0,-3388846]})",
                     "application/x-www-form-urlencoded"});
    return m;
}

TEST_F(Hostile, BadInputMatrixIsAllNamed4xx) {
    const auto matrix = badInputMatrix();
    int failures = 0;
    double worst = 0.0;
    for (const Case& c : matrix) worst = std::max(worst, check(*server_, c, failures));
    ASSERT_TRUE(server_->running()) << server_->log();
    const double health = healthzMs(*server_);
    EXPECT_LT(health, 10.0);
    std::printf(
        "[ hostile ] bad-input matrix: %zu requests, %zu answered as expected, %d failed; slowest %.1f ms; "
        "/healthz after %.2f ms\n",
        matrix.size(), matrix.size() - std::size_t(failures), failures, worst, health);
    EXPECT_EQ(failures, 0);
}

TEST_F(Hostile, IfNoneMatchDoesNotSkipValidation) {
    auto cl = server_->client(30);
    // A plane that misses the model and a tiny frame: errors, not 304, whatever the client holds.
    for (const std::string& path :
         {kSection + "plane=0,1,0,0&size=64x64", kSection + kPlane + "&frame=0,1e-300,0,1e-300"}) {
        auto r = cl.Get(path.c_str(), httplib::Headers{{"If-None-Match", "*"}});
        ASSERT_TRUE(r);
        EXPECT_GE(r->status, 400) << path;
    }
}

TEST_F(Hostile, HeadersOfOperationalRoutes) {
    auto cl = server_->client(30);
    for (const char* path : {"/readyz", "/metrics", "/healthz", "/v1/models"}) {
        auto r = cl.Get(path);
        ASSERT_TRUE(r);
        EXPECT_EQ(r->get_header_value("X-Content-Type-Options"), "nosniff") << path;
    }
    for (const char* path : {"/readyz", "/metrics"}) {
        auto r = cl.Get(path);
        ASSERT_TRUE(r);
        EXPECT_FALSE(r->has_header("Access-Control-Allow-Origin")) << path;
    }
    auto ready = cl.Get("/readyz");
    ASSERT_TRUE(ready);
    EXPECT_EQ(ready->body.find("\"/"), std::string::npos) << ready->body;  // no absolute paths
}

}  // namespace
}  // namespace geoslice::test
