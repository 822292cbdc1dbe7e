// bench_gl_blocks [--size L4] [--cells 100] [--image 1024] [--frames 5] [--shape box|sgrid|both]:
// GL perspective views coloured by a block model (issue 15), through the render worker as the
// server draws them (workers/gl_worker.hpp, full detail, the context's default backend).
// A synthetic model (L4 = 10M triangles) with a cells^3 block model over its bounds clipped
// by every body; sgrid: the same lattice with every interior point's elevation moved by up
// to 0.3 of a cell (no cell is a box), coloured through its cells' exact pieces on the cut
// (renderer/passes/block_caps.hpp); box: the boxes, both through the class texture
// (renderer/passes/block_texture.hpp, "box-texture") and through their pieces ("box-pieces").
// Per view (one vertical plane through the middle; a corner cut out by three planes), wall
// clock ms of the worker's renderPerspective:
//   uncoloured       median of `frames` frames of the view without colour=
//   colouredFirst    the first coloured frame: class texture upload or the pieces cut and
//                    uploaded, + the frame
//   coloured         median of `frames` more (the texture or pieces kept by the worker),
//                    alternating with the uncoloured frames
//   ...CpuMedianMs   the same as CPU time of the whole process (all llvmpipe threads): on a
//                    shared machine it shows the work without the waiting
//   cutMs            pieces: api::blockCapTriangles alone for the view's planes, and its triangles
// Prints one JSON document with the load average at start and end (the machine is shared).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
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
#include "workers/gl_worker.hpp"

using namespace geoslice;
using json = nlohmann::ordered_json;

namespace {

double msSince(double t0) { return (bench::nowSeconds() - t0) * 1000.0; }

// A cells^3 lattice over `b` with grade 2 + sin(i/5) cos(j/6) + sin(k/8); bent (an SGrid) or
// boxes.
Result<BlockModel> latticeBlocks(const Aabb& b, int cells, bool bent) {
    Grid g;
    g.type = bent ? "SGrid" : "Voxet";
    g.name = "bench";
    g.cellCentred = true;
    const glm::dvec3 step = (b.max - b.min) / double(cells);
    for (int a = 0; a < 3; ++a) g.dims[a] = std::size_t(cells) + 1;  // corners; properties on cells
    GridProperty grade{"grade", "g/t Au", std::nullopt, {}};
    for (int k = 0; k < cells; ++k)
        for (int j = 0; j < cells; ++j)
            for (int i = 0; i < cells; ++i)
                grade.values.push_back(float(2.0 + std::sin(i / 5.0) * std::cos(j / 6.0) + std::sin(k / 8.0)));
    g.properties.push_back(std::move(grade));
    if (!bent) {  // a Voxet with properties on cells: its cells are the lattice's boxes
        g.origin = b.min;
        for (int a = 0; a < 3; ++a) g.step[a] = glm::dvec3(a == 0, a == 1, a == 2) * step[a];
        return blockModelFromGrid(g);
    }
    for (int k = 0; k <= cells; ++k)
        for (int j = 0; j <= cells; ++j)
            for (int i = 0; i <= cells; ++i) {
                glm::dvec3 p = b.min + glm::dvec3(i, j, k) * step;
                if (k > 0 && k < cells) p.z += 0.3 * step.z * std::sin(0.31 * i) * std::sin(0.23 * j);
                g.points.push_back(p);
            }
    return blockModelFromGrid(g);
}

}  // namespace

