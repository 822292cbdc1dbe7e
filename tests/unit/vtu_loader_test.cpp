// .vtu loader tests on small grids written here (tests/common/vtu_writer.hpp) in every
// encoding the loader reads, and on corrupt and truncated variants of them.
// Volumes compare to 1e-12 relative: the cells are unit cubes with coordinates 0, 1, 2 (exact
// in binary), so the only error is the rounding of the divergence-theorem sum.
#include <unistd.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "tests/common/vtu_writer.hpp"

namespace geoslice {
namespace {

using testing::VtuEncoding;
using testing::VtuGrid;
// Cubic metres: unit cubes from integer coordinates: exact up to a few double steps.
constexpr double kCubeVolumeTol = 1e-12;

// Two unit cubes side by side: [0,1]^3 as one hexahedron (formation 5) and [1,2]x[0,1]^2
// as six tetrahedra around its diagonal (formation 7). Point data "temperature" = x + 10 z;
// cell data "density" constant per formation, "rock" the formation, "noise" not constant.
VtuGrid twoCubes(const std::string& rockType = "Int32") {
    VtuGrid g;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) g.points.push_back({double(i), double(j), double(k)});
    auto id = [](int i, int j, int k) { return std::int64_t(i + 3 * (j + 2 * k)); };
    g.addCell(12,
              {id(0, 0, 0), id(1, 0, 0), id(1, 1, 0), id(0, 1, 0), id(0, 0, 1), id(1, 0, 1), id(1, 1, 1), id(0, 1, 1)});
    // Kuhn's six tetrahedra of the cube [1,2]x[0,1]x[0,1]: paths 000 -> 111 along the axes.
    const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& p : perms) {
        int c[3] = {0, 0, 0};
        std::int64_t v[4];
        v[0] = id(1, 0, 0);
        for (int s = 0; s < 3; ++s) {
            c[p[s]] = 1;
            v[s + 1] = id(1 + c[0], c[1], c[2]);
        }
        g.addCell(10, {v[0], v[1], v[2], v[3]});
    }
    g.cellData.push_back({"noise", "Float64", 1, {0.5, 1, 2, 3, 4, 5, 6}});
    g.cellData.push_back({"density", "Float32", 1, {2.5, 2.75, 2.75, 2.75, 2.75, 2.75, 2.75}});
    g.cellData.push_back({"rock", rockType, 1, {5, 7, 7, 7, 7, 7, 7}});
    g.cellData.push_back({"block", "Int64", 1, {1, 1, 1, 1, 2, 2, 2}});
    std::vector<double> temp;
    for (const auto& p : g.points) temp.push_back(p.x + 10 * p.z);
    g.pointData.push_back({"temperature", "Float64", 1, temp});
    return g;
}

const Part* bodyNamed(const Model& m, const std::string& name) {
    for (const auto& b : m.bodies)
        if (b.name == name) return &b;
    return nullptr;
}

void expectTwoCubes(const Model& m, const std::string& label) {
    SCOPED_TRACE(label);
    ASSERT_EQ(m.bodies.size(), 2u);
    EXPECT_TRUE(m.surfaces.empty());
    EXPECT_FALSE(m.validation.hasErrors());
    const Part* a = bodyNamed(m, "rock 5");
    const Part* b = bodyNamed(m, "rock 7");
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->record, 5u);
    EXPECT_EQ(b->record, 7u);
    EXPECT_NEAR(signedVolume(a->mesh), 1.0, kCubeVolumeTol);
    EXPECT_NEAR(signedVolume(b->mesh), 1.0, kCubeVolumeTol);
    EXPECT_EQ(a->mesh.triangleCount(), 12u);  // six quads, two triangles each
    EXPECT_EQ(b->mesh.triangleCount(), 12u);
    const Aabb box = m.bounds();
    EXPECT_EQ(box.min, glm::dvec3(0, 0, 0));
    EXPECT_EQ(box.max, glm::dvec3(2, 1, 1));
    // Point data -> per-vertex property; constant cell data -> record fields.
    ASSERT_EQ(a->mesh.propertyNames, std::vector<std::string>{"temperature"});
    for (std::size_t v = 0; v < a->mesh.positions.size(); ++v)
        EXPECT_EQ(a->mesh.propertyValues[v], float(a->mesh.positions[v].x + 10 * a->mesh.positions[v].z));
    const AttributeRecord* ra = m.attributes.find(5);
    const AttributeRecord* rb = m.attributes.find(7);
    ASSERT_TRUE(ra && rb);
    EXPECT_EQ(ra->extra.value("density", 0.0), 2.5);
    EXPECT_EQ(rb->extra.value("density", 0.0), 2.75);
    EXPECT_EQ(rb->extra.value("rock", 0), 7);
    EXPECT_FALSE(ra->extra.contains("noise") && rb->extra.contains("noise"));
    EXPECT_FALSE(rb->extra.contains("block"));  // not constant over formation 7
}

