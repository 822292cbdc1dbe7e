// Block models (issue 15 items 1-3): the CSV and Voxet readers, cell ∩ plane polygons, exact
// cell ∩ body volumes and grade-tonnage tables against analytic cases, and a coloured
// section whose image, ID/cell buffers and pixel query agree at every pixel and with an
// independent oracle (point in box over every cell + point in tetrahedron for the body).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "../common/tet_model.hpp"
#include "api/catalog.hpp"
#include "api/pixel_query.hpp"
#include "api/plan.hpp"
#include "api/reserves.hpp"
#include "api/view.hpp"
#include "model/blocks/block_model.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/volume_mesh.hpp"
#include "section/blocks/block_reserves.hpp"
#include "section/blocks/block_section.hpp"
#include "section/cut/polyline.hpp"
#include "section/volumes/reserves.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

// Tolerances of this file (the comments at each check say more).
// Square metres: areas of polygons and pieces from clipped coordinates of 10-100 m: rounding.
constexpr double kAreaTolM2 = 1e-9;
// Relative: the same area or kept volume two ways (pieces summed, a closed shell, the mesh
// cut by the plane): rounding only.
constexpr double kSameQuantityRelTol = 1e-9;
// Cubic metres: one cell's exact volume (up to 1000 m^3) from sums of ~10 products of 10 m
// numbers, or from its pieces and the fan's cancelling overlaps: rounding.
constexpr double kCellVolumeTolM3 = 1e-9;
// Cubic metres: a whole grid's or orebody's volume (~1e5 m^3) summed from hundreds of cells.
constexpr double kGridTotalTolM3 = 1e-7;
// Cubic metres: the box orebody's volume from its cells: rounding of ~1e5 m^3.
constexpr double kOreVolumeTolM3 = 1e-9;
// Relative: a sphere's cells against the mesh's own volume: rounding of ~1e4 terms.
constexpr double kSphereCellsRelTol = 1e-12;
// Relative (absolute for mean grades under 2 g/t): grade-tonnage rows from sums of a few
// hundred exact cell volumes: rounding.
constexpr double kGradeTonnageRelTol = 1e-12;
// Relative: metal sums products of cell volume, density and grade over a few hundred cells.
constexpr double kMetalRelTol = 1e-9;
// Cubic metres: the closed-form box x half-space oracle checks itself: cancellation of eight
// cubes of ~80 m distances.
constexpr double kClosedFormTolM3 = 1e-8;
// Relative: a sphere cut obliquely, its cells against the kept mesh volume: rounding of ~1e4
// terms and of the fan's overlaps.
constexpr double kSphereKeptRelTol = 1e-11;
// A plane's d after normalisation: a few double steps.
constexpr double kNormalisedPlaneTol = 1e-12;
// Relative (absolute for mean grades): kept-side grade-tonnage rows: per-cell errors of 1e-9 m^3
// over ~1e4 m^3.
constexpr double kKeptGradeTonnageRelTol = 1e-10;

// A CSV of an nx x ny x nz grid of `cell`-metre cells from `lo` (cell corner), grade = f(centre).
template <class F>
std::string gridCsv(glm::dvec3 lo, double cell, int nx, int ny, int nz, F grade, bool density = false) {
    std::string s = std::string("x,y,z,dx,dy,dz,grade [g/t Au]") + (density ? ",density\n" : "\n");
    char buf[256];
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const glm::dvec3 c = lo + cell * glm::dvec3(i + 0.5, j + 0.5, k + 0.5);
                std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", c.x, c.y, c.z, cell, cell,
                              cell, grade(c));
                s += buf;
                if (density) {
                    std::snprintf(buf, sizeof buf, ",%.17g", 2.5 + 0.001 * c.z);
                    s += buf;
                }
                s += '\n';
            }
    return s;
}

double overlap1(double a0, double a1, double b0, double b1) {
    return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
}

}  // namespace

TEST(BlockModel, CsvGridUnitsAndErrors) {
    auto b = blockModelFromCsv("Z;X;y;dz;dx;dy;grade [g/t Au];density\n5;5;5;10;10;10;1.5;2.7\n5;25;15;10;10;10;;2.6\n",
                               "b.csv");
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_EQ(b->dims[0], 3u);
    EXPECT_EQ(b->dims[1], 2u);
    EXPECT_EQ(b->dims[2], 1u);
    EXPECT_EQ(b->origin, glm::dvec3(0, 0, 0));
    ASSERT_EQ(b->properties.size(), 2u);
    EXPECT_EQ(b->properties[0].name, "grade");
    EXPECT_EQ(b->properties[0].unit, "g/t Au");
    EXPECT_EQ(b->properties[0].values[0], 1.5);
    EXPECT_TRUE(std::isnan(b->properties[0].values[b->linear(2, 1, 0)]));  // empty field: no value
    EXPECT_TRUE(std::isnan(b->properties[0].values[b->linear(1, 0, 0)]));  // no row: no value
    EXPECT_EQ(b->properties[1].values[b->linear(2, 1, 0)], 2.6);
    // Half-open cells: x = 10 belongs to cell 1, x = 0 to cell 0, x = 30 is outside.
    EXPECT_EQ(b->cellAt({10, 0, 0}), b->linear(1, 0, 0));
    EXPECT_EQ(b->cellAt({0, 0, 0}), b->linear(0, 0, 0));
    EXPECT_EQ(b->cellAt({30, 0, 0}), BlockModel::kNoCell);
    auto err = [](const char* text) { return blockModelFromCsv(text, "b.csv").error().message; };
    EXPECT_NE(err("x,y,z,dx,dy,g\n1,2,3,4,5,6\n").find("dz"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz\n").find("value column"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n5,5,5,10,10,10,1\n10,5,5,10,10,10,1\n").find("b.csv:3"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n5,5,5,10,10,10,1\n15,5,5,5,10,10,1\n").find("size differs"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n5,5,5,10,10,10,1\n5,5,5,10,10,10,2\n").find("second row"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n5,5,5,10,10,10,x\n").find("not a finite number"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g,G\n").find("appears twice"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n0,0,0,1,1,1,1\n1e7,1e7,1e7,1,1,1,1\n").find("over the limit"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n").find("no blocks"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n1e7,0,0,1e-6,1,1,1\n").find("resolution"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n1e9,0,0,1,1,1,1\n").find("beyond"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,\"g\n1").find("unterminated quote"), std::string::npos);
}

