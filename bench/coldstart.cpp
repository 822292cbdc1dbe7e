// bench_coldstart PACKAGE_DIR... [--repeat N] [--rebuild]: what a server's start costs per
// baked package, phase by phase, in process (no HTTP): map + checksum the package
// (loadPackage), the model from it (packageModel: no validation), the section index from the
// stored BVH (loadSectionIndex), the one shared Embree scene (RayScene), and in all (the
// catalog's loadCatalogModel, which runs the index and the scene side by side). With
// --rebuild it also times what start-up did before packages carried these: the model through
// the glTF loader with validation, the BVH built, and the two Embree scenes of the classifier
// and the tracer. Prints one JSON document: medians of N runs per phase, seconds, with the
// load average at the start (the machine is shared; quote it with any figure).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "bake/package.hpp"
#include "bench/bench_util.hpp"
#include "model/loaders.hpp"
#include "section/borehole.hpp"
#include "section/classify.hpp"
#include "section/ray_scene.hpp"
#include "section/section_index.hpp"

using namespace geoslice;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

std::string loadAverage() {
    double l[3] = {0, 0, 0};
    if (getloadavg(l, 3) != 3) return "unknown";
    char b[64];
    std::snprintf(b, sizeof b, "%.2f %.2f %.2f", l[0], l[1], l[2]);
    return b;
}

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "bench_coldstart: %s\n", what.c_str());
    std::exit(1);
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> dirs;
    int repeat = 3;
    bool rebuild = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeat" && i + 1 < argc)
            repeat = std::max(1, std::atoi(argv[++i]));
        else if (a == "--rebuild")
            rebuild = true;
        else if (a.rfind("--", 0) == 0)
            fail("unknown option " + a + " (PACKAGE_DIR... [--repeat N] [--rebuild])");
        else
            dirs.push_back(a);
    }
    if (dirs.empty()) fail("usage: bench_coldstart PACKAGE_DIR... [--repeat N] [--rebuild]");

    nlohmann::ordered_json out;
    out["bench"] = "coldstart";
    out["loadAverageAtStart"] = loadAverage();
    out["repeat"] = repeat;
    for (const std::string& dir : dirs) {
        std::vector<double> tPkg, tModel, tIndex, tScene, tAll, tOldModel, tOldBvh, tOldScenes;
        std::size_t triangles = 0;
        for (int r = 0; r < repeat; ++r) {
            double t0 = bench::nowSeconds();
            auto pkg = bake::loadPackage(dir);
            if (!pkg) fail(pkg.error().message);
            double t1 = bench::nowSeconds();
            auto model = bake::packageModel(pkg.value());
            if (!model) fail(model.error().message);
            double t2 = bench::nowSeconds();
            auto index = loadSectionIndex(model.value(), pkg->sectionBvh, dir);
            if (!index) fail(index.error().message);
            double t3 = bench::nowSeconds();
            auto scene = RayScene::build(model.value());
            if (!scene) fail(scene.error().message);
            double t4 = bench::nowSeconds();
            tPkg.push_back(t1 - t0);
            tModel.push_back(t2 - t1);
            tIndex.push_back(t3 - t2);
            tScene.push_back(t4 - t3);
            triangles = model->triangleCount();
            index.value().reset();
            scene.value().reset();

            t0 = bench::nowSeconds();
            auto all = api::loadCatalogModel("bench", dir);
            if (!all) fail(all.error().message);
            tAll.push_back(bench::nowSeconds() - t0);
            all.value().reset();

            if (rebuild) {
                t0 = bench::nowSeconds();
                auto old = loadModel((std::filesystem::path(dir) / bake::kMeshFile).string());
                if (!old) fail(old.error().message);
                t1 = bench::nowSeconds();
                auto built = buildSectionIndex(old.value());
                if (!built) fail(built.error().message);
                t2 = bench::nowSeconds();
                auto c = Classifier::build(old.value());
                auto tr = BoreholeTracer::build(old.value());
                if (!c || !tr) fail("Embree scene build failed");
                t3 = bench::nowSeconds();
                tOldModel.push_back(t1 - t0);
                tOldBvh.push_back(t2 - t1);
                tOldScenes.push_back(t3 - t2);
            }
        }
        nlohmann::ordered_json j;
        j["package"] = dir;
        j["triangles"] = triangles;
        j["seconds"] = {{"loadPackage", median(tPkg)},
                        {"packageModel", median(tModel)},
                        {"loadSectionIndex", median(tIndex)},
                        {"rayScene", median(tScene)},
                        {"loadCatalogModel", median(tAll)}};
        if (rebuild)
            j["secondsBefore"] = {{"loadModelWithValidation", median(tOldModel)},
                                  {"buildSectionIndex", median(tOldBvh)},
                                  {"twoEmbreeScenes", median(tOldScenes)}};
        j["peakRssMiB"] = bench::peakRssMiB();
        out["packages"].push_back(j);
    }
    out["loadAverageAtEnd"] = loadAverage();
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
