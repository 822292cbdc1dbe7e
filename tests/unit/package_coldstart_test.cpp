// Cold start from a baked package (issue 13 item 4): the package carries the validation of
// its own mesh and the section BVH, so a server neither validates nor builds the BVH again.
// Checked here, exactly (no tolerance: the same doubles and the same tree must come out):
//  - packageModel() = loadModel(mesh.glb) (positions, indices, parts, records, reports,
//    findings, origin, CRS, notes), bit for bit, for a model with nested bodies;
//  - the section BVH loaded from the package = the one built from loadModel(mesh.glb)
//    (the saved bytes are equal), and sections through both indexes (ID buffers and RGBA of
//    20 random planes) are equal byte for byte;
//  - loadBvh refuses truncated bytes, another origin, another mesh set, out-of-range ids and
//    a node graph that is not a tree (which could loop or blow up a traversal);
//  - in a bake dir, a tampered section.bvh or a package of an older format is baked again,
//    and with mayBake = false (serve --no-bake) it is refused with the reason instead.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "api/catalog.hpp"
#include "bake/package.hpp"
#include "model/io/gltf/gltf_io.hpp"
#include "model/io/loaders.hpp"
#include "section/cut/contours.hpp"
#include "section/fill/raster.hpp"
#include "section/index/section_index.hpp"
#include "tests/common/random_plane.hpp"
#include "tests/common/synthetic_model.hpp"

using namespace geoslice;
namespace fs = std::filesystem;

namespace {

fs::path tempDir(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("geoslice_coldstart_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string readAll(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void writeAll(const fs::path& p, const std::string& s) {
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f << s;
}

// A baked package of a synthetic mine with a nested orebody (nesting parents matter).
fs::path bakePackage(const fs::path& root) {
    Model m = test::syntheticModel(6000, OreVariant::Nested, 3, "EPSG:4523");
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 1024;
    auto baked = bake::bakeModel(m, o);
    EXPECT_TRUE(baked.ok()) << (baked.ok() ? "" : baked.error().message);
    const fs::path dir = root / "pkg";
    auto s = bake::writePackage(m, baked.value(), dir.string());
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return dir;
}

void expectSameReport(const MeshReport& a, const MeshReport& b, const std::string& part) {
    SCOPED_TRACE(part);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.boundaryEdges, b.boundaryEdges);
    EXPECT_EQ(a.nonManifoldEdges, b.nonManifoldEdges);
    EXPECT_EQ(a.splitEdges, b.splitEdges);
    EXPECT_EQ(a.splitVertices, b.splitVertices);
    EXPECT_EQ(a.inconsistentEdges, b.inconsistentEdges);
    EXPECT_EQ(a.degenerateTriangles, b.degenerateTriangles);
    EXPECT_EQ(a.duplicateTriangles, b.duplicateTriangles);
    EXPECT_EQ(a.nonFiniteVertices, b.nonFiniteVertices);
    EXPECT_EQ(a.components, b.components);
    EXPECT_EQ(a.closed, b.closed);
    EXPECT_EQ(a.consistentlyOriented, b.consistentlyOriented);
    EXPECT_EQ(a.signedVolume, b.signedVolume);
    EXPECT_EQ(a.flipped, b.flipped);
    EXPECT_EQ(a.nestingDepth, b.nestingDepth);
    EXPECT_EQ(a.parent, b.parent);
    EXPECT_EQ(a.problemEdges, b.problemEdges);
}

void expectSameParts(const std::vector<Part>& a, const std::vector<Part>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].name, b[i].name);
        EXPECT_EQ(a[i].kind, b[i].kind);
        EXPECT_EQ(a[i].kindDeclared, b[i].kindDeclared);
        EXPECT_EQ(a[i].record, b[i].record);
        // Exact: the same doubles (operator== on dvec3 compares every bit of value).
        EXPECT_TRUE(a[i].mesh.positions == b[i].mesh.positions) << a[i].name;
        EXPECT_TRUE(a[i].mesh.indices == b[i].mesh.indices) << a[i].name;
        expectSameReport(a[i].report, b[i].report, a[i].name);
    }
}

}  // namespace

