// Who may read what, against the real server (a child process, tests/common/serve_process.hpp):
// a models directory with two boxes, alpha and beta, and API keys from a keys file and from
// GEOSLICE_KEYS (api/access_keys.hpp). Every model route is asked for each model with no
// key, a wrong key, a key for alpha only ("reader", Bearer), one for beta only ("surveyor",
// from the environment, X-Api-Key) and one for every model ("admin"): 401, 401, then
// 200/201 or 403 by scope. The measured matrix is printed as a table. Also: /v1/models lists
// a key's models only; 403 does not tell whether a model exists; open routes name no model;
// no key ever reaches the log (run at --log-level debug); CORS off by default with a models
// directory, * for the demo, and an allow-list that echoes listed origins only.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/common/serve_process.hpp"

namespace geoslice::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Keys: random-looking, each 32 characters (api/access_keys.hpp wants 16 to 512).
const std::string kReaderKey = "rK7fQ2xW9mB4vN8cL1pZ6tY3hJ5gD0sA";    // alpha
const std::string kSurveyorKey = "sV3nM8bQ1wE6rT9yU2iO5pA7dF4gH0jK";  // beta (GEOSLICE_KEYS)
const std::string kAdminKey = "aD9mI4nK2eY7xZ1cV6bN3mQ8wE5rT0yU";     // *
const std::string kWrongKey = "wR0nGkEy5xT8qP2lM7vB4nC9zX1aS6dF";     // not issued
const std::string kPlane = "plane=0,1,0,-50";                         // through both boxes, y = 50 m

// A closed box [lo, hi] as OBJ (outward faces), one body named `name`.
void writeBox(const fs::path& path, const std::string& name, double x0, double y0, double z0, double x1, double y1,
              double z1) {
    std::ofstream o(path);
    o << "o " << name << "\n";
    for (double x : {x0, x1})
        for (double y : {y0, y1})
            for (double z : {z0, z1}) o << "v " << x << " " << y << " " << z << "\n";
    for (const char* f :
         {"1 2 4", "1 4 3", "5 7 8", "5 8 6", "1 5 6", "1 6 2", "3 4 8", "3 8 7", "1 3 7", "1 7 5", "2 6 8", "2 8 4"})
        o << "f " << f << "\n";
}

enum class Who { None, Wrong, Reader, Surveyor, Admin };
const std::vector<std::pair<Who, std::string>> kWho = {{Who::None, "no key"},
                                                       {Who::Wrong, "wrong key"},
                                                       {Who::Reader, "reader (alpha)"},
                                                       {Who::Surveyor, "surveyor (beta)"},
                                                       {Who::Admin, "admin (*)"}};

// Reader sends Bearer, surveyor X-Api-Key, admin a lower-case "bearer" (the scheme is
// case-insensitive), the wrong key X-Api-Key.
httplib::Headers headersOf(Who w) {
    switch (w) {
        case Who::None:
            return {};
        case Who::Wrong:
            return {{"X-Api-Key", kWrongKey}};
        case Who::Reader:
            return {{"Authorization", "Bearer " + kReaderKey}};
        case Who::Surveyor:
            return {{"X-Api-Key", kSurveyorKey}};
        case Who::Admin:
            return {{"Authorization", "bearer " + kAdminKey}};
    }
    return {};
}

bool mayRead(Who w, const std::string& model) {
    return w == Who::Admin || (w == Who::Reader && model == "alpha") || (w == Who::Surveyor && model == "beta");
}

struct Route {
    std::string name;    // for the table
    std::string method;  // GET or POST
    std::string path;    // {m}: the model id; {sid}: a section id of that model
    std::string body;    // POST only (JSON)
    int ok;              // the status of an allowed request
};

