// bench_drillholes [--holes 10000] [--intervals 100] [--stations 20] [--repeats 3]:
// a generated drillhole database (collar.csv, survey.csv and lithology.csv written to a
// temporary folder: `holes` curved holes, `stations` survey stations and `intervals` 3 m
// intervals each, a text and a number column) read by loadDrillholes (CSV, validation,
// minimum curvature desurvey), median wall and process CPU seconds of `repeats` loads (goal
// <= 1 s on one core for 10,000 x 100 x 20), and the desurvey alone. Single-threaded.
// Prints one JSON document.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "model/drillholes/drillholes.hpp"

using namespace geoslice;

int main(int argc, char** argv) {
    std::size_t holes = 10000, intervals = 100, stations = 20, repeats = 3;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i];
        const std::size_t v = std::stoul(argv[i + 1]);
        if (k == "--holes")
            holes = v;
        else if (k == "--intervals")
            intervals = v;
        else if (k == "--stations")
            stations = v;
        else if (k == "--repeats")
            repeats = v;
    }
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("bench_drillholes_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    {
        std::mt19937_64 rng(42);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::ofstream collar(dir / "collar.csv"), survey(dir / "survey.csv"), lith(dir / "lithology.csv");
        collar << "\xEF\xBB\xBFhole_ID,x,y,z,max_depth\n";
        survey << "hole_ID,depth,azimuth,dip\n";
        lith << "hole_ID,depth_from,depth_to,rock code,Cu_pct\n";
        const double length = 3.0 * double(intervals);
        char buf[160];
        for (std::size_t h = 0; h < holes; ++h) {
            std::snprintf(buf, sizeof buf, "DH-%05zu,%.2f,%.2f,%.2f,%.2f\n", h, 500000.0 + 5000.0 * u(rng),
                          3600000.0 + 5000.0 * u(rng), 1000.0 + 100.0 * u(rng), length);
            collar << buf;
            double az = 360.0 * u(rng), dip = -90.0 + 60.0 * u(rng);
            for (std::size_t s = 0; s < stations; ++s) {
                std::snprintf(buf, sizeof buf, "DH-%05zu,%.2f,%.2f,%.2f\n", h, length * double(s) / double(stations),
                              az, dip);
                survey << buf;
                az = std::fmod(az + 2.0 * u(rng) + 359.0, 360.0);
                dip = std::clamp(dip + 2.0 * u(rng) - 1.0, -89.0, -1.0);
            }
            for (std::size_t i = 0; i < intervals; ++i) {
                std::snprintf(buf, sizeof buf, "DH-%05zu,%zu,%zu,%s,%.3f\n", h, 3 * i, 3 * i + 3,
                              u(rng) < 0.5 ? "mgp" : "pqd", 2.0 * u(rng));
                lith << buf;
            }
        }
    }
    std::vector<double> wall, cpu;
    std::size_t warnings = 0, stationCount = 0, intervalCount = 0;
    double desurveyWall = 0.0;
    for (std::size_t r = 0; r < repeats; ++r) {
        const double w0 = bench::nowSeconds(), c0 = bench::processCpuSeconds();
        auto db = loadDrillholes(dir.string());
        wall.push_back(bench::nowSeconds() - w0);
        cpu.push_back(bench::processCpuSeconds() - c0);
        if (!db) {
            std::fprintf(stderr, "bench_drillholes: %s\n", db.error().message.c_str());
            return 1;
        }
        warnings = db->warnings.size();
        stationCount = db->stationCount();
        intervalCount = db->intervals.empty() ? 0 : db->intervals[0].size();
        const double d0 = bench::nowSeconds();
        std::size_t nodes = 0;
        for (const Drillhole& h : db->holes) nodes += desurvey(h.collar, h.stations, h.totalDepth).depth.size();
        desurveyWall = bench::nowSeconds() - d0;
        if (nodes == 0) return 1;
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    nlohmann::ordered_json j = {{"benchmark", "drillholes"},
                                {"holes", holes},
                                {"stations", stationCount},
                                {"intervals", intervalCount},
                                {"warnings", warnings},
                                {"load_desurvey_wall_s_median", bench::median(wall)},
                                {"load_desurvey_cpu_s_median", bench::median(cpu)},
                                {"desurvey_only_wall_s", desurveyWall},
                                {"goal_s", 1.0},
                                {"peak_rss_mib", bench::peakRssMiB()},
                                {"load_average", bench::loadAverage()}};
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
}
