// geoslice render MODEL --plane a,b,c,d [--plane ...] [--union] [--profile [--frame u0,u1,v0,v1] |
//   --eye x,y,z --target x,y,z [--up x,y,z] [--fov deg]] [--size WxH] --out img.png [--ids ids.pgm]
//   [--gl auto|egl-device|egl-surfaceless|osmesa] [--device N] [--clip clip-distance|discard]
// Renders one frame of the slicing pass (renderer/slice_renderer.hpp) on a headless context.
// Planes are world (a,b,c,d), kept where a*x+b*y+c*z+d >= 0; points are world easting,
// northing, elevation in metres. The profile looks at the first plane's cut face (along +n).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "model/loaders.hpp"
#include "renderer/gl_context.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/image_io.hpp"
#include "renderer/slice_renderer.hpp"

namespace geoslice::cli {
namespace {

bool parseNumbers(const std::string& text, std::size_t count, std::vector<double>& out) {
    out.clear();
    const char* s = text.data();
    const char* end = s + text.size();
    while (s < end) {
        double v = 0.0;
        auto [next, ec] = std::from_chars(s, end, v);
        if (ec != std::errc() || !std::isfinite(v)) return false;
        out.push_back(v);
        s = next;
        if (s < end && *s != ',') return false;
        if (s < end) ++s;
    }
    return out.size() == count;
}

struct RenderArgs {
    std::string model, out, ids, gl = "auto", clip = "clip-distance", size = "1024x1024", frame, eye, target,
                                 up = "0,0,1", background = "#00000000";
    std::vector<std::string> planes;
    bool unionMode = false, profile = false;
    double fov = 45.0;
    int device = -1;
};

int run(const RenderArgs& a) {
    auto fail = [](const std::string& m) {
        std::fprintf(stderr, "geoslice render: %s\n", m.c_str());
        return 1;
    };
    SliceRequest req;
    std::vector<double> v;
    for (const std::string& p : a.planes) {
        if (!parseNumbers(p, 4, v)) return fail("--plane " + p + ": expected a,b,c,d (four numbers)");
        req.planes.push_back({v[0], v[1], v[2], v[3]});
    }
    if (std::sscanf(a.size.c_str(), "%dx%d", &req.width, &req.height) != 2)
        return fail("--size " + a.size + ": expected WxH, e.g. 1024x768");
    auto backend = parseGlBackend(a.gl);
    if (!backend) return fail("--gl " + a.gl + ": expected auto, egl-device, egl-surfaceless or osmesa");
    if (a.clip != "clip-distance" && a.clip != "discard")
        return fail("--clip " + a.clip + ": expected clip-distance or discard");
    req.clip = a.clip == "discard" ? ClipMethod::Discard : ClipMethod::ClipDistance;
    req.combine = a.unionMode ? PlaneCombine::Union : PlaneCombine::Intersection;
    auto bg = parseColour(a.background);
    if (!bg) return fail("--background " + a.background + ": expected #rrggbb or #rrggbbaa");
    req.background = *bg;

    auto model = loadModel(a.model);
    if (!model) return fail(model.error().message);
    const bool perspective = !a.eye.empty();
    if (perspective) {
        PerspectiveView pv;
        if (!parseNumbers(a.eye, 3, v)) return fail("--eye: expected x,y,z");
        pv.eye = {v[0], v[1], v[2]};
        if (!parseNumbers(a.target.empty() ? std::string() : a.target, 3, v)) return fail("--target: expected x,y,z");
        pv.target = {v[0], v[1], v[2]};
        if (!parseNumbers(a.up, 3, v)) return fail("--up: expected x,y,z");
        pv.up = {v[0], v[1], v[2]};
        pv.fovYDegrees = a.fov;
        req.view = pv;
    } else {
        if (req.planes.empty()) return fail("a profile needs --plane (or give --eye/--target for a 3D view)");
        auto unit = normalizePlane(req.planes[0]);
        if (!unit) return fail("--plane: " + unit.error().message);
        ProfileView pv = profileAround(*unit, model->bounds(), req.width, req.height);
        if (!a.frame.empty()) {
            if (!parseNumbers(a.frame, 4, v)) return fail("--frame: expected u0,u1,v0,v1 (plane metres)");
            pv.uMin = v[0], pv.uMax = v[1], pv.vMin = v[2], pv.vMax = v[3];
        }
        req.view = pv;
    }

    GlContextOptions o;
    o.backend = *backend;
    o.eglDeviceIndex = a.device;
    auto ctx = GlContext::create(o);
    if (!ctx) return fail(ctx.error().message);
    std::fprintf(stderr, "geoslice render: %s\n", (*ctx)->info().describe().c_str());
    auto gpu = GpuModel::upload(**ctx, *model);
    if (!gpu) return fail(gpu.error().message);
    auto renderer = SliceRenderer::create(**ctx);
    if (!renderer) return fail(renderer.error().message);
    req.readIds = !a.ids.empty();
    auto img = (*renderer)->render(**gpu, req);
    if (!img) return fail(img.error().message);
    if (auto s = writePngRgba(a.out, img->rgba, img->width, img->height); !s) return fail(s.error().message);
    if (!a.ids.empty())
        if (auto s = writeIdsPgm16(a.ids, img->ids, img->width, img->height); !s) return fail(s.error().message);
    std::fprintf(stderr,
                 "geoslice render: %dx%d, %zu triangles, %s, draw+finish %.1f ms (first frame, includes JIT), readback "
                 "%.2f ms -> %s\n",
                 img->width, img->height, (*gpu)->triangleCount(), clipMethodName(img->clipUsed), img->drawMs,
                 img->readbackMs, a.out.c_str());
    return 0;
}

}  // namespace

void addRender(CLI::App& app, int& exitCode) {
    auto a = std::make_shared<RenderArgs>();
    CLI::App* cmd =
        app.add_subcommand("render", "Render a cut of a model on a headless GL context (PNG colour, 16-bit PGM ids)");
    cmd->add_option("MODEL", a->model, "Model file")->required();
    cmd->add_option("--plane", a->planes,
                    "Cut plane a,b,c,d in world coordinates (repeat up to 6); kept where ax+by+cz+d >= 0");
    cmd->add_flag("--union", a->unionMode, "Keep the union of the planes' positive sides (cut a box or wedge out)");
    cmd->add_flag("--profile", a->profile, "Orthographic profile of the first plane (the default without --eye)");
    cmd->add_option("--frame", a->frame, "Profile frame u0,u1,v0,v1 in plane metres (default: the whole model)");
    cmd->add_option("--eye", a->eye, "Perspective eye x,y,z (world)");
    cmd->add_option("--target", a->target, "Perspective target x,y,z (world)");
    cmd->add_option("--up", a->up, "Perspective up direction (default 0,0,1)");
    cmd->add_option("--fov", a->fov, "Vertical field of view, degrees (default 45)");
    cmd->add_option("--size", a->size, "Image size WxH (default 1024x1024, at most 8192x8192)");
    cmd->add_option("--out", a->out, "Colour image (.png)")->required();
    cmd->add_option("--ids", a->ids, "Record-id image (16-bit .pgm, 0 = no geology)");
    cmd->add_option("--gl", a->gl, "GL backend: auto, egl-device, egl-surfaceless, osmesa");
    cmd->add_option("--device", a->device, "EGL device index for egl-device (default: prefer hardware)");
    cmd->add_option("--clip", a->clip, "clip-distance (default) or discard (the paper's fragment mask)");
    cmd->add_option("--background", a->background, "Background #rrggbb[aa] (default transparent)");
    cmd->callback([a, &exitCode] { exitCode = run(*a); });
}

}  // namespace geoslice::cli
