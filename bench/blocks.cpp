// bench_blocks [--size L4] [--cells 100] [--image 1024] [--planes 8] [--cutoffs 10] [--shape box|sgrid]
// [--all-bodies 1] [--repeats 1] [--line 0]:
// block models on sections (issue 15). A synthetic model (L4 = 10M triangles) with a
// cells^3 block model over its bounds (grade varying smoothly), clipped by every body;
// --shape sgrid makes it a curvilinear grid (an SGrid, model/blocks/block_model.hpp Hexahedron:
// the same lattice with every point's elevation moved by 0.3 of a cell x a product of sines,
// so no cell is a box), located and cut through its tetrahedra:
//  - section: the exact profile image (api::renderProfile) of `planes` vertical planes
//    through the model, uncoloured and coloured by grade (colour=grade&breaks=...), median
//    ms of each and their ratio (goal: coloured <= 2x uncoloured); each plane `repeats` times
//    (uncoloured and coloured alternately), the medians over all of them; --line 1: polyline
//    sections of three legs along those planes' traces instead;
//  - grade-tonnage: computeGradeTonnage over the orebody (the model's record of kind
//    "orebody") for `cutoffs` cut-offs, median ms of 3 (goal <= 200 ms; and the CPU ms of the
//    thread that runs it, less sensitive to other processes on the cores), and the same for
//    every body (all strata), and the orebody's on the kept side of an oblique plane through its centre,
//    reported beside it.
// Prints one JSON document with the load average at start and end (the machine is shared);
// images also report their process CPU time, which waiting for a core does not inflate.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "bench/bench_util.hpp"
#include "model/blocks/block_model.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "section/blocks/block_reserves.hpp"

using namespace geoslice;
using json = nlohmann::ordered_json;

