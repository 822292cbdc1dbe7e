// bench_drillhole_check [--size L2] [--holes 545] [--stations 10] [--intervals 13] [--repeats 5]:
// the model checked against its drillholes (api/drillhole_check.hpp) on a generated model.
// Holes like Copper Creek's (545 holes, about 10 survey stations and 13 lithology intervals
// each): collars spread over the inner 80 % of the model's map extent, 1 m above its top,
// dipping 55-85 degrees at a random azimuth and curving a few degrees between stations, as
// deep as 60 % of the model's height. Each hole's lithology log is the model itself (the unit
// at each interval's middle, from one trace made beforehand), so the check does all its work
// (contacts found). Times checkDrillholes alone (tracing every hole along its chords,
// shares, contacts): median wall and process CPU of `repeats` runs; goal <= 1 s. One thread.
// Prints one JSON document.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "api/drillhole_check.hpp"
#include "bench/bench_util.hpp"
#include "model/json_text.hpp"
#include "model/mesh/validate.hpp"
#include "section/rays/borehole.hpp"

using namespace geoslice;

int main(int argc, char** argv) {
    std::string size = "L2";
    std::size_t holes = 545, stations = 10, intervals = 13, repeats = 5;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i], v = argv[i + 1];
        if (k == "--size") size = v;
        if (k == "--holes") holes = std::stoul(v);
        if (k == "--stations") stations = std::max<std::size_t>(std::stoul(v), 1);
        if (k == "--intervals") intervals = std::max<std::size_t>(std::stoul(v), 1);
        if (k == "--repeats") repeats = std::max<std::size_t>(std::stoul(v), 1);
    }
    SyntheticOptions so;
    so.triangles = bench::triangleCountFor(size);
    double t = bench::nowSeconds();
    auto model = generateSynthetic(so);
    if (!model) {
        std::fprintf(stderr, "%s\n", model.error().message.c_str());
        return 1;
    }
    validate(model.value());
    const double genS = bench::nowSeconds() - t;
    t = bench::nowSeconds();
    auto tracer = BoreholeTracer::build(model.value());
    if (!tracer) {
        std::fprintf(stderr, "%s\n", tracer.error().message.c_str());
        return 1;
    }
    const double sceneS = bench::nowSeconds() - t;
    const Aabb b = model->bounds();
    const double height = b.max.z - b.min.z;

    // Collars and surveys.
    std::mt19937_64 rng(545);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::string collar = "hole,x,y,z,depth\n", survey = "hole,depth,azimuth,dip\n";
    std::vector<double> depths;
    for (std::size_t h = 0; h < holes; ++h) {
        const double x = b.min.x + (0.1 + 0.8 * u(rng)) * (b.max.x - b.min.x);
        const double y = b.min.y + (0.1 + 0.8 * u(rng)) * (b.max.y - b.min.y);
        const double depth = (0.3 + 0.3 * u(rng)) * height;
        depths.push_back(depth);
        collar += "H" + std::to_string(h) + "," + std::to_string(x) + "," + std::to_string(y) + "," +
                  std::to_string(b.max.z + 1.0) + "," + std::to_string(depth) + "\n";
        double az = 360.0 * u(rng), dip = -55.0 - 30.0 * u(rng);
        for (std::size_t s = 0; s < stations; ++s) {
            survey += "H" + std::to_string(h) + "," + std::to_string(depth * double(s) / double(stations)) + "," +
                      std::to_string(az) + "," + std::to_string(dip) + "\n";
            az = std::fmod(az + 6.0 * (u(rng) - 0.5) + 360.0, 360.0);
            dip = std::clamp(dip + 4.0 * (u(rng) - 0.5), -89.0, -30.0);
        }
    }
    DrillholeSources src;
    src.source = "bench";
    src.collar = {"collar", "collar.csv", collar, {}, {}, DipConvention::NegativeDown};
    src.survey = DrillholeTableSource{"survey", "survey.csv", survey, {}, {}, {}};
    auto first = buildDrillholes(src);
    if (!first) {
        std::fprintf(stderr, "%s\n", first.error().message.c_str());
        return 1;
    }
    // Lithology logs: the model's unit at each interval's middle (body name).
    std::string lith = "hole,from,to,lith\n";
    for (std::size_t h = 0; h < holes; ++h) {
        auto tr = api::traceHole(*tracer.value(), first.value(), first->holes[h]);
        if (!tr) continue;
        const double step = depths[h] / double(intervals);
        for (std::size_t i = 0; i < intervals; ++i) {
            const double mid = step * (double(i) + 0.5);
            std::string code = "AIR";
            for (const auto& iv : tr->intervals)
                if (iv.from <= mid && mid < iv.to) code = model->bodies[iv.body].name;
            lith += "H" + std::to_string(h) + "," + std::to_string(step * double(i)) + "," +
                    std::to_string(step * double(i + 1)) + "," + code + "\n";
        }
    }
    src.intervals.push_back({"lithology", "lithology.csv", lith, {}, {}, {}});
    auto db = buildDrillholes(src);
    if (!db) {
        std::fprintf(stderr, "%s\n", db.error().message.c_str());
        return 1;
    }
    std::vector<double> wall, cpu;
    nlohmann::ordered_json summary;
    std::size_t chords = 0;
    for (const Drillhole& h : db->holes) chords += holePolyline(h.path, h.totalDepth).points.size() - 1;
    for (std::size_t r = 0; r < repeats; ++r) {
        const double w0 = bench::nowSeconds(), c0 = bench::processCpuSeconds();
        auto c = api::checkDrillholes(model.value(), db.value(), *tracer.value());
        wall.push_back(bench::nowSeconds() - w0);
        cpu.push_back(bench::processCpuSeconds() - c0);
        if (!c) {
            std::fprintf(stderr, "%s\n", c.error().message.c_str());
            return 1;
        }
        summary = api::drillholeCheckJson(c.value(), size, "generated")["summary"];
    }
    nlohmann::ordered_json out = {{"bench", "drillhole_check"},
                                  {"size", size},
                                  {"triangles", model->triangleCount()},
                                  {"bodies", model->bodies.size()},
                                  {"generate_s", genS},
                                  {"ray_scene_s", sceneS},
                                  {"holes", holes},
                                  {"stations_per_hole", stations},
                                  {"intervals_per_hole", intervals},
                                  {"survey_stations", db->stationCount()},
                                  {"lithology_intervals", db->intervals[0].size()},
                                  {"chords_traced", chords},
                                  {"repeats", repeats},
                                  {"check_wall_s_median", bench::median(wall)},
                                  {"check_cpu_s_median", bench::median(cpu)},
                                  {"check_wall_s", wall},
                                  {"threads", 1},
                                  {"goal_s", 1.0},
                                  {"summary", summary},
                                  {"load_average", bench::loadAverage()}};
    std::printf("%s\n", jsonText(out, 2).c_str());
    return 0;
}