int main(int argc, char** argv) {
    std::string size = "L4", shapes = "both";
    int cells = 100, side = 1024, frames = 5;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size"))
            size = argv[i + 1];
        else if (!std::strcmp(argv[i], "--cells"))
            cells = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--image"))
            side = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--frames"))
            frames = std::max(1, std::stoi(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--shape"))
            shapes = argv[i + 1];
    }
    json out;
    out["bench"] = "gl_blocks";
    out["loadAverageStart"] = bench::loadAverage();
    SyntheticOptions so;
    so.triangles = bench::triangleCountFor(size);
    so.crs = Crs::fromEpsg(4523).value();
    auto generated = generateSynthetic(so);
    if (!generated) {
        std::fprintf(stderr, "%s\n", generated.error().message.c_str());
        return 1;
    }
    Model base = std::move(generated.value());
    validate(base);
    const Aabb b = base.bounds();
    out["model"] = {{"size", size}, {"triangles", base.triangleCount()}, {"bodies", base.bodies.size()}};
    auto worker = workers::GlWorker::create(GlBackend::Auto);
    if (!worker) {
        std::fprintf(stderr, "%s\n", worker.error().message.c_str());
        return 1;
    }
    out["gl"] = worker.value()->context->info().describe();

    // The views: eye south-west of the model and above it, looking at its centre.
    const glm::dvec3 c = b.centre(), extent = b.max - b.min;
    const glm::dvec3 eye = c + glm::dvec3(-0.9 * extent.x, -1.1 * extent.y, 1.2 * extent.z + 0.3 * extent.x);
    char eyeText[128], targetText[128], plane[160], planes[400];
    std::snprintf(eyeText, sizeof eyeText, "%.17g,%.17g,%.17g", eye.x, eye.y, eye.z);
    std::snprintf(targetText, sizeof targetText, "%.17g,%.17g,%.17g", c.x, c.y, c.z);
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.8, 0.6, 0.0));  // the eye on its removed side
    std::snprintf(plane, sizeof plane, "%.17g,%.17g,0,%.17g", n.x, n.y, -glm::dot(n, c));
    // A corner taken out (cut=intersection of the removed sides x < cx, y < cy, z > cz).
    std::snprintf(planes, sizeof planes, "1,0,0,%.17g;0,1,0,%.17g;0,0,-1,%.17g", -c.x, -c.y, c.z);
    const std::string sizeText = std::to_string(side) + "x" + std::to_string(side);
    struct View {
        const char* name;
        api::Params params;
    };
    const std::vector<View> views = {
        {"one plane", {{"plane", plane}}},
        {"corner cut out (3 planes)", {{"planes", planes}, {"cut", "intersection"}}},
    };

    for (const char* shape : {"box-texture", "box-pieces", "sgrid"}) {
        const bool sgrid = std::string(shape) == "sgrid";
        if (shapes != "both" && shapes != (sgrid ? "sgrid" : "box")) continue;
        worker.value()->boxBlocks = std::string(shape) == "box-texture" ? workers::GlWorker::BoxBlocks::Texture
                                                                        : workers::GlWorker::BoxBlocks::Pieces;
        Model model = base;
        double t = bench::nowSeconds();
        auto blocks = latticeBlocks(b, cells, sgrid);
        if (!blocks) {
            std::fprintf(stderr, "%s\n", blocks.error().message.c_str());
            return 1;
        }
        const double buildMs = msSince(t);
        if (auto s = resolveBlockClip(model, blocks.value()); !s) return 1;
        model.blocks = std::make_shared<const BlockModel>(std::move(blocks.value()));
        auto cm = api::catalogModelOf(std::string("bench-") + shape, model, "v1", api::RayBuild::Deferred);
        if (!cm) {
            std::fprintf(stderr, "%s\n", cm.error().message.c_str());
            return 1;
        }
        json shapeOut = {{"cells", model.blocks->cellCount()}, {"buildMs", buildMs}};
        for (const View& view : views) {
            api::Params p = view.params;
            p.insert({{"view", "perspective"}, {"eye", eyeText}, {"target", targetText}, {"size", sizeText}});
            auto plain = api::parseViewPlan(p, cm.value()->id, model.crs);
            p.insert({{"colour", "grade"}, {"breaks", "1.5,2,2.5"}});
            auto coloured = api::parseViewPlan(p, cm.value()->id, model.crs);
            if (!plain || !coloured) return 1;
            std::vector<double> plainMs, colouredMs, plainCpu, colouredCpu;
            double firstMs = 0.0;
            std::size_t cellPixels = 0;
            auto frame = [&](const api::ViewPlan& plan, std::vector<double>* ms, std::vector<double>* cpu) -> bool {
                const double t0 = bench::nowSeconds(), c0 = bench::processCpuSeconds();
                auto v = worker.value()->renderPerspective(*cm.value(), plan);
                if (!v) {
                    std::fprintf(stderr, "%s\n", v.error().message.c_str());
                    return false;
                }
                if (ms) ms->push_back(msSince(t0));
                if (cpu) cpu->push_back((bench::processCpuSeconds() - c0) * 1000.0);
                cellPixels = std::size_t(std::count_if(v->cells.begin(), v->cells.end(), [](auto x) { return x; }));
                return true;
            };
            if (!frame(plain.value(), nullptr, nullptr)) return 1;  // upload + warm-up, not timed
            t = bench::nowSeconds();
            if (!frame(coloured.value(), nullptr, nullptr)) return 1;
            firstMs = msSince(t);
            // Alternately, so that a change of the machine's load falls on both.
            for (int f = 0; f < frames; ++f)
                if (!frame(plain.value(), &plainMs, &plainCpu) || !frame(coloured.value(), &colouredMs, &colouredCpu))
                    return 1;
            json v = {{"view", view.name},
                      {"image", sizeText},
                      {"uncolouredMedianMs", bench::median(plainMs)},
                      {"colouredFirstMs", firstMs},
                      {"colouredMedianMs", bench::median(colouredMs)},
                      {"ratio", bench::median(colouredMs) / std::max(1e-9, bench::median(plainMs))},
                      {"uncolouredCpuMedianMs", bench::median(plainCpu)},
                      {"colouredCpuMedianMs", bench::median(colouredCpu)},
                      {"cpuRatio", bench::median(colouredCpu) / std::max(1e-9, bench::median(plainCpu))},
                      {"cellPixels", cellPixels}};
            if (std::string(shape) != "box-texture") {
                auto classes = api::blockClasses(*cm.value(), coloured->section);
                const api::CutOut cut = api::sectionCut(coloured->section);
                if (!classes || !classes.value()) return 1;
                auto pieces = api::blockCapTriangles(cm.value()->model, *classes.value(), cut.planes);
                if (!pieces) return 1;
                v["cutMs"] = pieces->cutMs;
                v["pieceTriangles"] = pieces->positions.size() / 3;
            }
            shapeOut["views"].push_back(v);
        }
        out[shape] = shapeOut;
    }
    out["loadAverageEnd"] = bench::loadAverage();
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
