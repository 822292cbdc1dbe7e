// The HTTP server, end to end: a real SectionServer on a loopback port, real HTTP.
// The demo model is generated small (20k triangles) so every test stays fast.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "api/openapi.hpp"
#include "api/plan.hpp"
#include "model/crs/crs.hpp"
#include "model/version.hpp"
#include "server/http_server.hpp"
#include "tests/common/run_command.hpp"
#include "tests/common/tolerances.hpp"
#include "tests/server/server_fixture.hpp"

namespace geoslice::server {
namespace {

using nlohmann::json;
using test::kGkWorldTolM;  // metres, world points at GK eastings (tests/common/tolerances.hpp)
// Metres: world y of a contour vertex on the plane y = 3388846: the double cut leaves ~1e-8 m;
// 1 mm bounds it and still tells a point off the plane.
constexpr double kContourOnPlaneM = 1e-3;
// Metres: a line given in lon/lat, through GeographicLib to world and back against the same
// line in world metres: round trips at GK eastings measure ~4e-9 m (crs_test).
constexpr double kLonLatRoundTripM = 1e-6;
// Degrees: the demo is generated at 105.05 E 30.62 N and spans a few hundredths of a degree.
constexpr double kDemoLonLatDeg = 0.05;

// The demo model's east-west section through its centre (northing 3388846 m).
const std::string kPlane = "plane=0,1,0,-3388846";

ServerConfig testConfig() {
    ServerConfig c = loopbackConfig();
    c.demoTriangles = 20000;
    c.cacheMiB = 64;
    c.deadlineMs = 20000;
    return c;
}

class Server : public InProcessServer {
protected:
    static void SetUpTestSuite() { startServer(testConfig()); }
    static void TearDownTestSuite() { stopServer(); }
};

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// A problem answer: status, RFC 9457 fields, and a detail containing `needle`.
void expectProblem(const httplib::Result& r, int status, const std::string& needle) {
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    const json j = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(j.is_object()) << r->body;
    EXPECT_EQ(j["status"], status);
    EXPECT_TRUE(j.contains("title") && j.contains("detail") && j.contains("type"));
    EXPECT_NE(j["detail"].get<std::string>().find(needle), std::string::npos)
        << "detail '" << j["detail"] << "' lacks '" << needle << "'";
}

TEST_F(Server, HealthReadyAndModels) {
    EXPECT_EQ(getJson("/healthz")["status"], "ok");
    EXPECT_EQ(getJson("/readyz")["ready"], true);
    const json models = getJson("/v1/models");
    ASSERT_EQ(models["models"].size(), 1u);
    EXPECT_EQ(models["models"][0]["id"], "demo");
    const json m = getJson("/v1/models/demo");
    EXPECT_EQ(m["crs"]["id"], "EPSG:4523");
    EXPECT_EQ(m["crs"]["zone"], 35);
    EXPECT_GT(m["legend"].size(), 5u);
    EXPECT_LT(m["bounds"]["min"][0].get<double>(), m["bounds"]["max"][0].get<double>());
    auto legend = get("/v1/models/demo/legend.png");
    ASSERT_TRUE(legend);
    EXPECT_EQ(legend->status, 200);
    EXPECT_TRUE(startsWith(legend->body, "\x89PNG"));
}

// Issue 14: one version string, generated from project(VERSION) (model/version.hpp).
TEST_F(Server, ReportsTheOneProjectVersion) {
    EXPECT_EQ(getJson("/healthz")["version"], kVersion);
    EXPECT_EQ(getJson("/openapi.json")["info"]["version"], kVersion);
}

// Issue 14: the legend is drawn and encoded on a render worker like every other image (the
// HTTP thread only waits), so it is counted as a render of kind "legend".
TEST_F(Server, LegendIsRenderedOnARenderWorker) {
    auto legend = get("/v1/models/demo/legend.png");
    ASSERT_TRUE(legend);
    EXPECT_EQ(legend->status, 200);
    EXPECT_TRUE(startsWith(legend->body, "\x89PNG"));
    EXPECT_FALSE(legend->get_header_value("ETag").empty());
    auto metrics = get("/metrics");
    ASSERT_TRUE(metrics);
    EXPECT_NE(metrics->body.find("geoslice_render_duration_seconds_count{kind=\"legend\"} "), std::string::npos)
        << "no legend render counted by a worker";
}

TEST_F(Server, SectionImagesInEveryFormat) {
    const std::map<std::string, std::string> magic = {{"jpg", "\xff\xd8\xff"}, {"png", "\x89PNG"}, {"webp", "RIFF"}};
    for (const auto& [ext, prefix] : magic) {
        auto r = get("/v1/models/demo/section." + ext + "?" + kPlane + "&size=256x128");
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 200) << r->body;
        EXPECT_TRUE(startsWith(r->body, prefix)) << ext;
        EXPECT_FALSE(r->get_header_value("ETag").empty());
        EXPECT_NE(r->get_header_value("Cache-Control").find("max-age"), std::string::npos);
    }
    // Elevation slice and a bent polyline section.
    auto e = get("/v1/models/demo/section.png?elevation=300&size=128x128");
    ASSERT_TRUE(e);
    EXPECT_EQ(e->status, 200) << e->body;
    auto l =
        get("/v1/models/demo/section.png?line=35502500,3388000,35504500,3389000,35506500,3388500&size=256x128&vx=2");
    ASSERT_TRUE(l);
    EXPECT_EQ(l->status, 200) << l->body;
}

TEST_F(Server, VectorSectionsAsGeoJsonAndSvg) {
    const json g = getJson("/v1/models/demo/section.geojson?" + kPlane + "&size=256x128&space=plane");
    EXPECT_EQ(g["type"], "FeatureCollection");
    ASSERT_GT(g["features"].size(), 3u);
    double area = 0.0;
    for (const auto& f : g["features"])
        if (f["properties"]["kind"] == "body") area += f["properties"]["area_m2"].get<double>();
    EXPECT_GT(area, 1e6);
    const json w = getJson("/v1/models/demo/section.geojson?" + kPlane + "&space=projected");
    const auto& ring = w["features"][0]["geometry"]["coordinates"][0][0];
    EXPECT_NEAR(ring[0][1].get<double>(), 3388846.0, kContourOnPlaneM);  // world y of a point on the plane
    EXPECT_EQ(w["crs"]["properties"]["name"], "urn:ogc:def:crs:EPSG::4523");
    // The default is RFC 7946: WGS 84 lon/lat, no crs member; the same point through PROJ.
    const json d = getJson("/v1/models/demo/section.geojson?" + kPlane);
    EXPECT_FALSE(d.contains("crs"));
    EXPECT_EQ(d["geoslice"]["frame"], "world");
    const auto& lonlat = d["features"][0]["geometry"]["coordinates"][0][0][0];
    const auto& projected = ring[0];
    auto ll = convertPoint(Crs::fromEpsg(4523).value(), Crs::fromEpsg(4326).value(),
                           {projected[0].get<double>(), projected[1].get<double>(), 0.0});
    ASSERT_TRUE(ll.ok());
    // The first exterior position may differ (rings are re-wound in lon/lat): compare any vertex.
    bool found = false;
    for (const auto& p : d["features"][0]["geometry"]["coordinates"][0][0])
        found = found || (std::abs(p[0].get<double>() - ll.value().x) < 1e-9 &&
                          std::abs(p[1].get<double>() - ll.value().y) < 1e-9);
    EXPECT_TRUE(found) << lonlat.dump() << " vs " << ll.value().x << "," << ll.value().y;
    auto svg = get("/v1/models/demo/section.svg?" + kPlane + "&size=256x128");
    ASSERT_TRUE(svg);
    EXPECT_EQ(svg->status, 200);
    EXPECT_EQ(svg->get_header_value("Content-Type"), "image/svg+xml");
    EXPECT_NE(svg->body.find("<svg"), std::string::npos);
    expectProblem(get("/v1/models/demo/section.geojson?" + kPlane + "&space=mars"), 400, "space");
    // DXF for CAD (dxflib; read back by ezdxf in tests/unit/section_cli_test.cpp).
    auto dxf = get("/v1/models/demo/section.dxf?" + kPlane);
    ASSERT_TRUE(dxf);
    EXPECT_EQ(dxf->status, 200) << dxf->body;
    EXPECT_EQ(dxf->get_header_value("Content-Type"), "image/vnd.dxf");
    EXPECT_NE(dxf->body.find("AC1015"), std::string::npos);
    EXPECT_NE(dxf->body.find("HATCH"), std::string::npos);
    EXPECT_EQ(dxf->body.substr(dxf->body.size() - 4), "EOF\n");
    auto dxf3 = get("/v1/models/demo/section.dxf?" + kPlane + "&space=projected");
    ASSERT_TRUE(dxf3);
    EXPECT_EQ(dxf3->status, 200) << dxf3->body;
    EXPECT_NE(dxf3->body.find("AC1009"), std::string::npos);
    expectProblem(get("/v1/models/demo/section.dxf?" + kPlane + "&space=world"), 400, "space");
}

// A polyline given in CGCS2000 lon/lat is the same section as the line in projected metres.
TEST_F(Server, LonLatLinesAndBoreholes) {
    const Crs crs = Crs::fromEpsg(4523).value();
    const glm::dvec2 a{35502500.0, 3388000.0}, b{35506500.0, 3388500.0};
    const glm::dvec2 la = crs.toLonLat(a.x, a.y).value(), lb = crs.toLonLat(b.x, b.y).value();
    char lonlat[256];
    std::snprintf(lonlat, sizeof lonlat, "line=%.12f,%.12f,%.12f,%.12f&coords=lonlat", la.x, la.y, lb.x, lb.y);
    const std::string world = "line=35502500,3388000,35506500,3388500";
    for (const char* px : {"40", "120", "200"}) {
        const std::string q = std::string("&size=256x96&px=") + px + "&py=50";
        const json w = getJson("/v1/models/demo/query?" + world + q);
        const json g = getJson("/v1/models/demo/query?" + std::string(lonlat) + q);
        EXPECT_EQ(w["record"], g["record"]);
        EXPECT_NEAR(w["world"]["x"].get<double>(), g["world"]["x"].get<double>(),
                    kLonLatRoundTripM);  // GeographicLib round trip
        EXPECT_NEAR(w["world"]["y"].get<double>(), g["world"]["y"].get<double>(), kLonLatRoundTripM);
    }
    const glm::dvec2 hole = crs.toLonLat(35504000.0, 3388000.0).value();
    char q[128];
    std::snprintf(q, sizeof q, "/v1/models/demo/borehole?lon=%.12f&lat=%.12f", hole.x, hole.y);
    const json byLonLat = getJson(q);
    const json byXy = getJson("/v1/models/demo/borehole?x=35504000&y=3388000");
    EXPECT_EQ(byLonLat["intervals"].size(), byXy["intervals"].size());
    expectProblem(get("/v1/models/demo/section.png?line=1,2,3,4&coords=mercator"), 400, "coords");
}

TEST_F(Server, EtagGives304) {
    const std::string path = "/v1/models/demo/section.jpg?" + kPlane + "&size=200x100&bg=%23ffffff";
    auto first = get(path);
    ASSERT_TRUE(first);
    ASSERT_EQ(first->status, 200);
    const std::string etag = first->get_header_value("ETag");
    ASSERT_EQ(etag.front(), '"');
    httplib::Headers h = {{"If-None-Match", etag}};
    auto second = client().Get(path.c_str(), h);
    ASSERT_TRUE(second);
    EXPECT_EQ(second->status, 304);
    EXPECT_TRUE(second->body.empty());
    httplib::Headers other = {{"If-None-Match", "\"0000000000000000\""}};
    auto third = client().Get(path.c_str(), other);
    ASSERT_TRUE(third);
    EXPECT_EQ(third->status, 200);
    EXPECT_EQ(third->body, first->body);
}

// RFC 9110 13: If-None-Match compares weakly; the gzip and identity bodies have distinct
// ETags and each revalidates to a 304 that carries Vary; routes without a cached answer
// (model list, OpenAPI, model summary) still have validators and a Cache-Control.
TEST_F(Server, ConditionalGetsFollowRfc9110) {
    const std::string png = "/v1/models/demo/section.png?" + kPlane + "&size=64x32";
    auto first = get(png);
    ASSERT_TRUE(first);
    const std::string etag = first->get_header_value("ETag");
    auto weak = client().Get(png.c_str(), httplib::Headers{{"If-None-Match", "W/" + etag}});
    ASSERT_TRUE(weak);
    EXPECT_EQ(weak->status, 304);
    EXPECT_NE(weak->get_header_value("Vary").find("Accept-Encoding"), std::string::npos);

    httplib::Client raw("127.0.0.1", server_->port());
    raw.set_decompress(false);
    const std::string gj = "/v1/models/demo/section.geojson?" + kPlane + "&size=64x32";
    auto identity = raw.Get(gj.c_str(), httplib::Headers{{"Accept-Encoding", "identity"}});
    auto gzipped = raw.Get(gj.c_str(), httplib::Headers{{"Accept-Encoding", "gzip"}});
    ASSERT_TRUE(identity && gzipped);
    ASSERT_EQ(gzipped->get_header_value("Content-Encoding"), "gzip");
    const std::string idTag = identity->get_header_value("ETag"), gzTag = gzipped->get_header_value("ETag");
    EXPECT_NE(idTag, gzTag);
    EXPECT_EQ(gzTag, idTag.substr(0, idTag.size() - 1) + "-gzip\"");
    auto again = raw.Get(gj.c_str(), httplib::Headers{{"Accept-Encoding", "gzip"}, {"If-None-Match", gzTag}});
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 304);
    EXPECT_EQ(again->get_header_value("ETag"), gzTag);
    EXPECT_NE(again->get_header_value("Vary").find("Accept-Encoding"), std::string::npos);

