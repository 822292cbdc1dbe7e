// GOCAD TSurf loader: the four SCEC CFM 5.3 samples (tests/data/cfm53, BSD-3-Clause) and
// small inline files for each feature and each kind of malformed input.
//
// Counts are taken independently from the file text (VRTX / TRGL lines). Coordinates are
// compared exactly: the loader only parses and, for depth or feet, negates or multiplies,
// so the expected value is the same double computed the same way.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "model/io/loaders.hpp"

namespace geoslice {
namespace {

const std::string kDataDir = std::string(GEOSLICE_TEST_DATA_DIR) + "/cfm53/";

std::string readData(const std::string& name) {
    auto r = readFile(kDataDir + name);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? r.value() : std::string();
}

std::vector<const Part*> allParts(const Model& m) {
    std::vector<const Part*> out;
    for (const auto& p : m.bodies) out.push_back(&p);
    for (const auto& p : m.surfaces) out.push_back(&p);
    return out;
}

// What the test reads from a sample independently of the loader.
struct FileFacts {
    std::size_t vrtx = 0, trgl = 0, tface = 0;
    std::string name;
    std::string colourText;
    double minZ = std::numeric_limits<double>::infinity();
    double maxZ = -std::numeric_limits<double>::infinity();
};

FileFacts scan(const std::string& text) {
    FileFacts f;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string kw;
        ls >> kw;
        if (kw == "VRTX" || kw == "PVRTX") {
            ++f.vrtx;
            long id;
            double x, y, z;
            ls >> id >> x >> y >> z;
            f.minZ = std::min(f.minZ, z);
            f.maxZ = std::max(f.maxZ, z);
        } else if (kw == "TRGL") {
            ++f.trgl;
        } else if (kw == "TFACE") {
            ++f.tface;
        } else if (line.rfind("name:", 0) == 0) {
            f.name = line.substr(5);
        } else if (line.rfind("*solid*color:", 0) == 0) {
            f.colourText = line.substr(13);
        }
    }
    return f;
}

Rgba8 gocadColour(const std::string& text) {
    std::istringstream in(text);
    double r, g, b, a;
    in >> r >> g >> b >> a;
    auto to8 = [](double v) { return static_cast<std::uint8_t>(std::lround(v * 255.0)); };
    return Rgba8{to8(r), to8(g), to8(b), to8(a)};
}

// The error names the source and "line N".
void expectErrorAt(const Result<Model>& r, const std::string& source, std::size_t line, const std::string& also = "") {
    ASSERT_FALSE(r.ok()) << "expected an error at line " << line;
    const std::string& msg = r.error().message;
    EXPECT_NE(msg.find(source), std::string::npos) << msg;
    EXPECT_NE(msg.find("line " + std::to_string(line) + ":"), std::string::npos) << msg;
    if (!also.empty()) {
        EXPECT_NE(msg.find(also), std::string::npos) << "expected '" << also << "' in: " << msg;
    }
}

// An error that names the source but no line (whole-file problems).
void expectError(const Result<Model>& r, const std::string& source, const std::string& also) {
    ASSERT_FALSE(r.ok());
    const std::string& msg = r.error().message;
    EXPECT_NE(msg.find(source), std::string::npos) << msg;
    EXPECT_NE(msg.find(also), std::string::npos) << "expected '" << also << "' in: " << msg;
}

// A minimal valid TSurf with `body` as the lines after the header (lines 1-4 are fixed).
std::string tsurf(const std::string& body, const std::string& name = "t") {
    return "GOCAD TSurf 1\nHEADER {\nname:" + name + "\n}\n" + body;
}

const char* kTwoTriangles =
    "TFACE\n"
    "VRTX 1 0 0 10\n"
    "VRTX 2 100 0 20\n"
    "VRTX 3 0 100 30\n"
    "VRTX 4 100 100 40\n"
    "TRGL 1 2 3\n"
    "TRGL 2 4 3\n"
    "END\n";

TEST(TsurfLoader, LoadsCfmSamplesWithIndependentCounts) {
    const char* files[] = {
        "PNRA-CRSF-OCOT-Ocotillo_set4-CFM4.ts",
        "CRFA-BPPM-EAST-Big_Pine_fault-CFM4.ts",
        "BNRA-BMFZ-MULT-Black_Mountain_fault-CFM3.ts",
        "SNFA-LLFZ-2019-Ridgecrest_ruptures-CFM5.ts",
    };
    for (const char* file : files) {
        SCOPED_TRACE(file);
        std::string text = readData(file);
        FileFacts facts = scan(text);
        ASSERT_GT(facts.trgl, 0u);
        auto r = parseTsurf(text, file);
        ASSERT_TRUE(r.ok()) << r.error().message;
        const Model& m = r.value();
        auto parts = allParts(m);
        ASSERT_EQ(parts.size(), 1u);
        const Part& p = *parts[0];
        // Every vertex of these files is used by a triangle, so none is dropped.
        EXPECT_EQ(p.mesh.vertexCount(), facts.vrtx);
        EXPECT_EQ(p.mesh.triangleCount(), facts.trgl);
        EXPECT_EQ(m.triangleCount(), facts.trgl);
        EXPECT_EQ(p.name, facts.name);
        // Fault sheets are open: classified as surfaces.
        EXPECT_EQ(p.kind, PartKind::Surface);
        EXPECT_EQ(m.surfaces.size(), 1u);
        const AttributeRecord* rec = m.attributes.find(p.record);
        ASSERT_NE(rec, nullptr);
        EXPECT_EQ(rec->name, facts.name);
        EXPECT_EQ(rec->kind, "surface");
        EXPECT_EQ(rec->colour, gocadColour(facts.colourText));
        ASSERT_TRUE(rec->extra.contains("gocad_coordinate_system"));
        EXPECT_NE(rec->extra["gocad_coordinate_system"].get<std::string>().find("ZPOSITIVE Elevation"),
                  std::string::npos);
        // ZPOSITIVE Elevation: z as written (exact, no arithmetic), elevation up.
        Aabb b = p.mesh.bounds();
        EXPECT_EQ(b.min.z, facts.minZ);
        EXPECT_EQ(b.max.z, facts.maxZ);
        // NAD27 / UTM 11N has no EPSG code in the file: the model stays local.
        EXPECT_TRUE(m.crs.isLocal());
        // UTM zone 11N eastings and northings of southern California, metres.
        EXPECT_GT(b.min.x, 200000.0);
        EXPECT_LT(b.max.x, 800000.0);
        EXPECT_GT(b.min.y, 3500000.0);
        EXPECT_LT(b.max.y, 4200000.0);
        EXPECT_EQ(m.source, file);
    }
}

TEST(TsurfLoader, RidgecrestKeepsEveryTfaceAndRupture) {
    const std::string file = "SNFA-LLFZ-2019-Ridgecrest_ruptures-CFM5.ts";
    std::string text = readData(file);
    FileFacts facts = scan(text);
    auto r = parseTsurf(text, file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    // All TFACEs of the one TSurf object are in the one part (this file has
    // facts.tface of them, holding 16 separate ruptures).
    EXPECT_GE(facts.tface, 1u);
    ASSERT_EQ(r->surfaces.size(), 1u);
    EXPECT_EQ(r->surfaces[0].mesh.triangleCount(), 14112u);
    EXPECT_EQ(r->surfaces[0].mesh.triangleCount(), facts.trgl);
    EXPECT_EQ(r->surfaces[0].report.components, 16u);
    EXPECT_EQ(r->surfaces[0].name, "SNFA-LLFZ-2019-Ridgecrest_ruptures-CFM5");
}

TEST(TsurfLoader, SeveralTfacesStitchedByAtomsFormOnePart) {
    // Two TFACEs; the second reuses vertices 2 and 3 of the first through ATOMs 5 and 6.
    std::string text = tsurf(
        "TFACE\n"
        "VRTX 1 0 0 0\n"
        "VRTX 2 10 0 0\n"
        "VRTX 3 0 10 0\n"
        "TRGL 1 2 3\n"
        "TFACE\n"
        "ATOM 5 2\n"
        "PATOM 6 3\n"
        "VRTX 7 10 10 0\n"
        "TRGL 5 7 6\n"
        "TFACE\n"
        "VRTX 8 20 0 0\n"
        "VRTX 9 20 10 0\n"
        "VRTX 10 30 0 0\n"
        "TRGL 8 10 9\n"
        "END\n",
        "faces");
    auto r = parseTsurf(text, "faces.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    auto parts = allParts(r.value());
    ASSERT_EQ(parts.size(), 1u);
    const Mesh& mesh = parts[0]->mesh;
    EXPECT_EQ(mesh.triangleCount(), 3u);
    EXPECT_EQ(mesh.vertexCount(), 7u);  // 1 2 3 7 8 9 10: the atoms add none
    // The second face's triangle uses the first face's vertices 2 and 3.
    EXPECT_EQ(mesh.indices[3], mesh.indices[1]);
    EXPECT_EQ(mesh.indices[5], mesh.indices[2]);
    EXPECT_EQ(parts[0]->report.components, 2u);
}

TEST(TsurfLoader, SparseIdsAndForwardReferences) {
    std::string text = tsurf(
        "VRTX 1000000007 0 0 0\n"
        "VRTX 3 1 0 0\n"
        "TRGL 1000000007 3 42\n"
        "VRTX 42 0 1 0\n"
        "END\n");
    auto r = parseTsurf(text, "sparse.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Mesh& mesh = allParts(r.value())[0]->mesh;
    ASSERT_EQ(mesh.vertexCount(), 3u);
    EXPECT_EQ(mesh.positions[mesh.indices[0]], glm::dvec3(0, 0, 0));
    EXPECT_EQ(mesh.positions[mesh.indices[1]], glm::dvec3(1, 0, 0));
    EXPECT_EQ(mesh.positions[mesh.indices[2]], glm::dvec3(0, 1, 0));
}

TEST(TsurfLoader, DepthPositiveZIsNegatedAndFeetConverted) {
    std::string text = tsurf(
        "GOCAD_ORIGINAL_COORDINATE_SYSTEM\n"
        "NAME Default\n"
        "AXIS_NAME \"X\" \"Y\" \"Z\"\n"
        "AXIS_UNIT \"m\" \"m\" \"ft\"\n"
        "ZPOSITIVE Depth\n"
        "END_ORIGINAL_COORDINATE_SYSTEM\n"
        "TFACE\n"
        "VRTX 1 500000 3900000 100\n"
        "VRTX 2 500100 3900000 250.5\n"
        "VRTX 3 500000 3900100 -20\n"
        "TRGL 1 2 3\n"
        "END\n");
    auto r = parseTsurf(text, "depth.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Mesh& mesh = allParts(r.value())[0]->mesh;
    ASSERT_EQ(mesh.vertexCount(), 3u);
    // Depth in feet -> elevation in metres: z = -depth * 0.3048 (same double arithmetic).
    EXPECT_EQ(mesh.positions[0], glm::dvec3(500000, 3900000, 100 * -0.3048));
    EXPECT_EQ(mesh.positions[1], glm::dvec3(500100, 3900000, 250.5 * -0.3048));
    EXPECT_EQ(mesh.positions[2], glm::dvec3(500000, 3900100, -20 * -0.3048));
    EXPECT_LT(mesh.bounds().max.z, 10.0);  // mostly below the datum now
}

TEST(TsurfLoader, CoordinateSystemCarriesToLaterObjectsWithoutOne) {
    std::string obj2 = std::string("GOCAD TSurf 1\nHEADER {\nname:second\n}\n") + kTwoTriangles;
    std::string text = tsurf(
                           "GOCAD_ORIGINAL_COORDINATE_SYSTEM\n"
                           "ZPOSITIVE Depth\n"
                           "END_ORIGINAL_COORDINATE_SYSTEM\n" +
                               std::string(kTwoTriangles),
                           "first") +
                       obj2;
    auto r = parseTsurf(text, "two.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    auto parts = allParts(r.value());
    ASSERT_EQ(parts.size(), 2u);
    for (const Part* p : parts) EXPECT_EQ(p->mesh.bounds().max.z, -10.0) << p->name;
}

TEST(TsurfLoader, UnsupportedUnitIsAnErrorNamingIt) {
    // km and feet are converted (tests/unit/gocad_loader_test.cpp); a unit geoslice does not
    // know is refused, naming it.
    std::string text = tsurf(
        "GOCAD_ORIGINAL_COORDINATE_SYSTEM\n"
        "AXIS_UNIT \"league\" \"league\" \"league\"\n"
        "END_ORIGINAL_COORDINATE_SYSTEM\n" +
        std::string(kTwoTriangles));
    auto r = parseTsurf(text, "league.ts");
    expectErrorAt(r, "league.ts", 6, "'league'");
    EXPECT_EQ(r.error().code, ErrorCode::Unsupported);
}

TEST(TsurfLoader, EpsgCodeGoesIntoModelCrs) {
    std::string text = tsurf(
        "GOCAD_ORIGINAL_COORDINATE_SYSTEM\n"
        "NAME \"CGCS2000 / 3-degree Gauss-Kruger zone 38\"\n"
        "PROJECTION \"EPSG:4526\"\n"
        "ZPOSITIVE Elevation\n"
        "END_ORIGINAL_COORDINATE_SYSTEM\n" +
        std::string(kTwoTriangles));
    auto r = parseTsurf(text, "epsg.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->crs.epsg(), 4526);

    // Two objects naming different codes: ambiguous, stays local, text kept.
    std::string other =
        "GOCAD TSurf 1\nGOCAD_ORIGINAL_COORDINATE_SYSTEM\nPROJECTION EPSG:4527\n"
        "END_ORIGINAL_COORDINATE_SYSTEM\n" +
        std::string(kTwoTriangles);
    auto r2 = parseTsurf(text + other, "epsg2.ts");
    ASSERT_TRUE(r2.ok()) << r2.error().message;
    EXPECT_TRUE(r2->crs.isLocal());
    const AttributeRecord* rec = r2->attributes.find(allParts(r2.value())[1]->record);
    ASSERT_NE(rec, nullptr);
    EXPECT_EQ(rec->extra["gocad_coordinate_system"], "PROJECTION EPSG:4527");
}

TEST(TsurfLoader, PvrtxPropertiesWithEsizesAndNoData) {
    std::string text = tsurf(
        "PROPERTIES grade dir\n"
        "PROPERTY_CLASSES grade dir\n"
        "NO_DATA_VALUES -99999 -1\n"
        "ESIZES 1 3\n"
        "PROPERTY_CLASS_HEADER grade {\n"
        "low_clip: 0\n"
        "}\n"
        "TFACE\n"
        "PVRTX 1 0 0 0 1.5 1 0 0\n"
        "PVRTX 2 1 0 0 -99999 0 1 0\n"
        "VRTX 3 0 1 0\n"
        "PATOM 4 2\n"
        "TRGL 1 4 3\n"
        "END\n");
    auto r = parseTsurf(text, "props.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Mesh& mesh = allParts(r.value())[0]->mesh;
    ASSERT_EQ(mesh.propertyNames, (std::vector<std::string>{"grade", "dir[0]", "dir[1]", "dir[2]"}));
    ASSERT_EQ(mesh.vertexCount(), 3u);
    ASSERT_EQ(mesh.propertyValues.size(), 12u);
    const float* v = mesh.propertyValues.data();
    EXPECT_EQ(v[0], 1.5f);
    EXPECT_EQ(v[1], 1.0f);
    EXPECT_EQ(v[2], 0.0f);
    EXPECT_TRUE(std::isnan(v[4]));                                    // -99999 is no data
    EXPECT_EQ(v[6], 1.0f);                                            // dir[1] of vertex 2
    for (int k = 8; k < 12; ++k) EXPECT_TRUE(std::isnan(v[k])) << k;  // plain VRTX: no data
}

TEST(TsurfLoader, PvrtxWithTheWrongNumberOfValuesIsAnError) {
    std::string text = tsurf(
        "PROPERTIES a b\n"
        "PVRTX 1 0 0 0 1 2\n"
        "PVRTX 2 1 0 0 1\n"
        "PVRTX 3 0 1 0 1 2\n"
        "TRGL 1 2 3\n"
        "END\n");
    expectErrorAt(parseTsurf(text, "pv.ts"), "pv.ts", 7, "expected 2");
    // Too many values (found by fuzzing: a read past the no-data table).
    std::string more = tsurf(
        "PROPERTIES a b\n"
        "PVRTX 1 0 0 0 1 2 3 4 5\n"
        "END\n");
    expectErrorAt(parseTsurf(more, "pv5.ts"), "pv5.ts", 6, "has 5 property values, expected 2");
}

TEST(TsurfLoader, AtomReusesAnEarlierVertex) {
    std::string text = tsurf(
        "VRTX 1 0 0 0\n"
        "VRTX 2 1 0 0\n"
        "VRTX 3 0 1 0\n"
        "ATOM 4 1\n"
        "ATOM 5 4\n"  // an atom of an atom
        "TRGL 5 2 3\n"
        "END\n");
    auto r = parseTsurf(text, "atom.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Mesh& mesh = allParts(r.value())[0]->mesh;
    ASSERT_EQ(mesh.vertexCount(), 3u);
    EXPECT_EQ(mesh.positions[mesh.indices[0]], glm::dvec3(0, 0, 0));

    std::string bad = tsurf(
        "VRTX 1 0 0 0\n"
        "ATOM 4 9\n"
        "VRTX 2 1 0 0\n"
        "TRGL 1 2 4\n"
        "END\n");
    expectErrorAt(parseTsurf(bad, "atom.ts"), "atom.ts", 6, "vertex id 9");
}

TEST(TsurfLoader, SeveralObjectsNamesColoursAndGeologicalType) {
    std::string text =
        "GOCAD TSurf 1\n"
        "HEADER {\n"
        "name:Fault A\n"
        "*solid*color:1 0 0 1\n"
        "}\n"
        "GEOLOGICAL_FEATURE F1\n"
        "GEOLOGICAL_TYPE fault\n" +
        std::string(kTwoTriangles) +
        "GOCAD PLine 1\n"  // another object type: skipped
        "HEADER {\nname:a line\n}\n"
        "VRTX 1 0 0 0\nVRTX 2 1 1 1\nSEG 1 2\nEND\n"
        "GOCAD TSurf 1\n"
        "HEADER {name:Top Xujiahe}\n"
        "color: #00ff0080\n" +
        std::string(kTwoTriangles) + "GOCAD TSurf 1\n" + std::string(kTwoTriangles);
    auto r = parseTsurf(text, "dir/multi.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    auto parts = allParts(r.value());
    ASSERT_EQ(parts.size(), 3u);
    EXPECT_EQ(parts[0]->name, "Fault A");
    EXPECT_EQ(parts[1]->name, "Top Xujiahe");
    EXPECT_EQ(parts[2]->name, "multi#3");  // unnamed: file stem and object number
    const AttributeRecord* a = r->attributes.find(parts[0]->record);
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->kind, "fault");
    EXPECT_EQ(a->colour, (Rgba8{255, 0, 0, 255}));
    EXPECT_EQ(a->extra["geological_feature"], "F1");
    // The inline header with a 'color:' line outside it: the colour line is not part of
    // the header, so it is an unknown keyword and the default colour stays.
    const AttributeRecord* b = r->attributes.find(parts[1]->record);
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(b->name, "Top Xujiahe");
    EXPECT_EQ(b->kind, "surface");
    EXPECT_EQ(r->name, "multi");
}

TEST(TsurfLoader, ClosedTsurfBecomesABody) {
    // A tetrahedron, outward counter-clockwise faces.
    std::string text = tsurf(
        "TFACE\n"
        "VRTX 1 0 0 0\n"
        "VRTX 2 10 0 0\n"
        "VRTX 3 0 10 0\n"
        "VRTX 4 0 0 10\n"
        "TRGL 1 3 2\n"
        "TRGL 1 2 4\n"
        "TRGL 2 3 4\n"
        "TRGL 3 1 4\n"
        "END\n",
        "lens");
    auto r = parseTsurf(text, "lens.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->bodies.size(), 1u);
    EXPECT_TRUE(r->surfaces.empty());
    const AttributeRecord* rec = r->attributes.find(r->bodies[0].record);
    ASSERT_NE(rec, nullptr);
    EXPECT_EQ(rec->kind, "body");
}

TEST(TsurfLoader, CrlfLineEndingsAndWhitespace) {
    const std::string file = "PNRA-CRSF-OCOT-Ocotillo_set4-CFM4.ts";
    std::string text = readData(file);
    std::string crlf;
    for (char c : text) {
        if (c == '\n') crlf += "  \t\r";
        crlf += c;
    }
    auto a = parseTsurf(text, file);
    auto b = parseTsurf(crlf, file);
    ASSERT_TRUE(a.ok()) << a.error().message;
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_EQ(a->surfaces[0].mesh.positions, b->surfaces[0].mesh.positions);
    EXPECT_EQ(a->surfaces[0].mesh.indices, b->surfaces[0].mesh.indices);
    EXPECT_EQ(a->surfaces[0].name, b->surfaces[0].name);
}

TEST(TsurfLoader, UnknownKeywordsAreSkipped) {
    std::string text = tsurf(
        "SOME_FUTURE_KEYWORD 1 2 3\n"
        "# a comment\n"
        "\n"
        "BSTONE 1\n"
        "BORDER 5 1 2\n" +
        std::string(kTwoTriangles));
    auto r = parseTsurf(text, "unknown.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->triangleCount(), 2u);
}

TEST(TsurfLoader, TruncatedFileIsAnError) {
    const std::string file = "BNRA-BMFZ-MULT-Black_Mountain_fault-CFM3.ts";
    std::string text = readData(file);
    FileFacts facts = scan(text);
    // Cut in the middle of a line, and at a line end.
    std::string half = text.substr(0, text.size() / 2);
    auto r = parseTsurf(half, file);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(file), std::string::npos);
    EXPECT_NE(r.error().message.find("truncated"), std::string::npos) << r.error().message;
    std::size_t lines = static_cast<std::size_t>(std::count(half.begin(), half.end(), '\n')) + 1;
    EXPECT_NE(r.error().message.find("line " + std::to_string(lines)), std::string::npos) << r.error().message;

    // Cut at a line end, after complete triangles: kept, with a warning (issue 10 item 6).
    std::string atLine = text.substr(0, text.rfind("TRGL"));
    auto r2 = parseTsurf(atLine, file);
    ASSERT_TRUE(r2.ok()) << r2.error().message;
    EXPECT_EQ(r2->triangleCount(), facts.trgl - 1);
    EXPECT_NE(r2->notes.at("loader_warnings").find("no final END"), std::string::npos);
    // Cut among the vertices (no triangle yet): still an error.
    std::string noTriangles = text.substr(0, text.find("TRGL"));
    auto r3 = parseTsurf(noTriangles, file);
    ASSERT_FALSE(r3.ok());
    EXPECT_NE(r3.error().message.find("missing END"), std::string::npos) << r3.error().message;
    EXPECT_NE(r3.error().message.find("truncated"), std::string::npos) << r3.error().message;

    // Every cut of a small file is an error or a smaller valid model, never a crash: a
    // valid one only when the cut falls at a line end after the first triangle.
    std::string small = readData("CRFA-BPPM-EAST-Big_Pine_fault-CFM4.ts");
    const std::size_t firstTrgl = small.find("\nTRGL") + 1;
    for (std::size_t n = 0; n + 1 < small.size(); n += 7) {
        auto c = parseTsurf(small.substr(0, n), file);
        const bool lineEnd = n > 0 && small[n - 1] == '\n';
        const std::size_t trglEnd = small.find('\n', firstTrgl) + 1;
        EXPECT_EQ(c.ok(), lineEnd && n >= trglEnd) << n;
    }
}

TEST(TsurfLoader, WrongMagicAndEmptyInput) {
    expectError(parseTsurf("", "empty.ts"), "empty.ts", "empty");
    expectErrorAt(parseTsurf("\n\n  \n", "blank.ts"), "blank.ts", 3, "empty");
    expectErrorAt(parseTsurf("GOCAD PLine 1\nEND\n", "pline.ts"), "pline.ts", 1, "TSurf");
    expectErrorAt(parseTsurf("solid cube\nfacet normal 0 0 1\n", "cube.ts"), "cube.ts", 1, "GOCAD");
    expectErrorAt(parseTsurf("HEADER {\nname:x\n}\n" + std::string(kTwoTriangles), "nohead.ts"), "nohead.ts", 1,
                  "GOCAD");
}

TEST(TsurfLoader, TrglErrorsNameTheLine) {
    // Line numbers: 1-4 are the header, the body starts at line 5.
    const std::string verts = "VRTX 1 0 0 0\nVRTX 2 1 0 0\nVRTX 3 0 1 0\n";
    expectErrorAt(parseTsurf(tsurf(verts + "TRGL 1 2 4\nEND\n"), "oor.ts"), "oor.ts", 8, "vertex id 4");
    expectErrorAt(parseTsurf(tsurf(verts + "TRGL 1 2\nEND\n"), "two.ts"), "two.ts", 8, "3 vertex ids");
    expectErrorAt(parseTsurf(tsurf(verts + "TRGL 1 2 3 1\nEND\n"), "four.ts"), "four.ts", 8, "more than 3");
    expectErrorAt(parseTsurf(tsurf(verts + "TRGL 99999999999999999999 1 2\nEND\n"), "huge.ts"), "huge.ts", 8,
                  "out of range");
    expectErrorAt(parseTsurf(tsurf(verts + "TRGL -1 1 2\nEND\n"), "neg.ts"), "neg.ts", 8, "'-1'");
    expectErrorAt(parseTsurf(tsurf(verts + "TRGL 1 2 x\nEND\n"), "nan.ts"), "nan.ts", 8, "'x'");
    expectError(parseTsurf(tsurf(verts + "END\n"), "none.ts"), "none.ts", "no triangles");
}

TEST(TsurfLoader, VertexErrorsNameTheLine) {
    expectErrorAt(parseTsurf(tsurf("VRTX 1 0 nan 0\nEND\n"), "nan.ts"), "nan.ts", 5, "finite");
    expectErrorAt(parseTsurf(tsurf("VRTX 1 0 inf 0\nEND\n"), "inf.ts"), "inf.ts", 5, "finite");
    expectErrorAt(parseTsurf(tsurf("VRTX 1 0 1e999 0\nEND\n"), "big.ts"), "big.ts", 5, "'1e999'");
    expectErrorAt(parseTsurf(tsurf("VRTX 1 0 abc 0\nEND\n"), "abc.ts"), "abc.ts", 5, "not a number");
    expectErrorAt(parseTsurf(tsurf("VRTX 1 0 0\nEND\n"), "short.ts"), "short.ts", 5, "x y z");
    expectErrorAt(parseTsurf(tsurf("VRTX 1 0 0 0\nVRTX 2 1 0 0\nVRTX 1 0 1 0\nTRGL 1 2 1\nEND\n"), "dup.ts"), "dup.ts",
                  7, "duplicate vertex id 1 (already defined on line 5)");
}

TEST(TsurfLoader, BinaryGarbageIsAnError) {
    std::string garbage("\x01\x02\xff\xfe\x00\x13garbage\x7f", 14);
    expectErrorAt(parseTsurf(tsurf(garbage + "\n" + kTwoTriangles), "bin.ts"), "bin.ts", 5, "not text");
    // High bytes that are not UTF-8, on a line with no keyword we know.
    expectErrorAt(parseTsurf(tsurf("\xc3\x28\xa0\xa1 zz\n" + std::string(kTwoTriangles)), "latin.ts"), "latin.ts", 5,
                  "not text");
    // A UTF-8 name is fine, and a non-UTF-8 name is kept readable as UTF-8.
    auto r = parseTsurf(tsurf(kTwoTriangles, "\xe8\x93\x9f\xe5\x8e\xbf\xe7\xbb\x84 top"), "utf8.ts");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(allParts(r.value())[0]->name, "\xe8\x93\x9f\xe5\x8e\xbf\xe7\xbb\x84 top");
    auto r2 = parseTsurf(tsurf(kTwoTriangles, "G\xe9ologie"), "latin1.ts");
    ASSERT_TRUE(r2.ok()) << r2.error().message;
    EXPECT_EQ(allParts(r2.value())[0]->name, "G\xef\xbf\xbdologie");
}

TEST(TsurfLoader, UnclosedBlocksAreErrors) {
    expectErrorAt(parseTsurf("GOCAD TSurf 1\nHEADER {\nname:x\n", "hdr.ts"), "hdr.ts", 3, "'}'");
    expectErrorAt(parseTsurf("GOCAD TSurf 1\nGOCAD_ORIGINAL_COORDINATE_SYSTEM\nNAME x\n", "crs.ts"), "crs.ts", 3,
                  "END_ORIGINAL_COORDINATE_SYSTEM");
    expectErrorAt(parseTsurf(tsurf("VRTX 1 0 0 0\nGOCAD TSurf 1\n"), "nested.ts"), "nested.ts", 6, "before END");
}

}  // namespace
}  // namespace geoslice
