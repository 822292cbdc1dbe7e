// Issue 11 item 6: a baked package that fails its checksums while its source is intact is
// baked again on load, and the corrupt one is kept aside (never deleted silently).
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/common/serve_process.hpp"

namespace geoslice::test {
namespace {

namespace fs = std::filesystem;

TEST(HostileFiles, CorruptPackageIsRebakedAndKeptAside) {
    const fs::path dir = fs::temp_directory_path() / ("geoslice_rebake_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "models");
    const std::string gen = std::string(GEOSLICE_BINARY) + " generate --triangles 2000 --out " +
                            (dir / "models" / "mine.glb").string() + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(gen.c_str()), 0);
    const std::vector<std::string> args = {
        "--gl", "none", "--models", (dir / "models").string(), "--bake-dir", (dir / "bake").string(), "--workers", "1"};
    {
        auto first = ServeProcess::start(args);
        ASSERT_NE(first, nullptr);
        ASSERT_TRUE(first->waitReady()) << first->log();
        first->terminate(std::chrono::milliseconds(10000));
    }
    // Flip bytes in the middle of the baked mesh: its checksum no longer matches.
    const fs::path mesh = dir / "bake" / "mine" / "mesh.glb";
    ASSERT_TRUE(fs::exists(mesh));
    {
        std::fstream f(mesh, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(fs::file_size(mesh) / 2));
        f.write("XXXXXXXX", 8);
    }
    auto second = ServeProcess::start(args);
    ASSERT_NE(second, nullptr);
    ASSERT_TRUE(second->waitReady()) << second->log();
    auto r = second->client().Get("/v1/models/mine");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << r->body;                                   // was 404 on every restart
    EXPECT_TRUE(fs::exists(dir / "bake" / "mine.corrupt-1" / "mesh.glb"));  // kept aside
    EXPECT_NE(second->log().find("event=package_rebaked id=mine"), std::string::npos) << second->log();
    second->terminate(std::chrono::milliseconds(10000));
    fs::remove_all(dir);
}

}  // namespace
}  // namespace geoslice::test
