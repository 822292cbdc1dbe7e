// A bake that checks itself (issue 10 item 4): a package whose float32 positions would merge
// vertices a fraction of a millimetre apart is refused by the server's loader; bake stores
// what float32 lost where that would happen, and `geoslice bake` loads and validates its own
// package, exiting 1 and naming the part when the server would refuse it.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "bake/bake.hpp"
#include "bake/package.hpp"
#include "model/io/gltf/gltf_io.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "test_meshes.hpp"
#include "tests/common/run_command.hpp"

// Metres: the model spans -100 km .. +100 km, so its origin (its bounds' rounded centre) is
// within a metre of 0.
constexpr double kOriginNearZeroM = 1.0;
// Metres: a vertex 100 km out, restored from float32 plus its _POSITION_LO residual: exact up
// to double rounding there (1.5e-11 m).
constexpr double kRestoredVertexM = 1e-9;

using namespace geoslice;
using namespace geoslice::test;
namespace fs = std::filesystem;

namespace {

constexpr double kFar = 100000.0;  // metres from the model origin
constexpr double kGap = 1e-4;      // 0.1 mm between two blocks of one body

// A 200 km wide model: a small "west" block at -100 km and, at +100 km, a body made of two
// 10 m blocks 0.1 mm apart. float32 steps are 7.8 mm at 100 km: without the residuals the
// blocks' facing vertices merge and the body is not a 2-manifold.
Model farModel() {
    Model m;
    m.name = "far";
    m.bodies.push_back(makePart("west", PartKind::Body, 1, boxMesh({-kFar - 10, 0, 0}, {-kFar, 10, 10})));
    Mesh twin = boxMesh({kFar - 10, 0, 0}, {kFar, 10, 10});
    append(twin, boxMesh({kFar + kGap, 0, 0}, {kFar + 10, 10, 10}));
    m.bodies.push_back(makePart("twin", PartKind::Body, 2, twin));
    for (RecordId id : {1u, 2u}) {
        AttributeRecord r;
        r.id = id;
        r.name = id == 1 ? "west" : "twin";
        m.attributes.put(r);
    }
    m.recentre();
    validate(m);
    return m;
}

fs::path tempDir(const char* name) {
    const fs::path dir = fs::temp_directory_path() / (std::string(name) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string readText(const fs::path& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(BakeSelfCheck, ResidualsKeepVerticesATenthOfAMillimetreApartAt100Km) {
    Model m = farModel();
    ASSERT_FALSE(m.validation.hasErrors());
    ASSERT_NEAR(m.origin.x, 0.0, kOriginNearZeroM);
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 256;
    auto baked = bake::bakeModel(m, o);
    ASSERT_TRUE(baked.ok()) << baked.error().message;
    const fs::path dir = tempDir("geoslice_selfcheck");
    // Without the residuals: refused, and the check names the part.
    ASSERT_TRUE(bake::writePackage(m, baked.value(), (dir / "float").string(), 1, false).ok());
    Status bad = bake::verifyPackage((dir / "float").string());
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("part \"twin\""), std::string::npos) << bad.error().message;
    EXPECT_NE(bad.error().message.find("not a closed 2-manifold"), std::string::npos) << bad.error().message;

    // With them (the default): accepted, and the vertices come back to ~1e-9 m (double
    // rounding of 1e5 m plus the float32 residual's own step, 2^-24 of 7.8 mm ~ 5e-10 m).
    ASSERT_TRUE(bake::writePackage(m, baked.value(), (dir / "exact").string()).ok());
    Status good = bake::verifyPackage((dir / "exact").string());
    EXPECT_TRUE(good.ok()) << good.error().message;
    auto loaded = loadModel((dir / "exact" / bake::kMeshFile).string());
    ASSERT_TRUE(loaded.ok());
    const Part* twin = nullptr;
    for (const Part& p : loaded->bodies)
        if (p.name == "twin") twin = &p;
    ASSERT_NE(twin, nullptr);
    EXPECT_TRUE(twin->report.closed);
    EXPECT_EQ(twin->report.components, 2u);
    bool sawGapFace = false;
    for (const auto& p : twin->mesh.positions) {
        double best = 1e9;
        for (double x : {kFar - 10, kFar, kFar + kGap, kFar + 10}) best = std::min(best, std::abs(p.x - x));
        EXPECT_LT(best, kRestoredVertexM) << p.x;
        sawGapFace = sawGapFace || std::abs(p.x - (kFar + kGap)) < kRestoredVertexM;
    }
    EXPECT_TRUE(sawGapFace);
    EXPECT_TRUE(bake::loadPackage((dir / "exact").string()).ok());
    fs::remove_all(dir);
}

TEST(BakeSelfCheck, CliBakesTheFarModelAndRefusesAPackageTheServerWouldRefuse) {
    const fs::path dir = tempDir("geoslice_selfcheck_cli");
    // OBJ keeps the coordinates in decimal text (a GLB would already be float32).
    {
        Model m = farModel();
        std::FILE* f = std::fopen((dir / "far.obj").c_str(), "w");
        ASSERT_NE(f, nullptr);
        std::size_t base = 1;
        for (const Part& p : m.bodies) {
            std::fprintf(f, "o %s\n", p.name.c_str());
            for (const auto& v : p.mesh.positions) std::fprintf(f, "v %.6f %.6f %.6f\n", v.x, v.y, v.z);
            for (std::size_t t = 0; t < p.mesh.triangleCount(); ++t)
                std::fprintf(f, "f %zu %zu %zu\n", base + p.mesh.indices[3 * t], base + p.mesh.indices[3 * t + 1],
                             base + p.mesh.indices[3 * t + 2]);
            base += p.mesh.positions.size();
        }
        std::fclose(f);
    }
    auto r = runGeoslice("bake " + (dir / "far.obj").string() + " --size 256 --out " + (dir / "pkg").string());
    EXPECT_EQ(r.exitCode, 0) << r.out;

    // A declared body with a hole (a glTF part whose geoslice extras say "body"): the bake
    // writes a package, then refuses it by name instead of exiting 0.
    {
        Model m;
        m.name = "holed";
        Mesh box = boxMesh({0, 0, 0}, {10, 10, 10});
        box.indices.resize(box.indices.size() - 3);  // one triangle missing
        m.bodies.push_back(makePart("holed box", PartKind::Body, 7, box));
        AttributeRecord rec;
        rec.id = 7;
        rec.name = "holed box";
        m.attributes.put(rec);
        m.recentre();
        ASSERT_TRUE(writeGlb(m, (dir / "holed.glb").string()).ok());
    }
    const std::string errFile = (dir / "err.txt").string();
    auto bad = runCommand(std::string(GEOSLICE_BINARY) + " bake " + (dir / "holed.glb").string() + " --size 64 --out " +
                          (dir / "pkg2").string() + " 2>" + errFile);
    EXPECT_EQ(bad.exitCode, 1);
    const std::string msg = readText(errFile);
    EXPECT_NE(msg.find("would be refused: part \"holed box\""), std::string::npos) << msg;
    EXPECT_NE(msg.find("3 open (boundary) edges"), std::string::npos) << msg;
    // `info` says the same and exits 1: a declared volume is never served as a surface.
    auto info = runGeoslice("info " + (dir / "holed.glb").string());
    EXPECT_EQ(info.exitCode, 1) << info.out;
    EXPECT_NE(info.out.find("holed box: body is not a closed 2-manifold: 3 open (boundary) edges, 0 non-manifold "
                            "edges, e.g. at ("),
              std::string::npos)
        << info.out;
    fs::remove_all(dir);
}
