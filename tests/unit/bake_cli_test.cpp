// geoslice bake end to end: generate a small model, bake it with an attribute table, load the
// package and check every part's record survives; a model over the texture budget and a bad
// model path exit 1 with the reason on stderr.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>

#include "bake/package.hpp"
#include "tests/common/run_command.hpp"

using namespace geoslice;
namespace fs = std::filesystem;

TEST(BakeCli, BakesAModelIntoALoadablePackage) {
    const fs::path dir = fs::temp_directory_path() / ("geoslice_bake_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string model = (dir / "m.glb").string(), out = (dir / "pkg").string();
    ASSERT_EQ(test::runGeoslice("generate --triangles 5000 --out " + model).exitCode, 0);
    {
        std::ofstream csv(dir / "extra.csv");
        csv << "id,name,lithology\n900,Test record,granite\n";
    }
    auto r = test::runGeoslice("bake " + model + " --attributes " + (dir / "extra.csv").string() +
                               " --size 512 --out " + out);
    ASSERT_EQ(r.exitCode, 0) << r.out;
    EXPECT_NE(r.out.find("charts"), std::string::npos) << r.out;
    auto pkg = bake::loadPackage(out);
    ASSERT_TRUE(pkg.ok()) << pkg.error().message;
    EXPECT_EQ(pkg->width, 512u);
    ASSERT_NE(pkg->attributes.find(900), nullptr);
    EXPECT_EQ(pkg->attributes.find(900)->lithology, "granite");
    EXPECT_GT(pkg->parts.size(), 2u);
    for (const auto& p : pkg->parts) {
        // The texel under each part's first triangle's centroid holds the part's record.
        glm::vec2 c(0.0f);
        for (int k = 0; k < 3; ++k) c += glm::vec2(p.uvs[2 * p.indices[k]], p.uvs[2 * p.indices[k] + 1]) / 3.0f;
        EXPECT_EQ(pkg->fetch(glm::dvec2(c)), p.record) << p.name;
    }
    // Over budget: a clear error and exit code 1.
    const std::string errFile = (dir / "err.txt").string();
    auto bad =
        test::runCommand(std::string(GEOSLICE_BINARY) + " bake " + model +
                         " --size 64 --min-density 1 --max-pages 1 --out " + (dir / "pkg2").string() + " 2>" + errFile);
    EXPECT_EQ(bad.exitCode, 1);
    std::ifstream err(errFile);
    const std::string msg((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
    EXPECT_NE(msg.find("does not fit the texture budget"), std::string::npos) << msg;
    EXPECT_EQ(test::runGeoslice("bake " + (dir / "missing.glb").string() + " --out " + out).exitCode, 1);
    // A block-model field: class records appear in the package's table; a bad CSV is exit 1.
    {
        std::ofstream csv(dir / "blocks.csv");
        csv << "x,y,z,dx,dy,dz,SiO2\n1500,2000,700,3000,4000,3000,90\n4500,2000,700,3000,4000,3000,99\n";
    }
    r = test::runGeoslice("bake " + model + " --size 512 --field " + (dir / "blocks.csv").string() +
                          " --breaks 95,98 --field-unit '% SiO2' --out " + (dir / "pkgf").string());
    ASSERT_EQ(r.exitCode, 0);
    auto withField = bake::loadPackage((dir / "pkgf").string());
    ASSERT_TRUE(withField.ok()) << withField.error().message;
    std::size_t classRecords = 0;
    for (const auto& [id, rec] : withField->attributes.records()) classRecords += rec.extra.contains("class");
    EXPECT_GT(classRecords, 0u);
    EXPECT_EQ(classRecords % 3, 0u);  // three classes for each part record
    {
        std::ofstream csv(dir / "bad.csv");
        csv << "x,y,z,dx,dy,dz,SiO2\n1,2,3,4,5,-6,7\n";
    }
    EXPECT_EQ(test::runGeoslice("bake " + model + " --field " + (dir / "bad.csv").string() + " --out " + out).exitCode,
              1);
    fs::remove_all(dir);
}
