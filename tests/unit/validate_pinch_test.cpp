// Bodies that touch themselves along an edge or at a vertex (pinch-outs) are split into
// closed shells, physically, so that sections through the pinch give the right polygons;
// what cannot be split is an error for a declared body and a surface for an undeclared one.
#include <gtest/gtest.h>

#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "section/cut/contours.hpp"
#include "section/index/section_index.hpp"
#include "test_meshes.hpp"

// Cubic metres or square metres: exact box volumes and square areas, summed in double.
constexpr double kExactBoxTol = 1e-9;

using namespace geoslice;
using namespace geoslice::test;

namespace {

// Two unit-ish boxes welded into one mesh by position (their shared edge or corner has one
// vertex id per position), as a loader that welds would deliver them.
Mesh welded(const Mesh& a, const Mesh& b) {
    Mesh m = a;
    append(m, b);
    Mesh out;
    for (std::uint32_t i : m.indices) {
        const glm::dvec3 p = m.positions[i];
        std::uint32_t id = 0;
        while (id < out.positions.size() && out.positions[id] != p) ++id;
        if (id == out.positions.size()) out.positions.push_back(p);
        out.indices.push_back(id);
    }
    return out;
}

Model oneBody(Mesh mesh, bool declared) {
    Model m;
    Part p = makePart("pinched", PartKind::Body, 0, std::move(mesh));
    p.kindDeclared = declared;
    m.bodies.push_back(std::move(p));
    finishLoadedModel(m, /*classifyByClosure=*/true);
    return m;
}

}  // namespace

TEST(ValidatePinch, BoxesSharingAnEdgeAreTwoClosedShells) {
    for (bool inward : {false, true}) {
        Mesh m = welded(boxMesh({0, 0, 0}, {10, 10, 10}), boxMesh({10, 10, 0}, {20, 20, 10}));
        if (inward) reverse(m);
        ASSERT_EQ(m.positions.size(), 14u);  // 16 corners, 2 shared
        MeshReport r = analyseMesh(m, true);
        EXPECT_TRUE(r.closed);
        EXPECT_TRUE(r.consistentlyOriented);
        EXPECT_EQ(r.splitEdges, 1u);
        EXPECT_EQ(r.splitVertices, 2u);
        EXPECT_EQ(r.components, 2u);
        EXPECT_EQ(r.flipped, inward);
        EXPECT_NEAR(r.signedVolume, 2000.0, kExactBoxTol);  // exact box volumes, summed in double
        EXPECT_EQ(m.positions.size(), 16u);                 // the shared edge is now two edges
        // Idempotent: analysing the split mesh again (it welds by position, so it finds the
        // same pinch) leaves it as it is.
        const std::vector<std::uint32_t> indices = m.indices;
        MeshReport again = analyseMesh(m, true);
        EXPECT_TRUE(again.closed);
        EXPECT_EQ(again.components, 2u);
        EXPECT_EQ(m.positions.size(), 16u);
        EXPECT_EQ(m.indices, indices);
    }
}

TEST(ValidatePinch, BoxesSharingAnEdgeWoundDifferentlyAreTwoClosedShells) {
    // One box outward, the other inward: round the shared edge the triangles' directions run
    // B F F B, not alternating; the pairing must still give each box its own two triangles.
    for (int inwardBox : {0, 1}) {
        Mesh a = boxMesh({0, 0, 0}, {10, 10, 10}), b = boxMesh({10, 10, 0}, {20, 20, 10});
        reverse(inwardBox == 0 ? a : b);
        Mesh m = welded(a, b);
        // By closure (a loader's part of unknown kind) it is closed, hence a body.
        Mesh probe = m;
        const MeshReport judged = analyseMesh(probe, false);
        EXPECT_TRUE(judged.closed);
        EXPECT_TRUE(judged.consistentlyOriented);
        MeshReport r = analyseMesh(m, true);
        EXPECT_TRUE(r.closed);
        EXPECT_TRUE(r.consistentlyOriented);
        EXPECT_EQ(r.splitEdges, 1u);
        EXPECT_EQ(r.splitVertices, 2u);
        EXPECT_EQ(r.components, 2u);
        EXPECT_TRUE(r.flipped);
        EXPECT_NEAR(r.signedVolume, 2000.0, kExactBoxTol);
        EXPECT_EQ(m.positions.size(), 16u);
    }
}

