// glTF / GLB: round trips of geoslice's own layout (plain and Draco), generic glTF scene
// graphs (transforms in double, y-up to z-up, extras as records, mirroring), and malformed
// inputs, each of which must give an error that names the input and what is wrong.
//
// Tolerances (per axis, metres):
//  - plain GLB: positions are float32 in the local frame (world minus the rounded bounds
//    centre); the synthetic model's half extent is 3000 m, where the float32 step is
//    2^-12 m = 2.4e-4 m, so rounding moves a coordinate by at most half that, 2^-13 m.
//    Adding the double origin back costs at most half a double step at 3.55e7 m (3.7e-9 m).
//  - Draco: positions quantised with 20 bits; libdraco's step is the part's largest axis
//    extent / (2^20 - 1) (one step for all three axes, 3.8 mm for a 4 km part), error at most
//    half a step plus libdraco's float32 arithmetic: kDracoSteps * step + kDracoFloatTol
//    (2.9 mm for 4 km; measured worst 0.61 step = 2.3 mm).
//  - generic glTF: small integer coordinates through transforms made of integers are exact;
//    a 90-degree quaternion written as 0.7071067811865476 leaves errors of ~1e-15 m.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/io/gltf/gltf_io.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"

namespace geoslice {
namespace {

using Json = nlohmann::json;

constexpr double kFloatLocalTol = 1.0 / 8192.0 + 1e-8;  // 2^-13 m + double rounding at 3.55e7 m
// Draco (see the file comment): half a step, plus 1/16 step because libdraco multiplies by
// 1/step in float32 (near 2^20 quantisation units a float's spacing is 1/8 unit), plus four
// float32 roundings: of the local value and of the result min + q * step (values under
// 4096 m: 2^-13 m each), and of the intermediates x - min and q * step (values up to the
// 6000 m extent: 2^-12 m each).
constexpr double kDracoSteps = 0.5 + 1.0 / 16.0;
constexpr double kDracoFloatTol = 2.0 / 8192.0 + 2.0 / 4096.0;
constexpr double kGenericTol = 1e-12;  // see the file comment
// Relative: every coordinate moves by at most the Draco tolerance (under a millimetre), so a
// body's volume moves by about that times its area: under 1e-5 of these bodies' volumes.
constexpr double kDracoVolumeRelTol = 1e-5;

// ---------------------------------------------------------------------------------------
// Helpers: bytes, base64, GLB containers.

Result<Model> parseText(const std::string& text, const std::string& source, const std::string& baseDir = "") {
    return parseGltf(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), source, baseDir);
}
Result<Model> parseBytes(const std::vector<std::uint8_t>& b, const std::string& source,
                         const std::string& baseDir = "") {
    return parseGltf(b.data(), b.size(), source, baseDir);
}

std::string base64(const std::vector<std::uint8_t>& in) {
    static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < in.size(); i += 3) {
        std::uint32_t v = std::uint32_t(in[i]) << 16;
        if (i + 1 < in.size()) v |= std::uint32_t(in[i + 1]) << 8;
        if (i + 2 < in.size()) v |= in[i + 2];
        out.push_back(kAlphabet[(v >> 18) & 63]);
        out.push_back(kAlphabet[(v >> 12) & 63]);
        out.push_back(i + 1 < in.size() ? kAlphabet[(v >> 6) & 63] : '=');
        out.push_back(i + 2 < in.size() ? kAlphabet[v & 63] : '=');
    }
    return out;
}

void putU32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) { std::memcpy(b.data() + at, &v, 4); }
std::uint32_t getU32(const std::vector<std::uint8_t>& b, std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}

// A GLB split into its JSON and its BIN chunk payload, and joined back.
struct GlbParts {
    Json json;
    std::vector<std::uint8_t> bin;
};
GlbParts splitGlb(const std::vector<std::uint8_t>& glb) {
    GlbParts p;
    const std::uint32_t jsonLen = getU32(glb, 12);
    p.json = Json::parse(glb.begin() + 20, glb.begin() + 20 + jsonLen);
    const std::size_t binAt = 20 + std::size_t(jsonLen);
    if (binAt + 8 <= glb.size()) {
        const std::uint32_t binLen = getU32(glb, binAt);
        p.bin.assign(glb.begin() + static_cast<std::ptrdiff_t>(binAt + 8),
                     glb.begin() + static_cast<std::ptrdiff_t>(binAt + 8 + binLen));
    }
    return p;
}
std::vector<std::uint8_t> joinGlb(const Json& json, std::vector<std::uint8_t> bin) {
    std::string text = json.dump();
    while (text.size() % 4) text.push_back(' ');
    while (bin.size() % 4) bin.push_back(0);
    std::vector<std::uint8_t> out(20 + text.size() + (bin.empty() ? 0 : 8 + bin.size()));
    putU32(out, 0, 0x46546C67);
    putU32(out, 4, 2);
    putU32(out, 8, static_cast<std::uint32_t>(out.size()));
    putU32(out, 12, static_cast<std::uint32_t>(text.size()));
    putU32(out, 16, 0x4E4F534A);
    std::memcpy(out.data() + 20, text.data(), text.size());
    if (!bin.empty()) {
        const std::size_t at = 20 + text.size();
        putU32(out, at, static_cast<std::uint32_t>(bin.size()));
        putU32(out, at + 4, 0x004E4942);
        std::memcpy(out.data() + at + 8, bin.data(), bin.size());
    }
    return out;
}

// Error expected: the message names the input and contains every fragment.
void expectError(const Result<Model>& r, const std::string& source, std::initializer_list<std::string> fragments) {
    ASSERT_FALSE(r.ok()) << "expected an error from " << source;
    const std::string& msg = r.error().message;
    EXPECT_EQ(msg.rfind(source + ": ", 0), 0u) << "message should start with the source: " << msg;
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "expected '" << f << "' in: " << msg;
}

