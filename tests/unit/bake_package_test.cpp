// The baked package: XXH64 against the specification's reference values, a write/load round
// trip that keeps every id, UV and texel, and clear errors (never a crash) for missing,
// truncated, corrupt and inconsistent packages.
#include <gtest/gtest.h>

#include <png.h>
#include <unistd.h>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "bake/package.hpp"
#include "model/io/loaders.hpp"
#include "tests/common/synthetic_model.hpp"

using namespace geoslice;
namespace fs = std::filesystem;

namespace {

fs::path tempDir(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("geoslice_bake_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
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

struct Baked {
    Model model;
    bake::BakedModel baked;
};

Baked smallBake() {
    Baked b{test::syntheticModel(4000), {}};
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 1024;  // one page at the default minimum density
    auto r = bake::bakeModel(b.model, o);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    if (r.ok()) b.baked = std::move(r).value();
    return b;
}

}  // namespace

TEST(BakePackage, Xxh64ReferenceValues) {
    // Reference values of XXH64 (xxhsum -H64) for seed 0: libxxhash gives the checksums that
    // packages were written with (before it, a hand-written XXH64 with these same values).
    EXPECT_EQ(bake::xxh64("", 0), 0xEF46DB3751D8E999ull);
    EXPECT_EQ(bake::xxh64("abc", 3), 0x44BC2CF5AD770999ull);
    const std::string s = "Nobody inspects the spammish repetition";
    EXPECT_EQ(bake::xxh64(s.data(), s.size()), 0xFBCEA83C8A378BF1ull);
}

// The fuzz_package seeds (tests/fuzz/corpus/package, written by tests/fuzz/make_package_seeds.sh)
// must be packages of the current format, or the fuzzer never gets past the version check:
// each parses, with its checksums when its flag byte asks for them, into a mesh with parts.
TEST(BakePackage, FuzzSeedsAreOfTheCurrentFormat) {
    const fs::path corpus = fs::path(GEOSLICE_TEST_DATA_DIR) / ".." / "fuzz" / "corpus" / "package";
    int seeds = 0;
    for (const auto& e : fs::directory_iterator(corpus)) {
        SCOPED_TRACE(e.path().string());
        const std::string in = readAll(e.path());
        ASSERT_GT(in.size(), 13u);
        std::size_t at = 1;
        std::string_view files[3];
        for (auto& f : files) {
            std::uint32_t n = 0;
            std::memcpy(&n, in.data() + at, 4);
            at += 4;
            ASSERT_LE(n, in.size() - at);
            f = std::string_view(in).substr(at, n);
            at += n;
        }
        // The mesh is handed out as float/uint32 arrays: give it an aligned buffer.
        std::vector<std::uint32_t> mesh((files[1].size() + 3) / 4);
        std::memcpy(mesh.data(), files[1].data(), files[1].size());
        bake::PackageReadOptions o;
        o.verifyChecksums = in[0] & 1;
        auto p =
            bake::parsePackage(files[0], std::span(reinterpret_cast<const std::uint8_t*>(mesh.data()), files[1].size()),
                               std::span(reinterpret_cast<const std::uint8_t*>(files[2].data()), files[2].size()),
                               std::string_view(in).substr(at), o, e.path().filename().string());
        ASSERT_TRUE(p.ok()) << p.error().message;
        EXPECT_EQ(p->manifest.at("version").get<int>(), bake::kPackageVersion);
        EXPECT_FALSE(p->parts.empty());
        ++seeds;
    }
    EXPECT_GE(seeds, 2);
}

TEST(BakePackage, RoundTripKeepsMeshUvsTexelsAndAttributes) {
    Baked b = smallBake();
    const fs::path dir = tempDir("roundtrip");
    ASSERT_TRUE(bake::writePackage(b.model, b.baked, dir.string()).ok());
    auto p = bake::loadPackage(dir.string());
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ(p->texels, b.baked.texels);
    EXPECT_EQ(p->width, 1024u);
    EXPECT_EQ(p->pages, 1u);
    EXPECT_EQ(p->pages, b.baked.pages);
    EXPECT_EQ(p->attributes.size(), b.model.attributes.size());
    EXPECT_EQ(p->crs, b.model.crs.id());
    EXPECT_EQ(p->origin, b.model.origin);
    ASSERT_EQ(p->parts.size(), b.baked.parts.size());
    for (std::size_t i = 0; i < p->parts.size(); ++i) {
        const auto& a = b.baked.parts[i];
        const auto& q = p->parts[i];
        EXPECT_EQ(q.record, a.record);
        EXPECT_EQ(q.kind, a.kind);
        ASSERT_EQ(q.vertexCount, a.positions.size());
        ASSERT_EQ(q.indexCount, a.indices.size());
        EXPECT_TRUE(std::equal(a.indices.begin(), a.indices.end(), q.indices));
        for (std::size_t v = 0; v < q.vertexCount; ++v) {
            // glTF axes: (east, up, -north), bit-exact float copies.
            ASSERT_EQ(q.positions[3 * v], a.positions[v].x);
            ASSERT_EQ(q.positions[3 * v + 1], a.positions[v].z);
            ASSERT_EQ(q.positions[3 * v + 2], -a.positions[v].y);
            ASSERT_EQ(q.uvs[2 * v], a.uvs[v].x);
            ASSERT_EQ(q.uvs[2 * v + 1], a.uvs[v].y);
        }
    }
    // The GLB is an ordinary geoslice model too.
    auto m = loadModel((dir / bake::kMeshFile).string());
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->triangleCount(), b.model.triangleCount());
    fs::remove_all(dir);
}

TEST(BakePackage, MissingTruncatedAndCorruptPackagesAreClearErrors) {
    Baked b = smallBake();
    const fs::path dir = tempDir("corrupt");
    ASSERT_TRUE(bake::writePackage(b.model, b.baked, dir.string()).ok());
    for (const char* f : {bake::kManifestFile, bake::kMeshFile, bake::kTextureFile, bake::kAttributesFile}) {
        const std::string good = readAll(dir / f);
        SCOPED_TRACE(f);
        // Truncated at several points.
        for (std::size_t cut : {std::size_t(0), good.size() / 3, good.size() - 2}) {
            writeAll(dir / f, good.substr(0, cut));
            auto p = bake::loadPackage(dir.string());
            ASSERT_FALSE(p.ok());
            EXPECT_NE(p.error().message.find(dir.string()), std::string::npos) << p.error().message;
        }
        // One flipped byte in the middle.
        std::string bad = good;
        std::size_t at = bad.size() / 2;
        while (std::isspace(static_cast<unsigned char>(bad[at]))) ++at;  // JSON whitespace carries nothing
        bad[at] ^= 0x5A;
        writeAll(dir / f, bad);
        auto p = bake::loadPackage(dir.string());
        ASSERT_FALSE(p.ok());
        EXPECT_EQ(p.error().code, ErrorCode::ParseError) << p.error().message;
        EXPECT_NE(p.error().message.find("corrupt"), std::string::npos) << p.error().message;
        writeAll(dir / f, good);
        ASSERT_TRUE(bake::loadPackage(dir.string()).ok());
    }
    fs::remove(dir / bake::kTextureFile);
    auto p = bake::loadPackage(dir.string());
    ASSERT_FALSE(p.ok());
    EXPECT_EQ(p.error().code, ErrorCode::NotFound);
    EXPECT_NE(p.error().message.find("not a complete baked package"), std::string::npos);
    fs::remove_all(dir);
}

TEST(BakePackage, InconsistentContentIsRejectedWithoutChecksums) {
    // With checksums off (as the fuzzer runs), the structural checks still catch lies.
    Baked b = smallBake();
    const fs::path dir = tempDir("lies");
    ASSERT_TRUE(bake::writePackage(b.model, b.baked, dir.string()).ok());
    const std::string manifest = readAll(dir / bake::kManifestFile), mesh = readAll(dir / bake::kMeshFile),
                      texture = readAll(dir / bake::kTextureFile), attributes = readAll(dir / bake::kAttributesFile);
    auto span = [](const std::string& s) {
        return std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
    };
    bake::PackageReadOptions noSums;
    noSums.verifyChecksums = false;
    ASSERT_TRUE(bake::parsePackage(manifest, span(mesh), span(texture), attributes, noSums, "pkg").ok());
    // A texture layout that disagrees with the zstd frame.
    nlohmann::json m = nlohmann::json::parse(manifest);
    m["texture"]["width"] = 512;
    auto r = bake::parsePackage(m.dump(), span(mesh), span(texture), attributes, noSums, "pkg");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("texture layout"), std::string::npos) << r.error().message;
    // Another version.
    m = nlohmann::json::parse(manifest);
    m["version"] = 99;
    r = bake::parsePackage(m.dump(), span(mesh), span(texture), attributes, noSums, "pkg");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::Unsupported);
    // An index past the vertices: patch the first index of the first part in the BIN chunk.
    std::string badMesh = mesh;
    std::uint32_t jsonLen = 0;
    std::memcpy(&jsonLen, &mesh[12], 4);
    auto doc = nlohmann::json::parse(badMesh.substr(20, jsonLen));
    const std::size_t idxView = doc["accessors"][2]["bufferView"];
    const std::size_t off = 20 + jsonLen + 8 + std::size_t(doc["bufferViews"][idxView]["byteOffset"]);
    const std::uint32_t huge = 0x7FFFFFFF;
    std::memcpy(&badMesh[off], &huge, 4);
    r = bake::parsePackage(manifest, span(badMesh), span(texture), attributes, noSums, "pkg");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("refers to vertex"), std::string::npos) << r.error().message;
    fs::remove_all(dir);
}

