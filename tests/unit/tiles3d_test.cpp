// 3D Tiles (renderer/tiles3d/tileset3d.hpp) against independent oracles:
//  - placement: every vertex of every tile, taken through the root transform to Earth-fixed
//    coordinates and back to the model's CRS by PROJ's own EPSG:4978 -> EPSG:4523 pipeline
//    (proj_create_crs_to_crs here, not geoslice's CRS code), is a vertex of the model within
//    5 mm (float32 ENU at < 3 km from the centre is good to 0.25 mm);
//  - the hierarchy: leaves hold every triangle of the model exactly once; geometric error is
//    0 at the leaves and never smaller than a child's; a tile's box holds its content and its
//    children's boxes;
//  - no cracks: for every cut of the tree (all tiles at depth d, or leaves above it) every
//    closed body's triangles still close: each edge is used by an even number of triangles
//    (the mod-2 boundary is empty; 2 at full detail, where the model is manifold; quadric
//    simplification may fold a thin slab so that four meet at an edge, which is no crack);
//  - content: a glTF 2.0 GLB read by the parser below (not geoslice's): a primitive per part
//    with POSITION, NORMAL (unit length) and _FEATURE_ID_0 (the row of the part's record),
//    a material in the record's colour (sRGB -> linear), the property table with a colour.
#include <gtest/gtest.h>
#include <proj.h>

#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "model/synthetic/synthetic.hpp"
#include "renderer/tiles3d/tileset3d.hpp"

using namespace geoslice;
using json = nlohmann::json;

namespace {

struct Glb {
    json doc;
    std::vector<std::uint8_t> bin;
    template <class T>
    std::vector<T> accessor(std::size_t index, int components) const {
        const json& a = doc["accessors"][index];
        const json& v = doc["bufferViews"][a["bufferView"].get<std::size_t>()];
        const std::size_t offset = v.value("byteOffset", std::size_t(0)) + a.value("byteOffset", std::size_t(0));
        const std::size_t n = a["count"].get<std::size_t>() * std::size_t(components);
        std::vector<T> out(n);
        EXPECT_LE(offset + n * sizeof(T), bin.size());
        std::memcpy(out.data(), bin.data() + offset, n * sizeof(T));
        return out;
    }
};

Glb parseGlb(const std::vector<std::uint8_t>& b) {
    auto u32 = [&](std::size_t at) {
        std::uint32_t x;
        std::memcpy(&x, b.data() + at, 4);
        return x;
    };
    Glb g;
    EXPECT_GE(b.size(), 20u);
    EXPECT_EQ(u32(0), 0x46546C67u);  // "glTF"
    EXPECT_EQ(u32(4), 2u);
    EXPECT_EQ(u32(8), b.size());
    const std::uint32_t jsonLen = u32(12);
    EXPECT_EQ(u32(16), 0x4E4F534Au);
    g.doc = json::parse(b.begin() + 20, b.begin() + 20 + jsonLen);
    const std::size_t binAt = 20 + jsonLen;
    if (binAt + 8 <= b.size()) {
        EXPECT_EQ(u32(binAt + 4), 0x004E4942u);
        g.bin.assign(b.begin() + std::ptrdiff_t(binAt + 8), b.begin() + std::ptrdiff_t(binAt + 8 + u32(binAt)));
    }
    return g;
}

Model synthetic(std::size_t triangles) {
    SyntheticOptions o;
    o.triangles = triangles;
    o.crs = Crs::fromEpsg(4523).value();
    auto m = generateSynthetic(o);
    EXPECT_TRUE(m) << m.error().message;
    return std::move(m.value());
}

std::shared_ptr<const Tileset3d> build(const Model& model, const Tiles3dOptions& options = {}) {
    const api::Wgs84Choice w = api::chooseWgs84Transform(model.crs, model.bounds());
    EXPECT_TRUE(w.lonLat) << w.lonLatNote;
    auto ts = Tileset3d::build(
        model, [&](const glm::dvec3& p) { return w.lonLat->apply(p); }, options);
    EXPECT_TRUE(ts) << ts.error().message;
    return ts.value();
}

}  // namespace

