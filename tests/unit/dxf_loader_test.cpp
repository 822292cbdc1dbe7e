// DXF reader (model/io/dxf/dxf_loader.cpp) on files written by ezdxf
// (tests/data/dxf/make_dxf.py): 3DFACE, polyface and polygon-mesh POLYLINEs and MESH on
// layers, each layer a part (volumes and sections against closed forms), lines, skipped
// entities, DXF R12, and hostile inputs that must be errors naming the line.
#include <gtest/gtest.h>

#include <string>

#include "tests/unit/wire_loader_util.hpp"

namespace geoslice {
namespace {

using namespace geoslice::test;

TEST(DxfLoader, EzdxfSolidsOneLayerPerPart) {
    auto r = loadModel(wireData("dxf/solids.dxf"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Model& m = r.value();
    EXPECT_EQ(m.bodies.size(), 3u);
    EXPECT_EQ(m.surfaces.size(), 2u);
    expectBody(m, "box_faces", 24000.0);
    expectBody(m, "box_polyface", 1000.0);
    expectBody(m, "box_mesh", 192.0);
    expectSurface(m, "topo");
    expectSurface(m, "grid");
    EXPECT_EQ(wirePart(m, "topo")->mesh.triangleCount(), 18u);
    EXPECT_EQ(wirePart(m, "grid")->mesh.triangleCount(), 12u);  // 3 x 2 cells of the 4 x 3 mesh
    EXPECT_NEAR(wireSectionArea(m, "box_faces", Plane{{0, 0, 1}, -350.25}), 600.0, 600.0 * kWireRelTol);
    EXPECT_NEAR(wireSectionArea(m, "box_polyface", Plane{{0, 0, 1}, -305.0}), 100.0, 100.0 * kWireRelTol);
    EXPECT_NEAR(wireSectionArea(m, "box_mesh", Plane{{1, 0, 0}, -500302.0}), 48.0, 48.0 * kWireRelTol);
    const Polyline* l = wireLine(m, "contours");
    ASSERT_NE(l, nullptr);
    EXPECT_EQ(l->points.size(), 6u);                                  // closed LWPOLYLINE (3) + 3D POLYLINE (3)
    EXPECT_EQ(l->segments.size(), 10u);                               // 3 + 2 segments
    EXPECT_EQ(l->points[0], glm::dvec3(500050.0, 7000150.0, 330.0));  // the LWPOLYLINE's elevation
    EXPECT_EQ(l->points[4], glm::dvec3(500100.0, 7000200.0, 350.0));
    EXPECT_EQ(m.notes.at("dxf_skipped"), "CIRCLE 1");
}

TEST(DxfLoader, EzdxfR12) {
    auto r = loadModel(wireData("dxf/solids_r12.dxf"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectBody(r.value(), "box_faces", 24000.0);
    expectBody(r.value(), "box_polyface", 1000.0);
}

std::string entities(const std::string& body) { return "0\nSECTION\n2\nENTITIES\n" + body + "0\nENDSEC\n0\nEOF\n"; }

std::string face(const std::string& layer, const double c[4][3]) {
    std::string s = "0\n3DFACE\n8\n" + layer + "\n";
    for (int k = 0; k < 4; ++k)
        for (int a = 0; a < 3; ++a) s += std::to_string(10 * (a + 1) + k) + "\n" + std::to_string(c[k][a]) + "\n";
    return s;
}

TEST(DxfLoader, TetrahedronOf3dFacesIsABody) {
    const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    std::string body;
    for (const auto& t : f) {
        const double c[4][3] = {{p[t[0]][0], p[t[0]][1], p[t[0]][2]},
                                {p[t[1]][0], p[t[1]][1], p[t[1]][2]},
                                {p[t[2]][0], p[t[2]][1], p[t[2]][2]},
                                {p[t[2]][0], p[t[2]][1], p[t[2]][2]}};
        body += face("ore", c);
    }
    auto r = parseDxf(entities(body), "tet.dxf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectBody(r.value(), "ore", 1.0 / 6.0);
}

TEST(DxfLoader, HostileInputsAreErrorsNamingTheLine) {
    expectWireError(parseDxf("0\nSECTION\nx\nENTITIES\n", "c.dxf"), "c.dxf", {"line 3", "not a DXF group code"});
    expectWireError(parseDxf("0\nSECTION\n2\n", "v.dxf"), "v.dxf", {"line 3", "no value line"});
    expectWireError(parseDxf(entities("0\n3DFACE\n8\na\n10\n0\n20\nnan\n30\n0\n"), "n.dxf"), "n.dxf",
                    {"line 12", "not finite"});
    expectWireError(parseDxf(entities("0\n3DFACE\n8\na\n10\n0\n20\n0\n30\n0\n"), "m.dxf"), "m.dxf",
                    {"line 5", "first three corners"});
    // A polyface face record naming vertex 9 of 3.
    std::string pf = "0\nPOLYLINE\n8\nb\n66\n1\n70\n64\n71\n3\n72\n1\n";
    for (int v = 0; v < 3; ++v) pf += "0\nVERTEX\n70\n192\n10\n" + std::to_string(v) + "\n20\n0\n30\n0\n";
    pf += "0\nVERTEX\n70\n128\n71\n1\n72\n2\n73\n-9\n0\nSEQEND\n";
    expectWireError(parseDxf(entities(pf), "p.dxf"), "p.dxf", {"line 47", "refers to vertex 9 of 3"});
    expectWireError(parseDxf(entities("0\nPOLYLINE\n70\n64\n0\nVERTEX\n70\n192\n"), "s.dxf"), "s.dxf",
                    {"line 13", "POLYLINE of line 5", "expected VERTEX or SEQEND, found 'ENDSEC'"});
    expectWireError(parseDxf("0\nSECTION\n2\nENTITIES\n0\nPOLYLINE\n70\n64\n0\nVERTEX\n70\n192\n", "q.dxf"), "q.dxf",
                    {"line 5", "without SEQEND"});
    // A polygon mesh whose M x N wraps around 2^64 to the (zero) VERTEX records it has.
    expectWireError(parseDxf(entities("0\nPOLYLINE\n70\n16\n71\n4294967296\n72\n4294967296\n0\nSEQEND\n"), "w.dxf"),
                    "w.dxf", {"line 5", "polygon mesh of 4294967296 x 4294967296", "has 0 VERTEX records"});
    // MESH with a vertex count far past its groups: refused before reserving.
    expectWireError(parseDxf(entities("0\nMESH\n8\nm\n92\n1000000000000\n10\n0\n20\n0\n30\n0\n93\n0\n"), "h.dxf"),
                    "h.dxf", {"line 9", "vertex count 1000000000000"});
    expectWireError(parseDxf(entities("0\nMESH\n92\n3\n10\n0\n20\n0\n30\n0\n10\n1\n20\n0\n30\n0\n10\n0\n20\n1\n30\n0\n"
                                      "93\n4\n90\n3\n90\n0\n90\n1\n90\n5\n"),
                             "i.dxf"),
                    "i.dxf", {"vertex index 5 out of range"});
    auto binary = parseDxf(std::string("AutoCAD Binary DXF\r\n\x1a\0", 22), "b.dxf");
    ASSERT_FALSE(binary.ok());
    EXPECT_EQ(binary.error().code, ErrorCode::Unsupported);
    EXPECT_NE(binary.error().message.find("binary DXF"), std::string::npos);
    expectWireError(parseDxf(entities("0\nCIRCLE\n8\na\n"), "e.dxf"), "e.dxf", {"nothing to load"});
}

}  // namespace
}  // namespace geoslice
