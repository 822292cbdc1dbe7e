// Wavefront OBJ loader: parts from o/g, per-part compacted vertices, index forms, negative
// indices, polygon fans, and errors that name the file and line. Coordinates are small
// integers, exact in double: compared exactly.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/io/loaders.hpp"

namespace geoslice {
namespace {

std::vector<const Part*> allParts(const Model& m) {
    std::vector<const Part*> out;
    for (const auto& p : m.bodies) out.push_back(&p);
    for (const auto& p : m.surfaces) out.push_back(&p);
    return out;
}

const Part* findPart(const Model& m, const std::string& name) {
    for (const Part* p : allParts(m))
        if (p->name == name) return p;
    return nullptr;
}

void expectErrorAt(const Result<Model>& r, const std::string& source, std::size_t line, const std::string& also = "") {
    ASSERT_FALSE(r.ok()) << "expected an error at line " << line;
    const std::string& msg = r.error().message;
    EXPECT_NE(msg.find(source), std::string::npos) << msg;
    EXPECT_NE(msg.find("line " + std::to_string(line) + ":"), std::string::npos) << msg;
    if (!also.empty()) {
        EXPECT_NE(msg.find(also), std::string::npos) << "expected '" << also << "' in: " << msg;
    }
}

// Eight corners of the unit cube at `offset` along x (z up).
std::string cubeVertices(int offset) {
    std::string s;
    const int c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (const auto& v : c)
        s += "v " + std::to_string(v[0] + offset) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
    return s;
}

// The six outward (counter-clockwise from outside) quads of a cube whose first vertex is
// `base` (1-based), written as positive indices.
std::string cubeQuads(int base) {
    const int q[6][4] = {{1, 4, 3, 2}, {5, 6, 7, 8}, {1, 2, 6, 5}, {3, 4, 8, 7}, {1, 5, 8, 4}, {2, 3, 7, 6}};
    std::string s;
    for (const auto& f : q) {
        s += "f";
        for (int i : f) s += " " + std::to_string(base + i - 1);
        s += "\n";
    }
    return s;
}

TEST(ObjLoader, TwoCubesInTwoGroupsAreTwoBodies) {
    std::string text = "# two unit cubes\nmtllib rocks.mtl\n" + cubeVertices(0) + cubeVertices(5) +
                       "g sandstone\nusemtl sand\n" + cubeQuads(1) + "g ore lens\ns 1\n" + cubeQuads(9);
    auto r = parseObj(text, "models/two_cubes.obj");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Model& m = r.value();
    EXPECT_EQ(m.name, "two_cubes");
    ASSERT_EQ(m.bodies.size(), 2u);
    EXPECT_TRUE(m.surfaces.empty());
    const Part* a = findPart(m, "sandstone");
    const Part* b = findPart(m, "ore lens");
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    for (const Part* p : {a, b}) {
        EXPECT_EQ(p->kind, PartKind::Body);
        EXPECT_EQ(p->mesh.triangleCount(), 12u);  // 6 quads, 2 triangles each
        EXPECT_EQ(p->mesh.vertexCount(), 8u);     // compacted: only its own cube's corners
        EXPECT_TRUE(p->report.closed);
        const AttributeRecord* rec = m.attributes.find(p->record);
        ASSERT_NE(rec, nullptr);
        EXPECT_EQ(rec->name, p->name);
        EXPECT_EQ(rec->kind, "body");
    }
    EXPECT_EQ(b->mesh.bounds().min, glm::dvec3(5, 0, 0));
    EXPECT_EQ(b->mesh.bounds().max, glm::dvec3(6, 1, 1));
    // z up as written: no axis swap.
    EXPECT_EQ(a->mesh.bounds().max, glm::dvec3(1, 1, 1));
    EXPECT_DOUBLE_EQ(a->report.signedVolume, 1.0);
}

TEST(ObjLoader, CubeSplitIntoTwoGroupsGivesTwoOpenSurfaces) {
    std::string quads = cubeQuads(1);
    std::size_t third = 0;
    for (int i = 0; i < 3; ++i) third = quads.find('\n', third) + 1;
    std::string text =
        cubeVertices(0) + "g bottom_half\n" + quads.substr(0, third) + "g top_half\n" + quads.substr(third);
    auto r = parseObj(text, "split.obj");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->bodies.empty());
    ASSERT_EQ(r->surfaces.size(), 2u);
    for (const auto& p : r->surfaces) EXPECT_EQ(p.mesh.triangleCount(), 6u) << p.name;
}

TEST(ObjLoader, NegativeIndicesMatchPositiveOnes) {
    // Each quad written right after its own four vertices, with relative indices.
    const int c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const int q[6][4] = {{1, 4, 3, 2}, {5, 6, 7, 8}, {1, 2, 6, 5}, {3, 4, 8, 7}, {1, 5, 8, 4}, {2, 3, 7, 6}};
    std::string rel, abs;
    int n = 0;
    for (const auto& f : q) {
        for (int i : f) {
            std::string v = "v " + std::to_string(c[i - 1][0]) + " " + std::to_string(c[i - 1][1]) + " " +
                            std::to_string(c[i - 1][2]) + "\n";
            rel += v;
            abs += v;
        }
        rel += "f -4 -3 -2 -1\n";
        abs += "f " + std::to_string(n + 1) + " " + std::to_string(n + 2) + " " + std::to_string(n + 3) + " " +
               std::to_string(n + 4) + "\n";
        n += 4;
    }
    auto a = parseObj(rel, "rel.obj");
    auto b = parseObj(abs, "abs.obj");
    ASSERT_TRUE(a.ok()) << a.error().message;
    ASSERT_TRUE(b.ok()) << b.error().message;
    auto pa = allParts(a.value());
    auto pb = allParts(b.value());
    ASSERT_EQ(pa.size(), 1u);
    ASSERT_EQ(pb.size(), 1u);
    EXPECT_EQ(pa[0]->name, "rel");  // faces before any o/g: part named after the file stem
    EXPECT_EQ(pa[0]->mesh.positions, pb[0]->mesh.positions);
    EXPECT_EQ(pa[0]->mesh.indices, pb[0]->mesh.indices);
    EXPECT_EQ(pa[0]->mesh.triangleCount(), 12u);
    // Corners split per face but welded by position: validation still sees a closed cube.
    EXPECT_EQ(pa[0]->kind, PartKind::Body);
}

TEST(ObjLoader, CornerFormsAndPolygonFans) {
    std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
        "f 1/1 2/2 3/3\n"
        "f 1//1 3//1 4//1\n"
        "f 1/1/1 4/3/1 5/2/1\n"
        "f 1 2 3 4 5\n";  // a pentagon: 3 triangles 1-2-3, 1-3-4, 1-4-5
    auto r = parseObj(text, "forms.obj");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Mesh& mesh = allParts(r.value())[0]->mesh;
    ASSERT_EQ(mesh.triangleCount(), 6u);
    // The pentagon's fan, as positions (indices are compacted in first-use order).
    auto at = [&](std::size_t k) { return mesh.positions[mesh.indices[k]]; };
    EXPECT_EQ(at(9), glm::dvec3(0, 0, 0));
    EXPECT_EQ(at(10), glm::dvec3(1, 0, 0));
    EXPECT_EQ(at(11), glm::dvec3(1, 1, 0));
    EXPECT_EQ(at(15), glm::dvec3(0, 0, 0));
    EXPECT_EQ(at(16), glm::dvec3(0.5, 1.5, 0));
    EXPECT_EQ(at(17), glm::dvec3(0, 1, 0));
}

TEST(ObjLoader, ObjectAndGroupNames) {
    // The rule (model/io/obj/obj_loader.cpp): the group names the part, then the object, then the file.
    std::string text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
        "f 1 2 3\n"                             // before any o/g: "names"
        "o Orebody 1\nf 1 2 4\n"                // "Orebody 1"
        "g upper\nf 1 3 4\n"                    // "upper"
        "g\nf 2 3 4\n"                          // group closed: back to "Orebody 1"
        "o Fault\ng upper\nf 3 2 1\n"           // "upper" again: group names are global
        "o Sandstone\ng Sandstone\nf 1 4 2\n";  // Leapfrog's o + g: "Sandstone", not "Sandstone/Sandstone"
    auto r = parseObj(text, "dir.v2/names.obj");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(allParts(r.value()).size(), 4u);
    ASSERT_NE(findPart(r.value(), "names"), nullptr);
    ASSERT_NE(findPart(r.value(), "Orebody 1"), nullptr);
    ASSERT_NE(findPart(r.value(), "upper"), nullptr);
    ASSERT_NE(findPart(r.value(), "Sandstone"), nullptr);
    EXPECT_EQ(findPart(r.value(), "Sandstone/Sandstone"), nullptr);
    EXPECT_EQ(findPart(r.value(), "upper")->mesh.triangleCount(), 2u);
    const Part* ore = findPart(r.value(), "Orebody 1");
    EXPECT_EQ(ore->mesh.triangleCount(), 2u);  // reopened: both faces in one part
    EXPECT_EQ(ore->mesh.vertexCount(), 4u);
    EXPECT_EQ(findPart(r.value(), "names")->mesh.vertexCount(), 3u);
    const AttributeRecord* rec = r->attributes.find(ore->record);
    ASSERT_NE(rec, nullptr);
    EXPECT_EQ(rec->name, "Orebody 1");
}

TEST(ObjLoader, CrlfContinuationsAndComments) {
    std::string text =
        "# comment\r\n"
        "v 0 0 0 1.0\r\n"          // with w
        "v 1 0 0 0.5 0.2 0.1\r\n"  // with a vertex colour
        "v 0 1 0   # trailing comment\r\n"
        "f 1 2 \\\r\n"
        "3\r\n";
    auto r = parseObj(text, "crlf.obj");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->triangleCount(), 1u);
    EXPECT_EQ(r->surfaces.size(), 1u);  // a single triangle is an open sheet
}

