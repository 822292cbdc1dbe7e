#include <gtest/gtest.h>

#include <random>

#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "section/rays/classify.hpp"
#include "test_meshes.hpp"

// Monte Carlo volume fractions: a 5-sigma band (a false failure about 6e-7 per record);
// the absolute 1e-9 keeps a zero-width band for fractions of 0 or 1.
constexpr double kSigmas = 5.0;
constexpr double kZeroFractionTol = 1e-9;

using namespace geoslice;
using namespace geoslice::test;

namespace {

std::unique_ptr<Classifier> buildFor(Model& m) {
    m.recentre();
    validate(m);
    auto c = Classifier::build(m);
    EXPECT_TRUE(c.ok());
    return std::move(c).value();
}

// The first direction the classifier casts along (kept in sync with section/rays/classify.cpp).
const glm::dvec3 kFirstDir = glm::normalize(glm::dvec3(0.5316705, 0.2876141, 0.7966510));

}  // namespace

TEST(Classify, BoxesSphereAndNestedLens) {
    Model m;
    m.bodies.push_back(makePart("host", PartKind::Body, 10, boxMesh({0, 0, 0}, {100, 100, 50})));
    m.bodies.push_back(makePart("lens", PartKind::Body, 20, sphereMesh({50, 50, 25}, 10)));
    m.bodies.push_back(makePart("east", PartKind::Body, 30, boxMesh({100, 0, 0}, {200, 100, 50})));
    auto c = buildFor(m);
    EXPECT_EQ(c->classify({50, 50, 25}), 20u);
    EXPECT_EQ(c->classify({50, 50, 34.9}), 20u);
    EXPECT_EQ(c->classify({50, 50, 35.5}), 10u);
    EXPECT_EQ(c->classify({5, 5, 5}), 10u);
    EXPECT_EQ(c->classify({150, 50, 25}), 30u);
    EXPECT_EQ(c->classify({99.99, 50, 25}), 10u);  // 1 cm from the shared face
    EXPECT_EQ(c->classify({100.01, 50, 25}), 30u);
    EXPECT_EQ(c->classify({250, 50, 25}), kNoRecord);
    EXPECT_EQ(c->classify({50, 50, 60}), kNoRecord);
    EXPECT_EQ(c->classify({std::nan(""), 0, 0}), kNoRecord);
}

TEST(Classify, RaysThroughEdgesAndVertices) {
    // Points placed so that the first ray passes exactly through a box edge or vertex:
    // the classifier must notice and re-cast.
    Model m;
    m.bodies.push_back(makePart("box", PartKind::Body, 5, boxMesh({0, 0, 0}, {10, 10, 10})));
    auto c = buildFor(m);
    const glm::dvec3 vertex(10, 10, 10), edge(10, 10, 4),
        faceDiagonal(5, 5, 10);  // the last: shared edge of two top triangles
    for (const glm::dvec3& target : {vertex, edge, faceDiagonal}) {
        for (double t : {0.5, 2.0, 4.0}) {
            glm::dvec3 inside = target - kFirstDir * t;
            bool truth =
                inside.x > 0 && inside.y > 0 && inside.z > 0 && inside.x < 10 && inside.y < 10 && inside.z < 10;
            EXPECT_EQ(c->classify(inside), truth ? 5u : kNoRecord) << inside.x << " " << inside.y << " " << inside.z;
        }
    }
}

TEST(Classify, PartitionWithCavityAndSharedFaces) {
    Mesh host = boxMesh({0, 0, 0}, {100, 100, 50});
    Mesh cavity = sphereMesh({50, 50, 25}, 10);
    reverse(cavity);
    append(host, cavity);
    Model m;
    m.bodies.push_back(makePart("host", PartKind::Body, 1, host));
    m.bodies.push_back(makePart("lens", PartKind::Body, 2, sphereMesh({50, 50, 25}, 10)));
    m.bodies.push_back(makePart("above", PartKind::Body, 3, boxMesh({0, 0, 50}, {100, 100, 80})));
    auto c = buildFor(m);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-5.0, 105.0), uz(-5.0, 85.0);
    for (int i = 0; i < 5000; ++i) {
        glm::dvec3 p(u(rng), u(rng), uz(rng));
        RecordId truth = kNoRecord;
        bool inBox = p.x > 0 && p.y > 0 && p.x < 100 && p.y < 100;
        if (inBox && p.z > 0 && p.z < 50) truth = 1;
        if (inBox && p.z > 50 && p.z < 80) truth = 3;
        if (pointInClosedMesh(m.bodies[1].mesh, p)) truth = 2;  // the faceted sphere, exactly
        ASSERT_EQ(c->classify(p), truth) << p.x << " " << p.y << " " << p.z;
    }
}