    for (const std::string path : {"/v1/models", "/openapi.json", "/v1/models/demo"}) {
        auto r = get(path);
        ASSERT_TRUE(r) << path;
        ASSERT_EQ(r->status, 200) << path;
        const std::string tag = r->get_header_value("ETag");
        EXPECT_FALSE(tag.empty()) << path;
        EXPECT_FALSE(r->get_header_value("Cache-Control").empty()) << path;
        auto cond = client().Get(path.c_str(), httplib::Headers{{"If-None-Match", tag}});
        ASSERT_TRUE(cond) << path;
        EXPECT_EQ(cond->status, 304) << path;
        EXPECT_TRUE(cond->body.empty()) << path;
    }
    auto metrics = get("/metrics");
    ASSERT_TRUE(metrics);
    EXPECT_EQ(metrics->get_header_value("Cache-Control"), "no-store");
}

// The demo's holes log age codes (J2s, T3x, ORE) mapped to the model's units, as a real
// project's sidecar does: the model agrees with its own holes.
TEST_F(Server, DemoModelAgreesWithItsHoles) {
    const json j = getJson("/v1/models/demo/drillholes/check");
    const json& s = j["summary"];
    EXPECT_EQ(s["holes_traced"], s["holes"]);
    EXPECT_GT(s["logged_m"].get<double>(), 10000.0) << s.dump();
    EXPECT_GT(s["share"].get<double>(), 0.95) << s.dump();
    EXPECT_GT(s["contacts_found"].get<int>(), 0) << s.dump();
    for (const auto& c : j["codes"]) EXPECT_TRUE(c["in_model"].get<bool>()) << c.dump();
}