TEST(PackageColdStart, PackageModelEqualsTheValidatedMesh) {
    const fs::path root = tempDir("model");
    const fs::path dir = bakePackage(root);
    auto pkg = bake::loadPackage(dir.string());
    ASSERT_TRUE(pkg.ok()) << pkg.error().message;
    auto fast = bake::packageModel(pkg.value());
    ASSERT_TRUE(fast.ok()) << fast.error().message;
    auto slow = loadModel((dir / bake::kMeshFile).string());  // parsed by tinygltf and validated
    ASSERT_TRUE(slow.ok()) << slow.error().message;
    const Model& f = fast.value();
    const Model& s = slow.value();
    EXPECT_EQ(f.name, s.name);
    EXPECT_EQ(f.source, s.source);
    EXPECT_EQ(f.crs.id(), s.crs.id());
    EXPECT_TRUE(f.origin == s.origin);
    EXPECT_EQ(f.notes, s.notes);
    EXPECT_EQ(f.attributes.toJson().dump(), s.attributes.toJson().dump());
    expectSameParts(f.bodies, s.bodies);
    expectSameParts(f.surfaces, s.surfaces);
    ASSERT_EQ(f.validation.issues.size(), s.validation.issues.size());
    for (std::size_t i = 0; i < f.validation.issues.size(); ++i) {
        EXPECT_EQ(f.validation.issues[i].severity, s.validation.issues[i].severity);
        EXPECT_EQ(f.validation.issues[i].part, s.validation.issues[i].part);
        EXPECT_EQ(f.validation.issues[i].message, s.validation.issues[i].message);
    }
    bool nested = false;
    for (const Part& p : f.bodies) nested = nested || p.report.parent >= 0;
    EXPECT_TRUE(nested) << "the test model should have a nested body";
    EXPECT_TRUE(pkg->manifest.at("validation").at("trusted").get<bool>());
    fs::remove_all(root);
}

TEST(PackageColdStart, SavedBvhGivesTheSameSectionsBitForBit) {
    const fs::path root = tempDir("bvh");
    const fs::path dir = bakePackage(root);
    auto pkg = bake::loadPackage(dir.string());
    ASSERT_TRUE(pkg.ok()) << pkg.error().message;
    ASSERT_FALSE(pkg->sectionBvh.empty());
    auto fast = bake::packageModel(pkg.value());
    ASSERT_TRUE(fast.ok()) << fast.error().message;
    auto slow = loadModel((dir / bake::kMeshFile).string());
    ASSERT_TRUE(slow.ok()) << slow.error().message;

    auto loaded = loadSectionIndex(fast.value(), pkg->sectionBvh, "section.bvh");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    auto built = buildSectionIndex(slow.value());
    ASSERT_TRUE(built.ok()) << built.error().message;
    EXPECT_TRUE(saveBvh(loaded.value()->bvh) == saveBvh(built.value()->bvh)) << "the loaded tree differs";

    std::mt19937_64 rng(7);
    const Aabb b = slow->bounds();
    int nonEmpty = 0;
    for (int k = 0; k < 20; ++k) {
        const Plane plane = test::randomPlane(b, rng, k);
        auto s1 = computeSection(*loaded.value(), plane);
        auto s2 = computeSection(*built.value(), plane);
        ASSERT_EQ(s1.ok(), s2.ok());
        if (!s1.ok()) continue;
        const FrameRect rect = fitFrame(s2.value(), 256, 192);
        auto i1 = rasterizeSection(*loaded.value(), s1.value(), rect, 256, 192);
        auto i2 = rasterizeSection(*built.value(), s2.value(), rect, 256, 192);
        ASSERT_EQ(i1.ok(), i2.ok());
        if (!i1.ok()) continue;
        EXPECT_TRUE(i1->ids == i2->ids) << "plane " << k;
        EXPECT_TRUE(i1->rgba == i2->rgba) << "plane " << k;
        bool any = false;
        for (auto id : i2->ids) any = any || id != 0;
        nonEmpty += any;
    }
    EXPECT_GE(nonEmpty, 10) << "most planes should cut the model";
    fs::remove_all(root);
}