const std::vector<Route> kRoutes = {
    {"GET /v1/models/{id}", "GET", "/v1/models/{m}", "", 200},
    {"GET legend.png", "GET", "/v1/models/{m}/legend.png", "", 200},
    {"GET section.png", "GET", "/v1/models/{m}/section.png?" + kPlane + "&size=64x32", "", 200},
    {"GET section.svg", "GET", "/v1/models/{m}/section.svg?" + kPlane, "", 200},
    {"GET section.geojson", "GET", "/v1/models/{m}/section.geojson?" + kPlane, "", 200},
    {"GET section.pdf", "GET", "/v1/models/{m}/section.pdf?" + kPlane, "", 200},
    {"GET section.dxf", "GET", "/v1/models/{m}/section.dxf?" + kPlane, "", 200},
    {"GET query", "GET", "/v1/models/{m}/query?" + kPlane + "&size=64x32&px=32&py=16", "", 200},
    {"POST query", "POST", "/v1/models/{m}/query",
     R"({"view": {"plane": "0,1,0,-50", "size": "64x32"}, "pixels": [[32, 16], [1, 1]]})", 200},
    {"GET borehole", "GET", "/v1/models/{m}/borehole?x=50&y=50", "", 200},
    {"GET reserves", "GET", "/v1/models/{m}/reserves", "", 200},
    {"GET reserves.csv", "GET", "/v1/models/{m}/reserves.csv", "", 200},
    {"POST sections", "POST", "/v1/models/{m}/sections", R"({"plane": "0,1,0,-50"})", 201},
    {"GET /v1/sections/{sid}", "GET", "/v1/sections/{sid}", "", 200},
    {"GET section tile", "GET", "/v1/sections/{sid}/tiles/0/0/0.png", "", 200},
    {"GET TileJSON", "GET", "/v1/sections/{sid}/tilejson.json", "", 200},
    {"GET OGC tileset", "GET", "/v1/sections/{sid}/tiles", "", 200},
    {"GET OGC TileMatrixSet", "GET", "/v1/sections/{sid}/tilematrixset", "", 200},
};

std::string replaced(std::string s, const std::string& from, const std::string& to) {
    for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
        s.replace(at, from.size(), to);
    return s;
}

// base64url without padding (a section id is that of its canonical definition).
std::string base64Url(const std::string& bytes) {
    static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = unsigned(static_cast<unsigned char>(bytes[i])) << 16 |
                           unsigned(static_cast<unsigned char>(bytes[i + 1])) << 8 |
                           unsigned(static_cast<unsigned char>(bytes[i + 2]));
        for (int k = 18; k >= 0; k -= 6) out += abc[(v >> k) & 63];
    }
    if (i < bytes.size()) {
        unsigned v = unsigned(static_cast<unsigned char>(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= unsigned(static_cast<unsigned char>(bytes[i + 1])) << 8;
        out += abc[(v >> 18) & 63];
        out += abc[(v >> 12) & 63];
        if (i + 1 < bytes.size()) out += abc[(v >> 6) & 63];
    }
    return out;
}

class Auth : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = fs::temp_directory_path() / ("geoslice_auth_" + std::to_string(getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "models");
        writeBox(dir_ / "models" / "alpha.obj", "ore", 0, 0, 0, 100, 100, 50);
        writeBox(dir_ / "models" / "beta.obj", "ore", 0, 0, 0, 100, 100, 50);
        std::ofstream(dir_ / "keys.txt") << "# name  key  models\n"
                                         << "reader " << kReaderKey << " alpha\n"
                                         << "admin\t" << kAdminKey << "\t*   # every model\n";
        server_ = ServeProcess::start({"--gl", "none", "--workers", "1", "--models", (dir_ / "models").string(),
                                       "--keys", (dir_ / "keys.txt").string(), "--log-level", "debug"},
                                      {{"GEOSLICE_KEYS", "surveyor " + kSurveyorKey + " beta"}})
                      .release();
        ASSERT_NE(server_, nullptr);
        ASSERT_TRUE(server_->waitReady()) << server_->log();
        // A section id of each model, made with the admin key.
        for (const std::string m : {"alpha", "beta"}) {
            auto r = server_->client().Post(("/v1/models/" + m + "/sections").c_str(), headersOf(Who::Admin),
                                            R"({"plane": "0,1,0,-50"})", "application/json");
            ASSERT_TRUE(r);
            ASSERT_EQ(r->status, 201) << r->body;
            sid_[m] = json::parse(r->body)["sid"];
        }
    }
    static void TearDownTestSuite() {
        delete server_;
        server_ = nullptr;
        fs::remove_all(dir_);
    }

    static httplib::Result send(const std::string& method, const std::string& path, const httplib::Headers& h,
                                const std::string& body = "") {
        auto cl = server_->client(60);
        return method == "GET" ? cl.Get(path.c_str(), h) : cl.Post(path.c_str(), h, body, "application/json");
    }

    static inline ServeProcess* server_ = nullptr;
    static inline fs::path dir_;
    static inline std::map<std::string, std::string> sid_;
};

