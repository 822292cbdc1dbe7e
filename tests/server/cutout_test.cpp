// Cut-outs over HTTP (api/cut.hpp): perspective views cut by up to six planes, rendered by a
// render worker's GL context (llvmpipe in CI), and the pixel queries of those views.
//
//  1. The demo model (faults, a nested orebody): for a wedge, an octant and a box taken out
//     (cut=intersection) and a wedge and a box kept (cut=union), the exact ray query (asked
//     before the image exists) and the GL ID buffer (asked after) are compared at every pixel.
//     Tolerance:
//     where they differ, each one's record must appear in the other's 3x3 neighbourhood (a
//     pixel centre within rasterisation precision of an edge between records), and at least
//     99 % of pixels must agree exactly.
//  2. The tetrahedral model of tests/common/tet_model.hpp served from a .vtu, against an exact
//     oracle written here: the ray through the pixel centre against every tetrahedron (double)
//     and the kept region (from the definition), first kept point. At 1,500 random pixels the
//     ray query gives the oracle's record (100 % of pixels whose oracle record is the same at
//     +-0.05 px around the centre; nearer an edge, float32 Embree and the double oracle may pick
//     either side) and its world point within 1 mm (Embree's float32 hit distance at 100 m
//     from the local origin is ~1e-5 m; 1 mm leaves room for the tracer's tolerance band), and
//     the GL ID buffer agrees at >= 99 % of them (rasterisation at edges).
//  3. The golden cases with "runner": "http" (tests/data/goldens/api_wedge_cutout: a wedge
//     cut-out of the demo model) through the whole HTTP path, compared by the shared comparator
//     (tests/common/golden.hpp) with the tolerance and reason in the case's request.json (24 of
//     255 per channel, at most 0.5 % failing pixels: lighting rounding and one-pixel edge moves
//     between Mesa versions). UPDATE_GOLDENS=1 rewrites it; a failure writes the actual and a
//     diff image into the temp folder's geoslice_golden_failures/.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <sys/wait.h>

#include <gtest/gtest.h>
#include <httplib.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "api/plan.hpp"
#include "api/view.hpp"
#include "image/image_encode.hpp"
#include "server/http_server.hpp"
#include "tests/common/golden.hpp"
#include "tests/common/tet_model.hpp"
#include "tests/common/vtu_writer.hpp"
#include "tests/server/server_fixture.hpp"

namespace geoslice::server {
namespace {

// Metres: a ray query's hit comes from Embree in the float32 local frame of a model a few
// kilometres wide (float steps of ~0.5 mm at 4 km).
constexpr double kRayHitTolM = 1e-3;

namespace fs = std::filesystem;
using nlohmann::json;

ServerConfig glConfig() {
    ServerConfig c = loopbackConfig();
    c.gl = "auto";
    c.workers = 1;
    c.demoTriangles = 20000;
    c.cacheMiB = 256;
    c.deadlineMs = 120000;
    return c;
}

std::string queryString(const json& view) {
    std::string q;
    for (const auto& [k, v] : view.items()) {
        std::string value = v.get<std::string>();
        for (std::size_t p = value.find('#'); p != std::string::npos; p = value.find('#')) value.replace(p, 1, "%23");
        q += (q.empty() ? "" : "&") + k + "=" + value;
    }
    return q;
}

// The records of `pixels` of `view` from POST /query (batches of 5,000), and their world points.
struct Answers {
    std::vector<int> ids;
    std::vector<std::string> sources;
    std::vector<glm::dvec3> world;  // NaN where nothing is hit
};
Answers queryPixels(httplib::Client& cl, const std::string& model, const json& view,
                    const std::vector<std::array<int, 2>>& pixels) {
    Answers out;
    for (std::size_t first = 0; first < pixels.size(); first += 5000) {
        json batch = json::array();
        for (std::size_t i = first; i < std::min(pixels.size(), first + 5000); ++i)
            batch.push_back({pixels[i][0], pixels[i][1]});
        const json body = {{"view", view}, {"pixels", batch}};
        auto r = cl.Post(("/v1/models/" + model + "/query").c_str(), body.dump(), "application/json");
        EXPECT_TRUE(r);
        if (!r) return out;
        EXPECT_EQ(r->status, 200) << r->body.substr(0, 400);
        if (r->status != 200) return out;
        const json parsed = json::parse(r->body);
        for (const json& a : parsed["results"]) {
            out.ids.push_back(a["hit"].get<bool>() ? a["record"]["id"].get<int>() : 0);
            out.sources.push_back(a["source"]);
            const double nan = std::numeric_limits<double>::quiet_NaN();
            out.world.push_back(a["world"].is_null()
                                    ? glm::dvec3(nan)
                                    : glm::dvec3(a["world"]["x"].get<double>(), a["world"]["y"].get<double>(),
                                                 a["world"]["z"].get<double>()));
        }
    }
    return out;
}

std::vector<std::array<int, 2>> allPixels(int w, int h) {
    std::vector<std::array<int, 2>> p;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) p.push_back({x, y});
    return p;
}

bool inNeighbourhood(const std::vector<int>& ids, int w, int h, int x, int y, int id) {
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx >= 0 && yy >= 0 && xx < w && yy < h && ids[std::size_t(yy) * std::size_t(w) + std::size_t(xx)] == id)
                return true;
        }
    return false;
}

