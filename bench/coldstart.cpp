// bench_coldstart PACKAGE_DIR... [--repeat N] [--rebuild]: what a server's start costs per
// baked package, phase by phase, in process (no HTTP): map + checksum the package
// (loadPackage), the model from it (packageModel: no validation), the section index from the
// stored BVH (loadSectionIndex), the one shared Embree scene (RayScene), and in all (the
// catalog's loadCatalogModel, what a server does before /readyz, and catalogRays: the ray
// scene it then builds in the background, section/rays/ray_queries.hpp). With
// --rebuild it also times what start-up did before packages carried these: the model through
// the glTF loader with validation, the BVH built, and the two Embree scenes of the classifier
// and the tracer. --quality low|medium|high and --compact choose the Embree build, and the
// first run times --rays classify() calls and rays/20 vertical boreholes on that scene (one
// thread), so the build's saving can be weighed against the queries. Prints one JSON document: medians of N runs per
// phase, seconds, with the load average at the start (the machine is shared; quote it with any figure).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "bake/package.hpp"
#include "bench/bench_util.hpp"
#include "model/io/loaders.hpp"
#include "section/index/section_index.hpp"
#include "section/rays/borehole.hpp"
#include "section/rays/classify.hpp"
#include "section/rays/ray_scene.hpp"

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
    RaySceneOptions sceneOptions;
    int rays = 20000;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeat" && i + 1 < argc)
            repeat = std::max(1, std::atoi(argv[++i]));
        else if (a == "--rebuild")
            rebuild = true;
        else if (a == "--quality" && i + 1 < argc) {
            const std::string q = argv[++i];
            sceneOptions.quality = q == "low"    ? RTC_BUILD_QUALITY_LOW
                                   : q == "high" ? RTC_BUILD_QUALITY_HIGH
                                                 : RTC_BUILD_QUALITY_MEDIUM;
        } else if (a == "--compact")
            sceneOptions.compact = true;
        else if (a == "--rays" && i + 1 < argc)
            rays = std::max(0, std::atoi(argv[++i]));
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
        // Wall and process-CPU seconds per phase (CPU is what a quiet 2-core machine would
        // spend; on this shared one the wall time includes waiting for the cores).
        std::map<std::string, std::vector<double>> wall, cpu;
        auto timed = [&](const std::string& name, auto&& fn) {
            const double w0 = bench::nowSeconds(), c0 = bench::processCpuSeconds();
            fn();
            wall[name].push_back(bench::nowSeconds() - w0);
            cpu[name].push_back(bench::processCpuSeconds() - c0);
        };
        std::size_t triangles = 0, checksum = 0;
        double classifyUs = 0.0, boreholeUs = 0.0;
        for (int r = 0; r < repeat; ++r) {
            Result<bake::Package> pkg = makeError(ErrorCode::Internal, "");
            Result<Model> model = makeError(ErrorCode::Internal, "");
            Result<std::unique_ptr<SectionIndex>> index = makeError(ErrorCode::Internal, "");
            Result<std::shared_ptr<const RayScene>> scene = makeError(ErrorCode::Internal, "");
            timed("loadPackage", [&] { pkg = bake::loadPackage(dir); });
            if (!pkg) fail(pkg.error().message);
            timed("packageModel", [&] { model = bake::packageModel(pkg.value()); });
            if (!model) fail(model.error().message);
            timed("loadSectionIndex", [&] { index = loadSectionIndex(model.value(), pkg->sectionBvh, dir); });
            if (!index) fail(index.error().message);
            timed("rayScene", [&] { scene = RayScene::build(model.value(), sceneOptions); });
            if (!scene) fail(scene.error().message);
            triangles = model->triangleCount();
            if (r == 0 && rays > 0) {
                // What the scene's quality costs the queries: classify points and vertical
                // boreholes at seeded random places in the model's box, one thread.
                auto c = Classifier::build(model.value(), scene.value());
                auto tr = BoreholeTracer::build(model.value(), scene.value());
                if (!c || !tr) fail("classifier or tracer");
                const Aabb b = model->bounds();
                std::mt19937_64 rng(1);
                std::uniform_real_distribution<double> u(0.0, 1.0);
                std::size_t hits = 0;
                const double q0 = bench::nowSeconds();
                for (int k = 0; k < rays; ++k) {
                    const glm::dvec3 p = b.min + glm::dvec3(u(rng), u(rng), u(rng)) * (b.max - b.min);
                    hits += c.value()->classify(p) != kNoRecord;
                }
                const double q1 = bench::nowSeconds();
                const int holes = std::max(1, rays / 20);
                for (int k = 0; k < holes; ++k) {
                    auto h = tr.value()->traceVertical(b.min.x + u(rng) * (b.max.x - b.min.x),
                                                       b.min.y + u(rng) * (b.max.y - b.min.y));
                    if (h) hits += h->intervals.size();
                }
                const double q2 = bench::nowSeconds();
                classifyUs = (q1 - q0) / rays * 1e6;
                boreholeUs = (q2 - q1) / holes * 1e6;
                checksum = hits;
            }
            index.value().reset();
            scene.value().reset();
            // What a server does before /readyz (the ray scene deferred), then the catalog's
            // background ray build to the end (what ray queries wait for).
            Result<std::shared_ptr<const api::CatalogModel>> all = makeError(ErrorCode::Internal, "");
            timed("loadCatalogModel", [&] {
                all = api::loadCatalogModel("bench", dir, "", true, api::RayBuild::Deferred);
                if (!all) fail(all.error().message);
            });
            timed("catalogRays", [&] {
                all.value()->rays->start();
                if (auto e = all.value()->rays->wait(); !e) fail(e.error().message);
            });
            all = makeError(ErrorCode::Internal, "");
            if (rebuild) {
                Result<Model> old = makeError(ErrorCode::Internal, "");
                timed("before.loadModelWithValidation",
                      [&] { old = loadModel((std::filesystem::path(dir) / bake::kMeshFile).string()); });
                if (!old) fail(old.error().message);
                timed("before.buildSectionIndex", [&] {
                    if (!buildSectionIndex(old.value())) fail("buildSectionIndex");
                });
                timed("before.twoEmbreeScenes", [&] {
                    if (!Classifier::build(old.value()) || !BoreholeTracer::build(old.value())) fail("Embree");
                });
            }
        }
        nlohmann::ordered_json j;
        j["package"] = dir;
        j["triangles"] = triangles;
        for (const auto& [name, v] : wall) j["wallSeconds"][name] = median(v);
        for (const auto& [name, v] : cpu) j["cpuSeconds"][name] = median(v);
        j["rayScene"] = {{"quality", sceneOptions.quality == RTC_BUILD_QUALITY_LOW    ? "low"
                                     : sceneOptions.quality == RTC_BUILD_QUALITY_HIGH ? "high"
                                                                                      : "medium"},
                         {"compact", sceneOptions.compact},
                         {"classifyMicroseconds", classifyUs},
                         {"verticalBoreholeMicroseconds", boreholeUs},
                         {"hitsChecksum", checksum}};
        j["peakRssMiB"] = bench::peakRssMiB();
        out["packages"].push_back(j);
    }
    out["loadAverageAtEnd"] = loadAverage();
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