TEST(Tiles3d, EveryTileVertexIsAModelVertexWherePROJPutsIt) {
    const Model model = synthetic(20000);
    Tiles3dOptions o;
    o.trianglesPerTile = 2048;  // a tree several levels deep
    auto ts = build(model, o);
    ASSERT_GT(ts->tileCount(), 8u);
    // Model vertices by 1 cm key.
    std::map<std::array<long long, 3>, std::vector<glm::dvec3>> grid;
    auto key = [](const glm::dvec3& p) {
        return std::array<long long, 3>{(long long)std::floor(p.x * 100), (long long)std::floor(p.y * 100),
                                        (long long)std::floor(p.z * 100)};
    };
    for (const auto* list : {&model.bodies, &model.surfaces})
        for (const Part& part : *list)
            for (const glm::dvec3& p : part.mesh.positions) grid[key(p)].push_back(p);
    PJ_CONTEXT* ctx = proj_context_create();
    proj_context_set_enable_network(ctx, 0);
    PJ* raw = proj_create_crs_to_crs(ctx, "EPSG:4978", "EPSG:4523", nullptr);
    ASSERT_NE(raw, nullptr);
    PJ* toGk = proj_normalize_for_visualization(ctx, raw);  // easting, northing
    proj_destroy(raw);
    const glm::dmat4 m = ts->enuToEcef();
    std::size_t checked = 0;
    double worst = 0.0;
    for (std::size_t n = 0; n < ts->tileCount(); ++n) {
        auto bytes = ts->tileGlb(n);
        ASSERT_TRUE(bytes) << bytes.error().message;
        const Glb g = parseGlb(bytes.value());
        for (const json& mesh : g.doc["meshes"]) {
            const auto pos = g.accessor<float>(mesh["primitives"][0]["attributes"]["POSITION"], 3);
            for (std::size_t i = 0; i < pos.size(); i += 3 * 7) {               // every 7th vertex
                const glm::dvec3 enu(pos[i], -double(pos[i + 2]), pos[i + 1]);  // glTF y-up -> ENU
                const glm::dvec4 ecef = m * glm::dvec4(enu, 1.0);
                PJ_COORD c = proj_coord(ecef.x, ecef.y, ecef.z, 0);
                c = proj_trans(toGk, PJ_FWD, c);
                const glm::dvec3 w(c.xyz.x, c.xyz.y, c.xyz.z);
                double best = 1e9;
                const auto k = key(w);
                for (long long dx = -1; dx <= 1; ++dx)
                    for (long long dy = -1; dy <= 1; ++dy)
                        for (long long dz = -1; dz <= 1; ++dz) {
                            auto it = grid.find({k[0] + dx, k[1] + dy, k[2] + dz});
                            if (it == grid.end()) continue;
                            for (const glm::dvec3& p : it->second) best = std::min(best, glm::length(p - w));
                        }
                ASSERT_LT(best, 0.005) << "tile " << n << " vertex " << i / 3 << " at " << w.x << " " << w.y << " "
                                       << w.z << " is " << best << " m from every model vertex";
                worst = std::max(worst, best);
                ++checked;
            }
        }
    }
    proj_destroy(toGk);
    proj_context_destroy(ctx);
    EXPECT_GT(checked, 1000u);
    RecordProperty("worst_mm", std::to_string(worst * 1000));
}

TEST(Tiles3d, HierarchyHoldsEveryTriangleOnceAndErrorsGrowUpTheTree) {
    const Model model = synthetic(30000);
    Tiles3dOptions o;
    o.trianglesPerTile = 1024;
    auto ts = build(model, o);
    const auto& tiles = ts->tiles();
    std::size_t leafTriangles = 0;
    for (const auto& t : tiles) {
        if (t.children.empty()) {
            EXPECT_EQ(t.geometricError, 0.0) << "a leaf draws full detail";
            for (const auto& p : t.pieces) leafTriangles += p.count / 3;
        }
        for (std::uint32_t c : t.children) {
            EXPECT_GE(t.geometricError, tiles[c].geometricError);
            EXPECT_GT(t.geometricError, 0.0) << "a tile with children draws something coarser";
            EXPECT_TRUE(glm::all(glm::lessThanEqual(t.boxMin, tiles[c].boxMin)));
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(t.boxMax, tiles[c].boxMax)));
        }
    }
    EXPECT_EQ(leafTriangles, model.triangleCount());
    EXPECT_GT(tiles[0].children.size(), 0u);
    // The root draws fewer triangles than the model: levels of detail took some away.
    std::size_t rootTriangles = 0;
    for (const auto& p : tiles[0].pieces) rootTriangles += p.count / 3;
    EXPECT_LT(rootTriangles, model.triangleCount() / 2);
}

TEST(Tiles3d, EveryCutOfTheTreeKeepsClosedBodiesClosed) {
    const Model model = synthetic(30000);
    Tiles3dOptions o;
    o.trianglesPerTile = 1024;
    auto ts = build(model, o);
    const auto& tiles = ts->tiles();
    int depthMax = 0;
    std::function<void(std::uint32_t, int)> depthOf = [&](std::uint32_t n, int d) {
        depthMax = std::max(depthMax, d);
        for (std::uint32_t c : tiles[n].children) depthOf(c, d + 1);
    };
    depthOf(0, 0);
    ASSERT_GE(depthMax, 2);
    for (int cut = 0; cut <= depthMax; ++cut) {
        std::vector<std::uint32_t> shown;
        std::function<void(std::uint32_t, int)> collect = [&](std::uint32_t n, int d) {
            if (d == cut || tiles[n].children.empty()) return shown.push_back(n);
            for (std::uint32_t c : tiles[n].children) collect(c, d + 1);
        };
        collect(0, 0);
        std::map<std::uint32_t, std::map<std::pair<std::uint32_t, std::uint32_t>, int>> edges;  // per body part
        for (std::uint32_t n : shown)
            for (const auto& p : tiles[n].pieces) {
                if (ts->partKind(p.part) != PartKind::Body) continue;
                for (std::size_t i = 0; i + 2 < p.count; i += 3)
                    for (int k = 0; k < 3; ++k) {
                        std::uint32_t a = p.indices[i + std::size_t(k)], b = p.indices[i + std::size_t((k + 1) % 3)];
                        if (a > b) std::swap(a, b);
                        ++edges[p.part][{a, b}];
                    }
            }
        ASSERT_FALSE(edges.empty());
        for (const auto& [part, es] : edges)
            for (const auto& [e, count] : es)
                ASSERT_EQ(count % 2, 0) << "cut at depth " << cut << ": body part " << part << " edge " << e.first
                                        << "-" << e.second << " is used " << count << " times (a crack)";
    }
}