TEST(PackageColdStart, LoadBvhRefusesBadBytes) {
    Model m = test::syntheticModel(3000);
    auto index = buildSectionIndex(m);
    ASSERT_TRUE(index.ok());
    const SectionIndex& ix = *index.value();
    const std::vector<std::uint8_t> good = saveBvh(ix.bvh);
    auto load = [&](const std::vector<std::uint8_t>& bytes, const glm::dvec3& origin, std::size_t meshes) {
        return loadBvh(bytes, ix.meshes.data(), meshes, origin, "t.bvh");
    };
    ASSERT_TRUE(load(good, m.origin, ix.meshes.size()).ok());
    auto refused = [&](const Result<Bvh>& r, const char* what) {
        ASSERT_FALSE(r.ok()) << what;
        EXPECT_EQ(r.error().code, ErrorCode::ParseError) << what;
        EXPECT_NE(r.error().message.find("t.bvh"), std::string::npos) << r.error().message;
    };
    refused(load(std::vector<std::uint8_t>(good.begin(), good.end() - 4), m.origin, ix.meshes.size()), "truncated");
    refused(load(std::vector<std::uint8_t>(good.begin(), good.begin() + 10), m.origin, ix.meshes.size()), "header");
    refused(load(good, m.origin + glm::dvec3(1.0, 0.0, 0.0), ix.meshes.size()), "origin");
    refused(load(good, m.origin, ix.meshes.size() - 1), "mesh count");
    // Node 0 (the root, internal for a model this size) pointing at itself: not a tree.
    ASSERT_EQ(ix.bvh.nodes[0].count, 0u);
    std::vector<std::uint8_t> loop = good;
    const std::uint32_t zero = 0;
    std::memcpy(loop.data() + 64 + 12, &zero, 4);  // nodes[0].first
    refused(load(loop, m.origin, ix.meshes.size()), "cycle");
    // Two internal nodes sharing one pair of children (a DAG: traversal work could double per level).
    std::vector<std::uint8_t> dag = good;
    const BvhNode& left = ix.bvh.nodes[ix.bvh.nodes[0].first];
    const BvhNode& right = ix.bvh.nodes[ix.bvh.nodes[0].first + 1];
    ASSERT_EQ(left.count, 0u);
    ASSERT_EQ(right.count, 0u);
    std::memcpy(dag.data() + 64 + 32 * (ix.bvh.nodes[0].first + 1) + 12, &left.first, 4);
    refused(load(dag, m.origin, ix.meshes.size()), "shared children");
    // A triangle id past the model's triangles.
    std::vector<std::uint8_t> id = good;
    const std::uint32_t big = 0x7FFFFFFF;
    std::memcpy(id.data() + 64 + 32 * ix.bvh.nodes.size(), &big, 4);
    refused(load(id, m.origin, ix.meshes.size()), "triangle id");
}