// SGrid block models are tested in sgrid_blocks_test.cpp; here: properties on points are
// refused (a curvilinear block model's values belong to its hexahedra).
TEST(BlockModel, SGridPointPropertiesAreRefusedSayingWhy) {
    Grid g;
    g.name = "curved";
    g.type = "SGrid";
    g.dims[0] = g.dims[1] = g.dims[2] = 2;
    for (int c = 0; c < 8; ++c)
        g.points.push_back({double(c & 1), double((c >> 1) & 1) + 0.1 * (c & 1), double(c >> 2)});
    g.properties.push_back({"grade", "g/t", std::nullopt, std::vector<float>(8, 1.0f)});
    auto b = blockModelFromGrid(g);
    ASSERT_FALSE(b.ok());
    EXPECT_EQ(b.error().code, ErrorCode::Unsupported);
    EXPECT_NE(b.error().message.find("SGrid 'curved'"), std::string::npos) << b.error().message;
    EXPECT_NE(b.error().message.find("PROP_ALIGNMENT CELLS"), std::string::npos) << b.error().message;
}

TEST(BlockModel, VoxetPointSamplesBecomeCellCentres) {
    Grid g;
    g.type = "Voxet";
    g.name = "v";
    g.dims[0] = 2;
    g.dims[1] = 3;
    g.dims[2] = 1;
    g.origin = {100, 200, 300};
    g.step[0] = {0, 4, 0};  // rotated: u along +y, v along -x
    g.step[1] = {-2, 0, 0};
    g.step[2] = {0, 0, 5};
    g.properties.push_back({"grade", "%", std::nullopt, {0, 1, 2, 3, 4, 5}});
    auto b = blockModelFromGrid(g);
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_EQ(b->size[0], 4.0);
    EXPECT_EQ(b->size[1], 2.0);
    // Sample (1, 2, 0) is at origin + step0 + 2 step1 = (96, 204, 300): cell 1 + 2*2 = 5.
    EXPECT_EQ(b->cellAt({96, 204, 300}), 5u);
    EXPECT_EQ(b->properties[0].values[b->cellAt({96.5, 205.9, 302})], 5.0);
    g.step[1] = {-2, 1, 0};
    EXPECT_NE(blockModelFromGrid(g).error().message.find("not orthogonal"), std::string::npos);
    g.type = "SGrid";  // an SGrid with no points
    EXPECT_FALSE(blockModelFromGrid(g).ok());
}

TEST(BlockModel, CellPolygonsOfAHorizontalAndAnObliquePlane) {
    auto b = blockModelFromCsv(gridCsv({0, 0, 0}, 10.0, 3, 3, 3, [](glm::dvec3) { return 1.0; }), "g.csv");
    ASSERT_TRUE(b.ok());
    auto flat = cellPolygons(b.value(), makeSectionFrame(horizontalPlane(15.0), {0, 0, 0}));
    ASSERT_TRUE(flat.ok());
    ASSERT_EQ(flat->size(), 9u);
    for (const CellPolygon& c : flat.value()) {
        EXPECT_NEAR(ringArea(c.ring), 100.0, kAreaTolM2);  // exact squares; 1e-9 m² = rounding of 10 m coordinates
        EXPECT_EQ(b->ijk(c.cell)[2], 1u);
    }
    // Oblique: the polygons tile the plane's section of the grid box, whose area is that of
    // the same plane through one 30 m cell (the whole box), and each lies in its cell.
    auto p = makePlane(0.3, -0.5, 0.81, -12.0);
    ASSERT_TRUE(p.ok());
    const SectionFrame frame = makeSectionFrame(p.value(), {0, 0, 0});
    auto cells = cellPolygons(b.value(), frame);
    auto whole = cellPolygons(blockModelFromCsv("x,y,z,dx,dy,dz,g\n15,15,15,30,30,30,1\n", "w.csv").value(), frame);
    ASSERT_TRUE(cells.ok() && whole.ok());
    ASSERT_EQ(whole->size(), 1u);
    double sum = 0.0;
    for (const CellPolygon& c : cells.value()) {
        sum += ringArea(c.ring);
        glm::dvec2 mean(0.0);
        for (const auto& q : c.ring) mean += q;
        EXPECT_EQ(b->cellAt(frame.toWorld(mean / double(c.ring.size()))), c.cell);
    }
    EXPECT_NEAR(sum, ringArea(whole->front().ring), kSameQuantityRelTol * sum);  // rounding only
}

// A plane lying on a grid plane (a cut through the lattice's middle) at a Gauss-Kruger
// easting, either normal: its polygons tile the grid's 30 x 30 m section, as off the grid
// planes. (The plane's offset carries ~1e-8 m of rounding there: the column walk once found
// the crossing in one cell and the corners' signs in the other, and gave no polygon.)
TEST(BlockModel, CellPolygonsOfAPlaneOnAGridPlane) {
    const glm::dvec3 o(35500000.0, 3380000.0, 100.0);
    auto b = blockModelFromCsv(gridCsv(o, 10.0, 3, 3, 3, [](glm::dvec3) { return 1.0; }), "g.csv");
    ASSERT_TRUE(b.ok());
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {1.0, -1.0})
            for (double at : {10.0, 20.0}) {
                glm::dvec3 n(0.0);
                n[axis] = sign;
                auto p = makePlane(n.x, n.y, n.z, -sign * (o[axis] + at));
                ASSERT_TRUE(p.ok());
                auto cells = cellPolygons(b.value(), makeSectionFrame(p.value(), o));
                ASSERT_TRUE(cells.ok());
                double sum = 0.0;
                const SectionFrame frame = makeSectionFrame(p.value(), o);
                for (const CellPolygon& c : cells.value()) {
                    sum += ringArea(c.ring);
                    // The face between two layers goes to the cell cellAt names there (the
                    // layer above along the axis: floor), at its centre and at its corners'
                    // midpoints, as the images and the pixel query see it.
                    glm::dvec2 centre(0.0);
                    for (const glm::dvec2& q : c.ring) centre += q;
                    centre /= double(c.ring.size());
                    EXPECT_EQ(c.cell, b->cellAt(frame.toWorld(centre))) << "axis " << axis << " at " << at;
                    for (const glm::dvec2& q : c.ring)
                        EXPECT_EQ(c.cell, b->cellAt(frame.toWorld(0.5 * (q + centre))))
                            << "axis " << axis << " sign " << sign << " at " << at;
                    std::array<std::size_t, 3> expect = b->ijk(c.cell);
                    EXPECT_EQ(expect[std::size_t(axis)], std::size_t(at / 10.0)) << "axis " << axis << " at " << at;
                }
                // 900 m² of 10 m squares; 1e-6 m² = the offset's rounding x the 30 m side x a few
                EXPECT_NEAR(sum, 900.0, 1e-6) << "axis " << axis << " sign " << sign << " at " << at;
            }
}