TEST(ObjLoader, ErrorsNameTheLine) {
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";  // lines 1-3
    expectErrorAt(parseObj(tri + "f 1 2 0\n", "zero.obj"), "zero.obj", 4, "index 0");
    expectErrorAt(parseObj(tri + "f 1 2 4\n", "oor.obj"), "oor.obj", 4, "out of range");
    expectErrorAt(parseObj(tri + "f -1 -2 -4\n", "neg.obj"), "neg.obj", 4, "out of range");
    expectErrorAt(parseObj(tri + "f 1 2 99999999999999999999\n", "huge.obj"), "huge.obj", 4, "out of range");
    expectErrorAt(parseObj(tri + "f 1 2\n", "two.obj"), "two.obj", 4, "at least 3");
    expectErrorAt(parseObj(tri + "f 1 2 x\n", "x.obj"), "x.obj", 4, "'x'");
    expectErrorAt(parseObj(tri + "f 1 2 3/\n", "slash.obj"), "slash.obj", 4, "'3/'");
    expectErrorAt(parseObj(tri + "f 1 2 3/1/2/3\n", "slash3.obj"), "slash3.obj", 4, "v/vt/vn");
    expectErrorAt(parseObj("v 0 0 nan\n", "nan.obj"), "nan.obj", 1, "finite");
    expectErrorAt(parseObj("v 0 0 -inf\n", "inf.obj"), "inf.obj", 1, "finite");
    expectErrorAt(parseObj("v 0 0 1e400\n", "big.obj"), "big.obj", 1, "'1e400'");
    expectErrorAt(parseObj("v 0 0 zero\n", "nn.obj"), "nn.obj", 1, "not a number");
    expectErrorAt(parseObj("v 0 0\n", "short.obj"), "short.obj", 1, "x y z");
    expectErrorAt(parseObj("f 1 2 3\n", "early.obj"), "early.obj", 1, "out of range");
    expectErrorAt(parseObj(tri + "\x01\x02garbage\xff\n", "bin.obj"), "bin.obj", 4, "not text");
    expectErrorAt(parseObj(tri + "zz \xff\xfe\n", "bin2.obj"), "bin2.obj", 4, "not text");
}

