#include <gtest/gtest.h>

#include <cmath>

#include "../common/tet_model.hpp"
#include "model/mesh/validate.hpp"
#include "model/mesh/volume_mesh.hpp"
#include "tests/common/tolerances.hpp"

using namespace geoslice;
using namespace geoslice::test;
using CellType = VolumeMesh::CellType;

namespace {

// Unit cube corners in VTK hexahedron order.
VolumeMesh unitHex(glm::dvec3 at = glm::dvec3(0.0)) {
    VolumeMesh m;
    const glm::dvec3 c[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (const auto& p : c) m.positions.push_back(at + p);
    m.addCell(CellType::Hexahedron, {0, 1, 2, 3, 4, 5, 6, 7}, 0);
    return m;
}

std::vector<Mesh> boundaries(const VolumeMesh& m, std::size_t regions) {
    auto r = regionBoundaries(m, regions);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : std::vector<Mesh>{};
}

std::string errorOf(const VolumeMesh& m, std::size_t regions) {
    auto r = regionBoundaries(m, regions);
    return r.ok() ? "" : r.error().message;
}

// analyseMesh without orientation fixes: the boundary must come out closed and outward.
MeshReport closedOutward(Mesh mesh) {
    MeshReport r = analyseMesh(mesh, false);
    EXPECT_TRUE(r.closed) << r.boundaryEdges << " boundary, " << r.nonManifoldEdges << " non-manifold edges";
    EXPECT_TRUE(r.consistentlyOriented) << r.inconsistentEdges << " inconsistent edges";
    EXPECT_GT(signedVolume(mesh), 0.0);
    return r;
}

}  // namespace

// Volumes below are of shapes with small-integer corners: every product is exact in
// double, so the tolerance is a few ulps of the value.
// Cubic metres: volumes of 1 (a few ulps of 1).
constexpr double kUnitVolumeTol = 1e-15;
// Cubic metres: volumes of 1-4 from cells and their shells: a few ulps of the value.
constexpr double kSmallVolumeTol = 1e-14;
// Cubic metres: a tetrahedron's shell volume about the shell's own reference point (its
// triangles' divergence terms round separately): a few hundred ulps of 4.
constexpr double kTetShellVolumeTol = 1e-12;
TEST(VolumeMesh, TetraEitherOrientationIsOutward) {
    for (bool inverted : {false, true}) {
        VolumeMesh m;
        m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {0, 0, 4}};
        if (inverted)
            m.addCell(CellType::Tetra, {0, 2, 1, 3}, 0);
        else
            m.addCell(CellType::Tetra, {0, 1, 2, 3}, 0);
        EXPECT_NEAR(cellVolume(m, 0), inverted ? -4.0 : 4.0, kSmallVolumeTol);
        auto b = boundaries(m, 1);
        ASSERT_EQ(b.size(), 1u);
        EXPECT_EQ(b[0].triangleCount(), 4u);
        closedOutward(b[0]);
        EXPECT_NEAR(signedVolume(b[0]), 4.0, kTetShellVolumeTol);
    }
}

TEST(VolumeMesh, EveryCellTypeGivesAClosedOutwardShellOfItsVolume) {
    VolumeMesh hex = unitHex();
    EXPECT_NEAR(cellVolume(hex, 0), 1.0, kUnitVolumeTol);
    auto b = boundaries(hex, 1);
    EXPECT_EQ(b[0].triangleCount(), 12u);
    closedOutward(b[0]);

    // VTK wedge: (0, 1, 2)'s right-hand normal points away from (3, 4, 5). Triangle
    // (0,0,0) (0,1,0) (1,0,0) extruded by 2 in z: volume 1.
    VolumeMesh wedge;
    wedge.positions = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 2}, {0, 1, 2}, {1, 0, 2}};
    wedge.addCell(CellType::Wedge, {0, 1, 2, 3, 4, 5}, 0);
    EXPECT_NEAR(cellVolume(wedge, 0), 1.0, kUnitVolumeTol);
    b = boundaries(wedge, 1);
    EXPECT_EQ(b[0].triangleCount(), 8u);
    closedOutward(b[0]);
    EXPECT_NEAR(signedVolume(b[0]), 1.0, kSmallVolumeTol);

    VolumeMesh pyr;  // square base 2x2, apex height 3: volume 4
    pyr.positions = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {1, 1, 3}};
    pyr.addCell(CellType::Pyramid, {0, 1, 2, 3, 4}, 0);
    EXPECT_NEAR(cellVolume(pyr, 0), 4.0, kSmallVolumeTol);
    b = boundaries(pyr, 1);
    EXPECT_EQ(b[0].triangleCount(), 6u);
    closedOutward(b[0]);
    EXPECT_NEAR(signedVolume(b[0]), 4.0, kSmallVolumeTol);
}