std::vector<const Part*> allParts(const Model& m) {
    std::vector<const Part*> out;
    for (const auto& p : m.bodies) out.push_back(&p);
    for (const auto& p : m.surfaces) out.push_back(&p);
    return out;
}
const Part* findPart(const Model& m, const std::string& name) {
    for (const Part* p : allParts(m))
        if (p->name == name) return p;
    return nullptr;
}

// ---------------------------------------------------------------------------------------
// A hand-written generic glTF: no geoslice extras, one base64 buffer.

// Unit cube [0,1]^3 (glTF axes); triangles counter-clockwise seen from outside.
constexpr float kCube[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
constexpr std::uint32_t kCubeTris[36] = {0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                         3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
// A 4 x 3 quad in glTF's z = 0 plane: an open sheet.
constexpr float kQuad[4][3] = {{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}};
constexpr std::uint16_t kQuadTris[6] = {0, 1, 2, 0, 2, 3};

// Buffer layout: cube positions @0 (96 B), cube indices @96 (144 B, uint32),
// quad positions @240 (48 B), quad indices @288 (12 B, uint16), padded to 300.
std::vector<std::uint8_t> genericBuffer() {
    std::vector<std::uint8_t> b(300, 0);
    std::memcpy(b.data(), kCube, sizeof kCube);
    std::memcpy(b.data() + 96, kCubeTris, sizeof kCubeTris);
    std::memcpy(b.data() + 240, kQuad, sizeof kQuad);
    std::memcpy(b.data() + 288, kQuadTris, sizeof kQuadTris);
    return b;
}

Json genericDoc(const std::vector<std::uint8_t>& buffer) {
    const double s = std::sqrt(0.5);
    Json doc;
    doc["asset"] = {{"version", "2.0"}, {"generator", "gltf_io_test"}};
    doc["scene"] = 0;
    doc["scenes"] = Json::array({Json{{"name", "generic"}, {"nodes", {0, 2, 3, 4}}}});
    doc["nodes"] = Json::array({
        // glTF: T(10,20,30) * R(90 deg about +Y) * S(2); its child adds T(1,0,0).
        Json{{"name", "frame"},
             {"translation", {10, 20, 30}},
             {"rotation", {0, s, 0, s}},
             {"scale", {2, 2, 2}},
             {"children", Json::array({1})}},
        Json{{"name", "granite stock"},
             {"translation", {1, 0, 0}},
             {"mesh", 0},
             {"extras", Json{{"lithology", "granite"}, {"density", 2.7}}}},
        Json{{"name", "mirrored cube"}, {"translation", {100, 0, 0}}, {"scale", {-1, 1, 1}}, {"mesh", 0}},
        Json{{"name", "fault F1"}, {"translation", {0, 0, -50}}, {"mesh", 1}},
        Json{{"name", "matrix cube"}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 50, 60, 70, 1}}, {"mesh", 0}},
    });
    doc["meshes"] = Json::array({
        Json{{"name", "cube"},
             {"primitives", Json::array({Json{{"attributes", Json{{"POSITION", 0}}}, {"indices", 1}, {"mode", 4}}})}},
        Json{{"name", "quad"},
             {"primitives", Json::array({Json{{"attributes", Json{{"POSITION", 2}}}, {"indices", 3}}})}},
    });
    doc["accessors"] = Json::array({
        Json{{"bufferView", 0},
             {"componentType", 5126},
             {"count", 8},
             {"type", "VEC3"},
             {"min", {0, 0, 0}},
             {"max", {1, 1, 1}}},
        Json{{"bufferView", 1}, {"componentType", 5125}, {"count", 36}, {"type", "SCALAR"}},
        Json{{"bufferView", 2},
             {"componentType", 5126},
             {"count", 4},
             {"type", "VEC3"},
             {"min", {0, 0, 0}},
             {"max", {4, 3, 0}}},
        Json{{"bufferView", 3}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}},
    });
    doc["bufferViews"] = Json::array({
        Json{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 96}},
        Json{{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 144}},
        Json{{"buffer", 0}, {"byteOffset", 240}, {"byteLength", 48}},
        Json{{"buffer", 0}, {"byteOffset", 288}, {"byteLength", 12}},
    });
    doc["buffers"] = Json::array(
        {Json{{"byteLength", buffer.size()}, {"uri", "data:application/octet-stream;base64," + base64(buffer)}}});
    return doc;
}

// A one-node, one-primitive document over `buf` (POSITION = the whole buffer as VEC3 floats).
Json singleMeshDoc(const std::vector<std::uint8_t>& buf, const std::string& name, int mode) {
    Json doc;
    doc["asset"] = {{"version", "2.0"}};
    doc["scenes"] = Json::array({Json{{"nodes", Json::array({0})}}});
    doc["nodes"] = Json::array({Json{{"name", name}, {"mesh", 0}}});
    doc["meshes"] =
        Json::array({Json{{"primitives", Json::array({Json{{"attributes", Json{{"POSITION", 0}}}, {"mode", mode}}})}}});
    doc["accessors"] =
        Json::array({Json{{"bufferView", 0}, {"componentType", 5126}, {"count", buf.size() / 12}, {"type", "VEC3"}}});
    doc["bufferViews"] = Json::array({Json{{"buffer", 0}, {"byteLength", buf.size()}}});
    doc["buffers"] =
        Json::array({Json{{"byteLength", buf.size()}, {"uri", "data:application/octet-stream;base64," + base64(buf)}}});
    return doc;
}
Json genericDoc() { return genericDoc(genericBuffer()); }