class CutOutServer : public InProcessServer {
protected:
    static void SetUpTestSuite() { startServer(glConfig(), 300, spdlog::level::err); }
    static void TearDownTestSuite() { stopServer(); }
};

// The demo model's centre (metres, EPSG:4523) and a camera from the south-east, above.
const std::string kCentreX = "35504794", kCentreY = "3388846", kCentreZ = "700";
json demoView(const std::string& planes, const std::string& cut, int w, int h) {
    return {{"planes", planes},
            {"cut", cut},
            {"view", "perspective"},
            {"eye", "35509500,3383500,4500"},
            {"target", kCentreX + "," + kCentreY + "," + kCentreZ},
            {"size", std::to_string(w) + "x" + std::to_string(h)},
            {"vx", "2"}};
}

TEST_F(CutOutServer, IdBufferAndQueryAgreeAtEveryPixel) {
    auto cl = client();
    const int w = 160, h = 120;
    // Planes through the centre: x = 35504794 (east), y = 3388846 (north), z = 700 (up).
    const std::string east = "-1,0,0," + kCentreX, north = "0,1,0,-" + kCentreY, up = "0,0,-1," + kCentreZ;
    const std::string south = "0,1,0,-3387600";
    const std::vector<std::pair<std::string, json>> cases = {
        // The south-east quarter taken out (removed: x > cx and y < cy).
        {"wedge", demoView(east + ";" + north, "intersection", w, h)},
        // The upper south-east octant taken out.
        {"octant", demoView(east + ";" + north + ";" + up, "intersection", w, h)},
        // A box taken out: six planes, each keeping the outside of one face; the box reaches
        // past the model's south side and top, so it is open to the camera.
        {"box", demoView("1,0,0,-35506500;-1,0,0,35504000;0,1,0,-3388846;0,-1,0,3386000;0,0,1,-3000;0,0,-1,0",
                         "intersection", w, h)},
        // A wedge kept (cut=union): the part on the kept side of both planes; rays near its
        // apex enter and leave it inside one body.
        {"kept wedge",
         demoView("0.8,0.6,0,-" + std::to_string(0.8 * 35504794.0 + 0.6 * 3388846.0) + ";" + south, "union", w, h)},
        // A kept box (cut=union, six planes): every ray through it leaves it inside a body.
        {"kept box", demoView("1,0,0,-35503000;-1,0,0,35506500;0,1,0,-3387500;0,-1,0,3390000;0,0,1,-300;0,0,-1,1500",
                              "union", w, h)},
    };
    for (const auto& [name, view] : cases) {
        SCOPED_TRACE(name);
        const auto pixels = allPixels(w, h);
        const Answers ray = queryPixels(cl, "demo", view, pixels);
        auto image = cl.Get(("/v1/models/demo/section.png?" + queryString(view)).c_str());
        ASSERT_TRUE(image);
        ASSERT_EQ(image->status, 200) << image->body;
        const Answers ids = queryPixels(cl, "demo", view, pixels);
        ASSERT_EQ(ray.ids.size(), pixels.size());
        ASSERT_EQ(ids.ids.size(), pixels.size());
        std::size_t exact = 0, edge = 0, bad = 0, hits = 0, records = 0;
        std::vector<int> seen;
        for (std::size_t i = 0; i < pixels.size(); ++i) {
            ASSERT_EQ(ray.sources[i], "ray");
            ASSERT_EQ(ids.sources[i], "id-buffer");
            const int x = pixels[i][0], y = pixels[i][1];
            hits += ray.ids[i] != 0;
            if (std::find(seen.begin(), seen.end(), ray.ids[i]) == seen.end()) seen.push_back(ray.ids[i]);
            if (ray.ids[i] == ids.ids[i]) {
                ++exact;
            } else if (inNeighbourhood(ids.ids, w, h, x, y, ray.ids[i]) &&
                       inNeighbourhood(ray.ids, w, h, x, y, ids.ids[i])) {
                ++edge;
            } else {
                ++bad;
                ADD_FAILURE() << "pixel (" << x << ", " << y << "): ray " << ray.ids[i] << ", ID buffer " << ids.ids[i]
                              << ", neither at an edge";
                if (bad > 10) return;
            }
        }
        records = seen.size();
        std::printf(
            "cut-out %s: ray and ID buffer agree at %zu of %zu pixels, %zu more at an edge, %zu not; %zu on "
            "geology, %zu records\n",
            name.c_str(), exact, pixels.size(), edge, bad, hits, records);
        EXPECT_EQ(bad, 0u);
        EXPECT_GE(double(exact) / double(pixels.size()), 0.99);
        EXPECT_GT(hits, pixels.size() / 8);
        EXPECT_GE(records, 4u);  // the cut shows several strata, not one colour
    }
}