TEST(BlockModel, ExactCellVolumesOfBoxesAndASphere) {
    // A 10 x 8 x 6 grid of 10 m cells from (-20, -10, -5).
    auto b = blockModelFromCsv(gridCsv({-20, -10, -5}, 10.0, 10, 8, 6, [](glm::dvec3) { return 1.0; }), "g.csv");
    ASSERT_TRUE(b.ok());
    struct Box {
        glm::dvec3 lo, hi;
    };
    // Off the grid planes; faces on grid planes; a face on the grid's own boundary.
    for (const Box& box : {Box{{-3.7, 1.3, 2.2}, {47.9, 33.3, 41.1}}, Box{{0, 10, 5}, {30, 40, 35}},
                           Box{{-20, -10, -5}, {-5, 5, 12.5}}}) {
        const Mesh mesh = boxMesh(box.lo, box.hi);
        const auto cells = cellBodyVolumes(b.value(), mesh);
        double total = 0.0;
        std::size_t checked = 0;
        for (std::size_t c = 0; c < b->cellCount(); ++c) {
            const auto ijk = b->ijk(c);
            const glm::dvec3 lo = b->origin + 10.0 * glm::dvec3(ijk[0], ijk[1], ijk[2]);
            const double expect = overlap1(lo.x, lo.x + 10, box.lo.x, box.hi.x) *
                                  overlap1(lo.y, lo.y + 10, box.lo.y, box.hi.y) *
                                  overlap1(lo.z, lo.z + 10, box.lo.z, box.hi.z);
            double got = 0.0;
            for (const CellVolume& cv : cells)
                if (cv.cell == c) got = cv.volume;
            // 1e-9 m³ of a 1000 m³ cell: rounding of sums of ~10 products of 10 m numbers.
            EXPECT_NEAR(got, expect, kCellVolumeTolM3) << "cell " << ijk[0] << "," << ijk[1] << "," << ijk[2];
            total += got;
            ++checked;
        }
        EXPECT_EQ(checked, b->cellCount());
        EXPECT_NEAR(total, meshVolume(mesh), kGridTotalTolM3);
    }
    // A sphere (1152 triangles, vertices anywhere): the cells' volumes sum to the mesh's own
    // volume (section/volumes/reserves.hpp), relative 1e-12 (rounding of about 10^4 terms).
    const Mesh sphere = sphereMesh({22.2, 17.7, 23.3}, 21.5);
    double sum = 0.0;
    for (const CellVolume& cv : cellBodyVolumes(b.value(), sphere)) {
        EXPECT_GT(cv.volume, -1e-9);
        EXPECT_LT(cv.volume, 1000.0 + 1e-9);
        sum += cv.volume;
    }
    EXPECT_NEAR(sum, meshVolume(sphere), kSphereCellsRelTol * meshVolume(sphere));
}

TEST(BlockModel, GradeTonnageOfABoxOrebodyWithALinearGrade) {
    // Orebody [3.3, 71.7] x [5.5, 44.5] x [12.1, 47.9] in a host box; grade = 0.02 x (cell
    // centre x) g/t; density 2.8 t/m³ from the orebody's record. Expected figures from the
    // analytic cell ∩ box overlaps (products of interval lengths).
    const glm::dvec3 oreLo{3.3, 5.5, 12.1}, oreHi{71.7, 44.5, 47.9};
    Model m = modelOf({makePart("host", PartKind::Body, 1, boxMesh({-50, -50, -50}, {150, 150, 150})),
                       makePart("ore", PartKind::Body, 2, boxMesh(oreLo, oreHi))});
    AttributeRecord host{}, ore{};
    host.id = 1;
    host.name = "host";
    ore.id = 2;
    ore.name = "ore";
    ore.density = 2.8;
    m.attributes.put(host);
    m.attributes.put(ore);
    auto grade = [](glm::dvec3 c) { return 0.02 * c.x; };
    auto blocks = blockModelFromCsv(gridCsv({0, 0, 0}, 8.0, 10, 7, 7, grade), "ore.csv");
    ASSERT_TRUE(blocks.ok());
    blocks->clipBodies = {"ore"};
    ASSERT_TRUE(resolveBlockClip(m, blocks.value()).ok());
    m.blocks = std::make_shared<const BlockModel>(std::move(blocks.value()));
    const std::vector<double> cutoffs{0.0, 0.5, 1.0};
    auto table = computeGradeTonnage(m, "grade", cutoffs);
    ASSERT_TRUE(table.ok()) << table.error().message;
    ASSERT_EQ(table->bodies.size(), 1u);
    const BodyGradeTonnage& bt = table->bodies[0];
    EXPECT_EQ(bt.densitySource, "record");
    const BlockModel& bm = *m.blocks;
    for (std::size_t c = 0; c < cutoffs.size(); ++c) {
        double vol = 0.0, metal = 0.0;
        for (std::size_t cell = 0; cell < bm.cellCount(); ++cell) {
            const auto ijk = bm.ijk(cell);
            const glm::dvec3 lo = 8.0 * glm::dvec3(ijk[0], ijk[1], ijk[2]);
            const double g = grade(lo + 4.0);
            if (!(g >= cutoffs[c])) continue;
            const double v = overlap1(lo.x, lo.x + 8, oreLo.x, oreHi.x) * overlap1(lo.y, lo.y + 8, oreLo.y, oreHi.y) *
                             overlap1(lo.z, lo.z + 8, oreLo.z, oreHi.z);
            vol += v;
            metal += v * 2.8 * g;
        }
        const GradeTonnageRow& row = bt.rows[c];
        // Relative 1e-12: rounding of sums of a few hundred cell volumes.
        EXPECT_NEAR(row.volume, vol, kGradeTonnageRelTol * vol);
        ASSERT_TRUE(row.tonnage && row.meanGrade && row.metal);
        EXPECT_NEAR(*row.tonnage, 2.8 * vol, kGradeTonnageRelTol * 2.8 * vol);
        EXPECT_NEAR(*row.meanGrade, metal / (2.8 * vol), kGradeTonnageRelTol);
        EXPECT_NEAR(*row.metal, metal, kMetalRelTol * metal);  // g/t x t = g
        EXPECT_EQ(row.metalUnit, "g");
    }
    // Cut-off 0: the whole orebody inside the grid ([0, 80] x [0, 56] x [0, 56] holds it).
    EXPECT_NEAR(bt.rows[0].volume, (oreHi - oreLo).x * (oreHi - oreLo).y * (oreHi - oreLo).z, kOreVolumeTolM3);
    // The host, clipped too, is net of the orebody nested in it.
    m.blocks = nullptr;
    auto b2 = blockModelFromCsv(gridCsv({0, 0, 0}, 8.0, 10, 7, 7, grade), "ore.csv").value();
    ASSERT_TRUE(resolveBlockClip(m, b2).ok());
    m.blocks = std::make_shared<const BlockModel>(std::move(b2));
    auto both = computeGradeTonnage(m, "grade", {0.0});
    ASSERT_TRUE(both.ok());
    ASSERT_EQ(both->bodies.size(), 2u);
    EXPECT_NEAR(both->bodies[0].volume + both->bodies[1].volume, 80.0 * 56 * 56, kGridTotalTolM3);
    EXPECT_FALSE(both->bodies[0].rows[0].tonnage);  // the host has no density
    // JSON and CSV layouts.
    const auto j = api::gradeTonnageJson(m, both.value());
    EXPECT_EQ(j["bodies"][1]["body"], "ore");
    const std::string csv = api::gradeTonnageCsv(m, both.value());
    EXPECT_EQ(csv.substr(0, csv.find('\n')),
              "body,record,cutoff,cells,volume_m3,tonnage_t,mean_grade,grade_unit,metal,metal_unit");
    EXPECT_NE(computeGradeTonnage(m, "gold", {1.0}).error().message.find("properties: grade"), std::string::npos);
    EXPECT_FALSE(computeGradeTonnage(m, "grade", {1.0, 0.5}).ok());
}