TEST(VolumeMesh, SharedFacesOfOneRegionAreInteriorAndOfTwoRegionsAreKeptTwice) {
    // Two unit hexes side by side along x, sharing the face x = 1.
    VolumeMesh m = unitHex();
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1},
                   {1, 1, 1}, {0, 1, 1}, {2, 0, 0}, {2, 1, 0}, {2, 0, 1}, {2, 1, 1}};
    m.addCell(CellType::Hexahedron, {1, 8, 9, 2, 5, 10, 11, 6}, 0);
    auto one = boundaries(m, 1);
    EXPECT_EQ(one[0].triangleCount(), 20u);  // 10 outer quads
    closedOutward(one[0]);
    EXPECT_NEAR(signedVolume(one[0]), 2.0, kSmallVolumeTol);

    m.cellRegions[1] = 1;
    auto two = boundaries(m, 3);
    ASSERT_EQ(two.size(), 3u);
    for (int r = 0; r < 2; ++r) {
        EXPECT_EQ(two[static_cast<std::size_t>(r)].triangleCount(), 12u);
        closedOutward(two[static_cast<std::size_t>(r)]);
        EXPECT_NEAR(signedVolume(two[static_cast<std::size_t>(r)]), 1.0, kSmallVolumeTol);
    }
    EXPECT_EQ(two[2].triangleCount(), 0u);  // a region without cells
}

TEST(VolumeMesh, HexAndTetrahedraSplitASharedQuadAlike) {
    // A hex next to a hex given as five tetrahedra would not share faces; but two hexes of
    // different regions split their shared (non-planar) quad along the same diagonal, so
    // the two boundaries coincide there exactly.
    VolumeMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.3}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1},
                   {1, 1, 1}, {0, 1, 1}, {2, 0, 0},   {2, 1, 0}, {2, 0, 1}, {2, 1, 1}};
    m.addCell(CellType::Hexahedron, {0, 1, 2, 3, 4, 5, 6, 7}, 0);
    m.addCell(CellType::Hexahedron, {1, 8, 9, 2, 5, 10, 11, 6}, 1);
    auto b = boundaries(m, 2);
    closedOutward(b[0]);
    closedOutward(b[1]);
    EXPECT_NEAR(signedVolume(b[0]) + signedVolume(b[1]), cellVolume(m, 0) + cellVolume(m, 1), kSmallVolumeTol);
}

TEST(VolumeMesh, CollapsedHexahedronIsAWedge) {
    // A hexahedron with 3 == 2 and 7 == 6 (how some exporters write wedges).
    VolumeMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
    m.addCell(CellType::Hexahedron, {0, 1, 2, 2, 3, 4, 5, 5}, 0);
    auto b = boundaries(m, 1);
    EXPECT_EQ(b[0].triangleCount(), 8u);
    closedOutward(b[0]);
    EXPECT_NEAR(signedVolume(b[0]), 1.0, kSmallVolumeTol);
}