// The whole matrix: route x model x key.
TEST_F(Auth, EveryRouteAnswersByKeyAndScope) {
    std::string table = "| route | model |";
    for (const auto& [w, name] : kWho) table += " " + name + " |";
    table += "\n|---|---|";
    for (std::size_t i = 0; i < kWho.size(); ++i) table += "---|";
    table += "\n";
    for (const Route& route : kRoutes)
        for (const std::string m : {"alpha", "beta"}) {
            const std::string path = replaced(replaced(route.path, "{m}", m), "{sid}", sid_[m]);
            table += "| " + route.name + " | " + m + " |";
            for (const auto& [w, name] : kWho) {
                const int want = w == Who::None || w == Who::Wrong ? 401 : mayRead(w, m) ? route.ok : 403;
                auto r = send(route.method, path, headersOf(w), route.body);
                ASSERT_TRUE(r) << route.name << " " << m << " " << name;
                table += " " + std::to_string(r->status) + " |";
                EXPECT_EQ(r->status, want) << route.method << " " << path << " as " << name << ": " << r->body;
                if (r->status == 401) {
                    EXPECT_EQ(r->get_header_value("WWW-Authenticate").rfind("Bearer", 0), 0u) << path;
                    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
                    EXPECT_EQ(r->get_header_value("Cache-Control"), "no-store");
                    if (w == Who::Wrong) {
                        EXPECT_NE(r->get_header_value("WWW-Authenticate").find("invalid_token"), std::string::npos);
                    }
                }
                if (r->status == 403) {
                    EXPECT_NE(r->body.find("\"forbidden\""), std::string::npos) << r->body;
                }
                // Keyed answers are never for shared caches (nginx's proxy_cache).
                EXPECT_EQ(r->get_header_value("Cache-Control").find("public"), std::string::npos) << path;
                EXPECT_NE(r->get_header_value("Vary").find("Authorization"), std::string::npos) << path;
                for (const std::string& k : {kReaderKey, kSurveyorKey, kAdminKey, kWrongKey})
                    EXPECT_EQ(r->body.find(k), std::string::npos) << "a key in the answer to " << path;
            }
            table += "\n";
        }
    // The listing, by key.
    const std::map<Who, std::vector<std::string>> lists = {
        {Who::Reader, {"alpha"}}, {Who::Surveyor, {"beta"}}, {Who::Admin, {"alpha", "beta"}}};
    table += "| GET /v1/models | (listing) |";
    for (const auto& [w, name] : kWho) {
        auto r = send("GET", "/v1/models", headersOf(w));
        ASSERT_TRUE(r);
        table += " " + std::to_string(r->status);
        if (w == Who::None || w == Who::Wrong) {
            EXPECT_EQ(r->status, 401) << name;
            table += " |";
            continue;
        }
        ASSERT_EQ(r->status, 200) << name;
        std::vector<std::string> ids;
        const json listing = json::parse(r->body);
        for (const auto& m : listing["models"]) ids.push_back(m["id"]);
        EXPECT_EQ(ids, lists.at(w)) << name;
        std::string shown;
        for (const auto& id : ids) shown += (shown.empty() ? "" : ",") + id;
        table += " [" + shown + "] |";
    }
    std::cout << "\nAuth matrix (status by route, model and key):\n" << table << "\n";
}

