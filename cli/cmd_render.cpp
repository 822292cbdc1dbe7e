// geoslice render MODEL --plane a,b,c,d [--plane ... --cut union|intersection] [--profile [--frame u0,u1,v0,v1] |
//   --eye x,y,z --target x,y,z [--up x,y,z] [--fov deg]] [--size WxH] --out img.jpg|png|webp
//   [--quality Q] [--lossless] [--ids ids.png|ids.pgm]
//   [--gl auto|egl-device|egl-surfaceless|osmesa] [--device N] [--clip clip-distance|discard]
//   [--background transparent|#rrggbb[aa]] [--exaggeration F] [--aa auto|none|fxaa|msaa]
//   [--no-traces] [--lod auto|on|off] [--baked [--bake-size N]]
//   [--colour PROP [--breaks a,b,..] [--ramp NAME] [--cells cells.png|cells.pgm]]
// Renders one frame of the slicing pass (renderer/slice_renderer.hpp) on a headless context.
// Planes are world (a,b,c,d), kept where a*x+b*y+c*z+d >= 0; points are world easting,
// northing, elevation in metres. The profile looks at the first plane's cut face (along +n).
// Two or more planes (up to 6) make a cut-out, as the API's plane=...&cut=... (api/cut.hpp):
// --cut union removes the union of the planes' removed sides, --cut intersection removes what
// lies on the removed side of every plane (a wedge, octant or box taken out).
// With --exaggeration F the picture is stretched vertically by F about the centre elevation
// of the model's bounds, as HTTP's vx= (view/exaggeration.hpp): --eye/--target are true
// world points (mapped into display space here); --frame is in the plane's true u/v metres,
// as HTTP's frame=, and without it the profile has the default frame of view/view_frame.hpp,
// so `render --profile` and GET section.png frame a plane alike. --baked bakes the model's attribute texture in memory
// first (bake/bake.hpp, N x N texels per page) and takes every fragment's record id from it (issue 4 item 8), as the
// server does with a baked package. --colour colours the block model's clipping bodies' cut faces by a
// block property, as HTTP's colour= (workers/block_colouring.hpp, the render workers' own colouring:
// box grids by a class texture on a GPU, else every cell's exact piece on the planes); --cells writes
// each pixel's block cell + 1 (0 = none) as 16-bit grey.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "api/cut.hpp"
#include "api/params.hpp"
#include "bake/bake.hpp"
#include "cli/commands.hpp"
#include "image/image_encode.hpp"
#include "image/image_io.hpp"
#include "model/io/loaders.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/slice_renderer.hpp"
#include "workers/block_colouring.hpp"