namespace {

// Closed form of |[lo, hi] ∩ {n . p + d >= 0}| (n with no zero component): the third mixed
// derivative of max(0, n . p + d)^3 / (6 n_x n_y n_z) is the half-space's indicator, so the
// box's volume is the inclusion-exclusion sum of that function over its 8 corners.
// Computed relative to lo (the numbers stay near the box's size).
double boxHalfSpace(glm::dvec3 lo, glm::dvec3 hi, glm::dvec3 n, double d) {
    const glm::dvec3 e = hi - lo;
    if (!(e.x > 0 && e.y > 0 && e.z > 0)) return 0.0;
    const double d0 = glm::dot(n, lo) + d;
    double v = 0.0;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner{(c & 1) ? e.x : 0.0, (c & 2) ? e.y : 0.0, (c & 4) ? e.z : 0.0};
        const int lower = !(c & 1) + !(c & 2) + !(c & 4);
        const double s = std::max(0.0, glm::dot(n, corner) + d0);
        v += (lower % 2 ? -1.0 : 1.0) * s * s * s;
    }
    return v / (6.0 * n.x * n.y * n.z);
}

}  // namespace

TEST(BlockModel, KeptSideOfAPlaneCellVolumesAreExact) {
    // 10 x 7 x 7 cells of 8 m from the origin; a box orebody off the grid planes.
    auto b = blockModelFromCsv(gridCsv({0, 0, 0}, 8.0, 10, 7, 7, [](glm::dvec3) { return 1.0; }), "g.csv");
    ASSERT_TRUE(b.ok());
    const glm::dvec3 lo{3.3, 5.5, 12.1}, hi{71.7, 44.5, 47.9};
    const Mesh ore = boxMesh(lo, hi);
    // The closed-form oracle checks itself: planes just missing the box keep all or nothing
    // (1e-8 m³: cancellation of eight cubes of ~80 m distances).
    const glm::dvec3 n0 = glm::normalize(glm::dvec3(1, 2, 3));
    EXPECT_NEAR(boxHalfSpace(lo, hi, n0, -glm::dot(n0, lo) + 0.5), meshVolume(ore), kClosedFormTolM3);
    EXPECT_NEAR(boxHalfSpace(lo, hi, n0, -glm::dot(n0, hi) - 0.5), 0.0, kClosedFormTolM3);
    for (const glm::dvec3 dir : {glm::dvec3(0.6, -0.5, 0.62), glm::dvec3(-0.31, 0.8, -0.2), glm::dvec3(1, 1, 1)}) {
        const glm::dvec3 n = glm::normalize(dir);
        const double d = -glm::dot(n, glm::dvec3(40.2, 25.1, 29.7));
        const Plane plane{n, d};
        // The closed shell's own volume is the kept volume section/volumes/reserves.hpp finds.
        const Mesh shell = keptSideShell(ore, plane);
        EXPECT_NEAR(meshVolume(shell), meshVolume(ore, &plane), kSameQuantityRelTol * meshVolume(ore));
        EXPECT_NEAR(meshVolume(shell), boxHalfSpace(lo, hi, n, d), kSameQuantityRelTol * meshVolume(ore));
        const auto cells = cellBodyVolumes(b.value(), ore, plane);
        std::size_t c = 0, nonzero = 0;
        for (std::size_t cell = 0; cell < b->cellCount(); ++cell) {
            const auto ijk = b->ijk(cell);
            const glm::dvec3 clo = 8.0 * glm::dvec3(ijk[0], ijk[1], ijk[2]);
            const double expect = boxHalfSpace(glm::max(clo, lo), glm::min(clo + 8.0, hi), n, d);
            double got = 0.0;
            while (c < cells.size() && cells[c].cell < cell) ++c;
            if (c < cells.size() && cells[c].cell == cell) got = cells[c].volume;
            // 1e-9 m³ of a 512 m³ cell: rounding of the pieces' sums and the fan's cancelling
            // overlaps (the closed form itself is good to ~1e-12 m³ at this size).
            EXPECT_NEAR(got, expect, kCellVolumeTolM3) << "cell " << ijk[0] << "," << ijk[1] << "," << ijk[2];
            nonzero += expect > kCellVolumeTolM3;
        }
        EXPECT_GT(nonzero, 50u);
    }
    // A plane on a grid plane (x = 40) and its opposite: cells split exactly at the plane,
    // and the two sides add up to the whole body in every cell.
    const auto whole = cellBodyVolumes(b.value(), ore);
    const auto east = cellBodyVolumes(b.value(), ore, Plane{{1, 0, 0}, -40.0});
    const auto west = cellBodyVolumes(b.value(), ore, Plane{{-1, 0, 0}, 40.0});
    for (const CellVolume& cv : east) EXPECT_GE(b->ijk(cv.cell)[0], 5u);
    for (const CellVolume& cv : west) EXPECT_LE(b->ijk(cv.cell)[0], 4u);
    EXPECT_EQ(east.size() + west.size(), whole.size());
    double sum = 0.0, all = 0.0;
    for (const auto* v : {&east, &west})
        for (const CellVolume& cv : *v) sum += cv.volume;
    for (const CellVolume& cv : whole) all += cv.volume;
    EXPECT_NEAR(sum, all, kSameQuantityRelTol * all);
    EXPECT_NEAR(sum, meshVolume(ore), kSameQuantityRelTol * all);
    // A sphere (vertices anywhere) cut obliquely: the cells sum to the kept mesh volume.
    const Mesh sphere = sphereMesh({41.2, 27.7, 28.3}, 21.5);
    const Plane cut{glm::normalize(glm::dvec3(0.3, -0.7, 0.4)), 0.0};
    const Plane p2{cut.normal, -glm::dot(cut.normal, glm::dvec3(44.0, 25.0, 30.0))};
    double ssum = 0.0;
    for (const CellVolume& cv : cellBodyVolumes(b.value(), sphere, p2)) {
        EXPECT_GT(cv.volume, -1e-9);
        EXPECT_LT(cv.volume, 512.0 + 1e-9);
        ssum += cv.volume;
    }
    // Relative 1e-11: rounding of ~10^4 terms and of the fan's overlaps.
    EXPECT_NEAR(ssum, meshVolume(sphere, &p2), kSphereKeptRelTol * meshVolume(sphere));
    EXPECT_TRUE(keptSideShell(sphere, Plane{{0, 0, 1}, -1e4}).indices.empty());
}