TEST(VtuLoader, EveryEncodingGivesTheSameTwoBodies) {
    for (const VtuEncoding& e : testing::allVtuEncodings()) {
        const std::string file = testing::writeVtu(twoCubes(), e);
        auto m = parseVtu(file, "cubes.vtu");
        ASSERT_TRUE(m) << e.label() << ": " << m.error().message;
        expectTwoCubes(m.value(), e.label());
        EXPECT_EQ(m->notes.at("vtu_region_array"), "rock");
    }
}

TEST(VtuLoader, Float32PointsAndOtherIntegerTypes) {
    for (const char* rockType : {"UInt8", "Int16", "UInt32", "Int64", "UInt64"}) {
        VtuEncoding e;
        e.format = VtuEncoding::Format::Appended;
        e.zlib = true;
        e.pointType = "Float32";
        e.indexType = "Int32";
        auto m = parseVtu(testing::writeVtu(twoCubes(rockType), e), "cubes.vtu");
        ASSERT_TRUE(m) << rockType << ": " << m.error().message;
        expectTwoCubes(m.value(), rockType);
    }
}

TEST(VtuLoader, RegionArrayByNameOrDefault) {
    VtuGrid g = twoCubes();
    VtuEncoding e;
    // By name: "block" splits the cells differently.
    auto m = parseVtu(testing::writeVtu(g, e), "cubes.vtu", VtuOptions{"block"});
    ASSERT_TRUE(m) << m.error().message;
    ASSERT_EQ(m->bodies.size(), 2u);
    EXPECT_TRUE(bodyNamed(m.value(), "block 1") && bodyNamed(m.value(), "block 2"));
    double total = 0;
    for (const auto& b : m->bodies) total += signedVolume(b.mesh);
    EXPECT_NEAR(total, 2.0, kCubeVolumeTol);
    // A name that is not there: the error lists what is.
    auto bad = parseVtu(testing::writeVtu(g, e), "cubes.vtu", VtuOptions{"formation"});
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, ErrorCode::NotFound);
    EXPECT_NE(bad.error().message.find("cubes.vtu"), std::string::npos);
    EXPECT_NE(bad.error().message.find("'rock'"), std::string::npos) << bad.error().message;
    // No integer array: the first whole-numbered float array is taken.
    g.cellData = {{"gempy_id", "Float64", 1, {1, 2, 2, 2, 2, 2, 2}}};
    m = parseVtu(testing::writeVtu(g, e), "cubes.vtu");
    ASSERT_TRUE(m) << m.error().message;
    EXPECT_TRUE(bodyNamed(m.value(), "gempy_id 1") && bodyNamed(m.value(), "gempy_id 2"));
    // No cell data at all: one formation.
    g.cellData.clear();
    m = parseVtu(testing::writeVtu(g, e), "cubes.vtu");
    ASSERT_TRUE(m) << m.error().message;
    ASSERT_EQ(m->bodies.size(), 1u);
    EXPECT_NEAR(signedVolume(m->bodies[0].mesh), 2.0, kCubeVolumeTol);
}

