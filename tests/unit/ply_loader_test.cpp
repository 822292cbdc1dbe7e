// PLY reader (model/io/ply/ply_loader.cpp) on files written by VTK's vtkPLYWriter (ASCII,
// binary little- and big-endian) and by tests/data/ply/make_ply.py (a "region" face property,
// extra vertex and face properties to skip): volumes and sections against closed forms,
// regions as parts, and hostile inputs (counts past the end, indices out of range, NaN).
#include <gtest/gtest.h>

#include <string>

#include "tests/unit/wire_loader_util.hpp"

namespace geoslice {
namespace {

using namespace geoslice::test;

TEST(PlyLoader, VtkBoxInEveryEncodingIsAClosedBody) {
    for (const char* file : {"ply/box_ascii.ply", "ply/box_binary_le.ply", "ply/box_binary_be.ply"}) {
        SCOPED_TRACE(file);
        auto r = loadModel(wireData(file));
        ASSERT_TRUE(r.ok()) << r.error().message;
        ASSERT_EQ(r->bodies.size(), 1u);
        const std::string stem = std::string(file).substr(4, std::string(file).size() - 8);
        expectBody(r.value(), stem, 24000.0);
        EXPECT_EQ(r->bodies[0].mesh.bounds().min, glm::dvec3(500090.5, 7000185.5, 330.0));
        EXPECT_NEAR(wireSectionArea(r.value(), stem, Plane{{0, 0, 1}, -350.25}), 600.0, 600.0 * kWireRelTol);
        EXPECT_NEAR(wireSectionArea(r.value(), stem, Plane{{1, 0, 0}, -500100.0}), 1200.0, 1200.0 * kWireRelTol);
    }
}

TEST(PlyLoader, RegionPropertySplitsParts) {
    for (const char* file : {"ply/regions_ascii.ply", "ply/regions_binary_be.ply"}) {
        SCOPED_TRACE(file);
        auto r = loadModel(wireData(file));
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(r->bodies.size(), 2u);
        EXPECT_EQ(r->surfaces.size(), 1u);
        expectBody(r.value(), "region 1", 1000.0);
        expectBody(r.value(), "region 2", 64.0);
        expectSurface(r.value(), "region 7");
        EXPECT_EQ(r->notes.at("ply_region_property"), "region");
        EXPECT_NEAR(wireSectionArea(r.value(), "region 2", Plane{{0, 0, 1}, -3.0}), 8.0, 8.0 * kWireRelTol);
        EXPECT_NEAR(wireSectionArea(r.value(), "region 1", Plane{{0, 1, 0}, -2.5}), 100.0, 100.0 * kWireRelTol);
    }
}

TEST(PlyLoader, WithoutRegionPropertyOnePartNamedAfterTheStem) {
    // meshio's file: the two boxes and the sheet in one part, which is open (the sheet).
    auto r = loadModel(wireData("ply/regions_meshio.ply"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->surfaces.size(), 1u);
    EXPECT_EQ(r->surfaces[0].name, "regions_meshio");
    EXPECT_EQ(r->surfaces[0].mesh.triangleCount(), 26u);
}

const std::string kHead =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kVerts = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";

TEST(PlyLoader, AsciiTetrahedronAndQuads) {
    auto r = parsePly(kHead + kVerts + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", "tet.ply");
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectBody(r.value(), "tet", 1.0 / 6.0);
    // A quad face is fanned into two triangles.
    auto q = parsePly(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
        "element face 1\nproperty list int uint vertex_index\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
        "4 0 1 2 3\n",
        "quad.ply");
    ASSERT_TRUE(q.ok()) << q.error().message;
    EXPECT_EQ(q->surfaces.at(0).mesh.triangleCount(), 2u);
}

TEST(PlyLoader, HostileInputsAreErrorsNamingLineOrOffset) {
    expectWireError(parsePly(kHead + kVerts + "3 0 2 1\n3 0 1 9\n", "i.ply"), "i.ply",
                    {"line 15", "vertex index 9 is out of range", "4 vertices"});
    expectWireError(parsePly(kHead + "0 0 0\n1 nan 0\n0 1 0\n0 0 1\n", "n.ply"), "n.ply", {"non-finite"});
    expectWireError(parsePly(kHead + kVerts + "3 0 2 1\n", "t.ply"), "t.ply", {"ends inside the data"});
    expectWireError(parsePly("ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nproperty float y\n"
                             "property float z\nend_header\n0 0 0\n",
                             "c.ply"),
                    "c.ply", {"99999999999 items", "bytes are left"});
    expectWireError(parsePly("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "h.ply"), "h.ply",
                    {"line 4", "no 'end_header'"});
    expectWireError(parsePly("ply\nformat ascii 2.0\n", "v.ply"), "v.ply", {"line 2", "version"});
    expectWireError(parsePly("ply\nformat ascii 1.0\nproperty float x\n", "p.ply"), "p.ply",
                    {"line 3", "before any 'element'"});
    expectWireError(parsePly("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n", "q.ply"), "q.ply",
                    {"line 4", "unknown property type"});
    expectWireError(parsePly("solid x\n", "s.ply"), "s.ply", {"not PLY"});

    // Binary: a list count past the end, and a face count past the end, by byte offset.
    std::string bin =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::size_t body = bin.size();
    bin.append(36, '\0');
    std::string listPast = bin + std::string(1, '\xFF') + std::string(8, '\0');
    expectWireError(parsePly(listPast, "l.ply"), "l.ply",
                    {"byte offset " + std::to_string(body + 37), "255 items runs past the end"});
    std::string many = bin;
    many.replace(many.find("face 1"), 6, "face 4000000000");
    expectWireError(parsePly(many + "x", "m.ply"), "m.ply", {"4000000000 items", "bytes are left"});
    // Indices out of range in binary.
    std::string idx = bin + std::string(1, '\x03');
    for (std::int32_t v : {0, 1, 7}) idx.append(reinterpret_cast<const char*>(&v), 4);
    expectWireError(parsePly(idx, "x.ply"), "x.ply", {"vertex index 7 is out of range"});
}

}  // namespace
}  // namespace geoslice
