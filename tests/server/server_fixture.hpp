// The shared fixture of tests/server: one real SectionServer per test suite, in this process,
// on a loopback port, and the HTTP client helpers every suite uses. A suite derives from
// InProcessServer, starts the server from its SetUpTestSuite with the configuration it
// needs (loopbackConfig() and its own changes) and stops it in TearDownTestSuite.
//
// Threads: the server runs on its own threads; the helpers are called from the test thread
// (or from test threads that each make their own client).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <httplib.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "server/config.hpp"
#include "server/http_server.hpp"
#include "tests/common/http_json.hpp"

namespace geoslice::server {

// 127.0.0.1, any free port, no GL, two render workers; the demo model unless modelsDir is set.
inline ServerConfig loopbackConfig() {
    ServerConfig c;
    c.host = "127.0.0.1";
    c.port = 0;
    c.gl = "none";
    c.workers = 2;
    return c;
}

// A fresh directory under the system's temporary directory, named for this process.
inline std::filesystem::path freshTempDir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

class InProcessServer : public ::testing::Test {
protected:
    // Starts the suite's server and waits until every model loaded (fatal failures
    // otherwise). `readTimeoutS`: how long client() waits for an answer.
    static void startServer(const ServerConfig& config, int readTimeoutS = 60,
                            spdlog::level::level_enum logLevel = spdlog::level::warn) {
        spdlog::set_level(logLevel);
        readTimeoutS_ = readTimeoutS;
        server_ = new SectionServer(config);
        auto port = server_->start();
        ASSERT_TRUE(port) << port.error().message;
        ASSERT_TRUE(server_->waitUntilLoaded());
    }
    static void stopServer() {
        delete server_;
        server_ = nullptr;
    }
    static SectionServer& server() { return *server_; }
    static int port() { return server_->port(); }

    static httplib::Client client() {
        httplib::Client c("127.0.0.1", server_->port());
        c.set_read_timeout(readTimeoutS_, 0);
        return c;
    }
    static httplib::Result get(const std::string& path) { return client().Get(path.c_str()); }
    // GET `path`, expect `expectStatus`, parse the body (discarded JSON when it is not JSON).
    static nlohmann::json getJson(const std::string& path, int expectStatus = 200) {
        auto c = client();
        return test::getJson(c, path, expectStatus);
    }

    static inline SectionServer* server_ = nullptr;
    static inline int readTimeoutS_ = 60;
};

}  // namespace geoslice::server
