// Models from a directory: raw files, baked packages (bake/package.hpp), a corrupt package
// that must not take the others down, and raw models baked on first load (--bake-dir).
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "bake/bake.hpp"
#include "bake/package.hpp"
#include "model/io/gltf/gltf_io.hpp"
#include "server/http_server.hpp"
#include "tests/common/http_json.hpp"
#include "tests/common/synthetic_model.hpp"
#include "tests/server/server_fixture.hpp"

namespace geoslice::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& name)
        : path(fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()))) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
};

ServerConfig config(const fs::path& models, const std::string& bakeDir = "") {
    ServerConfig c = loopbackConfig();
    c.modelsDir = models.string();
    c.bakeDir = bakeDir;
    return c;
}

json getJson(int port, const std::string& path, int status = 200) {
    httplib::Client c("127.0.0.1", port);
    return test::getJson(c, path, status);
}

TEST(ModelsDir, RawFilesPackagesAndACorruptPackage) {
    spdlog::set_level(spdlog::level::off);
    TempDir dir("geoslice_models_dir");
    const Model model = test::syntheticModel(20000, OreVariant::Nested, 3, "EPSG:4523");
    ASSERT_TRUE(writeGlb(model, (dir.path / "raw.glb").string()));
    auto baked = bake::bakeModel(model);
    ASSERT_TRUE(baked) << baked.error().message;
    ASSERT_TRUE(bake::writePackage(model, baked.value(), (dir.path / "pkg").string()));
    ASSERT_TRUE(bake::writePackage(model, baked.value(), (dir.path / "broken").string()));
    fs::resize_file(dir.path / "broken" / bake::kTextureFile, 10);  // truncated texture
    std::ofstream(dir.path / "notes.txt") << "not a model";

    SectionServer s(config(dir.path));
    auto port = s.start();
    ASSERT_TRUE(port);
    EXPECT_FALSE(s.waitUntilLoaded());  // one model failed...
    const json ready = getJson(port.value(), "/readyz");
    EXPECT_EQ(ready["ready"], true);  // ...and the others serve
    ASSERT_EQ(ready["models"]["failed"].size(), 1u);
    EXPECT_EQ(ready["models"]["failed"][0]["id"], "broken");
    EXPECT_NE(ready["models"]["failed"][0]["error"].get<std::string>().find(bake::kTextureFile), std::string::npos);
    // Ray scenes build after the models are served (section/rays/ray_queries.hpp): /readyz reports
    // each served model's, whatever its state when asked.
    ASSERT_EQ(ready["rays"].size(), 2u) << ready.dump();
    for (const char* id : {"pkg", "raw"}) {
        const std::string st = ready["rays"][id]["state"];
        EXPECT_TRUE(st == "pending" || st == "building" || st == "ready") << id << ": " << st;
    }

    const json models = getJson(port.value(), "/v1/models");
    ASSERT_EQ(models["models"].size(), 2u);
    const json pkg = getJson(port.value(), "/v1/models/pkg");
    ASSERT_TRUE(pkg.contains("baked"));
    EXPECT_GE(pkg["baked"]["pages"].get<int>(), 1);
    EXPECT_FALSE(getJson(port.value(), "/v1/models/raw").contains("baked"));
    getJson(port.value(), "/v1/models/broken", 404);

    // The package's geometry is the raw model's: the same answers at the same pixels.
    const Aabb b = model.bounds();
    const std::string view = "plane=0,1,0," + std::to_string(-0.5 * (b.min.y + b.max.y)) + "&size=64x32";
    int hits = 0;
    for (int px = 0; px < 64; px += 7)
        for (int py = 0; py < 32; py += 5) {
            const std::string q = "/query?" + view + "&px=" + std::to_string(px) + "&py=" + std::to_string(py);
            const json a = getJson(port.value(), "/v1/models/raw" + q), p = getJson(port.value(), "/v1/models/pkg" + q);
            EXPECT_EQ(a["record"], p["record"]) << px << "," << py;
            hits += a["hit"].get<bool>();
        }
    EXPECT_GT(hits, 10);
    // Those queries needed the rays (no cached image) and waited for them: built now.
    const json after = getJson(port.value(), "/readyz");
    EXPECT_EQ(after["rays"]["pkg"]["state"], "ready");
    EXPECT_EQ(after["rays"]["raw"]["state"], "ready");
    httplib::Client c("127.0.0.1", port.value());
    auto metrics = c.Get("/metrics");
    ASSERT_TRUE(metrics);
    EXPECT_NE(metrics->body.find("\ngeoslice_ray_scenes_ready 2\n"), std::string::npos);
    EXPECT_NE(metrics->body.find("\ngeoslice_ray_scenes_building 0\n"), std::string::npos);
}