// Cube vertex i of a part, its expected world position under the given mapping.
template <class F>
void expectCubeVertices(const Part& p, F world) {
    ASSERT_EQ(p.mesh.vertexCount(), 8u);
    for (std::size_t i = 0; i < 8; ++i) {
        const glm::dvec3 want = world(glm::dvec3(kCube[i][0], kCube[i][1], kCube[i][2]));
        const glm::dvec3 got = p.mesh.positions[i];
        EXPECT_NEAR(got.x, want.x, kGenericTol) << p.name << " vertex " << i;
        EXPECT_NEAR(got.y, want.y, kGenericTol) << p.name << " vertex " << i;
        EXPECT_NEAR(got.z, want.z, kGenericTol) << p.name << " vertex " << i;
    }
}

// ---------------------------------------------------------------------------------------
// Round trips of geoslice's own layout.

Model generated(const Crs& crs) {
    SyntheticOptions o;
    o.triangles = 20000;
    o.crs = crs;
    auto m = generateSynthetic(o);
    EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().message);
    return std::move(m).value();
}

void expectSameParts(const std::vector<Part>& want, const std::vector<Part>& got) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t k = 0; k < want.size(); ++k) {
        EXPECT_EQ(got[k].name, want[k].name);
        EXPECT_EQ(got[k].kind, want[k].kind) << want[k].name;
        EXPECT_EQ(got[k].record, want[k].record) << want[k].name;
        EXPECT_EQ(got[k].mesh.triangleCount(), want[k].mesh.triangleCount()) << want[k].name;
    }
}

void expectNoValidationErrors(const Model& m) {
    for (const auto& issue : m.validation.issues)
        EXPECT_NE(issue.severity, ValidationIssue::Severity::Error) << issue.part << ": " << issue.message;
    for (const auto& b : m.bodies) {
        EXPECT_TRUE(b.report.closed) << b.name;
        EXPECT_TRUE(b.report.consistentlyOriented) << b.name;
        EXPECT_FALSE(b.report.flipped) << b.name << " came back inward";
        EXPECT_GT(b.report.signedVolume, 0.0) << b.name;
    }
}

void roundTrip(const Crs& crs) {
    const Model src = generated(crs);
    auto glb = encodeGlb(src);
    ASSERT_TRUE(glb.ok()) << glb.error().message;
    auto r = parseBytes(glb.value(), "round_trip.glb");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Model& m = r.value();

    EXPECT_EQ(m.name, src.name);
    EXPECT_EQ(m.crs.id(), src.crs.id());
    EXPECT_EQ(m.attributes.toJson(), src.attributes.toJson());
    expectSameParts(src.bodies, m.bodies);
    expectSameParts(src.surfaces, m.surfaces);
    EXPECT_EQ(m.triangleCount(), src.triangleCount());
    // The origin is recomputed from the loaded bounds: the same whole metres.
    EXPECT_EQ(m.origin, src.origin);

    // Same vertex order (the plain writer keeps it), each coordinate within kFloatLocalTol.
    double worst = 0.0;
    auto comparePositions = [&](const std::vector<Part>& want, const std::vector<Part>& got) {
        for (std::size_t k = 0; k < want.size() && k < got.size(); ++k) {
            ASSERT_EQ(got[k].mesh.vertexCount(), want[k].mesh.vertexCount()) << want[k].name;
            EXPECT_EQ(got[k].mesh.indices, want[k].mesh.indices) << want[k].name;
            for (std::size_t i = 0; i < want[k].mesh.positions.size(); ++i)
                for (int a = 0; a < 3; ++a)
                    worst = std::max(worst, std::abs(got[k].mesh.positions[i][a] - want[k].mesh.positions[i][a]));
        }
    };
    comparePositions(src.bodies, m.bodies);
    comparePositions(src.surfaces, m.surfaces);
    EXPECT_LE(worst, kFloatLocalTol) << "largest coordinate error " << worst << " m";
    EXPECT_GT(worst, 0.0) << "float32 storage should round something";
    expectNoValidationErrors(m);
}

TEST(Gltf, RoundTripLocalCrs) { roundTrip(Crs::local()); }

TEST(Gltf, RoundTripGaussKrugerKeepsPrecision) {
    auto crs = Crs::parse("EPSG:4523");
    ASSERT_TRUE(crs.ok()) << crs.error().message;
    const Model src = generated(crs.value());
    ASSERT_GT(src.bounds().min.x, 35.0e6) << "eastings should carry the zone number";
    roundTrip(crs.value());
}

// Nearest original vertex of each decoded one (a 1 m hash grid; vertices of the synthetic
// model lie metres apart, tolerances are millimetres).
struct VertexGrid {
    std::map<std::array<long long, 3>, std::vector<std::uint32_t>> cells;
    const std::vector<glm::dvec3>* pts = nullptr;
    explicit VertexGrid(const std::vector<glm::dvec3>& p) : pts(&p) {
        for (std::uint32_t i = 0; i < p.size(); ++i) cells[key(p[i])].push_back(i);
    }
    static std::array<long long, 3> key(const glm::dvec3& p) {
        return {static_cast<long long>(std::floor(p.x)), static_cast<long long>(std::floor(p.y)),
                static_cast<long long>(std::floor(p.z))};
    }
    // All original vertices within `tol` on every axis.
    std::vector<std::uint32_t> near(const glm::dvec3& p, double tol) const {
        std::vector<std::uint32_t> out;
        const auto k = key(p);
        for (long long dx = -1; dx <= 1; ++dx)
            for (long long dy = -1; dy <= 1; ++dy)
                for (long long dz = -1; dz <= 1; ++dz) {
                    auto it = cells.find({k[0] + dx, k[1] + dy, k[2] + dz});
                    if (it == cells.end()) continue;
                    for (std::uint32_t i : it->second) {
                        const glm::dvec3 d = glm::abs((*pts)[i] - p);
                        if (d.x <= tol && d.y <= tol && d.z <= tol) out.push_back(i);
                    }
                }
        return out;
    }
};

