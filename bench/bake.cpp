// bench_bake [--sizes L1,L2,L3,L4] [--size 4096] [--points 1000000] [--threads 2] [--out DIR]:
// the attribute-indexed texture bake (issue 4). Per model size: generate (EPSG:4523), bake
// (wall and CPU time per stage, peak RSS of the bake phase), chart count, split charts, texel
// utilisation, angle and area distortion; write the package (time, bytes per file); load it
// back (time, warm page cache: the package was just written) and its resident size (texture
// + mesh arrays: what a renderer uploads, the GPU figure); and the paper's attribute mapping
// accuracy: for `points` random surface points (area-uniform per triangle pick, barycentric
// interpolation of the loaded float UVs in float, as a GPU does) the id at the nearest texel
// against the part's record. Also the incremental re-bake of the largest and of the smallest
// body after a geometry change (time, fraction of the full bake, that part's accuracy).
// Prints one JSON document.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "bake/bake.hpp"
#include "bake/package.hpp"
#include "bench/bench_util.hpp"
#include "model/synthetic/synthetic.hpp"

using namespace geoslice;
using json = nlohmann::ordered_json;

namespace {

// Accuracy over the loaded package (bake::sampleIdAccuracy, the function the tests check);
// parts are sampled in proportion to their triangles.
json accuracy(const bake::Package& pkg, std::size_t points, std::uint64_t seed) {
    const bake::IdAccuracy a = bake::sampleIdAccuracy(pkg, points, seed);
    return {{"points", a.points}, {"correct", a.correct}, {"percent", 100.0 * a.fraction()}};
}

}  // namespace

