#include <gtest/gtest.h>

#include <map>
#include <set>

#include "model/io/gltf/gltf_io.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "tests/common/synthetic_model.hpp"

using namespace geoslice;

namespace {

// Relative: the generator meets its triangle target within 5 % (model/synthetic/synthetic.hpp).
constexpr double kTriangleTargetRelTol = 0.05;
// Degrees: the model's centre is placed exactly at the requested lon/lat; 1e-9 deg ~ 0.1 mm.
constexpr double kPlacedCentreDeg = 1e-9;
// Metres: the origin is the bounds' centre rounded to whole metres (model/model.hpp).
constexpr double kOriginRoundingM = 1.0;
// Metres: positions through float32 in the local frame (|local| <= ~3.1 km): half an ulp is
// 1.2e-4 m per axis; 5e-4 m allows for the sums.
constexpr double kFloat32LocalM = 5e-4;

// What the generator produced, before validation could fix anything.
Model generate(std::size_t triangles, OreVariant ore = OreVariant::Nested, std::uint64_t seed = 1) {
    return test::syntheticModel(triangles, ore, seed, nullptr, /*validated=*/false);
}

}  // namespace

TEST(Synthetic, NamedSizesWithinFivePercent) {
    for (const char* name : {"L1", "L2", "L3", "L4"}) {
        const double target = double(*namedModelSize(name));
        SyntheticOptions o;
        o.triangles = static_cast<std::size_t>(target);
        auto m = generateSynthetic(o);
        ASSERT_TRUE(m.ok());
        EXPECT_NEAR(double(m->triangleCount()), target, kTriangleTargetRelTol * target) << name;
    }
    for (std::size_t n : {2000u, 5000u, 20000u, 100000u}) {
        Model m = generate(n);
        EXPECT_NEAR(double(m.triangleCount()), double(n), kTriangleTargetRelTol * double(n)) << n;
    }
}

TEST(Synthetic, RejectsSizesOutsideRange) {
    SyntheticOptions o;
    o.triangles = 10;
    auto m = generateSynthetic(o);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().message.find("--triangles 10"), std::string::npos);
}

TEST(Synthetic, GeologyIsComplete) {
    Model m = generate(50000);
    std::set<std::string> kinds;
    std::size_t strata = 0;
    for (const auto& [id, r] : m.attributes.records()) {
        kinds.insert(r.kind);
        if (r.kind == "stratum") {
            ++strata;
            EXPECT_FALSE(r.lithology.empty());
            EXPECT_FALSE(r.age.empty());
            EXPECT_TRUE(r.density.has_value());
        }
    }
    EXPECT_GE(strata, 6u);
    EXPECT_TRUE(kinds.count("orebody"));
    EXPECT_EQ(m.surfaces.size(), 2u);  // two faults
    const AttributeRecord* ore = m.attributes.findByName("Xujiahe silica sandstone orebody");
    ASSERT_NE(ore, nullptr);
    EXPECT_TRUE(ore->grade.has_value());
    EXPECT_EQ(ore->gradeUnit, "% SiO2");

    // Terrain relief: the top stratum's highest and lowest top differ by hundreds of metres.
    const Aabb b = m.bounds();
    double lowestTop = 1e30;
    for (const auto& p : m.bodies)
        if (p.record == 7)
            for (const auto& v : p.mesh.positions)
                if (v.z > 1000) lowestTop = std::min(lowestTop, v.z);
    EXPECT_GT(b.max.z - lowestTop, 200.0);

    // Fault throw: the top of the Xujiahe Formation at the same map point differs across
    // F1 by more than 100 m (graben thrown down 150 m, minus fold and thickness change).
    auto topNear = [&](const std::string& name, double x, double y) {
        double best = 1e30, z = 0;
        for (const auto& p : m.bodies)
            if (p.name == name)
                for (const auto& v : p.mesh.positions) {
                    double d = std::hypot(v.x - x, v.y - y);
                    if (d < best - 1e-9 || (std::abs(d - best) < 1e-9 && v.z > z)) best = d, z = v.z;
                }
        return z;
    };
    const double west = topNear("Jialingjiang Formation (west block)", 1700, 2000);
    const double graben = topNear("Jialingjiang Formation (graben)", 2300, 2000);
    EXPECT_GT(west - graben, 60.0);
}