std::array<std::uint32_t, 3> rotatedToSmallest(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (a < b && a < c) return {a, b, c};
    if (b < a && b < c) return {b, c, a};
    return {c, a, b};
}

TEST(Gltf, DracoRoundTripWithinQuantisationStep) {
    auto crs = Crs::parse("EPSG:4523");
    ASSERT_TRUE(crs.ok());
    const Model src = generated(crs.value());
    GlbWriteOptions opt;
    opt.draco = true;
    ASSERT_EQ(opt.dracoPositionBits, 20);
    auto glb = encodeGlb(src, opt);
    ASSERT_TRUE(glb.ok()) << glb.error().message;
    auto plain = encodeGlb(src);
    ASSERT_TRUE(plain.ok());
    EXPECT_LT(glb->size(), plain->size() / 3) << "Draco should compress";
    auto r = parseBytes(glb.value(), "draco.glb");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Model& m = r.value();

    EXPECT_EQ(m.crs.id(), src.crs.id());
    EXPECT_EQ(m.attributes.toJson(), src.attributes.toJson());
    expectSameParts(src.bodies, m.bodies);
    expectSameParts(src.surfaces, m.surfaces);
    expectNoValidationErrors(m);

    // libdraco's edgebreaker reorders vertices but, on these closed manifold shells and
    // manifold sheets, neither splits nor welds them: the same vertex count, and a one-to-one
    // match of vertices that turns the decoded triangles into the original ones (same
    // winding), so validation finds the same closed, outward shells.
    auto check = [&](const std::vector<Part>& want, const std::vector<Part>& got) {
        for (std::size_t k = 0; k < want.size() && k < got.size(); ++k) {
            const Mesh& a = want[k].mesh;
            const Mesh& b = got[k].mesh;
            ASSERT_EQ(b.vertexCount(), a.vertexCount()) << want[k].name;
            const glm::dvec3 extent = a.bounds().size();
            const double step = std::max({extent.x, extent.y, extent.z}) / double((1u << 20) - 1);
            const double tol = kDracoSteps * step + kDracoFloatTol;
            VertexGrid grid(a.positions);
            std::vector<std::uint32_t> toOriginal(b.vertexCount());
            std::vector<char> used(a.vertexCount(), 0);
            double worst = 0.0;
            for (std::size_t i = 0; i < b.vertexCount(); ++i) {
                auto cand = grid.near(b.positions[i], tol);
                ASSERT_EQ(cand.size(), 1u) << want[k].name << " decoded vertex " << i << ": " << cand.size()
                                           << " original vertices within " << tol << " m";
                toOriginal[i] = cand[0];
                EXPECT_FALSE(used[cand[0]]) << want[k].name << ": two decoded vertices match original " << cand[0];
                used[cand[0]] = 1;
                const glm::dvec3 d = glm::abs(b.positions[i] - a.positions[cand[0]]);
                worst = std::max({worst, d.x, d.y, d.z});
            }
            EXPECT_LE(worst, tol) << want[k].name;
            std::vector<std::array<std::uint32_t, 3>> ta, tb;
            for (std::size_t t = 0; t < a.triangleCount(); ++t)
                ta.push_back(rotatedToSmallest(a.indices[3 * t], a.indices[3 * t + 1], a.indices[3 * t + 2]));
            for (std::size_t t = 0; t < b.triangleCount(); ++t)
                tb.push_back(rotatedToSmallest(toOriginal[b.indices[3 * t]], toOriginal[b.indices[3 * t + 1]],
                                               toOriginal[b.indices[3 * t + 2]]));
            std::sort(ta.begin(), ta.end());
            std::sort(tb.begin(), tb.end());
            EXPECT_EQ(ta, tb) << want[k].name << ": decoded triangles differ from the original ones";
            if (want[k].kind == PartKind::Body) {
                EXPECT_TRUE(got[k].report.closed) << want[k].name;
                // Every coordinate moves by at most `tol`: the volume by about tol * area.
                const double volume = signedVolume(a);
                EXPECT_NEAR(got[k].report.signedVolume, volume, kDracoVolumeRelTol * volume) << want[k].name;
            }
        }
    };
    check(src.bodies, m.bodies);
    check(src.surfaces, m.surfaces);
}

// ---------------------------------------------------------------------------------------
// Generic glTF.

