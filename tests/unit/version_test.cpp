// One version string (issue 14): model/version.hpp is generated from project(geoslice
// VERSION ...) in the top CMakeLists.txt, and the CLI's --version, the glTF files it writes
// and baked package manifests all carry it (the server's /healthz and OpenAPI document are
// checked in tests/server/server_test.cpp). The oracle is the CMakeLists.txt text itself.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bake/package.hpp"
#include "model/version.hpp"
#include "tests/common/run_command.hpp"

using namespace geoslice;
namespace fs = std::filesystem;

namespace {

std::string readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// The JSON chunk of a GLB file (glTF 2.0 binary container: 12-byte header, then chunks of
// {uint32 length, uint32 type, bytes}; the first chunk is JSON).
nlohmann::json glbJson(const std::string& bytes) {
    if (bytes.size() < 20) return {};
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (20 + std::size_t(length) > bytes.size()) return {};
    return nlohmann::json::parse(bytes.substr(20, length), nullptr, false);
}

}  // namespace

TEST(Version, IsTheProjectVersionOfCMakeLists) {
    const std::string cmake = readAll(fs::path(GEOSLICE_TEST_DATA_DIR) / ".." / ".." / "CMakeLists.txt");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(cmake, m, std::regex(R"(project\(geoslice VERSION ([0-9]+\.[0-9]+\.[0-9]+))")));
    EXPECT_EQ(m[1].str(), kVersion);
    EXPECT_EQ(std::string(kGeneratorName), "geoslice " + m[1].str());
}

TEST(Version, CliGltfAndPackageCarryIt) {
    const fs::path dir = fs::temp_directory_path() / ("geoslice_version_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto v = test::runGeoslice("--version");
    EXPECT_EQ(v.exitCode, 0);
    EXPECT_EQ(v.out, std::string(kGeneratorName) + "\n");

    const std::string model = (dir / "m.glb").string();
    ASSERT_EQ(test::runGeoslice("generate --triangles 2000 --out " + model).exitCode, 0);
    const nlohmann::json gltf = glbJson(readAll(model));
    ASSERT_TRUE(gltf.is_object());
    EXPECT_EQ(gltf["asset"]["generator"], kGeneratorName);

    const std::string out = (dir / "pkg").string();
    auto r = test::runGeoslice("bake " + model + " --size 256 --out " + out);
    ASSERT_EQ(r.exitCode, 0) << r.out;
    const nlohmann::json manifest = nlohmann::json::parse(readAll(fs::path(out) / bake::kManifestFile), nullptr, false);
    ASSERT_TRUE(manifest.is_object());
    EXPECT_EQ(manifest["generator"], kGeneratorName);
    fs::remove_all(dir);
}