TEST(BlockModel, GradeTonnageOnTheKeptSideOfAPlane) {
    // The box orebody of the test above in a host box; grade = 0.02 x (cell centre x) g/t,
    // density 2.8 t/m³ (record); an oblique plane through the orebody. Expected: per cell,
    // the closed-form volume of cell ∩ orebody ∩ half-space; tonnage, mean grade, metal.
    const glm::dvec3 oreLo{3.3, 5.5, 12.1}, oreHi{71.7, 44.5, 47.9};
    Model m = modelOf({makePart("host", PartKind::Body, 1, boxMesh({-50, -50, -50}, {150, 150, 150})),
                       makePart("ore", PartKind::Body, 2, boxMesh(oreLo, oreHi))});
    AttributeRecord host{}, ore{};
    host.id = 1;
    host.name = "host";
    ore.id = 2;
    ore.name = "ore";
    ore.density = 2.8;
    m.attributes.put(host);
    m.attributes.put(ore);
    auto grade = [](glm::dvec3 c) { return 0.02 * c.x; };
    auto blocks = blockModelFromCsv(gridCsv({0, 0, 0}, 8.0, 10, 7, 7, grade), "ore.csv");
    ASSERT_TRUE(blocks.ok());
    ASSERT_TRUE(resolveBlockClip(m, blocks.value()).ok());  // both bodies: the host is net
    m.blocks = std::make_shared<const BlockModel>(std::move(blocks.value()));
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.6, -0.5, 0.62));
    const double d = -glm::dot(n, glm::dvec3(40.2, 25.1, 29.7));
    const std::vector<double> cutoffs{0.0, 0.5, 1.0};
    // Not unit on input: normalised, the kept side unchanged.
    auto table = computeGradeTonnage(m, "grade", cutoffs, Plane{3.0 * n, 3.0 * d});
    ASSERT_TRUE(table.ok()) << table.error().message;
    ASSERT_TRUE(table->plane);
    EXPECT_NEAR(table->plane->d, d, kNormalisedPlaneTol);
    ASSERT_EQ(table->bodies.size(), 2u);
    const BlockModel& bm = *m.blocks;
    double oreKept = 0.0;
    for (std::size_t c = 0; c < cutoffs.size(); ++c) {
        double vol = 0.0, metal = 0.0;
        std::size_t cells = 0;
        for (std::size_t cell = 0; cell < bm.cellCount(); ++cell) {
            const auto ijk = bm.ijk(cell);
            const glm::dvec3 lo = 8.0 * glm::dvec3(ijk[0], ijk[1], ijk[2]);
            const double g = grade(lo + 4.0);
            if (!(g >= cutoffs[c])) continue;
            const double v = boxHalfSpace(glm::max(lo, oreLo), glm::min(lo + 8.0, oreHi), n, d);
            vol += v;
            metal += v * 2.8 * g;
            cells += v > kCellVolumeTolM3 * 512;
        }
        if (c == 0) oreKept = vol;
        const GradeTonnageRow& row = table->bodies[1].rows[c];
        // Relative 1e-10: per-cell errors of 1e-9 m³ (above) over ~10^4 m³.
        EXPECT_NEAR(row.volume, vol, kKeptGradeTonnageRelTol * vol);
        EXPECT_EQ(row.cells, cells);
        ASSERT_TRUE(row.tonnage && row.meanGrade && row.metal);
        EXPECT_NEAR(*row.tonnage, 2.8 * vol, kKeptGradeTonnageRelTol * 2.8 * vol);
        EXPECT_NEAR(*row.meanGrade, metal / (2.8 * vol), kKeptGradeTonnageRelTol);
        EXPECT_NEAR(*row.metal, metal, kKeptGradeTonnageRelTol * metal);
    }
    EXPECT_NEAR(oreKept, meshVolume(m.bodies[1].mesh, &*table->plane), kSameQuantityRelTol * oreKept);
    // The host (net of the orebody) plus the orebody: the grid's part on the kept side, the
    // grid [0, 80] x [0, 56]^2 lying inside the host.
    const double gridKept = boxHalfSpace({0, 0, 0}, {80, 56, 56}, n, d);
    EXPECT_NEAR(table->bodies[0].volume + table->bodies[1].volume, gridKept, kKeptGradeTonnageRelTol * gridKept);
    EXPECT_NEAR(table->bodies[1].volume, oreKept, kKeptGradeTonnageRelTol * oreKept);
    // The same request through the HTTP parameters: accepted now, the plane in the JSON.
    auto rr = api::parseReservesRequest(api::Params{{"plane", "0.6,-0.5,0.62,3"}, {"cutoffs", "0,1"}}, false);
    ASSERT_TRUE(rr.ok()) << rr.error().message;
    EXPECT_TRUE(rr->plane && rr->cutoffs);
    EXPECT_EQ(api::gradeTonnageJson(m, table.value())["plane"].size(), 4u);
    EXPECT_FALSE(computeGradeTonnage(m, "grade", cutoffs, Plane{{0, 0, 0}, 1.0}).ok());
}

