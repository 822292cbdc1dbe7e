// bench_classify [--size L4] [--points N] [--runs R]: the exact oracle's throughput.
// Generates the synthetic model in memory, builds the Embree classifier, then classifies
// N uniform random points in the model's bounds, R times, with 1 thread and with all
// cores. Prints JSON: build time, rates (median of runs), fraction of points inside a body.
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "section/rays/classify.hpp"

using namespace geoslice;

int main(int argc, char** argv) {
    std::string size = "L4";
    std::size_t nPoints = 2'000'000;
    int runs = 5;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size"))
            size = argv[i + 1];
        else if (!std::strcmp(argv[i], "--points"))
            nPoints = std::stoul(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--runs"))
            runs = std::stoi(argv[i + 1]);
    }
    SyntheticOptions so;
    so.triangles = bench::triangleCountFor(size);
    so.crs = Crs::fromEpsg(4523).value();
    double t0 = bench::nowSeconds();
    auto model = generateSynthetic(so);
    if (!model) {
        std::fprintf(stderr, "%s\n", model.error().message.c_str());
        return 1;
    }
    validate(model.value());
    double t1 = bench::nowSeconds();
    auto cls = Classifier::build(model.value());
    if (!cls) {
        std::fprintf(stderr, "%s\n", cls.error().message.c_str());
        return 1;
    }
    double t2 = bench::nowSeconds();

    Aabb b = model->bounds();
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> ux(b.min.x, b.max.x), uy(b.min.y, b.max.y), uz(b.min.z, b.max.z);
    std::vector<glm::dvec3> pts(nPoints);
    for (auto& p : pts) p = {ux(rng), uy(rng), uz(rng)};
    std::vector<RecordId> ids(nPoints);

    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    nlohmann::ordered_json rates = nlohmann::ordered_json::object();
    for (unsigned threads : {1u, cores}) {
        std::vector<double> r;
        for (int k = 0; k < runs; ++k) {
            double s = bench::nowSeconds();
            (*cls)->classifyBatch(pts.data(), pts.size(), ids.data(), threads);
            r.push_back(double(nPoints) / (bench::nowSeconds() - s));
        }
        rates[std::to_string(threads) + "_threads"] = {{"median_per_s", bench::median(r)}, {"runs", r}};
    }
    std::size_t inside = 0;
    for (RecordId id : ids) inside += id != kNoRecord;
    nlohmann::ordered_json out = {
        {"benchmark", "classify"},
        {"model", size},
        {"triangles", model->triangleCount()},
        {"crs", model->crs.id()},
        {"points", nPoints},
        {"cores", cores},
        {"generate_and_validate_s", t1 - t0},
        {"embree_build_s", t2 - t1},
        {"rate", rates},
        {"fraction_inside_bodies", double(inside) / double(nPoints)},
        {"peak_rss_mib", bench::peakRssMiB()},
    };
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