TEST(PackageColdStart, BakeDirRebakesTamperedAndOldPackagesAndNoBakeRefuses) {
    const fs::path root = tempDir("bakedir");
    const fs::path models = root / "models", bakeDir = root / "baked";
    fs::create_directories(models);
    Model m = test::syntheticModel(4000);
    ASSERT_TRUE(writeGlb(m, (models / "mine.glb").string()).ok());
    const std::string src = (models / "mine.glb").string();

    // Without a package, --no-bake refuses naming why; with baking allowed the first load bakes.
    auto none = api::loadCatalogModel("mine", src, bakeDir.string(), /*mayBake=*/false);
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().message.find("no baked package"), std::string::npos) << none.error().message;
    EXPECT_NE(none.error().message.find("--no-bake"), std::string::npos) << none.error().message;
    EXPECT_FALSE(fs::exists(bakeDir / "mine" / bake::kManifestFile));
    auto first = api::loadCatalogModel("mine", src, bakeDir.string());
    ASSERT_TRUE(first.ok()) << first.error().message;
    EXPECT_TRUE(first.value()->rebakedFrom.empty());
    EXPECT_TRUE(first.value()->loadWarning.empty()) << first.value()->loadWarning;
    const std::string version = first.value()->version;

    // Current package: served as it is, also with --no-bake.
    auto again = api::loadCatalogModel("mine", src, bakeDir.string(), /*mayBake=*/false);
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_EQ(again.value()->version, version);

    // One flipped byte in section.bvh: refused with --no-bake, moved aside and rebaked otherwise.
    const fs::path bvh = bakeDir / "mine" / bake::kSectionBvhFile;
    std::string bytes = readAll(bvh);
    bytes[bytes.size() / 2] ^= 0x20;
    writeAll(bvh, bytes);
    auto refused = api::loadCatalogModel("mine", src, bakeDir.string(), /*mayBake=*/false);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("fails its checks"), std::string::npos) << refused.error().message;
    auto rebaked = api::loadCatalogModel("mine", src, bakeDir.string());
    ASSERT_TRUE(rebaked.ok()) << rebaked.error().message;
    EXPECT_NE(rebaked.value()->rebakedFrom.find(".corrupt-1"), std::string::npos) << rebaked.value()->rebakedFrom;
    EXPECT_TRUE(fs::exists(bakeDir / "mine.corrupt-1" / bake::kSectionBvhFile));
    EXPECT_TRUE(bake::loadPackage((bakeDir / "mine").string()).ok());

    // A package of an older format (manifest version 1, its own checksum made right): baked
    // again in place; refused with --no-bake.
    const fs::path manifestPath = bakeDir / "mine" / bake::kManifestFile;
    auto manifest = nlohmann::ordered_json::parse(readAll(manifestPath));
    manifest["version"] = 1;
    manifest.erase("checksum");
    manifest["checksum"] = [&] {
        const std::string compact = manifest.dump();
        char hex[17];
        std::snprintf(hex, sizeof hex, "%016llx",
                      static_cast<unsigned long long>(bake::xxh64(compact.data(), compact.size())));
        return std::string(hex);
    }();
    writeAll(manifestPath, manifest.dump(2) + "\n");
    auto old = bake::loadPackage((bakeDir / "mine").string());
    ASSERT_FALSE(old.ok());
    EXPECT_EQ(old.error().code, ErrorCode::Unsupported) << old.error().message;
    auto stale = api::loadCatalogModel("mine", src, bakeDir.string(), /*mayBake=*/false);
    ASSERT_FALSE(stale.ok());
    EXPECT_NE(stale.error().message.find("stale"), std::string::npos) << stale.error().message;
    auto upgraded = api::loadCatalogModel("mine", src, bakeDir.string());
    ASSERT_TRUE(upgraded.ok()) << upgraded.error().message;
    EXPECT_FALSE(upgraded.value()->rebakedFrom.empty());
    EXPECT_TRUE(bake::loadPackage((bakeDir / "mine").string()).ok());

    // A changed source: baked again (stamp differs); --no-bake refuses it as baked from another version.
    Model other = test::syntheticModel(4000, OreVariant::Nested, 9);
    ASSERT_TRUE(writeGlb(other, src).ok());
    auto changed = api::loadCatalogModel("mine", src, bakeDir.string(), /*mayBake=*/false);
    ASSERT_FALSE(changed.ok());
    EXPECT_NE(changed.error().message.find("another version"), std::string::npos) << changed.error().message;
    auto fresh = api::loadCatalogModel("mine", src, bakeDir.string());
    ASSERT_TRUE(fresh.ok()) << fresh.error().message;
    EXPECT_NE(fresh.value()->version, version);
    fs::remove_all(root);
}