TEST(Gltf, GenericSceneGraphTransformsExtrasAndKinds) {
    auto r = parseText(genericDoc().dump(), "generic.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Model& m = r.value();
    EXPECT_EQ(m.name, "generic");
    EXPECT_EQ(m.crs.id(), Crs::local().id());
    ASSERT_EQ(m.bodies.size(), 3u);
    ASSERT_EQ(m.surfaces.size(), 1u);

    // Child of "frame": glTF p = T(10,20,30) R_y(90) S(2) (v + (1,0,0)) = (10 + 2z, 20 + 2y,
    // 28 - 2x); world = (X, -Z, Y).
    const Part* granite = findPart(m, "granite stock");
    ASSERT_NE(granite, nullptr);
    EXPECT_EQ(granite->kind, PartKind::Body);
    expectCubeVertices(*granite, [](glm::dvec3 v) { return glm::dvec3(10 + 2 * v.z, 2 * v.x - 28, 20 + 2 * v.y); });
    EXPECT_NEAR(granite->report.signedVolume, 8.0, kGenericTol);

    // Mirrored by scale (-1, 1, 1): glTF (100 - x, y, z) -> world (100 - x, -z, y). The
    // loader reverses the winding, so the shell stays outward without validation's help.
    const Part* mirrored = findPart(m, "mirrored cube");
    ASSERT_NE(mirrored, nullptr);
    EXPECT_EQ(mirrored->kind, PartKind::Body);
    expectCubeVertices(*mirrored, [](glm::dvec3 v) { return glm::dvec3(100 - v.x, -v.z, v.y); });
    EXPECT_FALSE(mirrored->report.flipped);
    EXPECT_NEAR(mirrored->report.signedVolume, 1.0, kGenericTol);

    // Column-major matrix with translation (50, 60, 70).
    const Part* matrix = findPart(m, "matrix cube");
    ASSERT_NE(matrix, nullptr);
    expectCubeVertices(*matrix, [](glm::dvec3 v) { return glm::dvec3(50 + v.x, -70 - v.z, 60 + v.y); });
    EXPECT_FALSE(matrix->report.flipped);

    // The open quad is a surface: glTF (x, y, -50) -> world (x, 50, y).
    const Part* fault = findPart(m, "fault F1");
    ASSERT_NE(fault, nullptr);
    EXPECT_EQ(fault->kind, PartKind::Surface);
    EXPECT_EQ(fault->mesh.triangleCount(), 2u);
    EXPECT_EQ(fault->mesh.bounds().min, glm::dvec3(0, 50, 0));
    EXPECT_EQ(fault->mesh.bounds().max, glm::dvec3(4, 50, 3));

    // Node extras become the part's record; parts without extras get a named record.
    const AttributeRecord* rec = m.attributes.find(granite->record);
    ASSERT_NE(rec, nullptr);
    EXPECT_EQ(rec->name, "granite stock");
    EXPECT_EQ(rec->lithology, "granite");
    ASSERT_TRUE(rec->density.has_value());
    EXPECT_DOUBLE_EQ(*rec->density, 2.7);
    const AttributeRecord* faultRec = m.attributes.find(fault->record);
    ASSERT_NE(faultRec, nullptr);
    EXPECT_EQ(faultRec->name, "fault F1");
    EXPECT_EQ(faultRec->kind, "surface");
    EXPECT_NE(fault->record, granite->record);

    EXPECT_FALSE(m.validation.hasErrors());
    for (const auto& b : m.bodies) {
        EXPECT_TRUE(b.report.closed) << b.name;
        EXPECT_FALSE(b.report.flipped) << b.name;
    }
}

TEST(Gltf, WithoutScenesRootNodesAreLoadedOnce) {
    Json doc = genericDoc();
    doc.erase("scene");
    doc.erase("scenes");
    auto r = parseText(doc.dump(), "noscene.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    // Node 1 is node 0's child: loaded once, with its parent's transform.
    EXPECT_EQ(r->bodies.size(), 3u);
    EXPECT_EQ(r->surfaces.size(), 1u);
    const Part* granite = findPart(r.value(), "granite stock");
    ASSERT_NE(granite, nullptr);
    expectCubeVertices(*granite, [](glm::dvec3 v) { return glm::dvec3(10 + 2 * v.z, 2 * v.x - 28, 20 + 2 * v.y); });
}

TEST(Gltf, StripsAndFansBecomeTriangles) {
    // The quad's four corners without indices, as a strip (0 1 3 2) and as a fan (0 1 2 3):
    // both must give two triangles facing the same way as the listed quad (+Z in glTF, -y in
    // world).
    for (int mode : {5, 6}) {
        std::vector<std::uint8_t> buf(48);
        const int order[2][4] = {{0, 1, 3, 2}, {0, 1, 2, 3}};
        for (int i = 0; i < 4; ++i) std::memcpy(buf.data() + 12 * i, kQuad[order[mode - 5][i]], 12);
        Json doc = singleMeshDoc(buf, "sheet", mode);
        auto r = parseText(doc.dump(), "strip.gltf");
        ASSERT_TRUE(r.ok()) << r.error().message;
        ASSERT_EQ(r->surfaces.size(), 1u) << "mode " << mode;
        const Mesh& mesh = r->surfaces[0].mesh;
        ASSERT_EQ(mesh.triangleCount(), 2u) << "mode " << mode;
        for (std::size_t t = 0; t < 2; ++t) {
            const glm::dvec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                             c = mesh.positions[mesh.indices[3 * t + 2]];
            const glm::dvec3 n = glm::cross(b - a, c - a);
            EXPECT_LT(n.y, 0.0) << "mode " << mode << " triangle " << t;
        }
        EXPECT_EQ(r->surfaces[0].report.inconsistentEdges, 0u);
    }
}

TEST(Gltf, ExternalBufferInsideTheFolderLoads) {
    const auto dir = std::filesystem::path(::testing::TempDir()) / "gltf_external_ok";
    std::filesystem::create_directories(dir / "bin");
    const auto buffer = genericBuffer();
    {
        std::ofstream f(dir / "bin" / "generic.bin", std::ios::binary);
        f.write(reinterpret_cast<const char*>(buffer.data()), static_cast<std::streamsize>(buffer.size()));
    }
    Json doc = genericDoc();
    doc["buffers"][0]["uri"] = "bin/generic.bin";
    {
        std::ofstream f(dir / "generic.gltf");
        f << doc.dump(2);
    }
    auto r = loadModel((dir / "generic.gltf").string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->bodies.size(), 3u);
    // The same bytes from memory with no folder: external files are refused.
    auto mem = parseText(doc.dump(), "memory.gltf");
    expectError(mem, "memory.gltf", {"buffer 0", "bin/generic.bin", "no folder"});
}

// ---------------------------------------------------------------------------------------
// Malformed inputs: errors, never crashes.

std::vector<std::uint8_t> smallGlb(bool draco = false) {
    SyntheticOptions o;
    o.triangles = 2000;
    auto m = generateSynthetic(o);
    EXPECT_TRUE(m.ok());
    GlbWriteOptions w;
    w.draco = draco;
    auto glb = encodeGlb(m.value(), w);
    EXPECT_TRUE(glb.ok());
    return glb.value();
}

TEST(Gltf, EmptyInputAndNotGltf) {
    expectError(parseGltf(nullptr, 0, "empty.glb"), "empty.glb", {"empty file"});
    expectError(parseText("hello, world", "hello.gltf"), "hello.gltf", {"byte 0", "not glTF", "magic"});
    expectError(parseText("  \n", "blank.gltf"), "blank.gltf", {"not glTF"});
    expectError(parseText("{\"asset\": {\"version\": \"2.0\"},\n \"nodes\": [}", "broken.gltf"), "broken.gltf",
                {"byte 41", "invalid JSON", "line 2"});
    expectError(parseText("[1, 2]", "array.gltf"), "array.gltf", {"not glTF"});
}

TEST(Gltf, GlbHeaderErrorsGiveByteOffsets) {
    const auto good = smallGlb();
    ASSERT_TRUE(parseBytes(good, "good.glb").ok());

    auto wrongMagic = good;
    wrongMagic[3] = 'X';
    expectError(parseBytes(wrongMagic, "magic.glb"), "magic.glb", {"byte 0", "magic"});

    auto v1 = good;
    putU32(v1, 4, 1);
    expectError(parseBytes(v1, "v1.glb"), "v1.glb", {"byte 4", "GLB version 1, expected 2"});

    auto jsonPastEnd = good;
    putU32(jsonPastEnd, 12, static_cast<std::uint32_t>(good.size()));
    expectError(parseBytes(jsonPastEnd, "json.glb"), "json.glb", {"byte 12", "JSON chunk length", "past the end"});

    const std::size_t binAt = 20 + getU32(good, 12);
    auto binPastEnd = good;
    putU32(binPastEnd, binAt, 0x7FFFFFF0u);
    expectError(parseBytes(binPastEnd, "bin.glb"), "bin.glb", {"byte " + std::to_string(binAt), "BIN chunk length"});

    auto notBin = good;
    putU32(notBin, binAt + 4, 0x12345678u);
    expectError(parseBytes(notBin, "chunk.glb"), "chunk.glb", {"byte " + std::to_string(binAt + 4), "not BIN"});

    auto badJson = good;
    badJson[20] = '[';  // ["asset":... fails at the colon, JSON byte 8
    expectError(parseBytes(badJson, "badjson.glb"), "badjson.glb", {"byte 28", "invalid JSON"});
}

TEST(Gltf, TruncatedGlbIsAnErrorAtEveryLength) {
    for (bool draco : {false, true}) {
        const auto good = smallGlb(draco);
        const std::size_t binAt = 20 + getU32(good, 12);
        std::vector<std::size_t> cuts = {1,
                                         3,
                                         4,
                                         12,
                                         16,
                                         19,
                                         20,
                                         21,
                                         100,
                                         binAt - 1,
                                         binAt,
                                         binAt + 4,
                                         binAt + 8,
                                         binAt + 9,
                                         good.size() / 2,
                                         good.size() - 4,
                                         good.size() - 1};
        for (std::size_t n = 23; n < good.size(); n += good.size() / 37) cuts.push_back(n);
        for (std::size_t n : cuts) {
            std::vector<std::uint8_t> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n));
            auto r = parseBytes(cut, "cut.glb");
            ASSERT_FALSE(r.ok()) << "cut at " << n << " of " << good.size() << (draco ? " (Draco)" : "");
            const std::string& msg = r.error().message;
            EXPECT_EQ(msg.rfind("cut.glb: byte ", 0), 0u) << msg;
        }
    }
}

