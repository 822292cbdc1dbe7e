// Surpac string and DTM reader (model/io/surpac/surpac_loader.cpp): a real string file
// written by Surpac (tests/data/surpac/profile_5m_circle.str), a .str/.dtm pair written by
// make_surpac.py (Y before X; a closed box -> body with the closed-form volume and sections, an
// open grid -> surface), and hostile inputs that must be errors naming the line.
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/unit/wire_loader_util.hpp"

namespace geoslice {
namespace {

using namespace geoslice::test;

TEST(SurpacLoader, RealStringFileIsLines) {
    auto r = loadModel(wireData("surpac/profile_5m_circle.str"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->lines.size(), 1u);
    const Polyline& l = r->lines[0];
    EXPECT_EQ(l.name, "string 1");
    EXPECT_EQ(l.points.size(), 34u);        // the centre, then 33 points of the circle
    EXPECT_EQ(l.segments.size(), 2u * 32);  // the centre is a segment of its own
    // Y first: the record "1, 4.900, 0.993, 0.000" is x = 0.993, y = 4.9.
    EXPECT_EQ(l.points[2], glm::dvec3(0.993, 4.9, 0.0));
    for (std::size_t i = 1; i < l.points.size(); ++i)
        EXPECT_NEAR(glm::length(l.points[i]), 5.0, 2e-3) << i;  // 3 decimals written
}

TEST(SurpacLoader, DtmWithItsStringFile) {
    auto r = loadModel(wireData("surpac/box.dtm"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectBody(r.value(), "object 1", 24000.0);
    expectSurface(r.value(), "object 2");
    const Part* box = wirePart(r.value(), "object 1");
    EXPECT_EQ(box->mesh.bounds().min, glm::dvec3(500090.5, 7000185.5, 330.0));  // Y, X swapped back
    EXPECT_NEAR(wireSectionArea(r.value(), "object 1", Plane{{0, 0, 1}, -350.25}), 600.0, 600.0 * kWireRelTol);
    EXPECT_NEAR(wireSectionArea(r.value(), "object 1", Plane{{0, 1, 0}, -7000200.0}), 800.0, 800.0 * kWireRelTol);
    EXPECT_EQ(wirePart(r.value(), "object 2")->mesh.triangleCount(), 18u);
}

TEST(SurpacLoader, StringFileOfThePairIsTwoStrings) {
    auto r = loadModel(wireData("surpac/box.str"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Polyline* grid = wireLine(r.value(), "string 2");
    ASSERT_NE(grid, nullptr);
    EXPECT_EQ(grid->points.size(), 16u);
    EXPECT_EQ(grid->segments.size(), 2u * 14);  // two segments of 8 points
}

const std::string kStr =
    "t,1-Jan-26,,\n0, 0.000, 0.000, 0.000, 0.000, 0.000, 0.000\n"
    "1, 0, 0, 0,\n1, 0, 1, 0,\n1, 1, 0, 0,\n1, 0, 0, 1,\n0, 0.000, 0.000, 0.000,\n"
    "0, 0.000, 0.000, 0.000, END\n";

TEST(SurpacLoader, TetrahedronDtm) {
    const std::string dtm =
        "t.str,\n0, 0.000, 0.000, 0.000, END\nOBJECT, 3,\nTRISOLATION, 1, closed=yes\n"
        "1, 1, 3, 2, 0, 0, 0,\n2, 1, 2, 4, 0, 0, 0,\n3, 1, 4, 3, 0, 0, 0,\n4, 2, 3, 4, 0, 0, 0,\nEND\n";
    auto r = parseSurpacDtm(dtm, "t.dtm", kStr, "t.str");
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectBody(r.value(), "object 3", 1.0 / 6.0);
}

TEST(SurpacLoader, HostileInputsAreErrorsNamingTheLine) {
    const std::string head = "t.str,\n0, 0.000, 0.000, 0.000, END\nOBJECT, 1,\nTRISOLATION, 1,\n";
    expectWireError(parseSurpacDtm(head + "1, 1, 2, 9, 0, 0, 0,\nEND\n", "o.dtm", kStr, "t.str"), "o.dtm",
                    {"line 5", "point number 9 is out of range", "4 points"});
    expectWireError(parseSurpacDtm(head + "1, 1, 2, 99999999999999999999,\nEND\n", "b.dtm", kStr, "t.str"), "b.dtm",
                    {"line 5", "not a whole number"});
    expectWireError(parseSurpacDtm(head + "1, 1, 2, 3, 0, 0, 0,\n", "e.dtm", kStr, "t.str"), "e.dtm",
                    {"without its END"});
    expectWireError(parseSurpacDtm("t.str,\n0,0,0,0,END\n1, 1, 2, 3,\nEND\n", "n.dtm", kStr, "t.str"), "n.dtm",
                    {"line 3", "before any OBJECT"});
    expectWireError(parseSurpacString("t,\n0, 0, 0, 0, 0, 0, 0\n1, nan, 0, 0,\n", "n.str"), "n.str",
                    {"line 3", "not finite"});
    expectWireError(parseSurpacString("t,\n0, 0, 0, 0, 0, 0, 0\n1, 2, 3,\n", "f.str"), "f.str",
                    {"line 3", "the Z field is empty"});
    expectWireError(parseSurpacString("t,\n0, 0, 0, 0, 0, 0, 0\n1, 2, 3, 4,\n", "u.str"), "u.str",
                    {"ends without its end record"});
    expectWireError(parseSurpacString("t,\nhello\n", "a.str"), "a.str", {"line 2", "axis record"});
    auto bin = parseSurpacString(std::string("\x01\x00\x02", 3), "b.str");
    ASSERT_FALSE(bin.ok());
    EXPECT_EQ(bin.error().code, ErrorCode::Unsupported);
    // A .dtm without its string file.
    auto missing = loadModel(wireData("surpac/no_such.dtm"));
    ASSERT_FALSE(missing.ok());
}

}  // namespace
}  // namespace geoslice

namespace geoslice {
namespace {

// probeModelFile (model/io/loaders.hpp) on the new extensions: cheap refusals with the reason.
TEST(WireProbe, BinaryDxfBinarySurpacAndNonPlyAreRefusedBeforeReading) {
    const auto dir = std::filesystem::temp_directory_path() / ("geoslice_wire_probe_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    auto write = [&](const std::string& name, const std::string& bytes) {
        const std::string path = (dir / name).string();
        std::ofstream(path, std::ios::binary) << bytes;
        return path;
    };
    auto dxf = probeModelFile(write("b.dxf", std::string("AutoCAD Binary DXF\r\n\x1a\0", 22)));
    ASSERT_FALSE(dxf.ok());
    EXPECT_EQ(dxf.error().code, ErrorCode::Unsupported);
    EXPECT_NE(dxf.error().message.find("binary DXF"), std::string::npos);
    auto dtm = probeModelFile(write("b.dtm", std::string("\x01\x02\0\x03", 4)));
    ASSERT_FALSE(dtm.ok());
    EXPECT_NE(dtm.error().message.find("binary Surpac"), std::string::npos);
    auto ply = probeModelFile(write("n.ply", "solid x\n"));
    ASSERT_FALSE(ply.ok());
    EXPECT_NE(ply.error().message.find("not PLY"), std::string::npos);
    EXPECT_TRUE(probeModelFile(test::wireData("stl/box_binary.stl")).ok());  // binary STL: NUL bytes are fine
    EXPECT_TRUE(probeModelFile(test::wireData("dxf/solids.dxf")).ok());
    EXPECT_TRUE(probeModelFile(test::wireData("surpac/box.dtm")).ok());
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace geoslice