TEST_F(Server, QueryAnswersGeologyAndCoordinates) {
    const json j = getJson("/v1/models/demo/query?" + kPlane + "&size=512x256&px=256&py=128");
    EXPECT_EQ(j["hit"], true) << j.dump();
    EXPECT_TRUE(j["record"].contains("name"));
    EXPECT_TRUE(j["record"].contains("lithology"));
    const json& w = j["world"];
    EXPECT_NEAR(w["y"].get<double>(), 3388846.0, kGkWorldTolM);  // on the plane
    EXPECT_EQ(w["projected"]["zone"], 35);
    EXPECT_NEAR(w["geodetic"]["lon"].get<double>(), 105.05, kDemoLonLatDeg);
    EXPECT_NEAR(w["geodetic"]["lat"].get<double>(), 30.62, kDemoLonLatDeg);
    // A pixel in the sky above the model: a 200 that says there is no geology.
    const json sky = getJson("/v1/models/demo/query?" + kPlane + "&size=512x256&px=5&py=0&vx=10");
    EXPECT_EQ(sky["hit"], false);
    EXPECT_TRUE(sky["record"].is_null());
}

TEST_F(Server, BoreholeListsIntervals) {
    const json j = getJson("/v1/models/demo/borehole?x=35504000&y=3388000");
    ASSERT_GE(j["intervals"].size(), 3u) << j.dump();
    double last = -1.0;
    for (const auto& iv : j["intervals"]) {
        EXPECT_GE(iv["from_collar_m"].get<double>(), last - 1e-6);
        EXPECT_GT(iv["to_collar_m"].get<double>(), iv["from_collar_m"].get<double>());
        last = iv["to_collar_m"].get<double>();
    }
    auto outside = get("/v1/models/demo/borehole?x=0&y=0");
    expectProblem(outside, 400, "");
}