TEST(Gltf, AccessorCountPastItsBuffer) {
    Json doc = genericDoc();
    doc["accessors"][0]["count"] = 1000000000;
    expectError(parseText(doc.dump(), "huge.gltf"), "huge.gltf",
                {"mesh \"granite stock\"", "accessor 0", "1000000000 elements", "runs past its buffer of 300 bytes"});
    // Offsets near 2^64, where an unchecked offset + length wraps to a small number.
    for (const char* field : {"bufferView", "accessor"}) {
        for (std::uint64_t offset : {18446744073709551615ull, 18446744073709551516ull, 9223372036854775808ull}) {
            doc = genericDoc();
            if (std::string(field) == "bufferView")
                doc["bufferViews"][0]["byteOffset"] = offset;
            else
                doc["accessors"][0]["byteOffset"] = offset;
            expectError(parseText(doc.dump(), "offset.gltf"), "offset.gltf", {"accessor 0", "runs past its buffer"});
        }
    }
}

TEST(Gltf, IndexOutOfRange) {
    auto buffer = genericBuffer();
    const std::uint32_t bad = 99;
    std::memcpy(buffer.data() + 96 + 4 * 7, &bad, 4);
    expectError(parseText(genericDoc(buffer).dump(), "index.gltf"), "index.gltf",
                {"mesh \"granite stock\"", "index 99 out of range (8 vertices)"});
}