TEST(ModelsDir, ADeclaredVolumeThatIsNotClosedIsAFailedModel) {
    // A glTF body (geoslice extras kind "body") with a triangle missing: never served as a
    // surface; /readyz names it, the part, and how many edges are open.
    spdlog::set_level(spdlog::level::off);
    TempDir dir("geoslice_models_open_body");
    Model m = test::syntheticModel(5000, OreVariant::Nested, 3);
    m.bodies[0].mesh.indices.resize(m.bodies[0].mesh.indices.size() - 3);
    ASSERT_TRUE(writeGlb(m, (dir.path / "holed.glb").string()));
    SectionServer s(config(dir.path));
    auto port = s.start();
    ASSERT_TRUE(port);
    EXPECT_FALSE(s.waitUntilLoaded());
    const json ready = getJson(port.value(), "/readyz", 503);  // no model to serve
    EXPECT_EQ(ready["ready"], false);
    ASSERT_EQ(ready["models"]["failed"].size(), 1u);
    EXPECT_EQ(ready["models"]["failed"][0]["id"], "holed");
    const std::string error = ready["models"]["failed"][0]["error"];
    EXPECT_NE(error.find(m.bodies[0].name + ": body is not a closed 2-manifold: 3 open (boundary) edges"),
              std::string::npos)
        << error;
    getJson(port.value(), "/v1/models/holed", 404);
}

TEST(ModelsDir, RawModelsBakedOnFirstLoadAndReused) {
    spdlog::set_level(spdlog::level::off);
    TempDir dir("geoslice_bake_on_load");
    TempDir cache("geoslice_bake_cache");
    const Model model = test::syntheticModel(20000, OreVariant::Nested, 5, "EPSG:4523");
    ASSERT_TRUE(writeGlb(model, (dir.path / "mine.glb").string()));
    fs::file_time_type first;
    {
        SectionServer s(config(dir.path, cache.path.string()));
        auto port = s.start();
        ASSERT_TRUE(port);
        ASSERT_TRUE(s.waitUntilLoaded());
        EXPECT_TRUE(getJson(port.value(), "/v1/models/mine").contains("baked"));
        ASSERT_TRUE(fs::exists(cache.path / "mine" / bake::kManifestFile));
        first = fs::last_write_time(cache.path / "mine" / bake::kManifestFile);
    }
    {
        SectionServer s(config(dir.path, cache.path.string()));
        auto port = s.start();
        ASSERT_TRUE(port);
        ASSERT_TRUE(s.waitUntilLoaded());
        EXPECT_TRUE(getJson(port.value(), "/v1/models/mine").contains("baked"));
        EXPECT_EQ(fs::last_write_time(cache.path / "mine" / bake::kManifestFile), first);  // not baked again
    }
}