TEST_F(Server, TilesFromAStatelessSectionId) {
    auto c = client();
    auto r = c.Post("/v1/models/demo/sections", R"({"plane": [0, 1, 0, -3388846], "vx": 2})", "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 201) << r->body;
    const json j = json::parse(r->body);
    const std::string sid = j["sid"];
    EXPECT_EQ(j["grid"]["tileSize"], 256);
    EXPECT_GE(j["grid"]["maxZoom"].get<int>(), 4);
    // The id is the canonical definition: decoding it needs no server state.
    auto decoded = api::base64UrlDecode(sid);
    ASSERT_TRUE(decoded);
    EXPECT_NE(decoded.value().find("plane=0,1,0,-3388846"), std::string::npos);
    for (const char* t : {"0/0/0", "1/0/0", "1/1/0", "2/1/1"}) {
        auto tile = get("/v1/sections/" + sid + "/tiles/" + t + ".png");
        ASSERT_TRUE(tile);
        EXPECT_EQ(tile->status, 200) << t << tile->body;
        EXPECT_TRUE(startsWith(tile->body, "\x89PNG"));
    }
    expectProblem(get("/v1/sections/" + sid + "/tiles/1/2/0.png"), 404, "outside the grid");
    expectProblem(get("/v1/sections/" + sid + "/tiles/-1/0/0.png"), 404, "");
    expectProblem(get("/v1/sections/AAAA/tiles/0/0/0.png"), 400, "section id");
    EXPECT_EQ(getJson("/v1/sections/" + sid)["model"], "demo");
    // Cache busters that map clients add are ignored: the same tile, the same ETag.
    auto plain = get("/v1/sections/" + sid + "/tiles/1/0/0.png");
    auto busted = get("/v1/sections/" + sid + "/tiles/1/0/0.png?v=1&_=12345");
    ASSERT_TRUE(plain && busted);
    EXPECT_EQ(busted->status, 200);
    EXPECT_EQ(busted->body, plain->body);
    EXPECT_EQ(busted->get_header_value("ETag"), plain->get_header_value("ETag"));
    // TileJSON 3.0 and OGC API - Tiles describe the same grid, with absolute URLs.
    const json tj = getJson("/v1/sections/" + sid + "/tilejson.json");
    EXPECT_EQ(tj["tilejson"], "3.0.0");
    EXPECT_EQ(tj["maxzoom"], j["grid"]["maxZoom"]);
    const std::string tiles = tj["tiles"][0];
    EXPECT_EQ(tiles.rfind("http://127.0.0.1:", 0), 0u) << tiles;
    EXPECT_NE(tiles.find("/v1/sections/" + sid + "/tiles/{z}/{x}/{y}.png"), std::string::npos) << tiles;
    const json ts = getJson("/v1/sections/" + sid + "/tiles");
    EXPECT_EQ(ts["dataType"], "map");
    const json tms = getJson("/v1/sections/" + sid + "/tilematrixset");
    ASSERT_EQ(tms["tileMatrices"].size(), j["grid"]["maxZoom"].get<std::size_t>() + 1);
    const auto& m0 = tms["tileMatrices"][0];
    EXPECT_EQ(m0["matrixWidth"], 1);
    EXPECT_DOUBLE_EQ(m0["cellSize"].get<double>() * 256.0, j["grid"]["size0"].get<double>());
    EXPECT_DOUBLE_EQ(m0["pointOfOrigin"][0].get<double>(), j["grid"]["origin"]["u"].get<double>());
    EXPECT_DOUBLE_EQ(tms["tileMatrices"][2]["cellSize"].get<double>() * 4.0, m0["cellSize"].get<double>());
    // Each tile of the OGC item template is the xyz tile of the same numbers.
    bool item = false;
    for (const auto& l : ts["links"])
        item = item || (l["rel"] == "item" &&
                        l["href"].get<std::string>().find("{tileMatrix}/{tileCol}/{tileRow}.png") != std::string::npos);
    EXPECT_TRUE(item) << ts.dump();
}

TEST_F(Server, BadRequestsGiveProblemsThatNameTheInput) {
    const std::string base = "/v1/models/demo/section.jpg?";
    expectProblem(get(base + "plane=abc,1,0,0"), 400, "plane");
    expectProblem(get(base + "plane=nan,1,0,0"), 400, "not a finite number");
    expectProblem(get(base + "plane=inf,1,0,0"), 400, "plane");
    expectProblem(get(base + "plane=0,0,0,1"), 400, "zero length");
    expectProblem(get(base + "plane=0,1,0"), 400, "expected 4");
    expectProblem(get(base + kPlane + "&size=0x100"), 400, "width outside");
    expectProblem(get(base + kPlane + "&size=100000x100"), 400, "width outside");
    expectProblem(get(base + kPlane + "&size=-5x100"), 400, "size");
    expectProblem(get(base + kPlane + "&size=8192x8193"), 400, "height outside");
    expectProblem(get(base + kPlane + "&vx=0"), 400, "vx");
    expectProblem(get(base + kPlane + "&view=sideways"), 400, "view");
    expectProblem(get(base + kPlane + "&frame=5,1,0,1"), 400, "frame");
    expectProblem(get(base + kPlane + "&plane=0,1,0,0"), 400, "more than once");
    expectProblem(get(base), 400, "no section geometry");
    expectProblem(get(base + "plane=0,1,0,0"), 400, "misses the model");
    expectProblem(get(base + "line=1,2"), 400, "line");
    expectProblem(get("/v1/models/nosuch/section.jpg?" + kPlane), 404, "no model 'nosuch'");
    expectProblem(get("/v1/models/demo/section.gif?" + kPlane), 404, "format");
    expectProblem(get("/v1/models/..%2F..%2Fetc%2Fpasswd/section.jpg?" + kPlane), 404, "");
    expectProblem(get("/v1/models/.hidden"), 404, "not a valid id");
    expectProblem(get("/v1/nothing/here"), 404, "no route");
    expectProblem(get("/v1/models/demo/query?" + kPlane + "&px=5"), 400, "py");
    expectProblem(get("/v1/models/demo/query?" + kPlane + "&size=10x10&px=10&py=0"), 400, "outside");
    expectProblem(get("/v1/models/demo/section.jpg?" + kPlane + "&view=perspective"), 422, "GL");

    auto c = client();
    expectProblem(c.Post("/v1/models/demo/sections", "{not json", "application/json"), 400, "not valid JSON");
    expectProblem(c.Post("/v1/models/demo/query", "[1,2]", "application/json"), 400, "JSON object");
    expectProblem(c.Post("/v1/models/demo/query", R"({"view": {"plane": "0,1,0,-3388846"}, "pixels": [[1, "x"]]})",
                         "application/json"),
                  400, "pixels[0]");
    // A body over the limit is refused from its Content-Length, before it is read: send the
    // header alone (a client streaming 2 MiB would race the server's close and get EPIPE).
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    ASSERT_GE(fd, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(server_->port()));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    const std::string head =
        "POST /v1/models/demo/sections HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
        "Content-Length: " +
        std::to_string(2 << 20) + "\r\n\r\n";
    ASSERT_EQ(send(fd, head.data(), head.size(), MSG_NOSIGNAL), static_cast<ssize_t>(head.size()));
    char buf[512] = {};
    const ssize_t n = recv(fd, buf, sizeof buf - 1, 0);
    close(fd);
    ASSERT_GT(n, 12);
    EXPECT_EQ(std::string(buf, 12), "HTTP/1.1 413") << buf;
}

TEST_F(Server, OpenApiListsExactlyTheRoutes) {
    const json doc = getJson("/openapi.json");
    EXPECT_EQ(doc["openapi"], "3.0.3");
    std::set<std::pair<std::string, std::string>> documented;
    for (const auto& [path, ops] : doc["paths"].items())
        for (const auto& [method, op] : ops.items()) {
            std::string m = method;
            std::transform(m.begin(), m.end(), m.begin(), ::toupper);
            documented.emplace(m, path);
        }
    std::set<std::pair<std::string, std::string>> routes;
    for (const auto& r : api::apiRoutes()) routes.emplace(r.method, r.path);
    EXPECT_EQ(documented, routes);
    // What a client generator needs: a unique operationId per operation, a server, and the
    // statuses the server sends.
    EXPECT_EQ(doc["servers"][0]["url"], "/");
    std::set<std::string> ids;
    for (const auto& [path, ops] : doc["paths"].items())
        for (const auto& [method, op] : ops.items()) {
            ASSERT_TRUE(op.contains("operationId")) << method << " " << path;
            EXPECT_TRUE(ids.insert(op["operationId"].get<std::string>()).second) << op["operationId"];
            EXPECT_TRUE(op["responses"].contains("500")) << path;
            if (method != "delete") {
                EXPECT_TRUE(op["responses"].contains(method == "get" ? "304" : "415")) << path;
            }
        }
    // Every listed route is served: a concrete request never falls through to "no route".
    auto c = client();
    for (const auto& r : api::apiRoutes()) {
        std::string path = r.path;
        auto sub = [&](const std::string& from, const std::string& to) {
            if (const auto p = path.find(from); p != std::string::npos) path.replace(p, from.size(), to);
        };
        sub("{id}", "demo");
        sub("{format}", "png");
        sub("{sid}", api::base64UrlEncode("model=demo&" + kPlane));
        sub("{z}", "0");
        sub("{x}", "0");
        sub("{y}", "0");
        sub("{asset}", "app.js");
        sub("{n}", "0");
        auto res = r.method == "GET"      ? c.Get(path.c_str())
                   : r.method == "DELETE" ? c.Delete(path.c_str())
                                          : c.Post(path.c_str(), "{}", "application/json");
        ASSERT_TRUE(res) << path;
        EXPECT_EQ(res->body.find("no route for"), std::string::npos) << r.method << " " << path;
    }
}

TEST_F(Server, JsonIsGzippedWhenAccepted) {
    httplib::Client c("127.0.0.1", server_->port());
    c.set_decompress(false);
    httplib::Headers h = {{"Accept-Encoding", "gzip"}};
    auto r = c.Get("/openapi.json", h);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->get_header_value("Content-Encoding"), "gzip");
}