int main(int argc, char** argv) {
    std::string sizes = "L1,L2,L3,L4";
    std::uint32_t side = 4096;
    std::size_t points = 1000000;
    unsigned threads = 2;
    std::string outDir = (std::filesystem::temp_directory_path() / "geoslice_bench_bake").string();
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--sizes"))
            sizes = argv[i + 1];
        else if (!std::strcmp(argv[i], "--size"))
            side = static_cast<std::uint32_t>(std::stoul(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--points"))
            points = std::stoul(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--threads"))
            threads = static_cast<unsigned>(std::stoul(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--out"))
            outDir = argv[i + 1];
    }
    json results = json::array();
    std::stringstream list(sizes);
    std::string size;
    while (std::getline(list, size, ',')) {
        json r;
        r["size"] = size;
        SyntheticOptions so;
        so.triangles = bench::triangleCountFor(size);
        so.crs = Crs::fromEpsg(4523).value();
        double t = bench::nowSeconds();
        auto model = generateSynthetic(so);
        if (!model) {
            std::fprintf(stderr, "%s\n", model.error().message.c_str());
            return 1;
        }
        r["triangles"] = model->triangleCount();
        r["generateSeconds"] = bench::nowSeconds() - t;
        const double rssModel = bench::currentRssMiB();

        bake::BakeOptions bo;
        bo.pack.width = bo.pack.height = side;
        bo.threads = threads;
        bench::resetPeakRss();
        t = bench::nowSeconds();
        const double cpu0 = bench::processCpuSeconds();
        auto baked = bake::bakeModel(model.value(), bo);
        const double bakeS = bench::nowSeconds() - t, bakeCpu = bench::processCpuSeconds() - cpu0;
        if (!baked) {
            std::fprintf(stderr, "%s\n", baked.error().message.c_str());
            return 1;
        }
        const auto& st = baked->stats;
        r["bake"] = {{"seconds", bakeS},
                     {"cpuSeconds", bakeCpu},
                     {"threads", threads},
                     {"stages",
                      {{"charts", st.secondsCharts},
                       {"lscm", st.secondsLscm},
                       {"pack", st.secondsPack},
                       {"raster", st.secondsRaster}}},
                     {"peakRssMiB", bench::peakRssSinceResetMiB()},
                     {"modelRssMiB", rssModel},
                     {"charts", st.charts},
                     {"splitCharts", st.splitCharts},
                     {"vertices", st.vertices},
                     {"pages", baked->pages},
                     {"texture", std::to_string(baked->width) + "x" + std::to_string(baked->height)},
                     {"texelsPerMetre", baked->density},
                     {"texelUtilisation", st.texelUtilisation},
                     {"angleDistortion", {{"mean", st.distortion.meanAngle}, {"max", st.distortion.maxAngle}}},
                     {"areaDistortion", {{"mean", st.distortion.meanArea}, {"max", st.distortion.maxArea}}}};

        // Incremental re-bake of one body (geometry changed: lifted 1 m, stretched 1 % east), the
        // largest and the smallest, each on a copy of the full bake.
        json rebake = json::array();
        for (const bool largest : {true, false}) {
            std::size_t p = baked->parts.size();
            for (std::size_t i = 0; i < baked->parts.size(); ++i) {
                if (baked->parts[i].source >= model->bodies.size()) continue;
                const std::size_t n = baked->parts[i].indices.size();
                if (p == baked->parts.size() ||
                    (largest ? n > baked->parts[p].indices.size() : n < baked->parts[p].indices.size()))
                    p = i;
            }
            if (p == baked->parts.size()) break;
            for (auto& q : model->bodies[baked->parts[p].source].mesh.positions)
                q = {q.x * 1.01 - 0.01 * model->origin.x, q.y, q.z + 1.0};
            bake::BakedModel copy = baked.value();
            t = bench::nowSeconds();
            auto st2 = bake::rebakePart(model.value(), p, copy, bo);
            const double rebakeS = bench::nowSeconds() - t;
            json entry = {{"body", copy.parts[p].name},
                          {"triangles", copy.parts[p].indices.size() / 3},
                          {"ok", st2.ok()},
                          {"seconds", rebakeS},
                          {"fractionOfFullBake", rebakeS / bakeS},
                          {"pagesAfter", copy.pages}};
            if (!st2.ok())
                entry["error"] = st2.error().message;
            else
                entry["accuracyPercent"] = 100.0 * bake::partIdAccuracy(copy, p, 200000, 99);
            rebake.push_back(entry);
        }
        r["rebake"] = rebake;

        const std::string dir = outDir + "/" + size;
        t = bench::nowSeconds();
        if (auto s = bake::writePackage(model.value(), baked.value(), dir); !s) {
            std::fprintf(stderr, "%s\n", s.error().message.c_str());
            return 1;
        }
        json files = json::object();
        for (const char* f : {bake::kMeshFile, bake::kTextureFile, bake::kAttributesFile, bake::kManifestFile})
            files[f] = std::filesystem::file_size(std::filesystem::path(dir) / f);
        r["write"] = {{"seconds", bench::nowSeconds() - t}, {"bytes", files}};
        baked = bake::BakedModel{};
        model = Model{};

        const double rssBefore = bench::currentRssMiB();
        t = bench::nowSeconds();
        auto pkg = bake::loadPackage(dir);
        const double loadS = bench::nowSeconds() - t;
        if (!pkg) {
            std::fprintf(stderr, "%s\n", pkg.error().message.c_str());
            return 1;
        }
        const double rssLoaded = bench::currentRssMiB();
        bake::PackageReadOptions noSums;
        noSums.verifyChecksums = false;
        t = bench::nowSeconds();
        auto pkg2 = bake::loadPackage(dir, noSums);
        const double loadNoSumsS = bench::nowSeconds() - t;
        pkg2 = Error{};
        r["load"] = {{"seconds", loadS},
                     {"secondsWithoutChecksums", loadNoSumsS},
                     {"cache", "warm (package just written)"},
                     {"rssDeltaMiB", rssLoaded - rssBefore},
                     {"residentMiB", double(pkg->residentBytes()) / (1024.0 * 1024.0)},
                     {"textureMiB", double(pkg->texels.size()) * 4.0 / (1024.0 * 1024.0)}};
        // What the renderer uploads for this package (renderer/gpu_model.cpp): the R32UI
        // texture array, float32 positions and UVs, uint32 indices. Computed from the buffer
        // sizes (a GPU driver adds its own padding); measure with the device where one is lent.
        std::size_t vertices = 0, indices = 0;
        for (const auto& part : pkg->parts) {
            vertices += part.vertexCount;
            indices += part.indexCount;
        }
        const double mib = 1024.0 * 1024.0;
        r["gpuEstimate"] = {{"textureMiB", double(pkg->texels.size()) * 4.0 / mib},
                            {"positionsMiB", double(vertices) * 12.0 / mib},
                            {"uvsMiB", double(vertices) * 8.0 / mib},
                            {"indicesMiB", double(indices) * 4.0 / mib},
                            {"totalMiB", double(pkg->texels.size() * 4 + vertices * 20 + indices * 4) / mib}};
        t = bench::nowSeconds();
        r["accuracy"] = accuracy(pkg.value(), points, 12345);
        r["accuracy"]["seconds"] = bench::nowSeconds() - t;
        results.push_back(r);
        std::fprintf(stderr, "%s done\n", size.c_str());
    }
    std::printf("%s\n", json{{"benchmark", "bake"}, {"results", results}}.dump(2).c_str());
    return 0;
}