TEST(Gltf, NanPositionLoadsWithAValidationError) {
    // A NaN vertex is a defect of the model, not of the file: the file loads and validation
    // reports it as an error (the part, no longer a closed shell, is classed as a surface).
    auto buffer = genericBuffer();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(buffer.data() + 12 * 6 + 4, &nan, 4);  // cube vertex 6, y
    auto r = parseText(genericDoc(buffer).dump(), "nan.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->validation.hasErrors());
    bool named = false;
    for (const auto& issue : r->validation.issues)
        if (issue.severity == ValidationIssue::Severity::Error &&
            issue.message.find("NaN or Inf") != std::string::npos) {
            named = true;
            EXPECT_FALSE(issue.part.empty());
        }
    EXPECT_TRUE(named);
    // Cube vertex 6 is NaN in all three cube instances (glTF Y is world z).
    std::size_t nanParts = 0;
    for (const Part* p : allParts(r.value())) {
        if (p->mesh.positions.size() != 8 || std::isfinite(p->mesh.positions[6].z)) continue;
        ++nanParts;
        EXPECT_EQ(p->kind, PartKind::Surface) << p->name;
        EXPECT_EQ(p->report.nonFiniteVertices, 1u) << p->name;
    }
    EXPECT_EQ(nanParts, 3u);
}

TEST(Gltf, ManyNanPositionsDoNotBreakValidation) {
    // Half of 600 vertices NaN, in every coordinate: sorting and welding must stay sane.
    const std::size_t n = 600;
    std::vector<float> pos(3 * n);
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
            pos[3 * i + static_cast<std::size_t>(a)] =
                (i + static_cast<std::size_t>(a)) % 2
                    ? std::numeric_limits<float>::quiet_NaN()
                    : static_cast<float>((i * 7 + static_cast<std::size_t>(a) * 13) % 17);
    std::vector<std::uint8_t> buf(pos.size() * 4);
    std::memcpy(buf.data(), pos.data(), buf.size());
    Json doc = singleMeshDoc(buf, "nan soup", 4);
    auto r = parseText(doc.dump(), "nansoup.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->validation.hasErrors());
}

TEST(Gltf, InstancingBeyondTheExpansionLimitIsRefused) {
    // One 10000-triangle soup (30000 vertices, 360 KB) drawn by 400 nodes: 432 MB of Mesh
    // storage from a ~0.5 MB file, past the limit of 64 times the file plus 256 MiB.
    const std::size_t n = 30000;
    std::vector<float> pos(3 * n);
    for (std::size_t i = 0; i < pos.size(); ++i) pos[i] = static_cast<float>(i % 1000);
    std::vector<std::uint8_t> buf(pos.size() * 4);
    std::memcpy(buf.data(), pos.data(), buf.size());
    Json doc = singleMeshDoc(buf, "marker", 4);
    Json roots = Json::array();
    for (int i = 0; i < 400; ++i) {
        doc["nodes"].push_back(Json{{"name", "marker " + std::to_string(i)}, {"mesh", 0}, {"translation", {i, 0, 0}}});
        roots.push_back(i + 1);
    }
    doc["scenes"][0]["nodes"] = roots;
    const std::string text = doc.dump();
    expectError(parseText(text, "instances.gltf"), "instances.gltf", {"64 times its size"});
    // Forty instances are fine.
    doc["scenes"][0]["nodes"] = Json::array();
    for (int i = 1; i <= 40; ++i) doc["scenes"][0]["nodes"].push_back(i);
    auto r = parseText(doc.dump(), "instances.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->triangleCount(), 40u * 10000u);
}

TEST(Gltf, NodeCycleAndBadReferences) {
    Json cycle = genericDoc();
    cycle["nodes"][1]["children"] = Json::array({0});  // granite stock -> frame -> granite stock
    expectError(parseText(cycle.dump(), "cycle.gltf"), "cycle.gltf", {"node 0", "cycle"});

    Json self = genericDoc();
    self["nodes"][3]["children"] = Json::array({3});
    expectError(parseText(self.dump(), "self.gltf"), "self.gltf", {"node 3", "cycle"});

    Json twoParents = genericDoc();
    twoParents["nodes"][2]["children"] = Json::array({1});  // node 1 is also frame's child
    expectError(parseText(twoParents.dump(), "parents.gltf"), "parents.gltf", {"node 1", "two parents"});

    Json badMesh = genericDoc();
    badMesh["nodes"][3]["mesh"] = 7;
    expectError(parseText(badMesh.dump(), "mesh.gltf"), "mesh.gltf", {"fault F1", "mesh 7", "does not exist"});

    Json badChild = genericDoc();
    badChild["nodes"][0]["children"] = Json::array({1, 42});
    expectError(parseText(badChild.dump(), "child.gltf"), "child.gltf", {"node 42 does not exist"});

    Json badScene = genericDoc();
    badScene["scene"] = 5;
    expectError(parseText(badScene.dump(), "scene.gltf"), "scene.gltf", {"scene 5 does not exist"});

    Json badAccessor = genericDoc();
    badAccessor["meshes"][1]["primitives"][0]["attributes"]["POSITION"] = 17;
    expectError(parseText(badAccessor.dump(), "accessor.gltf"), "accessor.gltf",
                {"fault F1", "accessor 17 does not exist"});

    Json badMode = genericDoc();
    badMode["meshes"][1]["primitives"][0]["mode"] = 9;
    expectError(parseText(badMode.dump(), "mode.gltf"), "mode.gltf", {"fault F1", "mode 9"});
}

TEST(Gltf, ExternalFilesOutsideTheFolderAreRefused) {
    const auto root = std::filesystem::path(::testing::TempDir()) / "gltf_external_bad";
    const auto dir = root / "models" / "m1";
    std::filesystem::create_directories(dir);
    const auto buffer = genericBuffer();
    {
        // A file that exists outside the model's folder, reachable with "..".
        std::ofstream f(root / "secret.bin", std::ios::binary);
        f.write(reinterpret_cast<const char*>(buffer.data()), static_cast<std::streamsize>(buffer.size()));
    }
    for (const std::string uri : {"../../etc/passwd", "../../secret.bin", "%2e%2e/%2e%2e/secret.bin", "/etc/passwd",
                                  "file:///etc/passwd", "sub/../../../secret.bin", "..\\..\\secret.bin"}) {
        Json doc = genericDoc();
        doc["buffers"][0]["uri"] = uri;
        expectError(parseText(doc.dump(), "outside.gltf", dir.string()), "outside.gltf",
                    {"buffer 0", "outside the model's folder"});
    }
    // A symbolic link inside the folder that leads out of it.
    std::error_code ec;
    std::filesystem::remove(dir / "link.bin", ec);
    std::filesystem::create_symlink(root / "secret.bin", dir / "link.bin", ec);
    if (!ec) {
        Json doc = genericDoc();
        doc["buffers"][0]["uri"] = "link.bin";
        expectError(parseText(doc.dump(), "link.gltf", dir.string()), "link.gltf", {"outside the model's folder"});
    }
}

TEST(Gltf, NoMeshes) {
    const std::string text =
        R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"name": "empty"}]})";
    expectError(parseText(text, "nomesh.gltf"), "nomesh.gltf", {"no triangle meshes"});
    // Points only: no triangles either.
    Json doc = genericDoc();
    doc["meshes"][0]["primitives"][0]["mode"] = 0;
    doc["meshes"][1]["primitives"][0]["mode"] = 1;
    expectError(parseText(doc.dump(), "points.gltf"), "points.gltf", {"no triangle meshes"});
}

