#include <gtest/gtest.h>

#include "model/mesh/validate.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {
constexpr double kPi = 3.14159265358979323846;
// Cubic metres: a box's volume with small-integer corners: exact up to a few double steps.
constexpr double kBoxVolumeTolM3 = 1e-12;
// Cubic metres: a 5e5 m^3 host minus a lens, from thousands of triangles: rounding only.
constexpr double kHostVolumeTolM3 = 1e-6;
// Relative: an inscribed 96 x 48 UV sphere's volume deficit, of order (pi/n)^2: under 1 %.
constexpr double kUvSphereRelTol = 0.01;
}  // namespace

TEST(Validate, ClosedBoxIsOutwardWithExactVolume) {
    Mesh m = boxMesh({0, 0, 0}, {2, 3, 4});
    MeshReport r = analyseMesh(m, true);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.consistentlyOriented);
    EXPECT_FALSE(r.flipped);
    EXPECT_EQ(r.components, 1u);
    EXPECT_NEAR(r.signedVolume, 24.0, kBoxVolumeTolM3);  // exact in double for a box
}

TEST(Validate, InwardBoxIsFlippedAndReported) {
    Mesh m = boxMesh({0, 0, 0}, {2, 3, 4});
    reverse(m);
    EXPECT_LT(signedVolume(m), 0.0);
    MeshReport r = analyseMesh(m, true);
    EXPECT_TRUE(r.flipped);
    EXPECT_NEAR(r.signedVolume, 24.0, kBoxVolumeTolM3);
    EXPECT_GT(signedVolume(m), 0.0);  // the mesh itself was fixed
}

TEST(Validate, SplitVerticesAreWeldedByPosition) {
    Mesh m = boxMesh({0, 0, 0}, {1, 1, 1});
    Mesh split;  // every triangle with its own three vertices, as glTF with flat normals
    for (auto i : m.indices) {
        split.indices.push_back(static_cast<std::uint32_t>(split.positions.size()));
        split.positions.push_back(m.positions[i]);
    }
    MeshReport r = analyseMesh(split, true);
    EXPECT_TRUE(r.closed);
    EXPECT_EQ(r.boundaryEdges, 0u);
}

TEST(Validate, OpenAndNonManifoldAndDegenerate) {
    Mesh m = boxMesh({0, 0, 0}, {1, 1, 1});
    m.indices.resize(m.indices.size() - 3);  // remove one triangle: 3 boundary edges
    MeshReport r = analyseMesh(m, true);
    EXPECT_FALSE(r.closed);
    EXPECT_EQ(r.boundaryEdges, 3u);

    Mesh fan = boxMesh({0, 0, 0}, {1, 1, 1});
    fan.positions.push_back({0.5, -1, 0.5});
    fan.indices.insert(fan.indices.end(), {0, 1, 8});  // a third triangle on edge 0-1
    r = analyseMesh(fan, true);
    EXPECT_EQ(r.nonManifoldEdges, 1u);
    EXPECT_FALSE(r.closed);

    Mesh deg = boxMesh({0, 0, 0}, {1, 1, 1});
    deg.indices.insert(deg.indices.end(), {0, 0, 1});  // repeated index
    deg.positions.push_back({2, 0, 0});
    deg.indices.insert(deg.indices.end(), {0, 1, 8});  // collinear: zero area
    deg.indices.insert(deg.indices.end(), {0, 2, 1});  // duplicate of the first face
    r = analyseMesh(deg, false);
    EXPECT_EQ(r.degenerateTriangles, 2u);
    EXPECT_EQ(r.duplicateTriangles, 1u);
}

TEST(Validate, NonFiniteVerticesAreErrors) {
    Model model;
    Mesh m = boxMesh({0, 0, 0}, {1, 1, 1});
    m.positions[3].y = std::numeric_limits<double>::quiet_NaN();
    model.bodies.push_back(makePart("nan box", PartKind::Body, 1, m));
    ValidationReport r = validate(model);
    EXPECT_TRUE(r.hasErrors());
    EXPECT_EQ(model.bodies[0].report.nonFiniteVertices, 1u);
}