namespace geoslice::cli {
namespace {

struct RenderArgs {
    std::string model, out, ids, gl = "auto", clip = "clip-distance", size = "1024x1024", frame, eye, target,
                                 up = "0,0,1", background = "#00000000";
    std::vector<std::string> planes;
    std::string cut;
    bool profile = false;
    double fov = 45.0;
    int device = -1;
    LoadOptions load;
    int quality = -1;  // JPEG/WebP quality; -1 = the encoder's default
    bool lossless = false;
    double exaggeration = 1.0;
    std::string aa = "auto", lod = "auto";
    bool noTraces = false;
    bool baked = false;
    unsigned bakeSize = 4096;
    ColourOptions colour;
    std::string cells;
};

// Values 0..65535 (record ids, cell + 1) as a 16-bit grey .png, or else .pgm, at `path`.
Status writeGray16(const std::string& path, const std::vector<std::uint32_t>& values, int width, int height) {
    if (path.ends_with(".png")) {
        auto bytes = encodeGray16Png(values.data(), width, height);
        if (!bytes) return makeError(bytes.error().code, path + ": " + bytes.error().message);
        return writeFile(path, *bytes);
    }
    return writeIdsPgm16(path, values, width, height);
}

int run(const RenderArgs& a) {
    auto fail = [](const std::string& m) {
        std::fprintf(stderr, "geoslice render: %s\n", m.c_str());
        return 1;
    };
    SliceRequest req;
    api::CutOut cut;
    if (!a.planes.empty()) {
        std::string list;
        for (const std::string& p : a.planes) list += (list.empty() ? "" : ";") + p;
        auto planes = api::parsePlaneList("--plane", list);
        if (!planes) return fail(planes.error().message);
        cut.planes = planes.value();
        if (!a.cut.empty()) {
            auto mode = api::parseCutMode("--cut", a.cut);
            if (!mode) return fail(mode.error().message);
            cut.mode = mode.value();
        } else if (cut.planes.size() > 1) {
            return fail("--cut: required with " + std::to_string(cut.planes.size()) +
                        " planes: union (keep what is on the kept side of every plane) or intersection (take out "
                        "what is on the removed side of every plane)");
        }
        for (const Plane& p : cut.planes) req.planes.push_back(WorldPlane(p.normal, p.d));
    }
    // The renderer names what is kept: --cut union keeps the intersection of the kept sides.
    req.combine = cut.mode == api::CutMode::Union ? PlaneCombine::Intersection : PlaneCombine::Union;
    // Size, exaggeration and field of view against the limits HTTP checks (view/view_limits.hpp).
    auto size = api::parseSize("--size", a.size, kMaxImageSide, static_cast<long long>(kMaxImagePixels));
    if (!size) return fail(size.error().message);
    req.width = size.value().width;
    req.height = size.value().height;
    if (auto s = checkExaggerationFactor("--exaggeration", a.exaggeration); !s) return fail(s.error().message);
    if (auto s = checkFov("--fov", a.fov); !s) return fail(s.error().message);
    auto backend = parseGlBackend(a.gl);
    if (!backend) return fail("--gl " + a.gl + ": expected auto, egl-device, egl-surfaceless or osmesa");
    if (a.clip != "clip-distance" && a.clip != "discard")
        return fail("--clip " + a.clip + ": expected clip-distance or discard");
    req.clip = a.clip == "discard" ? ClipMethod::Discard : ClipMethod::ClipDistance;
    auto bg = a.background == "transparent" ? std::optional<Rgba8>(Rgba8{0, 0, 0, 0}) : parseColour(a.background);
    if (!bg) return fail("--background " + a.background + ": expected transparent, #rrggbb or #rrggbbaa");
    req.background = *bg;
    if (a.aa == "auto")
        req.antiAlias = AntiAlias::Auto;
    else if (a.aa == "none")
        req.antiAlias = AntiAlias::None;
    else if (a.aa == "fxaa")
        req.antiAlias = AntiAlias::Fxaa;
    else if (a.aa == "msaa")
        req.antiAlias = AntiAlias::Msaa;
    else
        return fail("--aa " + a.aa + ": expected auto, none, fxaa or msaa");
    req.drawTraces = !a.noTraces;
    if (a.lod == "auto")
        req.lod = SliceRequest::Lod::Auto;
    else if (a.lod == "on")
        req.lod = SliceRequest::Lod::On;
    else if (a.lod == "off")
        req.lod = SliceRequest::Lod::Off;
    else
        return fail("--lod " + a.lod + ": expected auto, on or off");

    // The colour format comes from --out's extension; checked before any work is done.
    auto format = imageFormatFromPath(a.out);
    if (!format) return fail("--out: " + format.error().message);
    EncodeOptions enc;
    if (a.quality != -1) {
        if (a.quality < 1 || a.quality > 100)
            return fail("--quality " + std::to_string(a.quality) + ": expected 1..100");
        enc.jpegQuality = enc.webpQuality = a.quality;
    }
    enc.webpLossless = a.lossless;
    if (!a.ids.empty() && !a.ids.ends_with(".pgm") && !a.ids.ends_with(".png"))
        return fail("--ids " + a.ids + ": expected a .png or .pgm path (16-bit record ids)");
    if (!a.cells.empty() && !a.cells.ends_with(".pgm") && !a.cells.ends_with(".png"))
        return fail("--cells " + a.cells + ": expected a .png or .pgm path (16-bit block cell + 1)");
    if (!a.cells.empty() && a.colour.colour.empty()) return fail("--cells: needs --colour (the cells it shows)");

    auto model = loadModel(a.model, a.load);
    if (!model) return fail(model.error().message);
    auto classes = colourClasses(*model, a.colour);
    if (!classes) {
        std::fprintf(stderr, "geoslice render: %s\n", classes.error().message.c_str());
        return 2;
    }
    if (!a.cells.empty() && model->blocks->cellCount() > 65535)
        return fail("--cells: the block model has " + std::to_string(model->blocks->cellCount()) +
                    " cells; a 16-bit image holds cell + 1 up to 65535");
    if (!cut.planes.empty())
        if (auto s = api::checkCutKeepsSomething("--plane", cut, model->bounds()); !s) return fail(s.error().message);
    req.exaggeration = VerticalExaggeration::aboutCentreOf(a.exaggeration, model->bounds());
    const VerticalExaggeration& ve = req.exaggeration;
    const bool perspective = !a.eye.empty();
    if (perspective) {
        PerspectiveCamera pv;
        auto eye = parseNumbersFlag("--eye", a.eye, 3);
        if (!eye) return fail(eye.error().message);
        pv.eye = ve.toDisplay({eye.value()[0], eye.value()[1], eye.value()[2]});
        auto target = parseNumbersFlag("--target", a.target, 3);
        if (!target) return fail(target.error().message);
        pv.target = ve.toDisplay({target.value()[0], target.value()[1], target.value()[2]});
        auto up = parseNumbersFlag("--up", a.up, 3);
        if (!up) return fail(up.error().message);
        pv.up = {up.value()[0], up.value()[1], up.value()[2]};
        if (auto s = checkCameraDistance("--eye and --target", pv.eye, pv.target); !s) return fail(s.error().message);
        pv.fovYDegrees = a.fov;
        req.view = pv;
    } else {
        if (req.planes.empty()) return fail("a profile needs --plane (or give --eye/--target for a 3D view)");
        const WorldPlane& p0 = req.planes[0];
        auto plane = makePlane(p0.x, p0.y, p0.z, p0.w);
        if (!plane) return fail("--plane: " + plane.error().message);
        FrameRect frame = defaultFrame(*plane, model->bounds(), model->origin, req.width, req.height, ve);
        if (!a.frame.empty()) {
            auto f = parseNumbersFlag("--frame", a.frame, 4);
            if (!f) return fail(f.error().message + " (u0,u1,v0,v1 in plane metres)");
            frame = FrameRect{f.value()[0], f.value()[2], f.value()[1], f.value()[3]};
            if (auto s = checkFrame(frame, req.width, req.height); !s) return fail("--frame: " + s.error().message);
        }
        req.view = profileCamera(*plane, frame, ve);
    }

    GlContextOptions o;
    o.backend = *backend;
    o.eglDeviceIndex = a.device;
    auto ctx = GlContext::create(o);
    if (!ctx) return fail(ctx.error().message);
    std::fprintf(stderr, "geoslice render: %s\n", (*ctx)->info().describe().c_str());
    Result<std::unique_ptr<GpuModel>> gpu = makeError(ErrorCode::Internal, "no upload");
    if (a.baked) {
        if (a.bakeSize < 64 || a.bakeSize > 16384)
            return fail("--bake-size " + std::to_string(a.bakeSize) + ": expected 64..16384");
        bake::BakeOptions bo;
        bo.pack.width = bo.pack.height = a.bakeSize;
        auto baked = bake::bakeModel(*model, bo);
        if (!baked) return fail(baked.error().message);
        std::fprintf(stderr, "geoslice render: baked %ux%u x %u pages, %zu charts\n", baked->width, baked->height,
                     baked->pages, baked->stats.charts);
        gpu = GpuModel::upload(**ctx, *model, *baked);
    } else {
        gpu = GpuModel::upload(**ctx, *model);
    }
    if (!gpu) return fail(gpu.error().message);
    auto renderer = SliceRenderer::create(**ctx);
    if (!renderer) return fail(renderer.error().message);
    workers::BlockColouring colouring;
    if (classes.value()) {
        const bool texture = workers::colourWithTexture(*model->blocks, workers::BoxBlocks::Auto, **ctx);
        auto made = workers::uploadBlockColouring(**ctx, *model, blockClipRecords(*model, *model->blocks),
                                                  *classes.value(), cut.planes, texture);
        if (!made) return fail("--colour: " + made.error().message);
        colouring = std::move(made.value());
        colouring.setOn(req);
        std::fprintf(stderr, "geoslice render: coloured by %s, %zu classes, through %s\n", a.colour.colour.c_str(),
                     classes.value()->colours.size(), texture ? "a class texture" : "the cells' pieces on the planes");
    }
    req.readIds = !a.ids.empty() || !a.cells.empty();
    auto img = (*renderer)->render(**gpu, req);
    if (!img) return fail(img.error().message);
    if (auto s = writeImage(a.out, img->rgba.data(), img->width, img->height, enc); !s) return fail(s.error().message);
    if (!a.ids.empty())
        if (auto s = writeGray16(a.ids, img->ids, img->width, img->height); !s) return fail(s.error().message);
    if (!a.cells.empty())
        if (auto s = writeGray16(a.cells, img->cells, img->width, img->height); !s) return fail(s.error().message);
    std::fprintf(stderr,
                 "geoslice render: %dx%d, %zu triangles, %s, draw+finish %.1f ms (first frame, includes JIT), "
                 "anti-aliasing %s %.1f ms, readback %.2f ms, %zu trace segments, %zu triangles drawn%s -> %s\n",
                 img->width, img->height, (*gpu)->triangleCount(), clipMethodName(img->clipUsed), img->drawMs,
                 antiAliasName(img->aaUsed), img->aaMs, img->readbackMs, img->traceSegments, img->trianglesDrawn,
                 img->lodUsed ? " (LOD)" : "", a.out.c_str());
    return 0;
}

}  // namespace

void addRender(CLI::App& app, int& exitCode) {
    auto a = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand(
        "render", "Render a cut of a model on a headless GL context (JPEG/PNG/WebP colour, 16-bit PNG/PGM ids)");
    cmd->add_option("MODEL", a->model, "Model file")->required();
    addLoadOptions(cmd, a->load);
    cmd->add_option("--plane", a->planes,
                    "Cut plane a,b,c,d in world coordinates (repeat up to 6); kept where ax+by+cz+d >= 0");
    cmd->add_option("--cut", a->cut,
                    "With two or more planes: union (remove the union of their removed sides) or intersection "
                    "(remove what is on the removed side of every plane: a wedge, octant or box taken out)");
    cmd->add_flag("--profile", a->profile, "Orthographic profile of the first plane (the default without --eye)");
    cmd->add_option("--frame", a->frame,
                    "Profile frame u0,u1,v0,v1 in plane u/v metres, as HTTP frame= (default: the whole model)");
    cmd->add_option("--eye", a->eye, "Perspective eye x,y,z (world)");
    cmd->add_option("--target", a->target, "Perspective target x,y,z (world)");
    cmd->add_option("--up", a->up, "Perspective up direction (default 0,0,1)");
    cmd->add_option("--fov", a->fov, "Vertical field of view, degrees 1..170 as HTTP fov= (default 45)");
    cmd->add_option("--size", a->size, "Image size WxH (default 1024x1024, at most 8192x8192)");
    cmd->add_option("--out", a->out, "Colour image; the format follows the extension: .jpg/.jpeg, .png, .webp")
        ->required();
    cmd->add_option("--quality", a->quality, "JPEG/WebP quality 1..100 (default 85 JPEG, 80 WebP)");
    cmd->add_flag("--lossless", a->lossless, "WebP: lossless instead of lossy");
    cmd->add_option("--ids", a->ids, "Record-id image, 16-bit grey .png or .pgm (0 = no geology)");
    cmd->add_option("--gl", a->gl, "GL backend: auto, egl-device, egl-surfaceless, osmesa");
    cmd->add_option("--device", a->device, "EGL device index for egl-device (default: prefer hardware)");
    cmd->add_option("--clip", a->clip, "clip-distance (default) or discard (the paper's fragment mask)");
    cmd->add_option("--background", a->background, "Background: transparent (default) or #rrggbb[aa]");
    cmd->add_option("--exaggeration", a->exaggeration,
                    "Vertical exaggeration of the picture, 0.1..100, about the model's centre elevation (default 1; "
                    "ids and cut planes stay true)");
    cmd->add_option("--aa", a->aa,
                    "Anti-aliasing of the colour image: auto (MSAA on a GPU, FXAA on llvmpipe), none, fxaa, msaa");
    cmd->add_option("--lod", a->lod,
                    "Level of detail away from the cut: auto (3D views on llvmpipe), on, off (full detail)");
    cmd->add_flag("--no-traces", a->noTraces, "Do not draw fault traces on the cut");
    cmd->add_flag("--baked", a->baked, "Bake the attribute texture first and take record ids from it");
    cmd->add_option("--bake-size", a->bakeSize, "Texels per side of a baked page (default 4096)");
    addColourOptions(cmd, a->colour,
                     "Colour the block model's clipping bodies' cut faces by this block property; same as colour= "
                     "over HTTP");
    cmd->add_option("--cells", a->cells,
                    "With --colour: each pixel's block cell + 1 (0 = none), 16-bit grey .png or .pgm");
    cmd->callback([a, &exitCode] { exitCode = run(*a); });
}

}  // namespace geoslice::cli
