// `geoslice serve` as a user runs it: the real executable on a free port, configured by a
// file, the environment and flags; it answers, then SIGTERM stops it cleanly (exit 0).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "server/config.hpp"

namespace geoslice::server {
namespace {

TEST(ServeCli, StartsAnswersAndStopsOnSigterm) {
    const auto dir = std::filesystem::temp_directory_path() / ("geoslice_serve_cli_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    const std::string config = (dir / "server.json").string();
    std::ofstream(config) << R"({"demoTriangles": 20000, "gl": "none", "cors": "https://mine.example"})";
    int out[2];
    ASSERT_EQ(pipe(out), 0);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        dup2(out[1], 1);
        close(out[0]);
        const int devnull = open("/dev/null", O_WRONLY);
        dup2(devnull, 2);
        setenv("GEOSLICE_WORKERS", "1", 1);
        execl(GEOSLICE_BINARY, GEOSLICE_BINARY, "serve", "--port", "0", "--host", "127.0.0.1", "--config",
              config.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    close(out[1]);
    // The first line names the port: "geoslice serving on http://127.0.0.1:PORT ...".
    std::string line;
    char c;
    while (line.find("serving on") == std::string::npos) {
        line.clear();
        while (read(out[0], &c, 1) == 1 && c != '\n') line += c;
        if (line.empty()) break;
    }
    const auto colon = line.rfind(':', line.find("  "));
    ASSERT_NE(colon, std::string::npos) << line;
    const int port = std::stoi(line.substr(colon + 1));
    httplib::Client cl("127.0.0.1", port);
    bool ready = false;
    for (int i = 0; i < 200 && !ready; ++i) {
        auto r = cl.Get("/readyz");
        ready = r && r->status == 200;
        if (!ready) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    EXPECT_TRUE(ready);
    // The file's allow-list: a page of that origin may read the answer (its Origin echoed).
    auto models = cl.Get("/v1/models/demo", {{"Origin", "https://mine.example"}});
    ASSERT_TRUE(models);
    EXPECT_EQ(models->status, 200);
    EXPECT_EQ(models->get_header_value("Access-Control-Allow-Origin"), "https://mine.example");  // from the file
    auto page = cl.Get("/");
    ASSERT_TRUE(page);
    EXPECT_NE(page->body.find("/web/leaflet/leaflet.js"), std::string::npos);  // Leaflet from the binary
    auto app = cl.Get("/web/map.js");                                          // the Leaflet maps (web/map.js)
    ASSERT_TRUE(app);
    EXPECT_NE(app->body.find("L.CRS.Simple"), std::string::npos);
    kill(pid, SIGTERM);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
    close(out[0]);
    std::filesystem::remove_all(dir);
}

TEST(ServeConfig, SourcesAndErrors) {
    ServerConfig c;
    ASSERT_TRUE(applyConfigJson(c, R"({"port": 9000, "models": "/data", "cacheMiB": 64})", "test.json"));
    EXPECT_EQ(c.port, 9000);
    EXPECT_EQ(c.modelsDir, "/data");
    EXPECT_EQ(c.cacheMiB, 64u);
    ASSERT_TRUE(
        applyConfigEnv(c, {{"GEOSLICE_PORT", "9100"}, {"OTHER", "x"}, {"GEOSLICE_SHUTDOWN_GRACE_MS", "25000"}}));
    EXPECT_EQ(c.port, 9100);
    EXPECT_EQ(c.shutdownGraceMs, 25000);
    EXPECT_FALSE(applyConfigEnv(c, {{"GEOSLICE_SHUTDOWN_GRACE_MS", "-1"}}));
    auto unknown = applyConfigJson(c, R"({"prot": 1})", "test.json");
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.error().message.find("unknown setting 'prot'"), std::string::npos);
    auto bad = applyConfigEnv(c, {{"GEOSLICE_PORT", "70000"}});
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("GEOSLICE_PORT"), std::string::npos);
    EXPECT_FALSE(applyConfigJson(c, "{not json", "test.json"));
    EXPECT_FALSE(applyConfigJson(c, R"({"port": [1]})", "test.json"));
    c.gl = "vulkan";
    EXPECT_FALSE(checkConfig(c));
}

// CORS: auto is * for the demo and off with models; none, *, or an allow-list of origins
// (normalised: lower case, no trailing '/'), and anything that is not an origin refused.
TEST(ServeConfig, CorsPolicy) {
    ServerConfig c;
    EXPECT_EQ(c.cors, "auto");
    auto demo = corsPolicy(c);
    ASSERT_TRUE(demo);
    EXPECT_EQ(demo.value().allowOrigin("https://x.example"), "*");
    c.modelsDir = "/srv/models";
    auto models = corsPolicy(c);
    ASSERT_TRUE(models);
    EXPECT_EQ(models.value().mode, CorsPolicy::Mode::Off);
    EXPECT_EQ(models.value().allowOrigin("https://x.example"), "");
    ASSERT_TRUE(applyConfigEnv(c, {{"GEOSLICE_CORS", "https://Maps.Example/, http://localhost:8000"}}));
    auto list = corsPolicy(c);
    ASSERT_TRUE(list) << list.error().message;
    EXPECT_EQ(list.value().origins, (std::vector<std::string>{"https://maps.example", "http://localhost:8000"}));
    EXPECT_EQ(list.value().allowOrigin("https://maps.example"), "https://maps.example");
    EXPECT_EQ(list.value().allowOrigin("http://localhost:8000"), "http://localhost:8000");
    for (const char* other : {"", "null", "https://maps.example.evil", "http://maps.example", "http://localhost:8001"})
        EXPECT_EQ(list.value().allowOrigin(other), "") << other;
    ASSERT_TRUE(applyConfigJson(c, R"({"corsOrigins": "*"})", "test.json"));
    EXPECT_EQ(corsPolicy(c).value().allowOrigin("https://any.example"), "*");
    ASSERT_TRUE(applyConfigJson(c, R"({"cors": "none"})", "test.json"));
    EXPECT_EQ(corsPolicy(c).value().mode, CorsPolicy::Mode::Off);
    for (const char* bad : {"maps.example", "https://a.example/path", "*,https://a.example", "null", "https://",
                            "ftp://a.example", "https://a.example,"}) {
        c.cors = bad;
        EXPECT_FALSE(corsPolicy(c)) << bad;
        EXPECT_FALSE(checkConfig(c)) << bad;
    }
}

// Keys given inline are checked where they are given; an empty value is an error, not
// "no keys" (it would leave every model open).
TEST(ServeConfig, KeysSettings) {
    ServerConfig c;
    ASSERT_TRUE(applyConfigEnv(
        c, {{"GEOSLICE_KEYS_FILE", "/run/secrets/keys"}, {"GEOSLICE_KEYS", "a 0123456789abcdef0123456789abcdef *"}}));
    EXPECT_EQ(c.keysFile, "/run/secrets/keys");
    EXPECT_EQ(c.keys, "a 0123456789abcdef0123456789abcdef *");
    auto empty = applyConfigEnv(c, {{"GEOSLICE_KEYS", ""}});
    ASSERT_FALSE(empty);
    EXPECT_NE(empty.error().message.find("GEOSLICE_KEYS"), std::string::npos);
    auto shortKey = applyConfigEnv(c, {{"GEOSLICE_KEYS", "a tooshort *"}});
    ASSERT_FALSE(shortKey);
    EXPECT_EQ(shortKey.error().message.find("tooshort"), std::string::npos) << shortKey.error().message;
    ASSERT_TRUE(applyConfigJson(c, R"({"keysFile": "/etc/geoslice/keys"})", "test.json"));
    EXPECT_EQ(c.keysFile, "/etc/geoslice/keys");
}

}  // namespace
}  // namespace geoslice::server