TEST(VolumeMesh, ErrorsNameTheCell) {
    VolumeMesh m = unitHex();
    m.addCell(CellType::Tetra, {0, 1, 2, 9}, 0);
    EXPECT_NE(errorOf(m, 1).find("cell 1: vertex index 9 is out of range"), std::string::npos) << errorOf(m, 1);

    m = unitHex();
    m.addCell(CellType::Tetra, {0, 1, 2, 4}, 5);
    EXPECT_NE(errorOf(m, 1).find("cell 1: region 5 is outside [0, 1)"), std::string::npos) << errorOf(m, 1);
    m.cellRegions[1] = -1;
    EXPECT_NE(errorOf(m, 1).find("cell 1: region -1"), std::string::npos) << errorOf(m, 1);

    m = unitHex();
    m.addCell(CellType::Wedge, {0, 1, 2, 4}, 0);
    EXPECT_NE(errorOf(m, 1).find("cell 1: 4 vertices for a cell type that has 6"), std::string::npos) << errorOf(m, 1);

    m = unitHex();
    m.addCell(static_cast<CellType>(42), {0, 1, 2, 4}, 0);
    EXPECT_NE(errorOf(m, 1).find("cell 1: unknown cell type 42"), std::string::npos) << errorOf(m, 1);

    m = unitHex();
    m.positions[6].y = std::nan("");
    EXPECT_NE(errorOf(m, 1).find("cell 0: vertex 6 is not finite"), std::string::npos) << errorOf(m, 1);

    m = unitHex();
    m.cellOffsets.back() = 100;
    EXPECT_NE(errorOf(m, 1).find("cell 0: vertex offsets"), std::string::npos) << errorOf(m, 1);
    m.cellOffsets.pop_back();
    EXPECT_NE(errorOf(m, 1).find("cell offsets for 1 cells"), std::string::npos) << errorOf(m, 1);
}

TEST(VolumeMesh, TetModelBoundariesEncloseTheSummedTetrahedronVolumes) {
    // Divergence theorem: a region's outward boundary encloses exactly its cells' volume,
    // non-manifold pinch-outs or not. Tolerance 1e-9 relative: sums of ~10^3 products of
    // 100 m-scale coordinates round at ~1e-13 relative each.
    for (bool inverted : {false, true})
        for (double overlap : {0.0, 0.02}) {
            TetModelOptions o;
            o.invertOdd = inverted;
            o.overlap = overlap;
            TetModel tm = tetLayeredModel(o);
            std::vector<double> want(tm.regionCount(), 0.0);
            for (std::size_t c = 0; c < tm.mesh.cellCount(); ++c) {
                const double v = cellVolume(tm.mesh, c);
                EXPECT_EQ(v < 0, inverted && c % 6 >= 3) << "cell " << c;
                want[static_cast<std::size_t>(tm.mesh.cellRegions[c])] += std::abs(v);
            }
            auto b = boundaries(tm.mesh, tm.regionCount());
            ASSERT_EQ(b.size(), tm.regionCount());
            double total = 0.0;
            for (std::size_t r = 0; r < b.size(); ++r) {
                EXPECT_NEAR(signedVolume(b[r]), want[r], test::kShellVsCellSumRelTol * want[r]) << tm.regionNames[r];
                MeshReport rep = analyseMesh(b[r], false);
                EXPECT_EQ(rep.boundaryEdges, 0u) << tm.regionNames[r];
                total += want[r];
            }
            // The jitter moves opposite faces of the 80 x 80 x 60 m block alike: same volume.
            if (overlap == 0.0) {  // the regions tile the block: its outer boundary encloses their sum
                VolumeMesh all = tm.mesh;
                std::fill(all.cellRegions.begin(), all.cellRegions.end(), 0);
                auto whole = boundaries(all, 1);
                EXPECT_EQ(whole[0].triangleCount(), 2u * 2 * (8 * 8 + 8 * 6 + 8 * 6));
                EXPECT_NEAR(signedVolume(whole[0]), total, test::kShellVsCellSumRelTol * total);
            }
            // The lens has 3 cubes = 3 * 6 tetrahedra, 3 * 12 boundary triangles.
            EXPECT_EQ(b[3].triangleCount(), 36u);
        }
}