TEST(Gltf, DeeplyNestedJsonIsRefused) {
    Json doc = genericDoc();
    std::string text = doc.dump();
    // {"extras": [[[[...]]]]} 100000 deep on the first node: tinygltf would recurse on it.
    const std::string nest = std::string(100000, '[') + std::string(100000, ']');
    const std::string key = "\"nodes\":[{";
    const auto at = text.find(key);
    ASSERT_NE(at, std::string::npos);
    text.insert(at + key.size(), "\"extras\":" + nest + ",");
    expectError(parseText(text, "deep.gltf"), "deep.gltf", {"nested deeper than"});
}

TEST(Gltf, MalformedDracoIsAnError) {
    const auto good = smallGlb(/*draco=*/true);
    ASSERT_TRUE(parseBytes(good, "good.glb").ok());
    const GlbParts parts = splitGlb(good);
    auto ext = [](Json& j) -> Json& {
        return j["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"];
    };

    GlbParts p = parts;
    ext(p.json)["bufferView"] = 99;
    expectError(parseBytes(joinGlb(p.json, p.bin), "view.glb"), "view.glb",
                {"KHR_draco_mesh_compression", "bufferView 99 does not exist"});

    p = parts;
    ext(p.json)["bufferView"] = -1;
    expectError(parseBytes(joinGlb(p.json, p.bin), "neg.glb"), "neg.glb", {"bufferView -1 does not exist"});

    p = parts;
    ext(p.json)["attributes"]["POSITION"] = 7;
    expectError(parseBytes(joinGlb(p.json, p.bin), "att.glb"), "att.glb", {"no Draco attribute with id 7"});

    p = parts;
    ext(p.json)["attributes"] = Json::object();
    expectError(parseBytes(joinGlb(p.json, p.bin), "noatt.glb"), "noatt.glb", {"POSITION"});

    p = parts;
    ext(p.json) = "not an object";
    expectError(parseBytes(joinGlb(p.json, p.bin), "str.glb"), "str.glb", {"KHR_draco_mesh_compression"});

    // A bufferView running past the buffer, and one holding garbage.
    p = parts;
    const int view = ext(p.json)["bufferView"].get<int>();
    p.json["bufferViews"][static_cast<std::size_t>(view)]["byteLength"] = p.bin.size() * 2;
    expectError(parseBytes(joinGlb(p.json, p.bin), "long.glb"), "long.glb", {"runs past its buffer"});

    p = parts;
    const std::size_t offset =
        p.json["bufferViews"][static_cast<std::size_t>(view)].value("byteOffset", std::size_t(0));
    for (std::size_t i = 0; i < 64; ++i) p.bin[offset + i] = static_cast<std::uint8_t>(i * 37 + 11);
    expectError(parseBytes(joinGlb(p.json, p.bin), "garbage.glb"), "garbage.glb",
                {"KHR_draco_mesh_compression", "cannot decode"});

    p = parts;
    p.json["bufferViews"][static_cast<std::size_t>(view)]["byteLength"] = 10;
    expectError(parseBytes(joinGlb(p.json, p.bin), "short.glb"), "short.glb", {"cannot decode"});

    // The indices accessor's type does not matter: Draco's faces replace it.
    p = parts;
    const int indices = p.json["meshes"][0]["primitives"][0]["indices"].get<int>();
    p.json["accessors"][static_cast<std::size_t>(indices)]["componentType"] = 5130;
    EXPECT_TRUE(parseBytes(joinGlb(p.json, p.bin), "double.glb").ok());
}

TEST(Gltf, BadImageBufferViewIsAnError) {
    Json doc = genericDoc();
    doc["images"] = Json::array({Json{{"bufferView", 0}, {"mimeType", "image/png"}}});
    EXPECT_TRUE(parseText(doc.dump(), "image.gltf").ok()) << "images are ignored, not decoded";
    doc["bufferViews"].push_back(Json{{"buffer", 0}, {"byteOffset", 1000000}, {"byteLength", 4}});
    doc["images"] = Json::array({Json{{"bufferView", 4}, {"mimeType", "image/png"}}});
    expectError(parseText(doc.dump(), "image.gltf"), "image.gltf", {"image 0", "bufferView 4"});
}

}  // namespace
}  // namespace geoslice