TEST(ObjLoader, EmptyOrFacelessInputIsAnError) {
    auto e = parseObj("", "empty.obj");
    ASSERT_FALSE(e.ok());
    EXPECT_NE(e.error().message.find("empty.obj"), std::string::npos);
    EXPECT_NE(e.error().message.find("empty"), std::string::npos);
    auto f = parseObj("v 0 0 0\nv 1 0 0\nl 1 2\n", "lines.obj");
    ASSERT_FALSE(f.ok());
    EXPECT_NE(f.error().message.find("lines.obj"), std::string::npos);
    EXPECT_NE(f.error().message.find("no faces"), std::string::npos);
}

}  // namespace
}  // namespace geoslice

namespace geoslice {
namespace {

// Sidecar rows that match no part (by name or by id) are listed in a warning, not dropped.
TEST(ObjLoader, SidecarRowsThatMatchNoPartAreListed) {
    const auto dir = std::filesystem::temp_directory_path() / ("geoslice_obj_sidecar_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    {
        std::ofstream(dir / "m.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                        "g Ore\nf 1 2 3\ng Host\nf 1 2 4\n";
        std::ofstream(dir / "m.attributes.csv") << "id,name,grade\n1,Ore,2.5\n7,Granite,\n9,Basalt,\n";
    }
    auto m = loadModel((dir / "m.obj").string());
    ASSERT_TRUE(m.ok()) << m.error().message;
    const std::string& note = m->notes.at("sidecar_unmatched");
    EXPECT_NE(note.find("m.attributes.csv: 2 of 3 rows match no part by name or id: 'Granite' (id 7), 'Basalt' (id 9)"),
              std::string::npos)
        << note;
    bool warned = false;
    for (const auto& issue : m->validation.issues)
        warned |= issue.severity == ValidationIssue::Severity::Warning && issue.message == note;
    EXPECT_TRUE(warned);
    // A fully matched sidecar gives no warning.
    std::ofstream(dir / "m.attributes.csv", std::ios::trunc) << "id,name\n1,Ore\n2,Host\n";
    m = loadModel((dir / "m.obj").string());
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->notes.count("sidecar_unmatched"), 0u);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace geoslice

namespace geoslice {
namespace {

// Materials as another program writes them: VTK's vtkOBJExporter (tests/data/obj): each
// group takes its material's Kd, with the source named; a sidecar still wins; an .mtl that
// is missing or named with a folder is a note, and the model still loads.
TEST(ObjLoader, MaterialColoursFromTheMtlFile) {
    const std::string dir = std::string(GEOSLICE_TEST_DATA_DIR) + "/obj";
    auto r = loadModel(dir + "/two_cubes.obj");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->bodies.size(), 2u);
    for (const Part& p : r->bodies) {
        const AttributeRecord* rec = r->attributes.find(p.record);
        ASSERT_NE(rec, nullptr);
        // Kd 0.8 0.2 0.1 and 0.1 0.3 0.9 x 255; 1 unit for the .mtl's decimals read as float.
        const Rgba8 want = p.name == "grp1" ? Rgba8{204, 51, 26, 255} : Rgba8{26, 77, 230, 255};
        EXPECT_NEAR(rec->colour.r, want.r, 1) << p.name;
        EXPECT_NEAR(rec->colour.g, want.g, 1) << p.name;
        EXPECT_NEAR(rec->colour.b, want.b, 1) << p.name;
        EXPECT_EQ(rec->colour.a, 255) << p.name;
        EXPECT_NE(rec->colourSource.find("OBJ material"), std::string::npos) << rec->colourSource;
        EXPECT_NE(rec->colourSource.find("two_cubes.mtl"), std::string::npos) << rec->colourSource;
    }
    EXPECT_EQ(r->notes.count("obj_materials"), 0u);

    // The same OBJ text where its .mtl is not found, or named through a folder: grey
    // palette colours, a note, no error.
    std::ifstream in(dir + "/two_cubes.obj");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto missing = parseObj(text, "x.obj", "/nonexistent-folder");
    ASSERT_TRUE(missing.ok());
    EXPECT_NE(missing->notes.at("obj_materials").find("cannot open"), std::string::npos);
    const std::string escaped =
        std::string(text).replace(text.find("mtllib two_cubes.mtl"), 20, "mtllib ../etc/passwd");
    auto up = parseObj(escaped, "x.obj", dir);
    ASSERT_TRUE(up.ok());
    EXPECT_NE(up->notes.at("obj_materials").find("not followed"), std::string::npos);
    for (const Part& p : up->bodies)
        EXPECT_TRUE(up->attributes.find(p.record)->colourSource.find("OBJ") == std::string::npos);
}

}  // namespace
}  // namespace geoslice