TEST(Classify, AgreesWithBruteForceOnSyntheticModel) {
    for (OreVariant ore : {OreVariant::Nested, OreVariant::Partition}) {
        SyntheticOptions o;
        o.triangles = 20000;
        o.ore = ore;
        o.crs = Crs::fromEpsg(4523).value();  // far from the origin: exercises the local frame
        auto m = generateSynthetic(o);
        ASSERT_TRUE(m.ok());
        validate(m.value());
        auto c = Classifier::build(m.value());
        ASSERT_TRUE(c.ok());
        const Aabb b = m->bounds();
        std::mt19937_64 rng(11);
        std::uniform_real_distribution<double> ux(b.min.x, b.max.x), uy(b.min.y, b.max.y), uz(b.min.z, b.max.z);
        int disagreements = 0;
        const int n = 3000;
        for (int i = 0; i < n; ++i) {
            glm::dvec3 p(ux(rng), uy(rng), uz(rng));
            // Brute force in double: the deepest containing body, the later one of equal depths.
            int truth = -1;
            for (std::size_t k = 0; k < m->bodies.size(); ++k)
                if (pointInClosedMesh(m->bodies[k].mesh, p) &&
                    (truth < 0 || m->bodies[k].report.nestingDepth >=
                                      m->bodies[static_cast<std::size_t>(truth)].report.nestingDepth))
                    truth = static_cast<int>(k);
            disagreements += (*c)->classifyBody(p) != truth;
        }
        // Exact but for points within the float tolerance (~3 mm) of a boundary: with
        // 3000 uniform points in a 6x4x2.7 km box the expected count of those is << 1.
        EXPECT_EQ(disagreements, 0);
    }
}

TEST(Classify, MonteCarloVolumesMatchDivergenceTheorem) {
    SyntheticOptions o;
    o.triangles = 20000;
    auto m = generateSynthetic(o);
    ASSERT_TRUE(m.ok());
    validate(m.value());
    auto c = Classifier::build(m.value());
    ASSERT_TRUE(c.ok());
    const Aabb b = m->bounds();
    const double boxVolume = b.size().x * b.size().y * b.size().z;
    std::map<RecordId, double> exact;
    for (const auto& p : m->bodies) exact[p.record] += p.report.signedVolume;
    exact[5] -= exact[8];  // nested: the lens volume is inside the host's shell
    const std::size_t n = 400000;
    std::vector<glm::dvec3> pts(n);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> ux(b.min.x, b.max.x), uy(b.min.y, b.max.y), uz(b.min.z, b.max.z);
    for (auto& p : pts) p = {ux(rng), uy(rng), uz(rng)};
    std::vector<RecordId> ids(n);
    (*c)->classifyBatch(pts.data(), n, ids.data());
    std::map<RecordId, std::size_t> hits;
    for (RecordId id : ids) ++hits[id];
    for (const auto& [id, v] : exact) {
        const double frac = v / boxVolume;
        const double sigma = std::sqrt(frac * (1 - frac) / double(n));
        EXPECT_NEAR(double(hits[id]) / double(n), frac, kSigmas * sigma + kZeroFractionTol) << "record " << id;
    }
}

TEST(Classify, BatchEqualsSingle) {
    Model m;
    m.bodies.push_back(makePart("a", PartKind::Body, 1, boxMesh({0, 0, 0}, {1, 1, 1})));
    auto c = buildFor(m);
    std::vector<glm::dvec3> pts;
    for (int i = 0; i < 5000; ++i) pts.push_back({i * 0.001 - 1, 0.5, 0.5});
    std::vector<RecordId> ids(pts.size());
    c->classifyBatch(pts.data(), pts.size(), ids.data(), 2);
    for (std::size_t i = 0; i < pts.size(); ++i) ASSERT_EQ(ids[i], c->classify(pts[i]));
}
