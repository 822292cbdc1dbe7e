// Spatially varying attributes: the block-model CSV reader (columns by name, errors with line
// numbers) and a field bake on a flat sheet split by two blocks of known grade, where every
// point farther than two texels from a block face fetches the record of its block's class,
// and points outside every block keep the part's record.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <random>

#include "bake/bake.hpp"
#include "bake/package.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

TEST(BakeField, BlockCsvColumnsByNameAndErrors) {
    auto b = bake::parseBlockCsv("dz;SiO2_pct;x;y;z;dx;dy\n10;98.5;5;5;5;10;10\n10;90;15;5;5;10;10\n", "b.csv");
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_EQ(b->name, "SiO2_pct");
    ASSERT_EQ(b->values.size(), 2u);
    EXPECT_EQ(b->values[0], 98.5);
    EXPECT_EQ(b->centres[1], glm::dvec3(15, 5, 5));
    EXPECT_EQ(b->sizes[1], glm::dvec3(10, 10, 10));
    auto err = [](const char* text) { return bake::parseBlockCsv(text, "b.csv").error().message; };
    EXPECT_NE(err("x,y,z,dx,dy,grade\n1,2,3,4,5,6\n").find("dz"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n1,2,3,4,5,6,nan\n").find("b.csv:2"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n1,2,3,4,0,6,7\n").find("size must be > 0"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g\n1,2,3\n").find("3 fields"), std::string::npos);
    EXPECT_NE(err("x,y,z,dx,dy,dz,g,h\n").find("more than one value column"), std::string::npos);
    EXPECT_NE(err("").find("empty"), std::string::npos);
}

TEST(BakeField, SheetSplitByTwoBlocksFetchesTheBlockClass) {
    // A 100 m x 100 m sheet at z = 0 (20 x 20 cells), record 5. Blocks: x in [0, 50] grade 90,
    // x in [50, 100] grade 99, both for y in [0, 60]; breaks {95}: class 0 below 95, class 1 above.
    Mesh sheet;
    const int n = 20;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) sheet.positions.push_back({100.0 * x / n, 100.0 * y / n, 0.0});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const std::uint32_t a = std::uint32_t(y * (n + 1) + x), b = a + 1, c = a + n + 2, d = a + n + 1;
            sheet.indices.insert(sheet.indices.end(), {a, b, c, a, c, d});
        }
    Model m;
    m.name = "sheet";
    m.surfaces.push_back(makePart("sheet", PartKind::Surface, 5, sheet));
    AttributeRecord rec;
    rec.id = 5;
    rec.name = "Xujiahe Formation";
    rec.lithology = "quartz sandstone";
    m.attributes.put(rec);
    bake::BlockModel blocks;
    blocks.name = "SiO2";
    blocks.centres = {{25, 30, 0}, {75, 30, 0}};
    blocks.sizes = {{50, 60, 10}, {50, 60, 10}};
    blocks.values = {90.0, 99.0};
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 256;
    o.field.blocks = &blocks;
    o.field.breaks = {95.0};
    o.field.unit = "% SiO2";
    auto baked = bake::bakeModel(m, o);
    ASSERT_TRUE(baked.ok()) << baked.error().message;
    ASSERT_EQ(baked->fieldRecords.size(), 2u);
    const RecordId low = baked->fieldRecords[0].id, high = baked->fieldRecords[1].id;
    EXPECT_EQ(low, 6u);  // the table's next free id
    EXPECT_EQ(baked->fieldRecords[0].name, "Xujiahe Formation, SiO2 < 95");
    EXPECT_EQ(baked->fieldRecords[1].name, "Xujiahe Formation, SiO2 >= 95");
    EXPECT_EQ(baked->fieldRecords[1].lithology, "quartz sandstone");
    EXPECT_EQ(baked->fieldRecords[1].gradeUnit, "% SiO2");
    // Two texels (plus float slack) of the sheet: 2 / density metres.
    const double guard = 2.01 / baked->density;
    const auto& part = baked->parts[0];
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t checked = 0, wrong = 0;
    for (int i = 0; i < 50000; ++i) {
        const std::size_t t = std::size_t(rng() % (part.indices.size() / 3));
        double r1 = unit(rng), r2 = unit(rng);
        if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
        const glm::dvec3 w0(part.positions[part.indices[3 * t]]), w1(part.positions[part.indices[3 * t + 1]]),
            w2(part.positions[part.indices[3 * t + 2]]);
        const glm::dvec3 p = (1 - r1 - r2) * w0 + r1 * w1 + r2 * w2 + m.origin;  // world
        const glm::vec2 uv = float(1 - r1 - r2) * part.uvs[part.indices[3 * t]] +
                             float(r1) * part.uvs[part.indices[3 * t + 1]] +
                             float(r2) * part.uvs[part.indices[3 * t + 2]];
        RecordId expect;
        // Within 2 texels of a block face (inner or outer) the texel's point may be either side.
        if (std::abs(p.x - 50.0) < guard || std::abs(p.y - 60.0) < guard || p.x < guard || p.x > 100.0 - guard ||
            p.y < guard)
            continue;
        expect = p.y > 60.0 ? 5u : (p.x < 50.0 ? low : high);
        ++checked;
        const RecordId got =
            bake::fetchId(baked->texels.data(), baked->width, baked->height, baked->pages, glm::dvec2(uv));
        if (got != expect && ++wrong < 5)
            ADD_FAILURE() << "point " << p.x << "," << p.y << ": " << got << " not " << expect;
    }
    EXPECT_GT(checked, 35000u);
    EXPECT_EQ(wrong, 0u);
    // The class records reach the package's attribute table.
    const auto dir = std::filesystem::temp_directory_path() / ("geoslice_bake_field_" + std::to_string(::getpid()));
    ASSERT_TRUE(bake::writePackage(m, baked.value(), dir.string()).ok());
    auto pkg = bake::loadPackage(dir.string());
    ASSERT_TRUE(pkg.ok()) << pkg.error().message;
    ASSERT_NE(pkg->attributes.find(high), nullptr);
    EXPECT_EQ(pkg->attributes.find(high)->extra["min"], 95.0);
    std::filesystem::remove_all(dir);
    // Bad breaks are an error.
    o.field.breaks = {95.0, 90.0};
    EXPECT_EQ(bake::bakeModel(m, o).error().code, ErrorCode::InvalidArgument);
}