TEST_F(Server, CorsHeaders) {
    auto r = get("/healthz");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->get_header_value("Access-Control-Allow-Origin"), "*");
    auto pre = client().Options("/v1/models/demo/section.jpg");
    ASSERT_TRUE(pre);
    EXPECT_EQ(pre->status, 204);
    EXPECT_NE(pre->get_header_value("Access-Control-Allow-Methods").find("GET"), std::string::npos);
}

TEST_F(Server, MetricsInPrometheusFormat) {
    (void)get("/healthz");
    (void)get("/no/such/route");
    (void)get("/v1/models/demo/section.png?" + kPlane + "&size=64x32");
    auto r = get("/metrics");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->get_header_value("Content-Type"), "text/plain; version=0.0.4; charset=utf-8");
    EXPECT_NE(r->body.find("geoslice_http_requests_total{route=\"/healthz\",method=\"GET\",status=\"200\"}"),
              std::string::npos);
    // A request no route answered is counted too.
    EXPECT_NE(r->body.find("geoslice_http_requests_total{route=\"(unmatched)\",method=\"GET\",status=\"404\"} "),
              std::string::npos);
    EXPECT_NE(r->body.find("geoslice_http_request_duration_seconds_bucket{route=\"/healthz\""), std::string::npos);
    EXPECT_NE(r->body.find("\ngeoslice_queue_depth "), std::string::npos);
    EXPECT_NE(r->body.find("\ngeoslice_cache_bytes "), std::string::npos);
    // Counts from start, as counters: no counter without _total, no family twice.
    EXPECT_NE(r->body.find("\ngeoslice_deadline_exceeded_total 0\n"), std::string::npos);
    std::set<std::string> families;
    std::istringstream lines(r->body);
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("# TYPE ", 0) != 0) continue;
        std::istringstream f(line.substr(7));
        std::string name, type;
        f >> name >> type;
        EXPECT_TRUE(families.insert(name).second) << name << " exported twice";
        if (type == "counter") {
            EXPECT_TRUE(name.size() > 6 && name.substr(name.size() - 6) == "_total") << name;
        }
    }
    EXPECT_GE(families.size(), 25u);
    // Prometheus' own linter (Debian's prometheus package): no problem at all.
    const auto file = freshTempDir("geoslice_metrics") / "metrics.txt";
    {
        std::ofstream out(file, std::ios::binary);
        out << r->body;
    }
    const auto lint = test::runCommand("promtool check metrics < '" + file.string() + "' 2>&1");
    EXPECT_EQ(lint.exitCode, 0) << lint.out;
    EXPECT_EQ(lint.out, "") << lint.out;
}

