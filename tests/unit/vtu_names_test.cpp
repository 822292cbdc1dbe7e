// .vtu formation names (model/io/vtu/vtu_cells.cpp) on files written by VTK 9.1's
// vtkXMLUnstructuredGridWriter (tests/data/vtu/make_formation_names.py): a CellData string
// array in ascii, zlib-compressed binary and raw appended data, a FieldData string array
// indexed by the formation value from 0 and from 1, a name two formations share, and string
// arrays that lie about their size.
#include <gtest/gtest.h>

#include <string>

#include "tests/unit/wire_loader_util.hpp"

namespace geoslice {
namespace {

using namespace geoslice::test;

constexpr double kCubeVolume = 10.0 * 10.0 * 10.0;  // m³, each formation of the files

const char* const kNames[] = {"Nappe de Morcles", "Nappe du Wildhorn", "\xe5\x9c\xb0\xe5\xb1\x82 T3x"};  // 地层 T3x

void expectNamed(const std::string& file, const std::string& source) {
    SCOPED_TRACE(file);
    auto m = loadModel(wireData("vtu/" + file));
    ASSERT_TRUE(m) << m.error().message;
    ASSERT_EQ(m->bodies.size(), 3u);
    for (const char* name : kNames) {
        expectBody(m.value(), name, kCubeVolume);
        const Part* p = wirePart(m.value(), name);
        ASSERT_NE(p, nullptr) << name;
        const AttributeRecord* rec = m->attributes.find(p->record);
        ASSERT_NE(rec, nullptr);
        EXPECT_EQ(rec->name, name);
        EXPECT_EQ(rec->nameSource, source);
    }
    // The names follow the cells: the westernmost cube is the first formation.
    EXPECT_LT(wirePart(m.value(), kNames[0])->mesh.bounds().max.x, 1010.0 + 1e-9);
    EXPECT_GT(wirePart(m.value(), kNames[2])->mesh.bounds().min.x, 1020.0 - 1e-9);
}

TEST(VtuNames, CellStringArrayInEveryEncoding) {
    for (const char* mode : {"ascii", "binary", "appended"})
        expectNamed(std::string("names_cell_") + mode + ".vtu", "file (.vtu cell array 'formation_name')");
}

TEST(VtuNames, FieldStringArrayIndexedByTheFormationValue) {
    expectNamed("names_field_0.vtu", "file (.vtu field array 'FormationNames', by formation)");
    expectNamed("names_field_1.vtu", "file (.vtu field array 'FormationNames', by formation - 1)");
}

TEST(VtuNames, ASharedNameKeepsTheValueBesideIt) {
    auto m = loadModel(wireData("vtu/names_shared.vtu"));
    ASSERT_TRUE(m) << m.error().message;
    for (const char* name : {"Granite (formation 0)", "Schist", "Granite (formation 2)"})
        expectBody(m.value(), name, kCubeVolume);
}

TEST(VtuNames, StringArraysThatLieAboutTheirSizeAreErrors) {
    const std::string text = wireBytes("vtu/names_cell_ascii.vtu");
    // One string too few for the cells: an error naming the array, never a shifted name.
    std::string shortNames = text;
    const std::size_t at = shortNames.find("78 97 112 112 101");  // "Nappe..." as character codes
    ASSERT_NE(at, std::string::npos);
    const std::size_t nul = shortNames.find(" 0 ", at);
    ASSERT_NE(nul, std::string::npos);
    shortNames.erase(at, nul + 3 - at);  // drop the first name and its NUL
    auto r = parseVtu(shortNames, "short.vtu");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("formation_name"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("holds 2 strings, 3 declared"), std::string::npos) << r.error().message;
    // A character code out of range.
    std::string badCode = text;
    badCode.replace(at, 2, "999");
    r = parseVtu(badCode, "code.vtu");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("'999' is not a character code"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace geoslice