// 403 is decided from the key's scope before the catalog is consulted: a key without access
// learns nothing about which models exist. A key with access gets 404 for an unknown model.
TEST_F(Auth, ForbiddenDoesNotTellWhetherAModelExists) {
    auto beta = send("GET", "/v1/models/beta", headersOf(Who::Reader));
    auto gamma = send("GET", "/v1/models/gamma", headersOf(Who::Reader));
    ASSERT_TRUE(beta && gamma);
    EXPECT_EQ(beta->status, 403);
    EXPECT_EQ(gamma->status, 403);
    EXPECT_EQ(replaced(beta->body, "beta", "X"), replaced(gamma->body, "gamma", "X"));
    auto admin = send("GET", "/v1/models/gamma", headersOf(Who::Admin));
    ASSERT_TRUE(admin);
    EXPECT_EQ(admin->status, 404);
    // The same through section ids: beta's (exists) and one that names gamma (does not).
    const std::string gammaSid = base64Url("model=gamma&plane=0,1,0,-50&vx=1&bg=00000000");
    for (const std::string& sid : {sid_["beta"], gammaSid}) {
        auto tile = send("GET", "/v1/sections/" + sid + "/tiles/0/0/0.png", headersOf(Who::Reader));
        ASSERT_TRUE(tile);
        EXPECT_EQ(tile->status, 403) << tile->body;
    }
    auto tile = send("GET", "/v1/sections/" + gammaSid + "/tiles/0/0/0.png", headersOf(Who::Admin));
    ASSERT_TRUE(tile);
    EXPECT_EQ(tile->status, 404) << tile->body;
}

TEST_F(Auth, CredentialsOfOtherSchemesAreRefused) {
    auto basic = send("GET", "/v1/models", {{"Authorization", "Basic " + kReaderKey}});
    ASSERT_TRUE(basic);
    EXPECT_EQ(basic->status, 401);
    EXPECT_NE(basic->get_header_value("WWW-Authenticate").find("invalid_request"), std::string::npos);
    // A key that differs from a real one in its last character only.
    std::string near = kReaderKey;
    near.back() = near.back() == 'A' ? 'B' : 'A';
    auto close = send("GET", "/v1/models", {{"Authorization", "Bearer " + near}});
    ASSERT_TRUE(close);
    EXPECT_EQ(close->status, 401);
    // The real key with a prefix or suffix is another key.
    for (const std::string& k : {kReaderKey + "x", "x" + kReaderKey, kReaderKey.substr(1)}) {
        auto r = send("GET", "/v1/models", {{"X-Api-Key", k}});
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 401);
    }
    // Bearer wins over X-Api-Key when both are sent.
    auto both = send("GET", "/v1/models/alpha", {{"Authorization", "Bearer " + kReaderKey}, {"X-Api-Key", kWrongKey}});
    ASSERT_TRUE(both);
    EXPECT_EQ(both->status, 200);
}

// /, /web, /healthz, /readyz, /metrics and /openapi.json need no key and name no model and
// no file path.
TEST_F(Auth, OpenRoutesNameNoModel) {
    for (const char* path : {"/", "/web/api.js", "/healthz", "/readyz", "/metrics", "/openapi.json"}) {
        auto r = send("GET", path, {});
        ASSERT_TRUE(r) << path;
        EXPECT_EQ(r->status, 200) << path << ": " << r->body.substr(0, 300);
        if (std::string(path).rfind("/web", 0) == 0 || std::string(path) == "/") continue;
        for (const std::string& secret : {std::string("alpha"), std::string("beta"), dir_.string(),
                                          std::string("reader"), std::string("surveyor"), kReaderKey, kAdminKey})
            EXPECT_EQ(r->body.find(secret), std::string::npos) << path << " shows '" << secret << "':\n" << r->body;
    }
    auto ready = json::parse(send("GET", "/readyz", {})->body);
    EXPECT_EQ(ready["models"]["loaded"], 2);
    EXPECT_EQ(ready["models"]["failed"], 0);  // a count while keys are on
}