// 64 clients at once, a mix of views: every answer equals the serial one.
TEST_F(Server, ConcurrentClientsGetSerialResults) {
    std::vector<std::string> paths;
    for (int i = 0; i < 16; ++i) {
        const double y = 3387500.0 + 200.0 * i;
        paths.push_back("/v1/models/demo/section.png?plane=0,1,0," + api::formatNumber(-y) +
                        "&size=192x96&bg=%23ffffff");
    }
    std::vector<std::string> serial;
    for (const auto& p : paths) {
        auto r = get(p + "&quality=90");  // a different key: the concurrent run below renders afresh
        ASSERT_TRUE(r);
        ASSERT_EQ(r->status, 200);
        serial.push_back(r->body);
    }
    std::vector<std::string> concurrent(64);
    std::vector<int> status(64, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 64; ++t)
        threads.emplace_back([&, t] {
            httplib::Client c("127.0.0.1", server_->port());
            c.set_read_timeout(120, 0);
            auto r = c.Get((paths[std::size_t(t) % paths.size()] + "&quality=90").c_str());
            if (r) {
                status[std::size_t(t)] = r->status;
                concurrent[std::size_t(t)] = r->body;
            }
        });
    for (auto& t : threads) t.join();
    for (int t = 0; t < 64; ++t) {
        EXPECT_EQ(status[std::size_t(t)], 200) << t;
        EXPECT_EQ(concurrent[std::size_t(t)], serial[std::size_t(t) % paths.size()]) << t;
    }
    // And when none is cached: identical concurrent requests coalesce into one render each.
    std::vector<std::string> fresh(64);
    threads.clear();
    for (int t = 0; t < 64; ++t)
        threads.emplace_back([&, t] {
            httplib::Client c("127.0.0.1", server_->port());
            c.set_read_timeout(120, 0);
            auto r = c.Get((paths[std::size_t(t) % paths.size()] + "&quality=80").c_str());
            if (r && r->status == 200) fresh[std::size_t(t)] = r->body;
        });
    for (auto& t : threads) t.join();
    for (int t = 0; t < 64; ++t) EXPECT_EQ(fresh[std::size_t(t)], serial[std::size_t(t) % paths.size()]) << t;
}

// The query at a pixel equals the image's ID buffer at that pixel: 1000 random pixels over
// four views, answered first by the exact ray (nothing cached) and then from the cached ID
// buffer of the rendered image.
TEST_F(Server, QueryAgreesWithTheImageIdBuffer) {
    const std::vector<json> views = {
        {{"plane", "0,1,0,-3388846"}, {"size", "300x150"}},
        {{"plane", "0.6,0.8,0,-24013953"}, {"size", "256x256"}, {"vx", "3"}},
        {{"elevation", "200"}, {"size", "200x200"}},
        {{"line", "35502500,3388000,35504500,3389000,35506500,3388500"}, {"size", "320x120"}},
    };
    std::mt19937 rng(7);
    std::size_t total = 0, agree = 0;
    auto c = client();
    for (const json& view : views) {
        const auto size = api::parseSize("size", view["size"].get<std::string>(), 8192, 1 << 26).value();
        json pixels = json::array();
        for (int i = 0; i < 250; ++i)
            pixels.push_back({int(rng() % unsigned(size.width)), int(rng() % unsigned(size.height))});
        const json body = {{"view", view}, {"pixels", pixels}};
        auto ray = c.Post("/v1/models/demo/query", body.dump(), "application/json");
        ASSERT_TRUE(ray);
        ASSERT_EQ(ray->status, 200) << ray->body;
        // Render the identical view (its ID buffer is cached), then ask again.
        std::string q;
        for (const auto& [k, v] : view.items()) q += k + "=" + v.get<std::string>() + "&";
        auto image = get("/v1/models/demo/section.png?" + q);
        ASSERT_TRUE(image);
        ASSERT_EQ(image->status, 200) << image->body;
        auto cached = c.Post("/v1/models/demo/query", body.dump(), "application/json");
        ASSERT_TRUE(cached);
        const json a = json::parse(ray->body)["results"], b = json::parse(cached->body)["results"];
        ASSERT_EQ(a.size(), 250u);
        for (std::size_t i = 0; i < a.size(); ++i) {
            EXPECT_EQ(a[i]["source"], "ray");
            EXPECT_EQ(b[i]["source"], "id-buffer");
            const auto idA = a[i]["hit"] ? a[i]["record"]["id"].get<int>() : 0;
            const auto idB = b[i]["hit"] ? b[i]["record"]["id"].get<int>() : 0;
            ++total;
            agree += idA == idB;
            if (idA != idB)
                ADD_FAILURE() << view.dump() << " pixel " << pixels[i] << ": ray " << idA << ", id buffer " << idB;
            EXPECT_EQ(a[i]["world"]["x"], b[i]["world"]["x"]);
        }
    }
    EXPECT_EQ(total, 1000u);
    std::printf("profile queries: ray and ID buffer agree at %zu of %zu pixels\n", agree, total);
    // Pixel centres exactly on a boundary may go either way between the float ray oracle
    // and the exact double cut; the section engine tests measured 0 such pixels.
    EXPECT_GE(double(agree) / double(total), 0.999) << agree << " of " << total;
}