namespace {

double ms(double t0) { return (bench::nowSeconds() - t0) * 1000.0; }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    std::string size = "L4";
    int cells = 100, side = 1024, planes = 8, cutoffCount = 10, allBodies = 1, repeats = 1, line = 0;
    std::string shape = "box";
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size"))
            size = argv[i + 1];
        else if (!std::strcmp(argv[i], "--cells"))
            cells = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--image"))
            side = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--planes"))
            planes = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--cutoffs"))
            cutoffCount = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--shape"))
            shape = argv[i + 1];
        else if (!std::strcmp(argv[i], "--all-bodies"))
            allBodies = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--line"))
            line = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--repeats"))
            repeats = std::max(1, std::stoi(argv[i + 1]));
    }
    json out;
    out["bench"] = "blocks";
    out["loadAverageStart"] = bench::loadAverage();
    SyntheticOptions so;
    so.triangles = bench::triangleCountFor(size);
    so.crs = Crs::fromEpsg(4523).value();
    double t = bench::nowSeconds();
    auto generated = generateSynthetic(so);
    if (!generated) {
        std::fprintf(stderr, "%s\n", generated.error().message.c_str());
        return 1;
    }
    Model model = std::move(generated.value());
    validate(model);
    out["model"] = {
        {"size", size}, {"triangles", model.triangleCount()}, {"bodies", model.bodies.size()}, {"generateMs", ms(t)}};

    // The block model: cells^3 over the bounds, grade = a smooth field in 0..4.
    const Aabb b = model.bounds();
    BlockModel blocks;
    blocks.source = "bench";
    blocks.origin = b.min;
    for (int a = 0; a < 3; ++a) {
        blocks.size[std::size_t(a)] = (b.max[a] - b.min[a]) / cells;
        blocks.dims[std::size_t(a)] = std::size_t(cells);
    }
    BlockProperty grade{"grade", "g/t Au", {}};
    grade.values.resize(blocks.cellCount());
    for (std::size_t c = 0; c < blocks.cellCount(); ++c) {
        const auto ijk = blocks.ijk(c);
        grade.values[c] =
            2.0 + std::sin(0.21 * double(ijk[0])) * std::cos(0.17 * double(ijk[1])) + std::sin(0.13 * double(ijk[2]));
    }
    blocks.properties.push_back(std::move(grade));
    double buildMs = 0.0;
    const std::array<double, 3> cellSize = blocks.size;  // the box lattice's (sgrid: before bending)
    if (shape == "sgrid") {
        Grid g;
        g.type = "SGrid";
        g.name = "bench";
        g.cellCentred = true;
        for (int a = 0; a < 3; ++a) g.dims[a] = std::size_t(cells) + 1;
        for (int k = 0; k <= cells; ++k)
            for (int j = 0; j <= cells; ++j)
                for (int i = 0; i <= cells; ++i) {
                    glm::dvec3 p = blocks.corner(std::size_t(i), std::size_t(j), std::size_t(k));
                    // Interior points only, so the grid keeps the model's bounds.
                    if (k > 0 && k < cells) p.z += 0.3 * blocks.size[2] * std::sin(0.31 * i) * std::sin(0.23 * j);
                    g.points.push_back(p);
                }
        g.properties.push_back(
            {"grade", "g/t Au", std::nullopt,
             std::vector<float>(blocks.properties[0].values.begin(), blocks.properties[0].values.end())});
        t = bench::nowSeconds();
        auto sg = blockModelFromGrid(g);
        buildMs = ms(t);
        if (!sg) {
            std::fprintf(stderr, "%s\n", sg.error().message.c_str());
            return 1;
        }
        blocks = std::move(sg.value());
    } else if (shape != "box") {
        std::fprintf(stderr, "--shape box|sgrid\n");
        return 2;
    }
    if (auto s = resolveBlockClip(model, blocks); !s) {
        std::fprintf(stderr, "%s\n", s.error().message.c_str());
        return 1;
    }
    model.blocks = std::make_shared<const BlockModel>(blocks);
    out["blocks"] = {{"shape", shape},
                     {"buildMs", buildMs},
                     {"cells", blocks.cellCount()},
                     {"dims", {cells, cells, cells}},
                     {"cellSize", {cellSize[0], cellSize[1], cellSize[2]}},
                     {"clipBodies", blocks.clipBodyIndex.size()}};
    t = bench::nowSeconds();
    auto cm = api::catalogModelOf("bench", model, "bench");
    if (!cm) {
        std::fprintf(stderr, "%s\n", cm.error().message.c_str());
        return 1;
    }
    out["indexMs"] = ms(t);
    const api::CatalogModel& m = *cm.value();
    // The ray scene builds on a thread of its own (seconds at L4); the images are timed after
    // it, as a server that has been up a while renders them.
    t = bench::nowSeconds();
    if (auto rays = m.rays->wait(); !rays) {
        std::fprintf(stderr, "%s\n", rays.error().message.c_str());
        return 1;
    }
    out["rayWaitMs"] = ms(t);

    // Sections: vertical planes through the middle half of the model, turning.
    std::vector<double> plain, coloured, plainCpu, colouredCpu;
    std::size_t colouredPixels = 0;
    const std::string sizeText = std::to_string(side) + "x" + std::to_string(side);
    for (int p = 0; p < planes; ++p) {
        const double angle = 3.14159265358979 * (0.1 + 0.8 * p / std::max(1, planes - 1));
        const glm::dvec3 c = b.centre() + (b.max - b.min) * glm::dvec3(0.25 * std::cos(3.0 * p), 0.2, 0.0);
        const glm::dvec3 n{std::cos(angle), std::sin(angle), 0.0};
        char plane[160];
        std::snprintf(plane, sizeof plane, "%.17g,%.17g,0,%.17g", n.x, n.y, -glm::dot(n, c));
        // --line 1: a polyline section instead, three legs across the same plane's trace (bent
        // by a fifth of the model's width either way).
        std::string key = "plane", value = plane;
        if (line) {
            const glm::dvec3 along{-n.y, n.x, 0.0}, w = b.max - b.min;
            const double half = 0.45 * std::max(w.x, w.y), bend = 0.2 * std::max(w.x, w.y);
            char buf[320];
            const glm::dvec3 p0 = c - half * along, p1 = c - 0.3 * half * along + bend * n,
                             p2 = c + 0.3 * half * along - bend * n, p3 = c + half * along;
            std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", p0.x, p0.y, p1.x, p1.y,
                          p2.x, p2.y, p3.x, p3.y);
            key = "line";
            value = buf;
        }
        auto base = api::parseViewPlan({{key, value}, {"size", sizeText}}, "bench", model.crs);
        auto col = api::parseViewPlan(
            {{key, value}, {"size", sizeText}, {"colour", "grade"}, {"breaks", "1,1.5,2,2.5,3"}}, "bench", model.crs);
        if (!base || !col) return 1;
        for (int r = 0; r < repeats; ++r) {
            t = bench::nowSeconds();
            double cpu = bench::processCpuSeconds();
            auto a = api::renderProfile(m, base.value());
            plain.push_back(ms(t));
            plainCpu.push_back((bench::processCpuSeconds() - cpu) * 1000.0);
            t = bench::nowSeconds();
            cpu = bench::processCpuSeconds();
            auto v = api::renderProfile(m, col.value());
            coloured.push_back(ms(t));
            colouredCpu.push_back((bench::processCpuSeconds() - cpu) * 1000.0);
            if (!a || !v) {
                std::fprintf(stderr, "%s\n", (!a ? a.error() : v.error()).message.c_str());
                return 1;
            }
            if (r == 0)
                for (std::uint32_t cell : v.value().cells) colouredPixels += cell != 0;
        }
    }
    out["section"] = {{"image", sizeText},
                      {"geometry", line ? "polyline, 3 legs" : "plane"},
                      {"planes", planes},
                      {"repeats", repeats},
                      {"uncolouredMedianMs", median(plain)},
                      {"colouredMedianMs", median(coloured)},
                      {"ratio", median(coloured) / std::max(1e-9, median(plain))},
                      // CPU time of the process (both threads of the section engine): the cost
                      // without the waiting for a core that a loaded machine adds to wall time.
                      {"uncolouredCpuMedianMs", median(plainCpu)},
                      {"colouredCpuMedianMs", median(colouredCpu)},
                      {"cpuRatio", median(colouredCpu) / std::max(1e-9, median(plainCpu))},
                      {"meanColouredPixels", double(colouredPixels) / planes},
                      {"goal", "coloured <= 2x uncoloured"}};

    // Grade-tonnage: the orebody, then every body.
    std::vector<double> cutoffs;
    for (int c = 0; c < cutoffCount; ++c) cutoffs.push_back(0.5 + 0.3 * c);
    auto table = [&](const std::vector<std::string>& names, const std::optional<Plane>& plane) -> json {
        BlockModel copy = blocks;
        copy.clipBodies = names;
        if (auto s = resolveBlockClip(model, copy); !s) return {{"error", s.error().message}};
        Model mm;
        mm.bodies = model.bodies;
        mm.attributes = model.attributes;
        mm.blocks = std::make_shared<const BlockModel>(std::move(copy));
        std::vector<double> times, cpu;
        double volume = 0.0;
        for (int r = 0; r < 3; ++r) {
            const double t0 = bench::nowSeconds(), c0 = bench::threadCpuSeconds();
            auto gt = computeGradeTonnage(mm, "grade", cutoffs, plane);
            times.push_back(ms(t0));
            cpu.push_back((bench::threadCpuSeconds() - c0) * 1000.0);
            if (!gt) return {{"error", gt.error().message}};
            volume = 0.0;
            for (const auto& body : gt->bodies) volume += body.volume;
        }
        std::size_t triangles = 0;
        for (std::uint32_t i : mm.blocks->clipBodyIndex) triangles += mm.bodies[i].mesh.triangleCount();
        return {{"bodies", mm.blocks->clipBodyIndex.size()},
                {"triangles", triangles},
                {"cutoffs", cutoffs.size()},
                {"medianMs", median(times)},
                {"medianCpuMs", median(cpu)},
                {"volumeM3", volume}};
    };
    std::vector<std::string> ore;
    for (const Part& p : model.bodies)
        if (const AttributeRecord* r = model.attributes.find(p.record); r && r->kind == "orebody")
            ore.push_back(p.name);
    // An oblique plane through the orebody's bounding-box centre: its kept half.
    Aabb oreBox;
    for (const Part& p : model.bodies)
        if (std::find(ore.begin(), ore.end(), p.name) != ore.end()) oreBox.extend(p.mesh.bounds());
    const glm::dvec3 centre = oreBox.valid() ? oreBox.centre() : model.bounds().centre(),
                     normal = glm::normalize(glm::dvec3(1.0, 0.3, 0.2));
    const Plane half{normal, -glm::dot(normal, centre)};
    out["gradeTonnage"] = {{"orebody", table(ore, std::nullopt)},
                           {"orebodyKeptSideOfPlane", table(ore, half)},
                           {"allBodies", allBodies ? table({}, std::nullopt) : json("skipped (--all-bodies 0)")},
                           {"goal", "orebody table <= 200 ms"}};
    out["loadAverageEnd"] = bench::loadAverage();
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