namespace {

Model tetModel(const TetModel& tm) {
    auto b = regionBoundaries(tm.mesh, tm.regionCount());
    EXPECT_TRUE(b.ok());
    Model m;
    m.name = "tet";
    for (std::size_t r = 0; r < tm.regionCount(); ++r) {
        Part p;
        p.name = tm.regionNames[r];
        p.kind = PartKind::Body;
        p.kindDeclared = true;
        p.mesh = std::move(b.value()[r]);
        m.bodies.push_back(std::move(p));
    }
    finishLoadedModel(m, /*classifyByClosure=*/true);
    return m;
}

}  // namespace

TEST(BlockModel, ColouredSectionQueryAndOracleAgree) {
    TetModelOptions to;
    to.nx = 8;
    to.ny = 8;
    to.nz = 6;
    const TetModel tm = tetLayeredModel(to);
    Model m = tetModel(tm);
    // 7 m cells (no relation to the tetrahedra), grade = i + 10 j + 100 k at the centre,
    // clipped by the sandstone and the lens.
    auto blocks = blockModelFromCsv(gridCsv({-4.5, -3.5, -2.5}, 7.0, 13, 13, 10,
                                            [](glm::dvec3 c) {
                                                return std::floor((c.x + 4.5) / 7) + 10 * std::floor((c.y + 3.5) / 7) +
                                                       100 * std::floor((c.z + 2.5) / 7);
                                            }),
                                    "tet.csv");
    ASSERT_TRUE(blocks.ok());
    blocks->clipBodies = {"sandstone", "lens"};
    ASSERT_TRUE(resolveBlockClip(m, blocks.value()).ok());
    m.blocks = std::make_shared<const BlockModel>(std::move(blocks.value()));
    auto cm = api::catalogModelOf("tet", m, "v1");
    ASSERT_TRUE(cm.ok()) << cm.error().message;
    const api::CatalogModel& model = *cm.value();
    const BlockModel& bm = *model.model.blocks;
    for (const char* plane : {"0.3,0.8,0.2,-40", "0,0,1,-30"}) {
        auto plan = api::parseViewPlan(
            {{"plane", plane}, {"colour", "grade"}, {"breaks", "100,200,300"}, {"size", "240x180"}}, "tet", m.crs);
        ASSERT_TRUE(plan.ok()) << plan.error().message;
        auto image = api::renderProfile(model, plan.value());
        ASSERT_TRUE(image.ok()) << image.error().message;
        const api::ViewImage& v = image.value();
        ASSERT_EQ(v.cells.size(), v.ids.size());
        auto classes = api::blockClasses(model, plan->section);
        ASSERT_TRUE(classes.ok() && classes.value());
        std::size_t coloured = 0, recordsAgree = 0, pixels = 0;
        for (int j = 0; j < v.height; ++j)
            for (int i = 0; i < v.width; ++i) {
                const std::size_t p = std::size_t(j) * std::size_t(v.width) + std::size_t(i);
                // The query from the cached buffers answers the image's cell...
                auto cached = api::answerPixel(model, plan.value(), i, j, &v);
                ASSERT_TRUE(cached.ok());
                EXPECT_EQ(cached->record, v.ids[p]);
                const std::size_t cell = v.cells[p] == 0 ? BlockModel::kNoCell : v.cells[p] - 1;
                ASSERT_EQ(cached->cell, cell);
                // ... and so does a fresh query (the exact classifier), wherever its record is the image's.
                auto fresh = api::answerPixel(model, plan.value(), i, j, nullptr);
                ASSERT_TRUE(fresh.ok());
                ++pixels;
                if (fresh->record == v.ids[p]) {
                    ++recordsAgree;
                    ASSERT_EQ(fresh->cell, cell) << i << "," << j;
                }
                // The colour is the class colour of the cell's value.
                if (cell != BlockModel::kNoCell) {
                    ++coloured;
                    const Rgba8 c = classes.value()->colourOf(bm.properties[0].values[cell]);
                    ASSERT_EQ(v.rgba[4 * p], c.r);
                    ASSERT_EQ(v.rgba[4 * p + 1], c.g);
                    ASSERT_EQ(v.rgba[4 * p + 2], c.b);
                }
            }
        EXPECT_GT(coloured, pixels / 10);
        // The classifier and the ID buffer may differ within the stated tolerance band of a
        // boundary (tet_oracle_test); here they agree at >= 99.9 % of pixels.
        EXPECT_GE(double(recordsAgree), 0.999 * double(pixels));

        // 1000 random pixels against the oracle: point in tetrahedron for the record, point in
        // box over every cell (no grid arithmetic) for the cell.
        std::mt19937 rng(7);
        std::uniform_int_distribution<int> di(0, v.width - 1), dj(0, v.height - 1);
        std::size_t agree = 0, inClip = 0;
        for (int n = 0; n < 1000; ++n) {
            const int i = di(rng), j = dj(rng);
            const std::size_t p = std::size_t(j) * std::size_t(v.width) + std::size_t(i);
            const glm::dvec3 w = v.mapping->worldAt(i, j);
            RecordId oracle = kNoRecord;
            int best = -1;
            for (std::size_t c = 0; c < tm.mesh.cellCount(); ++c) {
                const std::uint32_t* t = tm.mesh.cellVertices.data() + tm.mesh.cellOffsets[c];
                const auto& P = tm.mesh.positions;
                if (!pointInTet(w, P[t[0]], P[t[1]], P[t[2]], P[t[3]])) continue;
                const int r = tm.mesh.cellRegions[c];
                auto depth = [&](int b) { return m.bodies[std::size_t(b)].report.nestingDepth; };
                if (best < 0 || depth(r) > depth(best) || (depth(r) == depth(best) && r > best)) best = r;
            }
            if (best >= 0) oracle = m.bodies[std::size_t(best)].record;
            if (oracle != v.ids[p]) continue;  // the boundary band (see above)
            ++agree;
            const bool clip = oracle == m.bodies[1].record || oracle == m.bodies[3].record;
            std::size_t boxCell = BlockModel::kNoCell;
            if (clip) {
                ++inClip;
                for (std::size_t c = 0; c < bm.cellCount(); ++c) {
                    const auto ijk = bm.ijk(c);
                    const glm::dvec3 lo = bm.origin + 7.0 * glm::dvec3(ijk[0], ijk[1], ijk[2]);
                    if (w.x >= lo.x && w.x < lo.x + 7 && w.y >= lo.y && w.y < lo.y + 7 && w.z >= lo.z && w.z < lo.z + 7)
                        boxCell = c;
                }
            }
            const std::size_t cell = v.cells[p] == 0 ? BlockModel::kNoCell : v.cells[p] - 1;
            ASSERT_EQ(cell, boxCell) << "pixel " << i << "," << j;
            // The query without the image (the exact classifier) answers the oracle's cell too.
            auto q = api::answerPixel(model, plan.value(), i, j, nullptr);
            ASSERT_TRUE(q.ok());
            if (q->record == oracle) {
                ASSERT_EQ(q->cell, boxCell) << "pixel " << i << "," << j;
            }
        }
        EXPECT_GE(agree, 995u);
        EXPECT_GT(inClip, 100u);
    }
}