// Nothing that identifies a key reaches the log: not the keys sent, right or wrong, not
// even at debug level; the log names the key (reader, admin) instead.
TEST_F(Auth, KeysNeverReachTheLog) {
    // Make sure every kind of request went by, including bad header bytes.
    (void)send("GET", "/v1/models/alpha", headersOf(Who::Reader));
    (void)send("GET", "/v1/models/alpha", headersOf(Who::Wrong));
    (void)send("GET", "/v1/models/beta", headersOf(Who::Reader));
    (void)send("GET", "/v1/models/alpha", {{"X-Api-Key", kReaderKey + "\xff"}});
    (void)send("GET", "/metrics", headersOf(Who::Admin));
    auto bad = send("GET", "/v1/models/alpha", {{"Authorization", "Bearer " + kAdminKey + "\xfe"}});
    ASSERT_TRUE(bad);
    EXPECT_EQ(bad->status, 400);
    EXPECT_EQ(bad->body.find(kAdminKey), std::string::npos) << bad->body;  // not echoed, even escaped
    const std::string log = server_->log();
    ASSERT_NE(log.find("event=request"), std::string::npos) << "the log is at debug level";
    EXPECT_NE(log.find("key=reader"), std::string::npos);
    for (const std::string& k : {kReaderKey, kSurveyorKey, kAdminKey, kWrongKey}) {
        EXPECT_EQ(log.find(k), std::string::npos) << "a key in the log";
        EXPECT_EQ(log.find(k.substr(0, 12)), std::string::npos) << "part of a key in the log";
    }
    auto metrics = send("GET", "/metrics", {});
    ASSERT_TRUE(metrics);
    EXPECT_NE(metrics->body.find("geoslice_auth_failures_total{reason=\"invalid\"}"), std::string::npos);
    for (const std::string& k : {kReaderKey, kSurveyorKey, kAdminKey, kWrongKey})
        EXPECT_EQ(metrics->body.find(k), std::string::npos);
}