TEST_F(CutOutServer, RequestsThatCutNothingOrEverythingAreRefused) {
    auto cl = client();
    const std::string base = "/v1/models/demo/section.png?view=perspective&size=64x48&";
    auto expect400 = [&](const std::string& q, const std::string& needle) {
        auto r = cl.Get((base + q).c_str());
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 400) << q << "\n" << r->body;
        EXPECT_NE(r->body.find(needle), std::string::npos) << q << "\n" << r->body;
    };
    // Everything removed: the octant beyond the model's far corner holds all of it.
    expect400("planes=1,0,0,-35600000;0,1,0,-3400000;0,0,1,-9000&cut=intersection", "removes the whole model");
    // Kept region beside the model (cut=union), and one plane whose kept side misses it.
    expect400("planes=1,0,0,-35600000;0,1,0,-3388846&cut=union", "removes the whole model");
    expect400("plane=0,0,1,-9000", "parameter 'plane': the cut removes the whole model");
    // Repeated plane= is the same request as planes=.
    auto a = cl.Get((base + "plane=-1,0,0,35504794&plane=0,1,0,-3388846&cut=intersection").c_str());
    auto b = cl.Get((base + "planes=0,1,0,-3388846;-1,0,0,35504794&cut=intersection").c_str());
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->status, 200) << a->body;
    ASSERT_EQ(b->status, 200) << b->body;
    EXPECT_EQ(a->get_header_value("ETag"), b->get_header_value("ETag"));
    EXPECT_EQ(a->body, b->body);
    // In a JSON body, planes as [[a,b,c,d], ...] are the same view as the text form.
    const json text = {{"planes", "0,1,0,-3388846;-1,0,0,35504794"},
                       {"cut", "intersection"},
                       {"view", "perspective"},
                       {"size", "64x48"}};
    json arrays = text;
    arrays["planes"] = json::array({json::array({0, 1, 0, -3388846}), json::array({-1, 0, 0, 35504794})});
    const json pixels = json::array({json::array({32, 24}), json::array({10, 40})});
    auto p = cl.Post("/v1/models/demo/query", json{{"view", text}, {"pixels", pixels}}.dump(), "application/json");
    auto q = cl.Post("/v1/models/demo/query", json{{"view", arrays}, {"pixels", pixels}}.dump(), "application/json");
    ASSERT_TRUE(p && q);
    ASSERT_EQ(p->status, 200) << p->body;
    ASSERT_EQ(q->status, 200) << q->body;
    EXPECT_EQ(p->body, q->body);
}

