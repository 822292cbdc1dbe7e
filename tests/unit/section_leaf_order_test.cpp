// section/index/leaf_order.hpp: the model in the BVH's leaf order is the same model, cut the same way.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "section/cut/plane_cut.hpp"
#include "section/index/leaf_order.hpp"
#include "section_test_util.hpp"

// Relative: the same mesh in another triangle order: volumes and areas are the same sums
// in another order (areas over ~1e3 points; the absolute 1e-9 m^2 covers zero areas).
constexpr double kReorderedRelTol = 1e-9;
constexpr double kReorderedAbsTolM2 = 1e-9;

using namespace geoslice;
using namespace geoslice::test;

namespace {

// A part's triangles as their three positions in vertex order (orientation kept), sorted:
// equal lists = the same triangles, whatever the numbering.
std::vector<std::array<double, 9>> triangleSet(const Mesh& mesh) {
    std::vector<std::array<double, 9>> out;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        std::array<double, 9> a{};
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c)
                a[std::size_t(3 * k + c)] = mesh.positions[mesh.indices[3 * t + std::size_t(k)]][c];
        out.push_back(a);
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST(SectionLeafOrder, SameTrianglesVerticesAndValidation) {
    Model m = syntheticModel(30000);
    // A per-vertex property (x + 2y of the vertex) to check that values follow their vertices.
    Mesh& s = m.surfaces.at(0).mesh;
    s.propertyNames = {"a", "b"};
    s.propertyValues.clear();
    for (const auto& p : s.positions) {
        s.propertyValues.push_back(float(p.x + 2.0 * p.y));
        s.propertyValues.push_back(float(p.z));
    }
    Model r = m;
    ASSERT_TRUE(reorderForSection(r).ok());
    ASSERT_EQ(r.bodies.size(), m.bodies.size());
    ASSERT_EQ(r.surfaces.size(), m.surfaces.size());
    std::size_t moved = 0;
    for (const auto* list : {&m.bodies, &m.surfaces})
        for (std::size_t i = 0; i < list->size(); ++i) {
            const Mesh& a = (*list)[i].mesh;
            const Mesh& b = (list == &m.bodies ? r.bodies : r.surfaces)[i].mesh;
            ASSERT_EQ(a.vertexCount(), b.vertexCount());
            ASSERT_EQ(a.triangleCount(), b.triangleCount());
            EXPECT_EQ(triangleSet(a), triangleSet(b)) << (*list)[i].name;
            std::vector<glm::dvec3> pa = a.positions, pb = b.positions;
            auto less = [](const glm::dvec3& x, const glm::dvec3& y) {
                return std::tie(x.x, x.y, x.z) < std::tie(y.x, y.y, y.z);
            };
            std::sort(pa.begin(), pa.end(), less);
            std::sort(pb.begin(), pb.end(), less);
            EXPECT_EQ(pa, pb) << (*list)[i].name;
            moved += a.indices != b.indices;
        }
    EXPECT_GT(moved, 0u);  // the generator's order is not the leaf order
    const Mesh& rs = r.surfaces.at(0).mesh;
    ASSERT_EQ(rs.propertyValues.size(), 2 * rs.vertexCount());
    for (std::size_t v = 0; v < rs.vertexCount(); ++v) {
        EXPECT_EQ(rs.propertyValues[2 * v], float(rs.positions[v].x + 2.0 * rs.positions[v].y));
        EXPECT_EQ(rs.propertyValues[2 * v + 1], float(rs.positions[v].z));
    }
    // Validation sees the same model: closed bodies, volumes (summation order differs: 1e-9
    // relative covers the rounding of ~1e4 triangle terms).
    validate(r);
    for (std::size_t i = 0; i < m.bodies.size(); ++i) {
        const MeshReport &a = m.bodies[i].report, &b = r.bodies[i].report;
        EXPECT_EQ(a.closed, b.closed);
        EXPECT_EQ(a.boundaryEdges, b.boundaryEdges);
        EXPECT_EQ(a.components, b.components);
        EXPECT_NEAR(a.signedVolume, b.signedVolume, kReorderedRelTol * std::abs(a.signedVolume)) << m.bodies[i].name;
    }
}

TEST(SectionLeafOrder, SectionsUnchanged) {
    Model m = syntheticModel(30000);
    Model r = m;
    ASSERT_TRUE(reorderForSection(r).ok());
    validate(r);
    auto a = indexFor(m);
    auto b = indexFor(r);
    std::mt19937_64 rng(5);
    for (int k = 0; k < 20; ++k) {
        const Plane p = randomPlane(m.bounds(), rng, k);
        PlaneCut ca, cb;
        beginCut(*a, p, ca);
        cutWithBvh(*a, nullptr, ca);
        beginCut(*b, p, cb);
        cutWithBvh(*b, nullptr, cb);
        ASSERT_EQ(ca.segments, cb.segments) << "plane " << k;
        auto sa = computeSection(*a, p);
        auto sb = computeSection(*b, p);
        ASSERT_TRUE(sa.ok() && sb.ok());
        ASSERT_EQ(sa->bodies.size(), sb->bodies.size());
        for (std::size_t i = 0; i < sa->bodies.size(); ++i) {
            EXPECT_EQ(sa->bodies[i].part, sb->bodies[i].part);
            EXPECT_EQ(sa->bodies[i].polygons.size(), sb->bodies[i].polygons.size());
            EXPECT_EQ(sa->bodies[i].openChains, sb->bodies[i].openChains);
            // Same segments chained from other starting points: areas agree to rounding
            // (1e-9 relative of sums over ~1e3 points).
            EXPECT_NEAR(sa->bodies[i].area, sb->bodies[i].area,
                        kReorderedRelTol * std::abs(sa->bodies[i].area) + kReorderedAbsTolM2)
                << "plane " << k << " body " << sa->bodies[i].part;
        }
        EXPECT_EQ(sa->traces.size(), sb->traces.size());
    }
}