TEST(ValidatePinch, BoxesSharingAVertexAreSplitThere) {
    Mesh m = welded(boxMesh({0, 0, 0}, {10, 10, 10}), boxMesh({10, 10, 10}, {20, 20, 20}));
    ASSERT_EQ(m.positions.size(), 15u);
    MeshReport r = analyseMesh(m, true);
    EXPECT_TRUE(r.closed);
    EXPECT_EQ(r.splitEdges, 0u);
    EXPECT_EQ(r.splitVertices, 1u);
    EXPECT_EQ(r.components, 2u);
    EXPECT_EQ(m.positions.size(), 16u);
}

TEST(ValidatePinch, DeclaredAndUndeclaredPinchedBodiesStayBodies) {
    for (bool declared : {false, true}) {
        Model m = oneBody(welded(boxMesh({0, 0, 0}, {10, 10, 10}), boxMesh({10, 10, 0}, {20, 20, 10})), declared);
        ASSERT_EQ(m.bodies.size(), 1u);
        EXPECT_TRUE(m.surfaces.empty());
        EXPECT_FALSE(m.validation.hasErrors());
        bool noted = false;
        for (const auto& i : m.validation.issues) noted = noted || i.message.find("pinch-outs") != std::string::npos;
        EXPECT_TRUE(noted);
    }
}

TEST(ValidatePinch, AFlapOnAnEdgeIsAnErrorForADeclaredBodyAndASurfaceOtherwise) {
    // A box with one extra triangle hanging off its edge (10,0,0)-(10,0,10): that edge is used
    // three times, which no pairing resolves.
    Mesh box = boxMesh({0, 0, 0}, {10, 10, 10});
    box.positions.push_back({15, -5, 5});
    const auto a = static_cast<std::uint32_t>(
        std::find(box.positions.begin(), box.positions.end(), glm::dvec3(10, 0, 0)) - box.positions.begin());
    const auto b = static_cast<std::uint32_t>(
        std::find(box.positions.begin(), box.positions.end(), glm::dvec3(10, 0, 10)) - box.positions.begin());
    box.indices.insert(box.indices.end(), {a, b, static_cast<std::uint32_t>(box.positions.size() - 1)});

    Model declared = oneBody(box, true);
    ASSERT_EQ(declared.bodies.size(), 1u);
    ASSERT_TRUE(declared.validation.hasErrors());
    std::string msg;
    for (const auto& i : declared.validation.issues)
        if (i.severity == ValidationIssue::Severity::Error) msg = i.part + ": " + i.message;
    // Names the part, the counts, and where: the flap's two open edges and the T edge.
    EXPECT_NE(msg.find("pinched: body is not a closed 2-manifold: 2 open (boundary) edges, 1 non-manifold edges, e.g. "
                       "at ("),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("(10.000, 0.000, 5.000)"), std::string::npos) << msg;

    Model undeclared = oneBody(box, false);
    EXPECT_TRUE(undeclared.bodies.empty());
    EXPECT_EQ(undeclared.surfaces.size(), 1u);
    EXPECT_FALSE(undeclared.validation.hasErrors());
}

TEST(ValidatePinch, SectionThroughAPinchEdgeGivesTwoClosedSquares) {
    Model m;
    m.bodies.push_back(makePart("pinched", PartKind::Body, 0,
                                welded(boxMesh({0, 0, 0}, {10, 10, 10}), boxMesh({10, 10, 0}, {20, 20, 10}))));
    m.bodies.push_back(makePart("host", PartKind::Body, 0, boxMesh({-5, -5, -5}, {25, 25, 15})));
    finishLoadedModel(m, false);
    ASSERT_FALSE(m.validation.hasErrors());
    EXPECT_EQ(m.bodies[0].report.parent, 1);  // the pinched pair is nested in the host
    auto index = buildSectionIndex(m);
    ASSERT_TRUE(index.ok());
    auto s = computeSection(*index.value(), horizontalPlane(5.0));
    ASSERT_TRUE(s.ok()) << s.error().message;
    const BodySection* pinched = nullptr;
    const BodySection* host = nullptr;
    for (const auto& b : s->bodies) (b.part == 0 ? pinched : host) = &b;
    ASSERT_NE(pinched, nullptr);
    ASSERT_NE(host, nullptr);
    EXPECT_EQ(pinched->openChains, 0u);
    EXPECT_EQ(pinched->polygons.size(), 2u);  // two squares touching at a corner, not a figure 8
    EXPECT_NEAR(pinched->area, 200.0, kExactBoxTol);
    EXPECT_EQ(host->openChains, 0u);
    EXPECT_NEAR(host->area, 900.0 - 200.0, kExactBoxTol);  // the squares are holes of the host
}