TEST(Tiles3d, TilesCarryNormalsColoursAndFeatureMetadata) {
    const Model model = synthetic(8000);
    auto ts = build(model);
    auto bytes = ts->tileGlb(0);
    ASSERT_TRUE(bytes);
    const Glb g = parseGlb(bytes.value());
    EXPECT_EQ(g.doc["asset"]["version"], "2.0");
    const json& meta = g.doc["extensions"]["EXT_structural_metadata"];
    const json& props = meta["schema"]["classes"]["geology"]["properties"];
    for (const char* p : {"id", "name", "kind", "lithology", "age", "colour", "density"})
        EXPECT_TRUE(props.contains(p)) << p;
    // Rows: ids ascending.
    const json& table = meta["propertyTables"][0];
    const auto ids = [&] {
        const json& v = g.doc["bufferViews"][table["properties"]["id"]["values"].get<std::size_t>()];
        std::vector<std::uint32_t> out(table["count"].get<std::size_t>());
        std::memcpy(out.data(), g.bin.data() + v["byteOffset"].get<std::size_t>(), out.size() * 4);
        return out;
    }();
    ASSERT_FALSE(ids.empty());
    std::size_t primitives = 0;
    for (const json& node : g.doc["nodes"]) {
        if (!node.contains("mesh")) continue;
        const json& prim = g.doc["meshes"][node["mesh"].get<std::size_t>()]["primitives"][0];
        const RecordId record = node["extras"]["geoslice"]["record"];
        const auto nrm = g.accessor<float>(prim["attributes"]["NORMAL"], 3);
        for (std::size_t i = 0; i < nrm.size(); i += 3)
            ASSERT_NEAR(std::sqrt(nrm[i] * nrm[i] + nrm[i + 1] * nrm[i + 1] + nrm[i + 2] * nrm[i + 2]), 1.0, 1e-5);
        const auto fid = g.accessor<float>(prim["attributes"]["_FEATURE_ID_0"], 1);
        ASSERT_FALSE(fid.empty());
        for (float f : fid) ASSERT_EQ(ids.at(std::size_t(f)), record) << "feature id -> the part's record";
        const json& fx = prim["extensions"]["EXT_mesh_features"]["featureIds"][0];
        EXPECT_EQ(fx["attribute"], 0);
        EXPECT_EQ(fx["propertyTable"], 0);
        const AttributeRecord* rec = model.attributes.find(record);
        ASSERT_NE(rec, nullptr);
        const json& colour =
            g.doc["materials"][prim["material"].get<std::size_t>()]["pbrMetallicRoughness"]["baseColorFactor"];
        const auto lin = [](int c) {
            const double v = c / 255.0;
            return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
        };
        EXPECT_NEAR(colour[0].get<double>(), lin(rec->colour.r), 1e-6);
        EXPECT_NEAR(colour[1].get<double>(), lin(rec->colour.g), 1e-6);
        EXPECT_NEAR(colour[2].get<double>(), lin(rec->colour.b), 1e-6);
        ++primitives;
    }
    EXPECT_GT(primitives, 2u);
    EXPECT_EQ(ts->tileGlb(ts->tileCount()).error().code, ErrorCode::OutOfRange);
    const json tileset = json::parse(ts->tilesetJson("tiles/", "test").dump());
    EXPECT_EQ(tileset["asset"]["version"], "1.1");
    EXPECT_EQ(tileset["root"]["transform"].size(), 16u);
    EXPECT_EQ(tileset["root"]["content"]["uri"], "tiles/0.glb");
}

TEST(Tiles3d, AVertexOffTheGlobeIsNamed) {
    const Model model = synthetic(4000);
    std::size_t calls = 0;
    auto ts = Tileset3d::build(model, [&](const glm::dvec3& p) -> Result<glm::dvec3> {
        if (++calls == 10) return glm::dvec3(std::nan(""), 0.0, 0.0);
        return glm::dvec3(105.0 + (p.x - 500000.0) * 1e-5, 30.6 + p.y * 1e-7, p.z);
    });
    ASSERT_FALSE(ts);
    EXPECT_NE(ts.error().message.find("vertex"), std::string::npos) << ts.error().message;
    Model empty;
    EXPECT_EQ(Tileset3d::build(empty, [](const glm::dvec3& p) -> Result<glm::dvec3> { return p; }).error().code,
              ErrorCode::InvalidArgument);
}