TEST(VtuLoader, ValuesOutsideRecordIdsGetRanks) {
    VtuGrid g = twoCubes();
    g.cellData = {{"zone", "Int32", 1, {-3, 0, 0, 0, 0, 0, 0}}};
    auto m = parseVtu(testing::writeVtu(g, VtuEncoding{}), "cubes.vtu");
    ASSERT_TRUE(m) << m.error().message;
    const Part* a = bodyNamed(m.value(), "zone -3");
    const Part* b = bodyNamed(m.value(), "zone 0");
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->record, 1u);
    EXPECT_EQ(b->record, 2u);
    EXPECT_TRUE(m->notes.count("vtu_record_ids"));
}

TEST(VtuLoader, SkipsFacesRefusesPolyhedraReadsVoxelsAndQuadratics) {
    VtuGrid g = twoCubes();
    g.addCell(5, {0, 1, 4});  // a boundary triangle, as Gmsh writes them
    for (auto& a : g.cellData) a.values.push_back(a.values.back());
    auto m = parseVtu(testing::writeVtu(g, VtuEncoding{}), "cubes.vtu");
    ASSERT_TRUE(m) << m.error().message;
    expectTwoCubes(m.value(), "with a triangle cell");
    EXPECT_EQ(m->notes.at("vtu_skipped_cells"), "1 point, line and face cells skipped");

    VtuGrid v = twoCubes();
    // The hexahedron as a voxel (VTK order 0,1,3,2,...).
    v.types[0] = 11;
    std::swap(v.connectivity[2], v.connectivity[3]);
    std::swap(v.connectivity[6], v.connectivity[7]);
    m = parseVtu(testing::writeVtu(v, VtuEncoding{}), "cubes.vtu");
    ASSERT_TRUE(m) << m.error().message;
    expectTwoCubes(m.value(), "voxel");

    VtuGrid p = twoCubes();
    p.types[1] = 42;
    auto bad = parseVtu(testing::writeVtu(p, VtuEncoding{}), "cubes.vtu");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, ErrorCode::Unsupported);
    EXPECT_NE(bad.error().message.find("cell 1 has VTK type 42 (polyhedron)"), std::string::npos)
        << bad.error().message;
}

// Every error names the file; loading never crashes on a damaged file, and what loads
// from a truncated one is the whole model (only trailing closing tags were lost).
TEST(VtuLoader, TruncatedFilesFailCleanlyOrLoadWhole) {
    for (const VtuEncoding& e : testing::allVtuEncodings()) {
        const std::string file = testing::writeVtu(twoCubes(), e);
        std::size_t loaded = 0;
        for (std::size_t n = 0; n < file.size(); n += 1 + n / 200) {
            auto m = parseVtu(std::string_view(file).substr(0, n), "cut.vtu");
            if (m) {
                expectTwoCubes(m.value(), e.label() + " cut at " + std::to_string(n));
                ++loaded;
            } else {
                EXPECT_EQ(m.error().message.rfind("cut.vtu: ", 0), 0u) << m.error().message;
            }
        }
        // Only the raw / base64 appended forms can lose their closing tags and still be whole.
        if (e.format != VtuEncoding::Format::Appended) {
            EXPECT_EQ(loaded, 0u) << e.label();
        }
    }
}

TEST(VtuLoader, CorruptBytesFailCleanly) {
    for (const VtuEncoding& e : testing::allVtuEncodings()) {
        const std::string file = testing::writeVtu(twoCubes(), e);
        // Flip every byte in turn to a few values; the loader must return (either result).
        for (std::size_t i = 0; i < file.size(); i += 3) {
            for (char c : {'\0', '9', '<', '\xff'}) {
                std::string bad = file;
                bad[i] = c;
                auto m = parseVtu(bad, "bad.vtu");
                if (!m) {
                    EXPECT_EQ(m.error().message.rfind("bad.vtu: ", 0), 0u);
                }
            }
        }
    }
}

std::string replaceOnce(std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
    return s;
}