TEST(BakePackage, FeatureGlbCarriesIdsAsMeshFeaturesAndMetadata) {
    Baked b = smallBake();
    const fs::path dir = tempDir("features");
    fs::create_directories(dir);
    const fs::path path = dir / "features.glb";
    auto written = bake::writeFeatureGlb(b.model, b.baked, path.string());
    ASSERT_TRUE(written.ok()) << written.error().message;
    const std::string glb = readAll(path);
    std::uint32_t jsonLen = 0;
    std::memcpy(&jsonLen, &glb[12], 4);
    auto doc = nlohmann::json::parse(glb.substr(20, jsonLen));
    const std::string bin = glb.substr(20 + jsonLen + 8);
    ASSERT_EQ(doc["extensionsUsed"].size(), 2u);
    const auto& table = doc["extensions"]["EXT_structural_metadata"]["propertyTables"][0];
    const std::size_t rows = table["count"];
    EXPECT_EQ(rows, b.model.attributes.size());
    auto viewBytes = [&](std::size_t v) {
        const auto& view = doc["bufferViews"][v];
        return bin.substr(std::size_t(view["byteOffset"]), std::size_t(view["byteLength"]));
    };
    const std::string idBytes = viewBytes(table["properties"]["id"]["values"]);
    std::vector<std::uint32_t> ids(rows);
    std::memcpy(ids.data(), idBytes.data(), rows * 4);
    // Decode the feature-ID PNG: row -> id must reproduce the baked R32UI texture exactly.
    const std::string png = viewBytes(doc["images"][0]["bufferView"]);
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_memory(&image, png.data(), png.size()));
    image.format = PNG_FORMAT_RGBA;
    std::vector<std::uint8_t> rgba(PNG_IMAGE_SIZE(image));
    ASSERT_TRUE(png_image_finish_read(&image, nullptr, rgba.data(), 0, nullptr));
    ASSERT_EQ(rgba.size(), b.baked.texels.size() * 4);
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < b.baked.texels.size(); ++i) {
        const std::uint32_t row =
            rgba[4 * i] | rgba[4 * i + 1] << 8 | rgba[4 * i + 2] << 16 | std::uint32_t(rgba[4 * i + 3]) << 24;
        const std::uint32_t id = row == 0xFFFFFFFFu ? 0u : ids.at(row);
        mismatches += id != b.baked.texels[i];
    }
    EXPECT_EQ(mismatches, 0u);
    // Every primitive points at texture 0 through TEXCOORD_0 and at the property table.
    for (const auto& mesh : doc["meshes"]) {
        const auto& f = mesh["primitives"][0]["extensions"]["EXT_mesh_features"]["featureIds"][0];
        EXPECT_EQ(f["texture"]["texCoord"], 0);
        EXPECT_EQ(f["propertyTable"], 0);
    }
    // Names round-trip through the string columns.
    const std::string names = viewBytes(table["properties"]["name"]["values"]);
    const std::string offsets = viewBytes(table["properties"]["name"]["stringOffsets"]);
    std::uint32_t o0 = 0, o1 = 0;
    std::memcpy(&o0, offsets.data(), 4);
    std::memcpy(&o1, offsets.data() + 4, 4);
    EXPECT_EQ(names.substr(o0, o1 - o0), b.model.attributes.find(ids[0])->name);
    // Several pages cannot be one glTF texture.
    bake::BakedModel paged = b.baked;
    paged.pages = 2;
    paged.texels.resize(paged.texels.size() * 2);
    EXPECT_EQ(bake::writeFeatureGlb(b.model, paged, (dir / "x.glb").string()).error().code, ErrorCode::Unsupported);
    fs::remove_all(dir);
}