// Identical requests that arrive while the first is rendering share its render.
TEST(ServerCoalescing, IdenticalRequestsShareOneRender) {
    spdlog::set_level(spdlog::level::err);
    ServerConfig c = testConfig();
    c.workers = 1;
    SectionServer s(c);
    auto port = s.start();
    ASSERT_TRUE(port);
    ASSERT_TRUE(s.waitUntilLoaded());
    std::vector<std::thread> threads;
    std::vector<std::string> bodies(8);
    for (int t = 0; t < 8; ++t)
        threads.emplace_back([&, t] {
            httplib::Client cl("127.0.0.1", port.value());
            cl.set_read_timeout(60, 0);
            auto r = cl.Get("/v1/models/demo/section.png?plane=0,1,0,-3388846&size=3000x3000");
            if (r && r->status == 200) bodies[std::size_t(t)] = r->body;
        });
    for (auto& t : threads) t.join();
    for (const auto& b : bodies) EXPECT_EQ(b, bodies[0]);
    httplib::Client cl("127.0.0.1", port.value());
    auto m = cl.Get("/metrics");
    ASSERT_TRUE(m);
    const std::string series = "\ngeoslice_renders_coalesced_total ";
    const auto at = m->body.find(series);
    ASSERT_NE(at, std::string::npos);
    const double coalesced = std::stod(m->body.substr(at + series.size()));
    // 8 requests, one render of about 100 ms: the ones that arrive during it join it (the
    // rest, if any, are cache hits).
    EXPECT_GE(coalesced, 1.0);
    std::printf("8 identical requests: %.0f joined another's render\n", coalesced);
}

// A full queue answers 503 with Retry-After; a render past its deadline answers 504.
TEST(ServerLimits, QueueFullAndDeadline) {
    spdlog::set_level(spdlog::level::err);
    ServerConfig c = testConfig();
    c.workers = 1;
    c.queue = 1;
    c.deadlineMs = 20000;
    SectionServer s(c);
    ASSERT_TRUE(s.start());
    ASSERT_TRUE(s.waitUntilLoaded());
    std::atomic<int> ok{0}, busy{0}, retryAfter{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 24; ++t)
        threads.emplace_back([&, t] {
            httplib::Client cl("127.0.0.1", s.port());
            cl.set_read_timeout(120, 0);
            const std::string p =
                "/v1/models/demo/section.png?plane=0,1,0," + std::to_string(-3387000 - 50 * t) + "&size=2048x2048";
            auto r = cl.Get(p.c_str());
            if (!r) return;
            if (r->status == 200) ++ok;
            if (r->status == 503) {
                ++busy;
                retryAfter += !r->get_header_value("Retry-After").empty();
            }
        });
    for (auto& t : threads) t.join();
    EXPECT_GE(ok.load(), 1);
    EXPECT_GE(busy.load(), 1);
    EXPECT_EQ(retryAfter.load(), busy.load());
    s.stop();

    ServerConfig d = testConfig();
    d.deadlineMs = 1;
    SectionServer slow(d);
    ASSERT_TRUE(slow.start());
    ASSERT_TRUE(slow.waitUntilLoaded());
    httplib::Client cl("127.0.0.1", slow.port());
    auto r = cl.Get("/v1/models/demo/section.png?plane=0,1,0,-3388846&size=4096x4096");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 504) << r->body;
}

// Graceful shutdown: a request in flight finishes; afterwards the port is closed.
TEST(ServerLifecycle, GracefulShutdown) {
    spdlog::set_level(spdlog::level::err);
    ServerConfig c = testConfig();
    SectionServer s(c);
    auto port = s.start();
    ASSERT_TRUE(port);
    ASSERT_TRUE(s.waitUntilLoaded());
    int status = 0;
    std::thread inflight([&] {
        httplib::Client cl("127.0.0.1", port.value());
        cl.set_read_timeout(60, 0);
        auto r = cl.Get("/v1/models/demo/section.png?plane=0,1,0,-3388846&size=3000x3000");
        status = r ? r->status : -1;
    });
    // Stop once the render is under way (a fixed 30 ms was not always enough under load: the
    // request then arrived after stop() and was refused with 503, as it should be).
    httplib::Client probe("127.0.0.1", port.value());
    for (int i = 0; i < 1000; ++i) {
        auto m = probe.Get("/metrics");
        if (m && m->body.find("\ngeoslice_workers_busy 0\n") == std::string::npos) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    s.stop();
    inflight.join();
    EXPECT_EQ(status, 200);
    httplib::Client after("127.0.0.1", port.value());
    after.set_connection_timeout(1, 0);
    EXPECT_FALSE(after.Get("/healthz"));
}

// Perspective views go through a render worker's own GL context (llvmpipe in CI).
TEST(ServerGl, PerspectiveViewThroughAWorkerContext) {
    spdlog::set_level(spdlog::level::err);
    ServerConfig c = testConfig();
    c.gl = "auto";
    SectionServer s(c);
    ASSERT_TRUE(s.start());
    ASSERT_TRUE(s.waitUntilLoaded());
    httplib::Client cl("127.0.0.1", s.port());
    cl.set_read_timeout(60, 0);
    auto r = cl.Get("/v1/models/demo/section.png?plane=0,1,0,-3388846&view=perspective&size=320x240");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << r->body;
    EXPECT_TRUE(startsWith(r->body, "\x89PNG"));
    auto ready = cl.Get("/readyz");
    ASSERT_TRUE(ready);
    const json j = json::parse(ready->body);
    EXPECT_EQ(j["gl"]["ready"], true) << ready->body;
    auto bad = cl.Get("/v1/models/demo/section.png?plane=0,1,0,-3388846&view=perspective&eye=1,2,3&target=1,2,3");
    expectProblem(bad, 400, "coincide");

    // Queries of a perspective view: the exact ray (before the view is rendered) against the
    // GL ID buffer (after). They differ only where a pixel centre falls within rasterisation
    // precision of an edge, so >= 99 % of 500 random pixels must agree.
    const json view = {{"plane", "0,1,0,-3388846"},        {"view", "perspective"}, {"eye", "35509000,3383000,4000"},
                       {"target", "35504794,3388846,700"}, {"size", "256x192"},     {"vx", "2"}};
    std::mt19937 rng(11);
    json pixels = json::array();
    for (int i = 0; i < 500; ++i) pixels.push_back({int(rng() % 256u), int(rng() % 192u)});
    const json body = {{"view", view}, {"pixels", pixels}};
    auto ray = cl.Post("/v1/models/demo/query", body.dump(), "application/json");
    ASSERT_TRUE(ray);
    ASSERT_EQ(ray->status, 200) << ray->body;
    std::string q;
    for (const auto& [k, v] : view.items()) q += k + "=" + v.get<std::string>() + "&";
    auto image = cl.Get(("/v1/models/demo/section.png?" + q).c_str());
    ASSERT_TRUE(image);
    ASSERT_EQ(image->status, 200) << image->body;
    auto fromIds = cl.Post("/v1/models/demo/query", body.dump(), "application/json");
    ASSERT_TRUE(fromIds);
    const json a = json::parse(ray->body)["results"], b = json::parse(fromIds->body)["results"];
    std::size_t agree = 0, hits = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i]["source"], "ray");
        EXPECT_EQ(b[i]["source"], "id-buffer");
        const int idA = a[i]["hit"] ? a[i]["record"]["id"].get<int>() : 0;
        const int idB = b[i]["hit"] ? b[i]["record"]["id"].get<int>() : 0;
        agree += idA == idB;
        hits += idA != 0;
    }
    std::printf("perspective queries: ray and GL ID buffer agree at %zu of %zu pixels (%zu on geology)\n", agree,
                a.size(), hits);
    EXPECT_GT(hits, 100u);
    EXPECT_GE(double(agree) / double(a.size()), 0.99) << agree << " of " << a.size();
}