// `geoslice render --plane ... --cut ...`: the same cut as the API. Bad cuts fail before any
// GL work with the option named; a wedge taken out renders, and its ID image agrees with the
// server's ID buffer of the same view (vx 1, full detail) at every pixel up to an edge, as
// in IdBufferAndQueryAgreeAtEveryPixel (the CLI renders the generated GLB, whose float32
// positions may round differently from the in-memory demo).
TEST_F(CutOutServer, CliRenderCutOut) {
    const fs::path dir = fs::temp_directory_path() / ("geoslice_cutout_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    auto run = [&](const std::string& args) {
        const std::string out = (dir / "stderr.txt").string();
        const int rc = std::system((std::string(GEOSLICE_BINARY) + " " + args + " > /dev/null 2> " + out).c_str());
        std::ifstream f(out);
        std::string err((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        return std::make_pair(WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, err);
    };
    const std::string glb = (dir / "demo.glb").string();
    ASSERT_EQ(run("generate --triangles 20000 --seed 1 --crs EPSG:4523 --at 105.05,30.62 --out " + glb).first, 0);
    const std::string a = "--plane -1,0,0," + kCentreX, b = "--plane 0,1,0,-" + kCentreY;
    const std::string cam = " --eye 35509500,3383500,4500 --target " + kCentreX + "," + kCentreY + "," + kCentreZ +
                            " --size 160x120 --lod off --out " + (dir / "w.png").string();
    for (const auto& [args, needle] :
         std::vector<std::pair<std::string, std::string>>{{a + " " + b, "--cut: required"},
                                                          {a + " " + b + " --cut xor", "--cut"},
                                                          {a + " " + a + " --cut union", "are the same plane"},
                                                          {a + " --plane 0,0,0,1 --cut union", "plane 2"},
                                                          {"--plane 0,0,1,-9000", "removes the whole model"}}) {
        const auto [rc, err] = run("render " + glb + " " + args + cam);
        EXPECT_EQ(rc, 1) << args;
        EXPECT_NE(err.find(needle), std::string::npos) << args << "\n" << err;
    }
    const std::string ids = (dir / "w.pgm").string();
    const auto [rc, err] = run("render " + glb + " " + a + " " + b + " --cut intersection --ids " + ids + cam);
    ASSERT_EQ(rc, 0) << err;
    // 16-bit binary PGM: "P5\n160 120\n65535\n", big-endian samples.
    std::ifstream f(ids, std::ios::binary);
    std::string magic;
    int w = 0, h = 0, maxval = 0;
    f >> magic >> w >> h >> maxval;
    f.get();
    ASSERT_EQ(magic, "P5");
    ASSERT_EQ(w, 160);
    ASSERT_EQ(h, 120);
    std::vector<int> cli(std::size_t(w) * std::size_t(h));
    for (int& v : cli) {
        const int hi = f.get(), lo = f.get();
        v = hi * 256 + lo;
    }
    ASSERT_TRUE(f.good());
    auto cl = client();
    const json view = {{"planes", "-1,0,0," + kCentreX + ";0,1,0,-" + kCentreY},
                       {"cut", "intersection"},
                       {"view", "perspective"},
                       {"eye", "35509500,3383500,4500"},
                       {"target", kCentreX + "," + kCentreY + "," + kCentreZ},
                       {"size", "160x120"}};
    auto image = cl.Get(("/v1/models/demo/section.png?" + queryString(view)).c_str());
    ASSERT_TRUE(image);
    ASSERT_EQ(image->status, 200) << image->body;
    const Answers server = queryPixels(cl, "demo", view, allPixels(w, h));
    ASSERT_EQ(server.ids.size(), cli.size());
    std::size_t exact = 0, bad = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            EXPECT_EQ(server.sources[i], "id-buffer");
            if (cli[i] == server.ids[i])
                ++exact;
            else if (!inNeighbourhood(server.ids, w, h, x, y, cli[i]) ||
                     !inNeighbourhood(cli, w, h, x, y, server.ids[i]))
                ++bad;
        }
    std::printf("cut-out CLI vs server ID buffer: %zu of %zu pixels equal, %zu differ away from an edge\n", exact,
                cli.size(), bad);
    EXPECT_EQ(bad, 0u);
    EXPECT_GE(double(exact), 0.99 * double(cli.size()));
    fs::remove_all(dir);
}

// ---- the tetrahedral model against an exact ray oracle ----------------------------------

testing::VtuGrid toVtu(const VolumeMesh& m) {
    testing::VtuGrid g;
    g.points = m.positions;
    testing::VtuGrid::Array formation{"formation", "Int32", 1, {}};
    for (std::size_t c = 0; c < m.cellCount(); ++c) {
        g.types.push_back(static_cast<std::uint8_t>(m.cellTypes[c]));
        for (std::uint32_t k = m.cellOffsets[c]; k < m.cellOffsets[c + 1]; ++k)
            g.connectivity.push_back(m.cellVertices[k]);
        g.offsets.push_back(static_cast<std::int64_t>(g.connectivity.size()));
        formation.values.push_back(m.cellRegions[c] + 1);  // record ids 1..4
    }
    g.cellData.push_back(std::move(formation));
    return g;
}

struct OraclePlane {
    glm::dvec3 n;
    double d;
};

// The first point of the ray origin + t dir (t >= 0) that is inside a tetrahedron and kept;
// record 0 and t = inf when there is none. Everything from the definitions, in double.
struct OracleHit {
    int record = 0;
    double t = std::numeric_limits<double>::infinity();
};
OracleHit oracle(const VolumeMesh& m, const std::vector<OraclePlane>& planes, bool keepAll, const glm::dvec3& o,
                 const glm::dvec3& dir) {
    const double inf = std::numeric_limits<double>::infinity();
    // Kept spans: keepAll (cut=union): the intersection of the kept half-lines; otherwise
    // (cut=intersection) their union.
    std::vector<std::pair<double, double>> kept;
    if (keepAll) {
        double lo = 0.0, hi = inf;
        for (const auto& p : planes) {
            const double s0 = glm::dot(p.n, o) + p.d, ds = glm::dot(p.n, dir);
            if (ds > 0)
                lo = std::max(lo, -s0 / ds);
            else if (ds < 0)
                hi = std::min(hi, -s0 / ds);
            else if (s0 < 0)
                hi = -1.0;
        }
        if (lo < hi) kept.push_back({lo, hi});
    } else {
        double fromLo = inf, toHi = -1.0;  // union of [l, inf) and of [0, h]
        for (const auto& p : planes) {
            const double s0 = glm::dot(p.n, o) + p.d, ds = glm::dot(p.n, dir);
            if (ds > 0)
                fromLo = std::min(fromLo, std::max(0.0, -s0 / ds));
            else if (ds < 0)
                toHi = std::max(toHi, -s0 / ds);
            else if (s0 >= 0)
                fromLo = 0.0;
        }
        if (toHi >= fromLo)
            kept.push_back({0.0, inf});
        else {
            if (toHi > 0.0) kept.push_back({0.0, toHi});
            if (fromLo < inf) kept.push_back({fromLo, inf});
        }
    }
    OracleHit best;
    for (std::size_t c = 0; c < m.cellCount(); ++c) {
        const std::uint32_t* v = &m.cellVertices[m.cellOffsets[c]];
        const glm::dvec3 P[4] = {m.positions[v[0]], m.positions[v[1]], m.positions[v[2]], m.positions[v[3]]};
        double lo = 0.0, hi = inf;
        for (int f = 0; f < 4 && lo < hi; ++f) {
            const glm::dvec3 a = P[(f + 1) % 4], b = P[(f + 2) % 4], e = P[(f + 3) % 4];
            glm::dvec3 n = glm::cross(b - a, e - a);
            if (glm::dot(n, P[f] - a) < 0) n = -n;  // inside: towards the opposite vertex
            const double s0 = glm::dot(n, o - a), ds = glm::dot(n, dir);
            if (ds > 0)
                lo = std::max(lo, -s0 / ds);
            else if (ds < 0)
                hi = std::min(hi, -s0 / ds);
            else if (s0 < 0)
                hi = -1.0;
        }
        if (!(lo < hi)) continue;
        for (const auto& [klo, khi] : kept) {
            const double from = std::max(lo, klo), to = std::min(hi, khi);
            if (from < to && from < best.t) best = {m.cellRegions[c] + 1, from};
        }
    }
    return best;
}

TEST(CutOutOracle, TetModelRayQueriesAndIdBufferAgainstTheOracle) {
    spdlog::set_level(spdlog::level::err);
    const fs::path dir = fs::temp_directory_path() / ("geoslice_cutout_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    test::TetModelOptions options;
    options.origin = {500000.0, 3000000.0, 100.0};
    const test::TetModel tm = test::tetLayeredModel(options);
    {
        std::ofstream f(dir / "tet.vtu", std::ios::binary);
        f << testing::writeVtu(toVtu(tm.mesh), testing::VtuEncoding{});
    }
    ServerConfig c = glConfig();
    c.modelsDir = dir.string();
    SectionServer s(c);
    ASSERT_TRUE(s.start());
    ASSERT_TRUE(s.waitUntilLoaded());
    httplib::Client cl("127.0.0.1", s.port());
    cl.set_read_timeout(300, 0);

    const glm::dvec3 centre = options.origin + glm::dvec3(40.0, 40.0, 30.0);
    const int w = 200, h = 150;
    struct Case {
        std::string name, cut;
        std::vector<OraclePlane> planes;
    };
    auto through = [&](glm::dvec3 n, glm::dvec3 p) {
        n = glm::normalize(n);
        return OraclePlane{n, -glm::dot(n, p)};
    };
    const std::vector<Case> cases = {
        {"wedge out", "intersection", {through({-1, 0, 0}, centre), through({0, 1, 0}, centre)}},
        {"octant out",
         "intersection",
         {through({-1, 0.2, 0}, centre), through({0, 1, 0.1}, centre),
          through({0, 0, -1}, centre + glm::dvec3(0, 0, 5))}},
        {"kept wedge", "union", {through({1, 1, 0}, centre - glm::dvec3(15, 0, 0)), through({0, 0, -1}, centre)}},
        // A tilted box kept: most rays that see it enter and leave it inside one formation.
        {"kept box",
         "union",
         {through({1, 0.1, 0}, centre - glm::dvec3(32, 0, 0)), through({-1, -0.1, 0}, centre + glm::dvec3(30, 0, 0)),
          through({0, 1, 0.05}, centre - glm::dvec3(0, 30, 0)), through({0, -1, -0.05}, centre + glm::dvec3(0, 31, 0)),
          through({0, 0, 1}, centre - glm::dvec3(0, 0, 24)), through({0.05, 0, -1}, centre + glm::dvec3(0, 0, 20))}},
    };
    std::mt19937 rng(5);
    std::vector<std::array<int, 2>> pixels;
    for (int i = 0; i < 1500; ++i) pixels.push_back({int(rng() % unsigned(w)), int(rng() % unsigned(h))});
    PerspectiveCamera cam;
    cam.eye = centre + glm::dvec3(110.0, -95.0, 80.0);
    cam.target = centre;
    cam.fovYDegrees = 45.0;
    for (const Case& k : cases) {
        SCOPED_TRACE(k.name);
        std::string planes;
        for (const auto& p : k.planes) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g", p.n.x, p.n.y, p.n.z, p.d);
            planes += (planes.empty() ? "" : ";") + std::string(buf);
        }
        char eye[128], target[128];
        std::snprintf(eye, sizeof eye, "%.17g,%.17g,%.17g", cam.eye.x, cam.eye.y, cam.eye.z);
        std::snprintf(target, sizeof target, "%.17g,%.17g,%.17g", cam.target.x, cam.target.y, cam.target.z);
        const json view = {{"planes", planes},      {"cut", k.cut},
                           {"view", "perspective"}, {"eye", eye},
                           {"target", target},      {"size", std::to_string(w) + "x" + std::to_string(h)}};
        const Answers ray = queryPixels(cl, "tet", view, pixels);
        auto image = cl.Get(("/v1/models/tet/section.png?" + queryString(view)).c_str());
        ASSERT_TRUE(image);
        ASSERT_EQ(image->status, 200) << image->body;
        const Answers ids = queryPixels(cl, "tet", view, pixels);
        ASSERT_EQ(ray.ids.size(), pixels.size());
        ASSERT_EQ(ids.ids.size(), pixels.size());
        const bool keepAll = k.cut == "union";
        std::size_t compared = 0, nearEdge = 0, rayAgree = 0, idAgree = 0, hits = 0, caps = 0;
        double worstWorld = 0.0;
        for (std::size_t i = 0; i < pixels.size(); ++i) {
            auto at = [&](double dx, double dy) {
                const PixelRay r = pixelRay(cam, w, h, pixels[i][0] + 0.5 + dx, pixels[i][1] + 0.5 + dy);
                return std::make_pair(r, oracle(tm.mesh, k.planes, keepAll, r.origin, r.direction));
            };
            const auto [r, o] = at(0.0, 0.0);
            bool edge = false;
            for (auto [dx, dy] : {std::pair{0.05, 0.0}, {-0.05, 0.0}, {0.0, 0.05}, {0.0, -0.05}})
                edge = edge || at(dx, dy).second.record != o.record;
            if (edge) {
                ++nearEdge;
                continue;
            }
            ++compared;
            hits += o.record != 0;
            rayAgree += ray.ids[i] == o.record;
            idAgree += ids.ids[i] == o.record;
            EXPECT_EQ(ray.ids[i], o.record) << "pixel (" << pixels[i][0] << ", " << pixels[i][1] << ")";
            if (o.record != 0 && ray.ids[i] == o.record) {
                const glm::dvec3 expected = r.origin + o.t * r.direction;
                const double err = glm::length(ray.world[i] - expected);
                worstWorld = std::max(worstWorld, err);
                EXPECT_LE(err, kRayHitTolM) << "pixel (" << pixels[i][0] << ", " << pixels[i][1] << ")";
                // On a cut face (a cap) the world point lies on one of the planes.
                for (const auto& p : k.planes) caps += std::abs(glm::dot(p.n, expected) + p.d) < 1e-6;
            }
        }
        std::printf(
            "cut-out oracle %s: %zu pixels compared (%zu near an edge), ray query agrees at %zu, ID buffer "
            "at %zu; %zu on geology, %zu on cut faces, world point within %.3g m\n",
            k.name.c_str(), compared, nearEdge, rayAgree, idAgree, hits, caps, worstWorld);
        EXPECT_LE(nearEdge, pixels.size() / 20);
        EXPECT_EQ(rayAgree, compared);
        EXPECT_GE(double(idAgree), 0.99 * double(compared));
        EXPECT_GT(hits, compared / 10);
        EXPECT_GT(caps, compared / 20);  // the cut faces are in view
    }
    s.stop();
    fs::remove_all(dir);
}

// ---- golden image ------------------------------------------------------------------------

// Every golden case with "runner": "http" (tests/data/goldens/<case>/request.json: the model
// id, path and query) through the whole HTTP path, compared by the shared comparator.
TEST_F(CutOutServer, GoldenCases) {
    auto cl = client();
    const std::vector<std::string> cases = test::goldenCases("http");
    ASSERT_FALSE(cases.empty());
    for (const std::string& name : cases) {
        SCOPED_TRACE(name);
        const json request = test::goldenRequest(name);
        ASSERT_EQ(request.value("model", ""), "demo") << "this fixture serves the demo model only";
        auto r = cl.Get((request.at("path").get<std::string>() + "?" + queryString(request.at("query"))).c_str());
        ASSERT_TRUE(r);
        ASSERT_EQ(r->status, 200) << r->body;
        const std::string actualPath =
            fs::temp_directory_path() / ("geoslice_golden_" + name + "_" + std::to_string(::getpid()) + ".png");
        {
            std::ofstream f(actualPath, std::ios::binary);
            f << r->body;
        }
        auto actual = readPngRgba(actualPath);
        fs::remove(actualPath);
        ASSERT_TRUE(actual) << actual.error().message;
        test::compareGolden(name, "colour", actual->rgba.data(), actual->width, actual->height,
                            test::goldenTolerance(request, "colour"),
                            (fs::temp_directory_path() / "geoslice_golden_failures").string());
    }
}

}  // namespace
}  // namespace geoslice::server