// The Kubernetes order (deploy/kubernetes/geoslice.yaml): replicas (--no-bake) start on an
// empty packages volume before the bake Job has written anything. They stay unready, keep
// looking, and become ready when a package appears; a package baked again replaces the
// served version without the replica ever turning unready.
TEST(ModelsDir, AReplicaStartedBeforeItsPackagesBecomesReadyWhenTheyAppear) {
    spdlog::set_level(spdlog::level::off);
    TempDir dir("geoslice_models_poll");
    ServerConfig c = config(dir.path);
    c.noBake = true;
    c.modelsPollMs = 50;
    SectionServer s(c);
    auto port = s.start();
    ASSERT_TRUE(port);
    EXPECT_TRUE(s.waitUntilLoaded());
    const json empty = getJson(port.value(), "/readyz", 503);
    EXPECT_EQ(empty["models"]["loaded"], 0);
    EXPECT_EQ(empty["models"]["pollMs"], 50);

    const Model first = test::syntheticModel(20000, OreVariant::Nested, 3, "EPSG:4523");
    auto baked = bake::bakeModel(first);
    ASSERT_TRUE(baked) << baked.error().message;
    ASSERT_TRUE(bake::writePackage(first, baked.value(), (dir.path / "mine").string()));
    httplib::Client cl("127.0.0.1", port.value());
    const auto t0 = std::chrono::steady_clock::now();
    auto since = [&t0] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    int status = 0;
    while (since() < 30) {
        auto r = cl.Get("/readyz");
        ASSERT_TRUE(r);
        if ((status = r->status) == 200) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_EQ(status, 200) << "not ready 30 s after its package appeared";
    // Ready means the ray scene is built: the first pixel query takes no build.
    const json ready = getJson(port.value(), "/readyz");
    EXPECT_EQ(ready["rays"]["mine"]["state"], "ready");
    const Aabb b = first.bounds();
    const std::string view = "plane=0,1,0," + std::to_string(-0.5 * (b.min.y + b.max.y)) + "&size=64x32";
    const auto q0 = std::chrono::steady_clock::now();
    const json answer = getJson(port.value(), "/v1/models/mine/query?" + view + "&px=32&py=16");
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - q0).count(), 2.0);
    EXPECT_TRUE(answer.contains("hit"));
    const std::string v1 = getJson(port.value(), "/v1/models/mine")["version"];

    // Baked again from another model: served once built, and /readyz stays 200 throughout.
    const Model second = test::syntheticModel(20000, OreVariant::Nested, 7, "EPSG:4523");
    auto rebaked = bake::bakeModel(second);
    ASSERT_TRUE(rebaked) << rebaked.error().message;
    ASSERT_TRUE(bake::writePackage(second, rebaked.value(), (dir.path / "mine").string()));
    std::string v2 = v1;
    const auto t1 = std::chrono::steady_clock::now();
    while (v2 == v1 && std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count() < 30) {
        auto r = cl.Get("/readyz");
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 200) << r->body;
        v2 = getJson(port.value(), "/v1/models/mine")["version"];
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    EXPECT_NE(v2, v1) << "the package baked again was not picked up within 30 s";
    // The old version's pinned URLs are gone, the new one's answer.
    getJson(port.value(), "/v1/models/mine/query?" + view + "&px=32&py=16&version=" + v1, 404);
    getJson(port.value(), "/v1/models/mine/query?" + view + "&px=32&py=16&version=" + v2);
}

}  // namespace
}  // namespace geoslice::server

namespace geoslice::server {
namespace {

// A baked package's perspective view draws through the attribute-indexed texture on a render
// worker's GL context; its ID buffer (read back through queries) holds the baked records.
TEST(ModelsDir, PerspectiveOfABakedPackageUsesItsTexture) {
    spdlog::set_level(spdlog::level::off);
    TempDir dir("geoslice_models_gl");
    const Model model = test::syntheticModel(20000, OreVariant::Nested, 3, "EPSG:4523");
    bake::BakeOptions options;
    options.pack.width = options.pack.height = 1024;
    auto baked = bake::bakeModel(model, options);
    ASSERT_TRUE(baked) << baked.error().message;
    ASSERT_TRUE(bake::writePackage(model, baked.value(), (dir.path / "pkg").string()));
    ServerConfig c = config(dir.path);
    c.gl = "auto";
    SectionServer s(c);
    auto port = s.start();
    ASSERT_TRUE(port);
    ASSERT_TRUE(s.waitUntilLoaded());
    const Aabb b = model.bounds();
    const std::string view =
        "plane=0,1,0," + std::to_string(-0.5 * (b.min.y + b.max.y)) + "&view=perspective&size=96x72";
    httplib::Client cl("127.0.0.1", port.value());
    cl.set_read_timeout(60, 0);
    auto image = cl.Get(("/v1/models/pkg/section.png?" + view).c_str());
    ASSERT_TRUE(image);
    ASSERT_EQ(image->status, 200) << image->body;
    int hits = 0;
    for (int px = 8; px < 96; px += 8)
        for (int py = 6; py < 72; py += 6) {
            const json q = getJson(port.value(), "/v1/models/pkg/query?" + view + "&px=" + std::to_string(px) +
                                                     "&py=" + std::to_string(py));
            EXPECT_EQ(q["source"], "id-buffer");
            if (q["hit"].get<bool>()) {
                ++hits;
                EXPECT_NE(model.attributes.find(q["record"]["id"].get<RecordId>()), nullptr);
            }
        }
    EXPECT_GT(hits, 5);
}

}  // namespace
}  // namespace geoslice::server