// With a models directory and no CORS setting, no cross-origin page reads anything.
TEST_F(Auth, CorsIsOffByDefaultWithModels) {
    auto r =
        send("GET", "/v1/models/alpha", {{"Authorization", "Bearer " + kReaderKey}, {"Origin", "https://x.example"}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_FALSE(r->has_header("Access-Control-Allow-Origin"));
    auto pre = server_->client().Options("/v1/models/alpha", {{"Origin", "https://x.example"},
                                                              {"Access-Control-Request-Method", "GET"},
                                                              {"Access-Control-Request-Headers", "authorization"}});
    ASSERT_TRUE(pre);
    EXPECT_EQ(pre->status, 204);  // preflights are never authenticated
    EXPECT_FALSE(pre->has_header("Access-Control-Allow-Origin"));
    EXPECT_FALSE(pre->has_header("Access-Control-Allow-Headers"));
}

// The demo (no models directory) keeps CORS open to every origin (the README's demo), and
// without keys every route is open.
TEST(AuthCors, DemoAllowsEveryOrigin) {
    auto demo = ServeProcess::start({"--gl", "none", "--workers", "1", "--demo-triangles", "20000"});
    ASSERT_NE(demo, nullptr);
    ASSERT_TRUE(demo->waitReady()) << demo->log();
    auto cl = demo->client();
    auto r = cl.Get("/v1/models/demo", {{"Origin", "https://anywhere.example"}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->get_header_value("Access-Control-Allow-Origin"), "*");
    EXPECT_EQ(r->get_header_value("Cache-Control").find("private"), std::string::npos);
    auto pre = cl.Options("/v1/models/demo/section.png", {{"Origin", "https://anywhere.example"}});
    ASSERT_TRUE(pre);
    EXPECT_EQ(pre->status, 204);
    EXPECT_NE(pre->get_header_value("Access-Control-Allow-Headers").find("Authorization"), std::string::npos);
    EXPECT_NE(pre->get_header_value("Access-Control-Allow-Headers").find("X-Api-Key"), std::string::npos);
}

// An allow-list: a listed Origin is echoed (with Vary: Origin), any other gets no CORS
// header; '*' given explicitly still opens a models directory to every origin.
TEST(AuthCors, AllowListEchoesListedOriginsOnly) {
    const fs::path dir = fs::temp_directory_path() / ("geoslice_auth_cors_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "models");
    writeBox(dir / "models" / "alpha.obj", "ore", 0, 0, 0, 100, 100, 50);
    const std::vector<std::string> base = {"--gl", "none", "--workers", "1", "--models", (dir / "models").string()};
    {
        auto args = base;
        args.insert(args.end(), {"--cors-origins", "https://maps.example, HTTP://localhost:8000/"});
        auto s = ServeProcess::start(args);
        ASSERT_NE(s, nullptr);
        ASSERT_TRUE(s->waitReady()) << s->log();
        auto cl = s->client();
        for (const std::string origin : {"https://maps.example", "http://localhost:8000"}) {
            auto r = cl.Get("/v1/models/alpha", {{"Origin", origin}});
            ASSERT_TRUE(r);
            EXPECT_EQ(r->status, 200);
            EXPECT_EQ(r->get_header_value("Access-Control-Allow-Origin"), origin);
            EXPECT_NE(r->get_header_value("Vary").find("Origin"), std::string::npos);
            auto pre = cl.Options("/v1/models/alpha/query", {{"Origin", origin}});
            ASSERT_TRUE(pre);
            EXPECT_EQ(pre->get_header_value("Access-Control-Allow-Origin"), origin);
            EXPECT_NE(pre->get_header_value("Access-Control-Allow-Methods").find("POST"), std::string::npos);
        }
        for (const std::string origin : {"https://evil.example", "https://maps.example.evil.example",
                                         "http://maps.example", "https://maps.example:8443", "null"}) {
            auto r = cl.Get("/v1/models/alpha", {{"Origin", origin}});
            ASSERT_TRUE(r);
            EXPECT_FALSE(r->has_header("Access-Control-Allow-Origin")) << origin;
            EXPECT_NE(r->get_header_value("Vary").find("Origin"), std::string::npos) << origin;
            auto pre = cl.Options("/v1/models/alpha", {{"Origin", origin}});
            ASSERT_TRUE(pre);
            EXPECT_FALSE(pre->has_header("Access-Control-Allow-Origin")) << origin;
            EXPECT_FALSE(pre->has_header("Access-Control-Allow-Methods")) << origin;
        }
        auto none = cl.Get("/v1/models/alpha");  // no Origin: a same-origin or non-browser client
        ASSERT_TRUE(none);
        EXPECT_FALSE(none->has_header("Access-Control-Allow-Origin"));
    }
    {
        auto s = ServeProcess::start(base, {{"GEOSLICE_CORS", "*"}});
        ASSERT_NE(s, nullptr);
        ASSERT_TRUE(s->waitReady()) << s->log();
        auto r = s->client().Get("/v1/models/alpha", {{"Origin", "https://evil.example"}});
        ASSERT_TRUE(r);
        EXPECT_EQ(r->get_header_value("Access-Control-Allow-Origin"), "*");
    }
    fs::remove_all(dir);
}

// Output and exit status of `geoslice serve ARGS` that refuses to start (stderr included).
std::pair<int, std::string> refusedStart(const std::string& args) {
    // timeout: a server that starts after all is a failure, not a hung test.
    const std::string cmd = "timeout 20 " + std::string(GEOSLICE_BINARY) +
                            " serve --host 127.0.0.1 --port 0 --gl none " + args + " 2>&1 </dev/null";
    std::string out;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return {-1, ""};
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    return {pclose(p), out};
}

// A bad keys file stops the server at start, naming the line and never the key; so do an
// empty one (it would otherwise leave every model open) and a bad origin.
TEST(AuthConfig, BadKeysAndOriginsStopTheServer) {
    const fs::path dir = fs::temp_directory_path() / ("geoslice_auth_cfg_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string secretish = "Sh0rtS3cr3t";  // too short
    std::ofstream(dir / "short.txt") << "# comment\nok " << kReaderKey << " alpha\nbad " << secretish << " *\n";
    std::ofstream(dir / "empty.txt") << "# nothing but comments\n\n";
    auto [st1, out1] = refusedStart("--keys " + (dir / "short.txt").string());
    EXPECT_NE(st1, 0) << out1;
    EXPECT_NE(out1.find("line 3"), std::string::npos) << out1;
    EXPECT_EQ(out1.find(secretish), std::string::npos) << out1;
    EXPECT_EQ(out1.find(kReaderKey), std::string::npos) << out1;
    auto [st2, out2] = refusedStart("--keys " + (dir / "empty.txt").string());
    EXPECT_NE(st2, 0) << out2;
    EXPECT_NE(out2.find("holds no keys"), std::string::npos) << out2;
    auto [st3, out3] = refusedStart("--keys " + (dir / "missing.txt").string());
    EXPECT_NE(st3, 0) << out3;
    auto [st4, out4] = refusedStart("--cors-origins 'https://a.example/path'");
    EXPECT_NE(st4, 0) << out4;
    EXPECT_NE(out4.find("not an origin"), std::string::npos) << out4;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace geoslice::test
