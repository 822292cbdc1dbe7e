// bench_drillholes [--holes 10000] [--intervals 100] [--stations 20] [--repeats 3]:
// a generated drillhole database (collar.csv, survey.csv and lithology.csv written to a
// temporary folder: `holes` curved holes, `stations` survey stations and `intervals` 3 m
// intervals each, a text and a number column) read by loadDrillholes (CSV, validation,
// minimum curvature desurvey), median wall and process CPU seconds of `repeats` loads (goal
// <= 1 s on one core for 10,000 x 100 x 20), and the desurvey alone; then the segment index
// (model/drillholes/hole_index.hpp): its build, and the median time to find the holes within
// 50 m of a new plane (`planes` random vertical, inclined and horizontal planes through the
// field; goal <= 1 ms); and a 1024 x 1024 profile image of the demo mine (api::renderProfile,
// 200,000 triangles, its 32 generated holes) with holes drawn (holes=200&holecolour=unit) and
// without (holes=0), interleaved, median of `repeats` x 3 (at least 5) each over three
// vertical sections (goal: with <= 1.2 x without). Single-threaded. Prints one JSON document.
#include <unistd.h>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "api/holes.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "bench/bench_util.hpp"
#include "model/drillholes/drillholes.hpp"
#include "model/drillholes/hole_index.hpp"

using namespace geoslice;

int main(int argc, char** argv) {
    std::size_t holes = 10000, intervals = 100, stations = 20, repeats = 3, planes = 200;
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
        else if (k == "--planes")
            planes = std::max<std::size_t>(v, 1);
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
    std::optional<DrillholeDatabase> last;
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
        last = std::move(db.value());
    }
    // The index, and the holes near new planes: vertical planes of any strike, planes dipping
    // 30-80 degrees and horizontal slices, all through the field (500-505 km E, 3600-3605 km N,
    // collars at 1000-1100 m, holes 3 x intervals m long).
    const double b0 = bench::nowSeconds();
    const HoleIndex index(*last);
    const double buildWall = bench::nowSeconds() - b0;
    std::mt19937_64 prng(7);
    std::uniform_real_distribution<double> pu(0.0, 1.0);
    std::vector<double> nearMs, nearCpuMs;
    std::vector<double> found;
    const double window = 50.0;
    for (std::size_t i = 0; i < planes; ++i) {
        const glm::dvec3 through(502500.0 + 2000.0 * (pu(prng) - 0.5), 3602500.0 + 2000.0 * (pu(prng) - 0.5),
                                 1000.0 - 1.5 * double(intervals) * pu(prng));
        const double strike = 6.283185307179586 * pu(prng);
        const int kind = int(i % 3);
        const double dip = kind == 0 ? 1.5707963267948966 : kind == 1 ? (0.52 + 0.87 * pu(prng)) : 0.0;
        const glm::dvec3 n(std::sin(dip) * std::cos(strike), std::sin(dip) * std::sin(strike), std::cos(dip));
        const double d = -glm::dot(n, through);
        timespec c0{}, c1{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c0);
        const double t0 = bench::nowSeconds();
        const std::vector<std::uint32_t> near = index.holesNearPlane(n, d, window);
        nearMs.push_back(1e3 * (bench::nowSeconds() - t0));
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c1);
        nearCpuMs.push_back(1e3 * double(c1.tv_sec - c0.tv_sec) + 1e-6 * double(c1.tv_nsec - c0.tv_nsec));
        found.push_back(double(near.size()));
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    // Profile images with and without holes.
    auto demo = api::makeDemoModel(200000);
    if (!demo) {
        std::fprintf(stderr, "bench_drillholes: %s\n", demo.error().message.c_str());
        return 1;
    }
    const api::CatalogModel& m = *demo.value();
    const glm::dvec3 centre = m.index->bounds.centre();
    std::vector<double> withMs, withoutMs, withCpuMs, withoutCpuMs, overlayMs, drawnPieces;
    const std::size_t imageRepeats = std::max<std::size_t>(5, 5 * repeats);
    for (std::size_t r = 0; r < imageRepeats; ++r)
        for (int k = 0; k < 3; ++k) {
            const double y = centre.y + 800.0 * (k - 1);
            char plane[96];
            std::snprintf(plane, sizeof plane, "0,1,0,%.17g", -y);
            for (const bool holesOn : {true, false}) {
                api::Params p{{"plane", plane}, {"size", "1024x1024"}};
                if (holesOn) {
                    p["holes"] = "200";
                    p["holecolour"] = "unit";
                } else {
                    p["holes"] = "0";
                }
                auto plan = api::parseViewPlan(p, "demo", m.model.crs);
                if (!plan) return 1;
                const double t0 = bench::nowSeconds(), c0 = bench::processCpuSeconds();
                auto image = api::renderProfile(m, plan.value());
                (holesOn ? withMs : withoutMs).push_back(1e3 * (bench::nowSeconds() - t0));
                (holesOn ? withCpuMs : withoutCpuMs).push_back(1e3 * (bench::processCpuSeconds() - c0));
                if (!image) return 1;
                if (holesOn) {
                    // The drawing alone: project and draw over the finished image again.
                    const double o0 = bench::nowSeconds();
                    auto drawn = api::viewHoles(m, plan.value().section, *image.value().mapping);
                    if (!drawn) return 1;
                    api::drawHoles(m, drawn.value(), *image.value().mapping, image.value());
                    overlayMs.push_back(1e3 * (bench::nowSeconds() - o0));
                    drawnPieces.push_back(double(drawn.value().section.pieces.size()));
                }
            }
        }
    const double withMedian = bench::median(withMs), withoutMedian = bench::median(withoutMs);
    nlohmann::ordered_json j = {
        {"benchmark", "drillholes"},
        {"holes", holes},
        {"stations", stationCount},
        {"intervals", intervalCount},
        {"warnings", warnings},
        {"load_desurvey_wall_s_median", bench::median(wall)},
        {"load_desurvey_cpu_s_median", bench::median(cpu)},
        {"desurvey_only_wall_s", desurveyWall},
        {"goal_s", 1.0},
        {"index_segments", index.segments().size()},
        {"index_segments_per_hole", double(index.segments().size()) / double(holes)},
        {"index_nodes", index.nodeCount()},
        {"index_build_wall_s", buildWall},
        {"holes_near_plane_window_m", window},
        {"holes_near_plane_planes", planes},
        {"holes_near_plane_ms_median", bench::median(nearMs)},
        {"holes_near_plane_ms_max", *std::max_element(nearMs.begin(), nearMs.end())},
        {"holes_near_plane_thread_cpu_ms_median", bench::median(nearCpuMs)},
        {"holes_near_plane_found_median", bench::median(found)},
        {"holes_near_plane_goal_ms", 1.0},
        {"section_1024_images_each", withMs.size()},
        {"section_1024_without_holes_ms_median", withoutMedian},
        {"section_1024_with_holes_ms_median", withMedian},
        {"section_1024_holes_ratio", withMedian / withoutMedian},
        {"section_1024_without_holes_cpu_ms_median", bench::median(withoutCpuMs)},
        {"section_1024_with_holes_cpu_ms_median", bench::median(withCpuMs)},
        {"section_1024_holes_cpu_ratio", bench::median(withCpuMs) / bench::median(withoutCpuMs)},
        {"section_1024_holes_overlay_ms_median", bench::median(overlayMs)},
        {"section_1024_holes_pieces_median", bench::median(drawnPieces)},
        {"section_1024_holes_ratio_goal", 1.2},
        {"peak_rss_mib", bench::peakRssMiB()},
        {"load_average", bench::loadAverage()}};
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
}