TEST(BlockModel, ColourParametersAndVectorPieces) {
    Model m = modelOf({makePart("host", PartKind::Body, 1, boxMesh({0, 0, 0}, {100, 100, 100})),
                       makePart("ore", PartKind::Body, 2, boxMesh({20.5, 20.5, 20.5}, {70.5, 60.5, 50.5}))});
    auto blocks = blockModelFromCsv(gridCsv({0, 0, 0}, 10.0, 10, 10, 10, [](glm::dvec3 c) { return c.x / 10; }), "b");
    ASSERT_TRUE(blocks.ok());
    blocks->clipBodies = {"ore"};
    ASSERT_TRUE(resolveBlockClip(m, blocks.value()).ok());
    m.blocks = std::make_shared<const BlockModel>(std::move(blocks.value()));
    auto cm = api::catalogModelOf("box", m, "v1");
    ASSERT_TRUE(cm.ok());
    auto plan = api::parseViewPlan({{"elevation", "35"}, {"colour", "grade"}, {"breaks", "3,5"}}, "box", m.crs);
    ASSERT_TRUE(plan.ok());
    EXPECT_NE(plan->canonical().find("&colour=grade&ramp=viridis&breaks=3,5"), std::string::npos);
    // GeoJSON: the pieces of the orebody's cells tile its section (50 x 40 m) exactly.
    auto geo = api::renderVector(*cm.value(), plan.value(), api::VectorFormat::GeoJson, VectorFrame::Plane);
    ASSERT_TRUE(geo.ok()) << geo.error().message;
    const auto doc = nlohmann::json::parse(geo.value());
    double area = 0.0;
    std::size_t pieces = 0;
    for (const auto& f : doc["features"])
        if (f["properties"]["kind"] == "block") {
            area += f["properties"]["area_m2"].get<double>();
            ++pieces;
        }
    EXPECT_EQ(pieces, 6u * 5u);  // x in 20.5..70.5 meets 6 cells, y in 20.5..60.5 meets 5
    EXPECT_NEAR(area, 50.0 * 40.0, kAreaTolM2);
    EXPECT_EQ(doc["blockLegend"]["breaks"].size(), 2u);
    auto svg = api::renderVector(*cm.value(), plan.value(), api::VectorFormat::Svg, VectorFrame::Plane);
    ASSERT_TRUE(svg.ok());
    EXPECT_NE(svg->find("data-cell=\"2,2,3\""), std::string::npos);
    // Errors name the parameter.
    auto bad = [&](api::Params p) {
        auto pl = api::parseViewPlan(p, "box", m.crs);
        if (!pl) return pl.error().message;
        auto img = api::renderProfile(*cm.value(), pl.value());
        return img ? std::string() : img.error().message;
    };
    EXPECT_NE(bad({{"elevation", "35"}, {"colour", "gold"}}).find("properties: grade"), std::string::npos);
    EXPECT_NE(bad({{"elevation", "35"}, {"colour", "grade"}, {"breaks", "2,1"}}).find("'breaks'"), std::string::npos);
    EXPECT_NE(bad({{"elevation", "35"}, {"colour", "grade"}, {"ramp", "jet"}}).find("'ramp'"), std::string::npos);
    EXPECT_NE(bad({{"elevation", "35"}, {"breaks", "1"}}).find("need 'colour"), std::string::npos);
    EXPECT_NE(bad({{"elevation", "35"}, {"colour", "a b"}}).find("'colour'"), std::string::npos);
}