TEST(VtuLoader, ErrorsNameTheArrayAndTheProblem) {
    VtuEncoding ascii;
    const std::string text = testing::writeVtu(twoCubes(), ascii);
    auto expectError = [](const std::string& file, const std::string& part) {
        auto m = parseVtu(file, "m.vtu");
        ASSERT_FALSE(m) << part;
        EXPECT_NE(m.error().message.find(part), std::string::npos) << m.error().message;
    };
    expectError(replaceOnce(text, "NumberOfPoints=\"12\"", "NumberOfPoints=\"999999999999\""), "more than a file");
    expectError(replaceOnce(text, "NumberOfPoints=\"12\"", "NumberOfPoints=\"13\""), "array 'Points'");
    expectError(replaceOnce(text, "NumberOfCells=\"7\"", "NumberOfCells=\"-1\""), "NumberOfCells '-1' is not a count");
    expectError(replaceOnce(text, "type=\"UnstructuredGrid\"", "type=\"PolyData\""), "not UnstructuredGrid");
    expectError(replaceOnce(text, "<VTKFile", "<VTKFile compressor=\"vtkLZ4DataCompressor\""), "vtkLZ4DataCompressor");
    expectError(replaceOnce(text, "format=\"ascii\">\n0 1 2 ", "format=\"ascii\">\n0 1 x "), "array 'temperature'");
    // A connectivity index past the points.
    VtuGrid g = twoCubes();
    g.connectivity[3] = 12;
    expectError(testing::writeVtu(g, ascii), "array 'connectivity'");
    // Offsets that go backwards, and a cell of the wrong size.
    g = twoCubes();
    g.offsets[1] = 7;
    expectError(testing::writeVtu(g, ascii), "array 'offsets'");
    g = twoCubes();
    g.types[0] = 10;
    expectError(testing::writeVtu(g, ascii), "cell 0 of type 10 has 8 vertices, not 4");

    // Compressed: a header that claims more than the data, and a damaged block.
    VtuEncoding z;
    z.format = VtuEncoding::Format::Appended;
    z.zlib = true;
    z.header64 = false;
    std::string zfile = testing::writeVtu(twoCubes(), z);
    const std::size_t data = zfile.find('_', zfile.find("<AppendedData")) + 1;
    std::string lie = zfile;
    lie[data] = '\x7f';  // 127 blocks for the first array ("noise")
    expectError(lie, "array 'temperature'");
    std::string damaged = zfile;
    damaged[data + 16 + 2] ^= 0x55;  // inside the first zlib stream
    expectError(damaged, "array 'temperature'");
    // Base64 with a character outside the alphabet.
    VtuEncoding b;
    b.format = VtuEncoding::Format::Binary;
    std::string bfile = testing::writeVtu(twoCubes(), b);
    const std::size_t payload = bfile.find("format=\"binary\">\n") + 17;
    bfile[payload + 5] = '*';
    expectError(bfile, "is not base64");
}

// Through loadModel: the extension dispatches, and a sidecar names the formations.
TEST(VtuLoader, LoadModelWithSidecarNames) {
    const auto dir = std::filesystem::temp_directory_path() / ("geoslice_vtu_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    {
        std::ofstream(dir / "cubes.vtu", std::ios::binary) << testing::writeVtu(twoCubes(), VtuEncoding{});
        std::ofstream(dir / "cubes.attributes.csv") << "id,name,lithology\n5,Xujiahe Formation,sandstone\n";
    }
    auto m = loadModel((dir / "cubes.vtu").string());
    ASSERT_TRUE(m) << m.error().message;
    ASSERT_EQ(m->bodies.size(), 2u);
    const Part* named = bodyNamed(m.value(), "Xujiahe Formation");
    ASSERT_TRUE(named);
    EXPECT_EQ(named->record, 5u);
    EXPECT_EQ(m->attributes.find(5)->lithology, "sandstone");
    EXPECT_TRUE(bodyNamed(m.value(), "rock 7"));
    // --region-array through loadModel.
    LoadOptions o;
    o.vtu.regionArray = "block";
    m = loadModel((dir / "cubes.vtu").string(), o);
    ASSERT_TRUE(m) << m.error().message;
    EXPECT_TRUE(bodyNamed(m.value(), "block 2"));
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace geoslice
