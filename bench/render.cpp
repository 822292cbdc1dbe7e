// bench_render [--size L1|N] [--width W] [--height H] [--runs R] [--backends a,b,...]:
// the slicing pass per GL backend. Generates the synthetic mine (EPSG:4523) in memory,
// uploads it once per context, warms every program, then times R frames per case and
// prints JSON medians: draw + glFinish (clear + draw, wall clock) and readback (RGBA8 +
// R32UI glReadPixels), for a profile view and a perspective view, clip distance vs discard.
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "model/synthetic.hpp"
#include "model/validate.hpp"
#include "renderer/gl_context.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/slice_renderer.hpp"

using namespace geoslice;

int main(int argc, char** argv) {
    std::string size = "L1", backends = "egl-device,egl-surfaceless,osmesa";
    int width = 1024, height = 1024, runs = 7;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size"))
            size = argv[i + 1];
        else if (!std::strcmp(argv[i], "--width"))
            width = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--height"))
            height = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--runs"))
            runs = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--backends"))
            backends = argv[i + 1];
    }
    SyntheticOptions so;
    so.triangles = bench::triangleCountFor(size);
    so.crs = Crs::fromEpsg(4523).value();
    const double t0 = bench::nowSeconds();
    auto model = generateSynthetic(so);
    if (!model) {
        std::fprintf(stderr, "%s\n", model.error().message.c_str());
        return 1;
    }
    validate(model.value());
    const double tModel = bench::nowSeconds() - t0;

    const Aabb b = model->bounds();
    const glm::dvec3 c = b.centre();
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, 1.0, 0.1));
    const WorldPlane plane(n.x, n.y, n.z, -glm::dot(n, c));
    PerspectiveView persp;
    persp.target = c;
    persp.eye = c - n * (1.5 * glm::length(b.size())) + glm::dvec3(1500.0, 0.0, 2500.0);
    persp.fovYDegrees = 40.0;

    nlohmann::ordered_json out;
    out["benchmark"] = "render";
    out["model"] = {{"triangles", model->triangleCount()}, {"crs", "EPSG:4523"}, {"generate_validate_s", tModel}};
    out["image"] = {{"width", width}, {"height", height}};
    out["runs"] = runs;
    out["backends"] = nlohmann::ordered_json::array();
    std::stringstream list(backends);
    std::string name;
    while (std::getline(list, name, ',')) {
        nlohmann::ordered_json jb;
        jb["backend"] = name;
        auto backend = parseGlBackend(name);
        GlContextOptions o;
        o.backend = backend.value_or(GlBackend::Auto);
        const double tc = bench::nowSeconds();
        auto ctx =
            backend
                ? GlContext::create(o)
                : Result<std::unique_ptr<GlContext>>(makeError(ErrorCode::InvalidArgument, "unknown backend " + name));
        if (!ctx) {
            jb["error"] = ctx.error().message;
            out["backends"].push_back(jb);
            continue;
        }
        jb["context_ms"] = (bench::nowSeconds() - tc) * 1e3;
        jb["vendor"] = (*ctx)->info().vendor;
        jb["renderer"] = (*ctx)->info().renderer;
        jb["version"] = (*ctx)->info().version;
        const double tu = bench::nowSeconds();
        auto gpu = GpuModel::upload(**ctx, *model);
        auto renderer = gpu ? SliceRenderer::create(**ctx) : Result<std::unique_ptr<SliceRenderer>>(gpu.error());
        if (!gpu || !renderer) {
            jb["error"] = gpu ? renderer.error().message : gpu.error().message;
            out["backends"].push_back(jb);
            continue;
        }
        (*ctx)->gl().Finish();
        jb["upload_ms"] = (bench::nowSeconds() - tu) * 1e3;
        const double tw = bench::nowSeconds();
        if (auto s = (*renderer)->warmUp(**gpu); !s) jb["warm_error"] = s.error().message;
        jb["warm_ms"] = (bench::nowSeconds() - tw) * 1e3;
        jb["cases"] = nlohmann::ordered_json::array();
        for (const char* viewName : {"profile", "perspective"})
            for (ClipMethod clip : {ClipMethod::ClipDistance, ClipMethod::Discard}) {
                SliceRequest req;
                req.width = width;
                req.height = height;
                req.planes = {plane};
                req.clip = clip;
                if (!std::strcmp(viewName, "profile"))
                    req.view = profileAround(plane, b, width, height);
                else
                    req.view = persp;
                std::vector<double> draw, read;
                std::size_t bodyPixels = 0;
                std::string error;
                for (int r = 0; r < runs + 1; ++r) {  // the first frame at this size allocates the target
                    auto img = (*renderer)->render(**gpu, req);
                    if (!img) {
                        error = img.error().message;
                        break;
                    }
                    if (r == 0) {
                        for (RecordId id : img->ids) bodyPixels += id != kNoRecord;
                        continue;
                    }
                    draw.push_back(img->drawMs);
                    read.push_back(img->readbackMs);
                }
                nlohmann::ordered_json jc;
                jc["view"] = viewName;
                jc["clip"] = clipMethodName(clip);
                if (!error.empty()) jc["error"] = error;
                jc["draw_finish_ms"] = bench::median(draw);
                jc["readback_rgba_ids_ms"] = bench::median(read);
                jc["geology_pixels"] = bodyPixels;
                jb["cases"].push_back(jc);
            }
        jb["peak_rss_mib"] = bench::peakRssMiB();
        out["backends"].push_back(jb);
    }
    out["peak_rss_mib"] = bench::peakRssMiB();
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