namespace {

// Length of segment ab inside the rectangle [lo, hi] (Liang-Barsky).
double lengthInRect(glm::dvec2 a, glm::dvec2 b, glm::dvec2 lo, glm::dvec2 hi) {
    double t0 = 0.0, t1 = 1.0;
    const glm::dvec2 d = b - a;
    for (int k = 0; k < 2; ++k) {
        if (d[k] == 0.0) {
            if (a[k] < lo[k] || a[k] > hi[k]) return 0.0;
            continue;
        }
        double ta = (lo[k] - a[k]) / d[k], tb = (hi[k] - a[k]) / d[k];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t1 > t0 ? (t1 - t0) * glm::length(d) : 0.0;
}

}  // namespace

TEST(BlockModel, PolylineSectionPiecesAreExact) {
    // The box orebody of the test above cut along A-B-C (two oblique legs, a bend inside the
    // orebody). Oracle per (leg, cell): the piece is the vertical strip over the leg's part
    // inside the cell's and the orebody's common map rectangle, as tall as their common z
    // range: area = length (Liang-Barsky) x height.
    const glm::dvec3 oreLo{20.5, 20.5, 20.5}, oreHi{70.5, 60.5, 50.5};
    Model m = modelOf({makePart("host", PartKind::Body, 1, boxMesh({0, 0, 0}, {100, 100, 100})),
                       makePart("ore", PartKind::Body, 2, boxMesh(oreLo, oreHi))});
    auto blocks = blockModelFromCsv(gridCsv({0, 0, 0}, 10.0, 10, 10, 10, [](glm::dvec3 c) { return c.x / 10; }), "b");
    ASSERT_TRUE(blocks.ok());
    blocks->clipBodies = {"ore"};
    ASSERT_TRUE(resolveBlockClip(m, blocks.value()).ok());
    m.blocks = std::make_shared<const BlockModel>(std::move(blocks.value()));
    auto cm = api::catalogModelOf("box", m, "v1");
    ASSERT_TRUE(cm.ok());
    const std::vector<glm::dvec2> pts{{10.3, 30.2}, {45.7, 47.1}, {83.9, 33.3}};
    auto section = computePolylineSection(*cm.value()->index, pts);
    ASSERT_TRUE(section.ok()) << section.error().message;
    auto pieces = blockPieces(*m.blocks, section.value(), cm.value()->index->origin);
    ASSERT_TRUE(pieces.ok()) << pieces.error().message;
    const SectionLine& line = section->line;
    std::map<std::pair<std::size_t, std::size_t>, double> got;  // (leg, cell) -> area
    for (const BlockPiece& p : pieces.value()) {
        EXPECT_EQ(p.record, 2u);
        // The centroid of the piece (convex: cell ∩ orebody ∩ strip) lies in its cell.
        glm::dvec2 c(0.0);
        double a = 0.0;
        for (const Ring& r : p.rings)
            for (std::size_t i = 0; i < r.size(); ++i) {
                const glm::dvec2 &u = r[i], &w = r[(i + 1) % r.size()];
                const double x = u.x * w.y - w.x * u.y;
                a += x;
                c += (u + w) * x;
            }
        c /= 3.0 * a;
        EXPECT_EQ(m.blocks->cellAt(line.worldAt(c.x, c.y)), p.cell);
        got[{line.legAt(c.x), p.cell}] += p.area;
    }
    std::size_t expected = 0;
    for (std::size_t leg = 0; leg + 1 < pts.size(); ++leg)
        for (std::size_t cell = 0; cell < m.blocks->cellCount(); ++cell) {
            const auto ijk = m.blocks->ijk(cell);
            const glm::dvec3 lo = glm::max(10.0 * glm::dvec3(ijk[0], ijk[1], ijk[2]), oreLo);
            const glm::dvec3 hi = glm::min(10.0 * glm::dvec3(ijk[0] + 1, ijk[1] + 1, ijk[2] + 1), oreHi);
            const double area = hi.x > lo.x && hi.y > lo.y && hi.z > lo.z
                                    ? lengthInRect(pts[leg], pts[leg + 1], {lo.x, lo.y}, {hi.x, hi.y}) * (hi.z - lo.z)
                                    : 0.0;
            const auto it = got.find({leg, cell});
            const double g = it == got.end() ? 0.0 : it->second;
            // 1e-9 m²: rounding of clipped coordinates of ~100 m (a piece is up to 140 m²).
            EXPECT_NEAR(g, area, kAreaTolM2) << "leg " << leg << " cell " << ijk[0] << "," << ijk[1] << "," << ijk[2];
            expected += area > kAreaTolM2;
        }
    EXPECT_EQ(got.size(), expected);
    EXPECT_GT(expected, 20u);
    // Over the API: GeoJSON features and SVG paths of the pieces, with the legend.
    auto plan = api::parseViewPlan({{"line", "10.3,30.2,45.7,47.1,83.9,33.3"}, {"colour", "grade"}, {"breaks", "3,5"}},
                                   "box", m.crs);
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    auto geo = api::renderVector(*cm.value(), plan.value(), api::VectorFormat::GeoJson, VectorFrame::Projected);
    ASSERT_TRUE(geo.ok()) << geo.error().message;
    const auto doc = nlohmann::json::parse(geo.value());
    double area = 0.0, oreArea = 0.0;
    std::size_t features = 0;
    for (const auto& f : doc["features"])
        if (f["properties"]["kind"] == "block") {
            area += f["properties"]["area_m2"].get<double>();
            ++features;
            // World coordinates: the first vertex is x, y, z, in the piece's cell (closed
            // boxes: a vertex lies in or on it, 1e-6 m for rounding).
            const nlohmann::json* v = &f["geometry"]["coordinates"];
            while (v->is_array() && !v->empty() && (*v)[0].is_array()) v = &(*v)[0];
            ASSERT_EQ(v->size(), 3u);
            const auto cell = f["properties"]["cell"];
            for (int k = 0; k < 3; ++k) {
                EXPECT_GE((*v)[k].get<double>(), 10.0 * cell[k].get<double>() - 1e-6);
                EXPECT_LE((*v)[k].get<double>(), 10.0 * (cell[k].get<double>() + 1) + 1e-6);
            }
        }
    for (const BlockPiece& p : pieces.value()) oreArea += p.area;
    EXPECT_EQ(features, pieces->size());
    EXPECT_NEAR(area, oreArea, kAreaTolM2);
    EXPECT_EQ(doc["blockLegend"]["breaks"].size(), 2u);
    auto svg = api::renderVector(*cm.value(), plan.value(), api::VectorFormat::Svg, VectorFrame::Plane);
    ASSERT_TRUE(svg.ok()) << svg.error().message;
    EXPECT_NE(svg->find("data-cell=\""), std::string::npos);
}
