// A model's CRS from its declarations (model/crs/model_crs.hpp, loadModel): the file's own, the
// JSON sidecar's "crs", a <stem>.crs file and --crs, with their precedence and warnings.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "model/crs/model_crs.hpp"
#include "model/io/gltf/gltf_io.hpp"
#include "model/io/loaders.hpp"
#include "model/synthetic/synthetic.hpp"

namespace geoslice {
namespace {

namespace fs = std::filesystem;

// A fresh directory under the test temp dir, removed at the end.
class TempDir {
public:
    TempDir() {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/geoslice_model_crs_XXXXXX";
        GS_ASSERT(mkdtemp(pattern.data()) != nullptr, "mkdtemp failed");
        path_ = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    std::string file(const std::string& name, const std::string& contents) const {
        const std::string p = (fs::path(path_) / name).string();
        std::ofstream(p, std::ios::binary) << contents;
        return p;
    }

private:
    std::string path_;
};

Result<Model> loadWithCrs(const std::string& path, const std::string& crs) {
    LoadOptions o;
    o.crs = crs;
    return loadModel(path, o);
}

// A closed tetrahedron near Bern in LV95 metres (OBJ carries no CRS).
const char* kTetraObj =
    "o Rock\n"
    "v 2600000 1200000 500\nv 2600100 1200000 500\nv 2600000 1200100 500\nv 2600000 1200000 600\n"
    "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

TEST(ModelCrs, ObjIsLocalUntilDeclared) {
    TempDir dir;
    const auto m = loadModel(dir.file("rock.obj", kTetraObj));
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_TRUE(m->crs.isLocal());
    EXPECT_EQ(m->notes.count("crs_warning"), 0u);
}

TEST(ModelCrs, SidecarDeclaresForObj) {
    TempDir dir;
    const std::string obj = dir.file("rock.obj", kTetraObj);
    const std::string side = dir.file("rock.attributes.json", R"({"crs": "EPSG:2056"})");
    const auto m = loadModel(obj);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->crs.epsg(), 2056);
    EXPECT_EQ(m->notes.at("crs_source"), side);
    EXPECT_EQ(m->notes.count("crs_warning"), 0u);
    // With records too, and by name.
    dir.file("rock.attributes.json", R"({"crs": "CH1903+ / LV95", "records": [{"id": 7, "name": "Rock"}]})");
    const auto named = loadModel(obj);
    ASSERT_TRUE(named.ok()) << named.error().message;
    EXPECT_EQ(named->crs.epsg(), 2056);
    // A bad value names the sidecar.
    dir.file("rock.attributes.json", R"({"crs": "EPSG:99999"})");
    const auto bad = loadModel(obj);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("rock.attributes.json"), std::string::npos) << bad.error().message;
    EXPECT_NE(bad.error().message.find("99999"), std::string::npos) << bad.error().message;
    dir.file("rock.attributes.json", R"({"crs": 2056})");
    EXPECT_FALSE(loadModel(obj).ok());
}

TEST(ModelCrs, CrsFileAndFlagOverrideWithWarnings) {
    TempDir dir;
    const std::string obj = dir.file("rock.obj", kTetraObj);
    dir.file("rock.attributes.json", R"({"crs": "EPSG:2056"})");
    const std::string crsFile = dir.file("rock.crs", "EPSG:21781\n");
    const auto m = loadModel(obj);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->crs.epsg(), 21781);
    EXPECT_EQ(m->notes.at("crs_source"), crsFile);
    const std::string& w = m->notes.at("crs_warning");
    EXPECT_NE(w.find("overrides EPSG:2056"), std::string::npos) << w;
    EXPECT_NE(w.find("EPSG:21781"), std::string::npos) << w;

    const auto flag = loadWithCrs(obj, "EPSG:2056");
    ASSERT_TRUE(flag.ok()) << flag.error().message;
    EXPECT_EQ(flag->crs.epsg(), 2056);
    EXPECT_EQ(flag->notes.at("crs_source"), "--crs");
    EXPECT_NE(flag->notes.at("crs_warning").find("--crs overrides EPSG:21781"), std::string::npos)
        << flag->notes.at("crs_warning");

    const auto local = loadWithCrs(obj, "local");
    ASSERT_TRUE(local.ok()) << local.error().message;
    EXPECT_TRUE(local->crs.isLocal());
}

TEST(ModelCrs, FeetAreRefusedForModels) {
    TempDir dir;
    const std::string obj = dir.file("rock.obj", kTetraObj);
    const auto m = loadWithCrs(obj, "EPSG:2227");
    ASSERT_FALSE(m.ok());
    EXPECT_EQ(m.error().code, ErrorCode::Unsupported);
    EXPECT_NE(m.error().message.find("US survey foot"), std::string::npos) << m.error().message;
    EXPECT_NE(m.error().message.find("--crs"), std::string::npos) << m.error().message;
}

TEST(ModelCrs, FileDeclarationWinsOverSidecar) {
    SyntheticOptions o;
    o.triangles = 2000;
    o.crs = Crs::fromEpsg(4523).value();
    auto model = generateSynthetic(o);
    ASSERT_TRUE(model.ok()) << model.error().message;
    auto glb = encodeGlb(model.value());
    ASSERT_TRUE(glb.ok()) << glb.error().message;
    TempDir dir;
    const std::string path = dir.file("mine.glb", std::string(glb->begin(), glb->end()));
    dir.file("mine.attributes.json", R"({"crs": "EPSG:2056"})");
    const auto m = loadModel(path);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->crs.epsg(), 4523);
    const std::string& w = m->notes.at("crs_warning");
    EXPECT_NE(w.find("declares EPSG:2056"), std::string::npos) << w;
    EXPECT_NE(w.find("keeping EPSG:4523"), std::string::npos) << w;
    // --crs is explicit: it wins.
    const auto over = loadWithCrs(path, "EPSG:4544");
    ASSERT_TRUE(over.ok()) << over.error().message;
    EXPECT_EQ(over->crs.epsg(), 4544);
}

TEST(ModelCrs, DeclareDirectly) {
    Model m;
    EXPECT_TRUE(declareModelCrs(m, "GDA2020 / MGA zone 55", CrsDeclaration::Override, "test").ok());
    EXPECT_EQ(m.crs.epsg(), 7855);
    const auto s = declareModelCrs(m, "not a crs at all", CrsDeclaration::Sidecar, "side.json");
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("side.json"), std::string::npos) << s.error().message;
    EXPECT_EQ(m.crs.epsg(), 7855);  // unchanged on error
}

}  // namespace
}  // namespace geoslice