TEST(Synthetic, EveryBodyWatertightAndOutward) {
    for (OreVariant ore : {OreVariant::Nested, OreVariant::Partition}) {
        Model m = generate(30000, ore);
        ValidationReport r = validate(m);
        for (const auto& i : r.issues)
            EXPECT_NE(i.severity, ValidationIssue::Severity::Error) << i.part << ": " << i.message;
        for (const auto& p : m.bodies) {
            EXPECT_TRUE(p.report.closed) << p.name;
            EXPECT_TRUE(p.report.consistentlyOriented) << p.name;
            EXPECT_FALSE(p.report.flipped) << p.name << " was generated inward";
            EXPECT_GT(p.report.signedVolume, 0.0) << p.name;
            EXPECT_EQ(p.report.degenerateTriangles, 0u) << p.name;
        }
        const Part& lens = m.bodies.back();
        ASSERT_EQ(lens.record, 8u);
        if (ore == OreVariant::Nested) {
            EXPECT_EQ(lens.report.nestingDepth, 1);
            ASSERT_GE(lens.report.parent, 0);
            EXPECT_EQ(m.bodies[static_cast<std::size_t>(lens.report.parent)].name, "Xujiahe Formation (west block)");
        } else {
            EXPECT_EQ(lens.report.nestingDepth, 0);
            const Part& host = m.bodies[4];
            EXPECT_EQ(host.name, "Xujiahe Formation (west block)");
            EXPECT_EQ(host.report.components, 2u);
        }
    }
}

TEST(Synthetic, DeterministicPerSeed) {
    auto a = encodeGlb(generate(5000, OreVariant::Nested, 7));
    auto b = encodeGlb(generate(5000, OreVariant::Nested, 7));
    auto c = encodeGlb(generate(5000, OreVariant::Nested, 8));
    ASSERT_TRUE(a.ok() && b.ok() && c.ok());
    EXPECT_EQ(a.value(), b.value());
    EXPECT_NE(a.value(), c.value());
}

TEST(Synthetic, PlacedAtGaussKrugerCoordinates) {
    SyntheticOptions o;
    o.triangles = 5000;
    o.crs = Crs::fromEpsg(4523).value();  // CGCS2000 3-degree GK zone 35, CM 105 E
    o.atLonLat = glm::dvec2(105.2, 30.5);
    auto m = generateSynthetic(o);
    ASSERT_TRUE(m.ok());
    const Aabb b = m->bounds();
    auto centre = m->crs.toLonLat(b.centre().x, b.centre().y);
    ASSERT_TRUE(centre.ok());
    // The param centre is placed exactly at the requested point; 1e-9 deg ~ 0.1 mm.
    EXPECT_NEAR(centre->x, 105.2, kPlacedCentreDeg);
    EXPECT_NEAR(centre->y, 30.5, kPlacedCentreDeg);
    EXPECT_GT(b.min.x, 35'000'000.0);  // zone number in the false easting
    EXPECT_LT(glm::length(m->origin - glm::round(b.centre())), kOriginRoundingM);

    o.crs = Crs();
    EXPECT_FALSE(generateSynthetic(o).ok());  // --at without a projected CRS
}

TEST(Synthetic, RoundTripsThroughGlb) {
    SyntheticOptions o;
    o.triangles = 20000;
    o.crs = Crs::fromEpsg(4523).value();
    auto m = generateSynthetic(o);
    ASSERT_TRUE(m.ok());
    m->notes["provenance"] = "geoslice generate, seed 1";  // model notes travel in scene extras
    auto bytes = encodeGlb(m.value());
    ASSERT_TRUE(bytes.ok());
    auto back = parseGltf(bytes->data(), bytes->size(), "synthetic.glb");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->triangleCount(), m->triangleCount());
    EXPECT_EQ(back->bodies.size(), m->bodies.size());
    EXPECT_EQ(back->surfaces.size(), m->surfaces.size());
    EXPECT_EQ(back->crs.epsg(), 4523);
    EXPECT_EQ(back->notes, m->notes);
    EXPECT_EQ(back->attributes.toJson(), m->attributes.toJson());
    EXPECT_FALSE(back->validation.hasErrors());
    // Positions go through float32 in the local frame: |local| <= ~3.1 km, so the error is
    // at most half an ulp there, 1.2e-4 m per axis; 5e-4 m allows for the sums.
    for (std::size_t i = 0; i < m->bodies.size(); ++i) {
        const auto& p = m->bodies[i].mesh.positions;
        const auto& q = back->bodies[i].mesh.positions;
        ASSERT_EQ(p.size(), q.size());
        for (std::size_t k = 0; k < p.size(); k += 7)
            ASSERT_LT(glm::length(p[k] - q[k]), kFloat32LocalM) << m->bodies[i].name;
    }
}