TEST(Validate, NestedLensWithoutHoleGetsDepthAndParent) {
    Model model;
    model.bodies.push_back(makePart("host", PartKind::Body, 1, boxMesh({0, 0, 0}, {100, 100, 50})));
    model.bodies.push_back(makePart("lens", PartKind::Body, 2, sphereMesh({50, 50, 25}, 10)));
    model.bodies.push_back(makePart("neighbour", PartKind::Body, 3, boxMesh({100, 0, 0}, {200, 100, 50})));
    ValidationReport r = validate(model);
    EXPECT_FALSE(r.hasErrors());
    EXPECT_EQ(model.bodies[1].report.nestingDepth, 1);
    EXPECT_EQ(model.bodies[1].report.parent, 0);
    EXPECT_EQ(model.bodies[0].report.nestingDepth, 0);
    EXPECT_EQ(model.bodies[2].report.nestingDepth, 0);  // shares a face, not nested
    EXPECT_EQ(model.bodies[2].report.parent, -1);
}

TEST(Validate, HostWithCavityIsOrientedPerShell) {
    // Host = box + reversed sphere (a cavity); the lens fills the cavity: a partition.
    Mesh host = boxMesh({0, 0, 0}, {100, 100, 50});
    Mesh cavity = sphereMesh({50, 50, 25}, 10);
    reverse(cavity);
    append(host, cavity);
    Model model;
    model.bodies.push_back(makePart("host", PartKind::Body, 1, host));
    model.bodies.push_back(makePart("lens", PartKind::Body, 2, sphereMesh({50, 50, 25}, 10)));
    ValidationReport r = validate(model);
    EXPECT_FALSE(r.hasErrors());
    EXPECT_EQ(model.bodies[0].report.components, 2u);
    EXPECT_FALSE(model.bodies[0].report.flipped);
    const double lensVolume = model.bodies[1].report.signedVolume;
    EXPECT_NEAR(model.bodies[0].report.signedVolume, 100.0 * 100 * 50 - lensVolume, kHostVolumeTolM3);
    EXPECT_EQ(model.bodies[1].report.nestingDepth, 0);  // inside the cavity, not the host

    // The same host with the cavity facing outward (a common exporter bug) is fixed.
    Mesh bad = boxMesh({0, 0, 0}, {100, 100, 50});
    append(bad, sphereMesh({50, 50, 25}, 10));
    MeshReport br = analyseMesh(bad, true);
    EXPECT_TRUE(br.flipped);
    EXPECT_NEAR(br.signedVolume, 100.0 * 100 * 50 - lensVolume, kHostVolumeTolM3);
}

TEST(Validate, SphereVolumeConvergesToAnalytic) {
    // Inscribed UV sphere: relative volume deficit ~ (pi/n)^2 scale; 1% at 96x48.
    Mesh s = sphereMesh({0, 0, 0}, 10.0, 96, 48);
    const double exact = 4.0 / 3.0 * kPi * 1000.0;
    EXPECT_NEAR(signedVolume(s) / exact, 1.0, kUvSphereRelTol);
}

TEST(Validate, PointInClosedMeshGrazingRays) {
    Mesh box = boxMesh({0, 0, 0}, {1, 1, 1});
    EXPECT_TRUE(pointInClosedMesh(box, {0.5, 0.5, 0.5}));
    EXPECT_TRUE(pointInClosedMesh(box, {0.5, 0.5, 0.999999}));
    EXPECT_FALSE(pointInClosedMesh(box, {0.5, 0.5, 1.000001}));
    // Points whose axis-aligned rays would run along faces and through edges and vertices.
    EXPECT_TRUE(pointInClosedMesh(box, {0.5, 0.5, 0.5}));
    EXPECT_FALSE(pointInClosedMesh(box, {-1, 0, 0}));
    EXPECT_FALSE(pointInClosedMesh(box, {0.5, 0.5, 2}));
    EXPECT_TRUE(pointInClosedMesh(box, {1e-6, 1e-6, 1e-6}));
}
