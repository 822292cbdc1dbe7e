// bench_render [--sizes L1,L2,L3,L4] [--resolutions 1024x1024,1920x1080] [--runs R]
//              [--backends egl-device,egl-surfaceless,osmesa] [--lod-levels N]
//              [--cell-triangles N] [--max-cells N]:
// the slicing pass per GL backend. For each model size the synthetic mine (EPSG:4523) is
// generated in memory; per backend it is uploaded once (with LOD clusters on software
// rasterisers, see renderer/gpu_model.hpp) and every program is warmed. Then, per image
// size, it times R frames per case and prints JSON medians (wall clock, ms):
//   draw_finish_ms   clear + draw + glFinish (the slicing pass itself)
//   aa_ms            anti-aliasing: FXAA pass (software) or MSAA resolve (hardware), + glFinish
//   readback_ms      glReadPixels of RGBA8 colour and R32UI ids, row flips included
//   encode_ms        JPEG q85, PNG zlib 1 + SUB, WebP q80 method 0 of the colour image
// Cases: a plain draw (the profile's view and geometry, no plane: the reference the paper's
// pixel mask is measured against), profile and perspective views, clip distance against
// discard; the perspective
// view also with level of detail ("lod": simplified clusters away from the cut), with the
// number of id pixels that differ from the full-detail frame and the triangles drawn.
//   frame_cpu_ms     CPU time of the whole process over one render() call (all llvmpipe
//                    threads): on a shared machine it shows the work without the waiting
// peak_rss_mib per size is the process's peak so far (models are generated one by one).
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "image/image_encode.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/slice_renderer.hpp"

using namespace geoslice;
using json = nlohmann::ordered_json;

namespace {

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream list(s);
    std::string item;
    while (std::getline(list, item, ','))
        if (!item.empty()) out.push_back(item);
    return out;
}

struct CaseResult {
    std::vector<double> draw, aa, read, cpu;
    std::vector<RecordId> ids;
    std::vector<std::uint8_t> rgba;
    std::size_t triangles = 0, skipped = 0, drawCalls = 0;
    std::string aaUsed, error;
    bool lodUsed = false;
};

CaseResult runCase(SliceRenderer& renderer, const GpuModel& gpu, const SliceRequest& req, int runs) {
    CaseResult r;
    for (int i = 0; i < runs + 1; ++i) {  // the first frame at a new size allocates the target
        const double c0 = bench::processCpuSeconds();
        auto img = renderer.render(gpu, req);
        const double cpuMs = (bench::processCpuSeconds() - c0) * 1e3;
        if (!img) {
            r.error = img.error().message;
            return r;
        }
        if (i == 0) continue;
        r.draw.push_back(img->drawMs);
        r.aa.push_back(img->aaMs);
        r.read.push_back(img->readbackMs);
        r.cpu.push_back(cpuMs);
        if (i == runs) {
            r.ids = std::move(img->ids);
            r.rgba = std::move(img->rgba);
            r.triangles = img->trianglesDrawn;
            r.skipped = img->clustersSkipped;
            r.drawCalls = img->drawCalls;
            r.aaUsed = antiAliasName(img->aaUsed);
            r.lodUsed = img->lodUsed;
        }
    }
    return r;
}

json encodeTimes(const std::vector<std::uint8_t>& rgba, int w, int h) {
    json j;
    const std::pair<const char*, ImageFormat> formats[] = {
        {"jpeg_q85", ImageFormat::Jpeg}, {"png_zlib1_sub", ImageFormat::Png}, {"webp_q80_m0", ImageFormat::Webp}};
    for (const auto& [name, f] : formats) {
        std::vector<double> t;
        std::size_t bytes = 0;
        for (int i = 0; i < 3; ++i) {
            const double t0 = bench::nowSeconds();
            auto out = encodeImage(rgba, w, h, f);
            t.push_back((bench::nowSeconds() - t0) * 1e3);
            if (out) bytes = out->size();
        }
        j[name] = {{"ms", bench::median(t)}, {"bytes", bytes}};
    }
    return j;
}

}  // namespace