// 3D Tiles of the demo (renderer/tiles3d/tileset3d.hpp; placement and content are checked in
// tests/unit/tiles3d_test.cpp and in CesiumJS by tests/web/cesium_test.mjs): the tileset, its
// tiles by the URIs it names, validators and 304s, a tile that does not exist.
TEST_F(Server, ModelAs3dTiles) {
    const json ts = getJson("/v1/models/demo/3dtiles/tileset.json");
    EXPECT_EQ(ts["asset"]["version"], "1.1");
    ASSERT_EQ(ts["root"]["transform"].size(), 16u);
    EXPECT_EQ(ts["root"]["refine"], "REPLACE");
    // The translation is Earth-fixed: about 6,370 km from the centre of the Earth.
    const double r = std::hypot(ts["root"]["transform"][12].get<double>(), ts["root"]["transform"][13].get<double>(),
                                ts["root"]["transform"][14].get<double>());
    EXPECT_NEAR(r, 6.37e6, 2e4);
    const std::string uri = ts["root"]["content"]["uri"];
    auto tile = client().Get(("/v1/models/demo/3dtiles/" + uri).c_str());
    ASSERT_TRUE(tile);
    EXPECT_EQ(tile->status, 200);
    EXPECT_EQ(tile->get_header_value("Content-Type"), "model/gltf-binary");
    ASSERT_GE(tile->body.size(), 12u);
    EXPECT_EQ(tile->body.substr(0, 4), "glTF");
    const std::string etag = tile->get_header_value("ETag");
    ASSERT_FALSE(etag.empty());
    auto again =
        client().Get(("/v1/models/demo/3dtiles/" + uri + "&v=1").c_str(), httplib::Headers{{"If-None-Match", etag}});
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 304);
    expectProblem(client().Get("/v1/models/demo/3dtiles/tiles/999999.glb"), 404, "tiles, no 999999");
    expectProblem(client().Get("/v1/models/nope/3dtiles/tileset.json"), 404, "nope");
}

// URLs pinned to the model's content version (server/routes/common.hpp versionPinHolds): the
// served version is immutable for a year, another version is a 404 naming both, no version a
// minute; the section templates, TileJSON and 3D Tiles carry the pin.
TEST_F(Server, VersionedUrlsAreImmutableAndStaleOnesAnswer404) {
    const json model = getJson("/v1/models/demo");
    const std::string version = model["version"];
    ASSERT_EQ(version.size(), 16u);
    const std::string png = "/v1/models/demo/section.png?" + kPlane + "&size=64x32";
    auto plain = client().Get(png.c_str());
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->status, 200);
    EXPECT_EQ(plain->get_header_value("Cache-Control"), "public, max-age=60");
    auto pinned = client().Get((png + "&version=" + version).c_str());
    ASSERT_TRUE(pinned);
    EXPECT_EQ(pinned->status, 200);
    EXPECT_EQ(pinned->get_header_value("Cache-Control"), "public, max-age=31536000, immutable");
    EXPECT_EQ(pinned->body, plain->body);
    auto again = client().Get((png + "&version=" + version).c_str(),
                              httplib::Headers{{"If-None-Match", pinned->get_header_value("ETag")}});
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 304);
    EXPECT_EQ(again->get_header_value("Cache-Control"), "public, max-age=31536000, immutable");
    expectProblem(client().Get((png + "&version=0123456789abcdef").c_str()), 404, "is at version " + version);
    expectProblem(client().Get(("/v1/models/demo/query?" + kPlane + "&size=64x32&px=1&py=1&version=old").c_str()), 404,
                  "names version 'old'");
    // Section templates and their standard descriptions are pinned.
    auto def = client().Post("/v1/models/demo/sections", "{\"plane\": \"0,1,0,-3388846\"}", "application/json");
    ASSERT_TRUE(def);
    ASSERT_EQ(def->status, 201);
    const json d = json::parse(def->body);
    EXPECT_EQ(d["version"], version);
    const std::string tiles = d["tiles"];
    EXPECT_NE(tiles.find("?version=" + version), std::string::npos) << tiles;
    const std::string sid = d["sid"];
    auto tile = client().Get(("/v1/sections/" + sid + "/tiles/0/0/0.png?version=" + version).c_str());
    ASSERT_TRUE(tile);
    EXPECT_EQ(tile->status, 200);
    EXPECT_EQ(tile->get_header_value("Cache-Control"), "public, max-age=31536000, immutable");
    expectProblem(client().Get(("/v1/sections/" + sid + "/tiles/0/0/0.png?version=0000").c_str()), 404, "version");
    const json tj = getJson("/v1/sections/" + sid + "/tilejson.json?version=" + version);
    EXPECT_NE(tj["tiles"][0].get<std::string>().find("?version=" + version), std::string::npos);
    const json ts = getJson("/v1/models/demo/3dtiles/tileset.json?version=" + version);
    EXPECT_NE(ts["root"]["content"]["uri"].get<std::string>().find("?version=" + version), std::string::npos);
}

}  // namespace
}  // namespace geoslice::server
