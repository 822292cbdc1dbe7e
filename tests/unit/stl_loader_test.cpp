// STL reader (model/io/stl/stl_loader.cpp) on files written by VTK's vtkSTLWriter
// (tests/data/stl/make_stl.py): ASCII and binary told apart by the size rule (also for a
// binary header that begins with "solid"), solids as parts, exact welding making a closed
// shell a body (volume and sections against the closed form) and an open sheet a surface,
// and hostile inputs that must be errors naming the file and the line or byte offset.
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "tests/unit/wire_loader_util.hpp"

namespace geoslice {
namespace {

using namespace geoslice::test;

constexpr double kBoxVolume = 20.0 * 30.0 * 40.0;  // m³

void expectBox(const Model& m, const std::string& name) {
    expectBody(m, name, kBoxVolume);
    const Part* p = wirePart(m, name);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(p->mesh.vertexCount(), 8u);  // welded: 36 facet corners -> 8 corners
    EXPECT_EQ(p->mesh.triangleCount(), 12u);
    const Aabb b = p->mesh.bounds();
    EXPECT_EQ(b.min, glm::dvec3(500090.5, 7000185.5, 330.0));
    EXPECT_EQ(b.max, glm::dvec3(500110.5, 7000215.5, 370.0));
    // Horizontal, north-south and east-west planes: 20 x 30, 30 x 40 and 20 x 40 m.
    EXPECT_NEAR(wireSectionArea(m, name, Plane{{0, 0, 1}, -350.25}), 600.0, 600.0 * kWireRelTol);
    EXPECT_NEAR(wireSectionArea(m, name, Plane{{1, 0, 0}, -500100.0}), 1200.0, 1200.0 * kWireRelTol);
    EXPECT_NEAR(wireSectionArea(m, name, Plane{{0, 1, 0}, -7000200.0}), 800.0, 800.0 * kWireRelTol);
}

TEST(StlLoader, AsciiBoxIsOneClosedBodyNamedAfterItsSolid) {
    auto r = loadModel(wireData("stl/box_ascii.stl"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->bodies.size(), 1u);
    EXPECT_TRUE(r->surfaces.empty());
    expectBox(r.value(), "Visualization Toolkit generated SLA File");
}

TEST(StlLoader, BinaryBoxIsOnePartNamedAfterTheFileStem) {
    for (const char* file : {"stl/box_binary.stl", "stl/box_binary_solid_header.stl"}) {
        SCOPED_TRACE(file);
        const std::string bytes = wireBytes(file);
        EXPECT_TRUE(isBinaryStl(bytes));
        auto r = loadModel(wireData(file));
        ASSERT_TRUE(r.ok()) << r.error().message;
        ASSERT_EQ(r->bodies.size(), 1u);
        const std::string stem = std::string(file).substr(4, std::strlen(file) - 8);
        expectBox(r.value(), stem);
        ASSERT_TRUE(r->notes.count("stl_header"));
    }
    auto r = loadModel(wireData("stl/box_binary_solid_header.stl"));
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->notes.at("stl_header"), "solid box");
}

TEST(StlLoader, OpenSheetIsASurface) {
    auto r = loadModel(wireData("stl/plane_binary.stl"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->bodies.empty());
    ASSERT_EQ(r->surfaces.size(), 1u);
    EXPECT_EQ(r->surfaces[0].mesh.triangleCount(), 32u);
    EXPECT_EQ(r->surfaces[0].mesh.vertexCount(), 25u);
}

TEST(StlLoader, TwoSolidsAreTwoPartsWithTheirNames) {
    auto r = loadModel(wireData("stl/two_solids.stl"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectBox(r.value(), "ore_lens");
    expectSurface(r.value(), "fault_7");
    ASSERT_NE(r->attributes.findByName("ore_lens"), nullptr);
    EXPECT_EQ(r->attributes.findByName("ore_lens")->kind, "body");
    EXPECT_EQ(r->attributes.findByName("fault_7")->kind, "surface");
}

TEST(StlLoader, ContentSniffingWithoutExtension) {
    const std::string ascii = wireBytes("stl/box_ascii.stl");
    const std::string binary = wireBytes("stl/box_binary_solid_header.stl");
    const auto dir = std::filesystem::temp_directory_path() / ("geoslice_stl_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (const auto& [name, bytes] : {std::pair{"a.model", ascii}, std::pair{"b.model", binary}}) {
        const auto path = (dir / name).string();
        std::ofstream(path, std::ios::binary) << bytes;
        auto r = loadModel(path);
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(r->bodies.size(), 1u) << name;
    }
    std::filesystem::remove_all(dir);
}

TEST(StlLoader, HostileBinaryInputsAreErrorsNamingTheOffset) {
    const std::string good = wireBytes("stl/box_binary.stl");
    ASSERT_EQ(good.size(), 84u + 12u * 50u);
    // Truncated: the count says 12 triangles, the bytes hold fewer.
    expectWireError(parseStl(good.substr(0, good.size() - 7), "t.stl"), "t.stl",
                    {"offset 80", "12", "needs 684 bytes", "677", "truncated"});
    // A count far past the end (would be 200 GB): refused from the size, nothing allocated.
    std::string huge = good;
    const std::uint32_t big = 0xFFFFFFF0u;
    std::memcpy(huge.data() + 80, &big, 4);
    expectWireError(parseStl(huge, "h.stl"), "h.stl", {"4294967280", "needs"});
    // A NaN coordinate in triangle 3, vertex 2, y.
    std::string nan = good;
    const float q = std::numeric_limits<float>::quiet_NaN();
    const std::size_t at = 84 + 3 * 50 + 12 + 12 + 4;
    std::memcpy(nan.data() + at, &q, 4);
    expectWireError(parseStl(nan, "n.stl"), "n.stl", {"triangle 3", "non-finite", "byte offset " + std::to_string(at)});
    // Too short for binary, not "solid".
    expectWireError(parseStl("abc", "s.stl"), "s.stl", {"not STL"});
    // Zero triangles.
    std::string empty = good.substr(0, 84);
    std::memset(empty.data() + 80, 0, 4);
    expectWireError(parseStl(empty, "e.stl"), "e.stl", {"no triangles"});
}

TEST(StlLoader, HostileAsciiInputsAreErrorsNamingTheLine) {
    const std::string facet =
        "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";
    ASSERT_TRUE(parseStl("solid a\n" + facet + "endsolid a\n", "ok.stl").ok());
    expectWireError(parseStl("solid a\n" + facet, "u.stl"), "u.stl", {"line 8", "no 'endsolid'"});
    expectWireError(parseStl("solid a\nfacet normal 0 0 1\n outer loop\n  vertex 0 nan 0\n", "n.stl"), "n.stl",
                    {"line 4", "not a finite number"});
    expectWireError(parseStl("solid a\nfacet normal 0 0 1\n outer loop\n  vertex 0 x 0\n", "x.stl"), "x.stl",
                    {"line 4", "not a number"});
    expectWireError(
        parseStl("solid a\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n endloop\n", "f.stl"),
        "f.stl", {"line 6", "3 vertices"});
    expectWireError(parseStl("solid a\nendsolid\n", "e.stl"), "e.stl", {"no facets"});
    expectWireError(parseStl("solid a\nfoo\n", "k.stl"), "k.stl", {"line 2", "expected 'facet'"});
}

}  // namespace
}  // namespace geoslice