int main(int argc, char** argv) {
    std::string sizes = "L1,L4", resolutions = "1024x1024,1920x1080", backends = "egl-device,egl-surfaceless,osmesa";
    int runs = 5, lodLevels = 5;
    std::size_t perCell = GpuModel::UploadOptions{}.trianglesPerCell, maxCells = GpuModel::UploadOptions{}.maxCells;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--sizes"))
            sizes = argv[i + 1];
        else if (!std::strcmp(argv[i], "--resolutions"))
            resolutions = argv[i + 1];
        else if (!std::strcmp(argv[i], "--runs"))
            runs = std::max(1, std::stoi(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--backends"))
            backends = argv[i + 1];
        else if (!std::strcmp(argv[i], "--lod-levels"))
            lodLevels = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--cell-triangles"))
            perCell = std::stoul(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--max-cells"))
            maxCells = std::stoul(argv[i + 1]);
    }
    std::vector<std::pair<int, int>> images;
    for (const std::string& r : split(resolutions)) {
        int w = 0, h = 0;
        if (std::sscanf(r.c_str(), "%dx%d", &w, &h) != 2 || w <= 0 || h <= 0) {
            std::fprintf(stderr, "bench_render: --resolutions %s: expected WxH[,WxH...]\n", resolutions.c_str());
            return 2;
        }
        images.push_back({w, h});
    }

    json out;
    out["benchmark"] = "render";
    out["runs"] = runs;
    out["sizes"] = json::array();
    for (const std::string& size : split(sizes)) {
        json js;
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
        js["size"] = size;
        js["model"] = {{"triangles", model->triangleCount()},
                       {"crs", "EPSG:4523"},
                       {"generate_validate_s", bench::nowSeconds() - t0}};

        const Aabb b = model->bounds();
        const glm::dvec3 c = b.centre();
        const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, 1.0, 0.1));
        const WorldPlane plane(n.x, n.y, n.z, -glm::dot(n, c));
        PerspectiveCamera persp;
        persp.target = c;
        persp.eye = c - n * (1.5 * glm::length(b.size())) + glm::dvec3(1500.0, 0.0, 2500.0);
        persp.fovYDegrees = 40.0;

        js["backends"] = json::array();
        for (const std::string& name : split(backends)) {
            json jb;
            jb["backend"] = name;
            auto backend = parseGlBackend(name);
            if (!backend) {
                jb["error"] = "unknown backend " + name;
                js["backends"].push_back(jb);
                continue;
            }
            GlContextOptions o;
            o.backend = *backend;
            const double tc = bench::nowSeconds();
            auto ctx = GlContext::create(o);
            if (!ctx) {
                jb["error"] = ctx.error().message;
                js["backends"].push_back(jb);
                continue;
            }
            jb["context_ms"] = (bench::nowSeconds() - tc) * 1e3;
            jb["renderer"] = (*ctx)->info().renderer;
            jb["version"] = (*ctx)->info().version;
            const double tu = bench::nowSeconds();
            GpuModel::UploadOptions uo;
            uo.lodLevels = lodLevels;
            uo.trianglesPerCell = perCell;
            uo.maxCells = maxCells;
            auto gpu = GpuModel::upload(**ctx, *model, uo);
            auto renderer = gpu ? SliceRenderer::create(**ctx) : Result<std::unique_ptr<SliceRenderer>>(gpu.error());
            if (!gpu || !renderer) {
                jb["error"] = gpu ? renderer.error().message : gpu.error().message;
                js["backends"].push_back(jb);
                continue;
            }
            (*ctx)->gl().Finish();
            jb["upload_ms"] = (bench::nowSeconds() - tu) * 1e3;
            jb["lod_build_ms"] = (*gpu)->lodBuildMs();
            jb["lod"] = (*gpu)->hasLod();
            const double tw = bench::nowSeconds();
            if (auto s = (*renderer)->warmUp(**gpu); !s) jb["warm_error"] = s.error().message;
            jb["warm_ms"] = (bench::nowSeconds() - tw) * 1e3;
            jb["images"] = json::array();
            for (auto [w, h] : images) {
                json ji;
                ji["width"] = w;
                ji["height"] = h;
                ji["cases"] = json::array();
                std::vector<RecordId> perspectiveFullIds;
                struct Spec {
                    const char* view;
                    ClipMethod clip;
                    SliceRequest::Lod lod;
                    float pixelError = 1.0f;  // LOD: screen-space error bound, pixels
                    bool plain = false;       // no plane: a plain draw of the same geometry
                };
                const Spec specs[] = {{"profile", ClipMethod::ClipDistance, SliceRequest::Lod::Off, 1.0f, true},
                                      {"profile", ClipMethod::ClipDistance, SliceRequest::Lod::Off},
                                      {"profile", ClipMethod::Discard, SliceRequest::Lod::Off},
                                      {"perspective", ClipMethod::ClipDistance, SliceRequest::Lod::Off},
                                      {"perspective", ClipMethod::Discard, SliceRequest::Lod::Off},
                                      {"perspective", ClipMethod::ClipDistance, SliceRequest::Lod::On, 1.0f},
                                      {"perspective", ClipMethod::ClipDistance, SliceRequest::Lod::On, 2.0f},
                                      {"perspective", ClipMethod::ClipDistance, SliceRequest::Lod::On, 4.0f}};
                for (const Spec& sp : specs) {
                    SliceRequest req;
                    req.width = w;
                    req.height = h;
                    if (!sp.plain) req.planes = {plane};
                    req.clip = sp.clip;
                    req.lod = sp.lod;
                    req.lodPixelError = sp.pixelError;
                    req.background = Rgba8{255, 255, 255, 255};
                    if (!std::strcmp(sp.view, "profile"))
                        req.view = profileAround(plane, b, w, h);
                    else
                        req.view = persp;
                    CaseResult r = runCase(**renderer, **gpu, req, runs);
                    json jc;
                    jc["view"] = sp.view;
                    jc["clip"] = sp.plain ? "none (plain draw)" : clipMethodName(sp.clip);
                    jc["detail"] = sp.lod == SliceRequest::Lod::On ? (r.lodUsed ? "lod" : "lod-unavailable") : "full";
                    if (sp.lod == SliceRequest::Lod::On) jc["lod_pixel_error"] = sp.pixelError;
                    if (!r.error.empty()) {
                        jc["error"] = r.error;
                        ji["cases"].push_back(jc);
                        continue;
                    }
                    jc["draw_finish_ms"] = bench::median(r.draw);
                    jc["aa"] = r.aaUsed;
                    jc["aa_ms"] = bench::median(r.aa);
                    jc["readback_ms"] = bench::median(r.read);
                    jc["frame_cpu_ms"] = bench::median(r.cpu);
                    jc["triangles_drawn"] = r.triangles;
                    jc["clusters_skipped"] = r.skipped;
                    jc["draw_calls"] = r.drawCalls;
                    std::size_t geology = 0;
                    for (RecordId id : r.ids) geology += id != kNoRecord;
                    jc["geology_pixels"] = geology;
                    if (!std::strcmp(sp.view, "perspective") && sp.clip == ClipMethod::ClipDistance) {
                        if (sp.lod == SliceRequest::Lod::Off) {
                            perspectiveFullIds = r.ids;
                        } else if (perspectiveFullIds.size() == r.ids.size()) {
                            std::size_t differ = 0;
                            for (std::size_t k = 0; k < r.ids.size(); ++k) differ += r.ids[k] != perspectiveFullIds[k];
                            jc["ids_differing_from_full"] = differ;
                        }
                    }
                    if (sp.clip == ClipMethod::ClipDistance && !sp.plain) jc["encode"] = encodeTimes(r.rgba, w, h);
                    ji["cases"].push_back(jc);
                }
                jb["images"].push_back(ji);
            }
            js["backends"].push_back(jb);
        }
        js["peak_rss_mib"] = bench::peakRssMiB();
        out["sizes"].push_back(js);
        std::fprintf(stderr, "bench_render: %s done\n", size.c_str());
    }
    out["peak_rss_mib"] = bench::peakRssMiB();
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
