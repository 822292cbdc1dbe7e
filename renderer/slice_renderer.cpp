#include "renderer/slice_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "model/clock.hpp"
#include "renderer/gl/gl_program.hpp"
#include "renderer/gl/render_target.hpp"
#include "renderer/lod/cluster_selection.hpp"
#include "renderer/passes/block_caps.hpp"
#include "renderer/passes/block_texture.hpp"
#include "renderer/passes/cut_pass.hpp"
#include "renderer/passes/fxaa_pass.hpp"
#include "renderer/passes/trace_pass.hpp"

namespace geoslice {
namespace {

// The request's planes, unit, in the model's local frame: float for the shaders (kMaxPlanes
// vec4s, unused ones zero), double for the CPU (cluster culling, traces).
struct LocalPlanes {
    float f[kMaxPlanes * 4] = {};
    std::vector<glm::dvec4> d;
};

Result<LocalPlanes> localPlanes(const SliceRequest& request, const glm::dvec3& origin) {
    if (request.planes.size() > std::size_t(kMaxPlanes))
        return makeError(ErrorCode::InvalidArgument, std::to_string(request.planes.size()) + " planes given, at most " +
                                                         std::to_string(kMaxPlanes));
    LocalPlanes out;
    for (std::size_t i = 0; i < request.planes.size(); ++i) {
        auto unit = normalizePlane(request.planes[i]);
        if (!unit)
            return makeError(ErrorCode::InvalidArgument, "plane " + std::to_string(i) + ": " + unit.error().message);
        const glm::dvec4 local = planeToLocal(*unit, origin);
        out.d.push_back(local);
        for (int k = 0; k < 4; ++k) out.f[i * 4 + std::size_t(k)] = float(local[k]);
    }
    return out;
}

// The request's other values, in the order render() has always reported them.
Status checkRequestValues(const SliceRequest& request) {
    if (auto s = checkExaggeration(request.exaggeration); !s) return s.error();
    if (!(request.lodPixelError > 0.0f && request.lodPixelError <= 1000.0f))
        return makeError(ErrorCode::InvalidArgument,
                         "LOD pixel error " + std::to_string(request.lodPixelError) + " is outside (0, 1000]");
    const BlockCaps* caps = request.blockCaps;
    if (request.blocks && caps)
        return makeError(ErrorCode::InvalidArgument, "a view takes a block texture or block caps, not both");
    if (caps && caps->planeCount() != request.planes.size())
        return makeError(ErrorCode::InvalidArgument, "block caps cut by " + std::to_string(caps->planeCount()) +
                                                         " planes for a view of " +
                                                         std::to_string(request.planes.size()));
    if (request.drawTraces && !(request.traceWidth > 0.0f && request.traceWidth <= 64.0f))
        return makeError(ErrorCode::InvalidArgument,
                         "trace width " + std::to_string(request.traceWidth) + " px is outside (0, 64]");
    return {};
}

// The view is built in display space around the display image of the origin; local
// positions q map to display-local as (q.x, q.y, f * q.z), so the exaggeration is one
// diagonal matrix on the right. Planes stay in the true local frame.
Result<ViewTransform> viewTransform(const GpuModel& model, const SliceRequest& request) {
    const VerticalExaggeration& ve = request.exaggeration;
    const glm::dvec3 displayOrigin = ve.toDisplay(model.origin());
    const Aabb displayBounds = ve.boundsToDisplay(model.worldBounds());
    Result<ViewTransform> view =
        std::holds_alternative<ProfileCamera>(request.view)
            ? profileTransform(std::get<ProfileCamera>(request.view), displayOrigin, displayBounds)
            : perspectiveTransform(std::get<PerspectiveCamera>(request.view), displayOrigin, displayBounds,
                                   request.width, request.height);
    if (!view) return view.error();
    if (!ve.identity()) {
        glm::dmat4 stretch(1.0);
        stretch[2][2] = ve.factor;
        view->viewProj = view->viewProj * stretch;
    }
    return view;
}

struct AaChoice {
    AntiAlias aa = AntiAlias::None;
    int samples = 0;  // MSAA samples of the draw target, 0: single-sampled
};

Result<AaChoice> chooseAntiAlias(const GlContext& context, const SliceRequest& request) {
    AaChoice c{request.antiAlias, 0};
    if (c.aa == AntiAlias::Auto) c.aa = context.info().software ? AntiAlias::Fxaa : AntiAlias::Msaa;
    if (c.aa != AntiAlias::Msaa) return c;
    if (request.msaaSamples < 2 || request.msaaSamples > 64)
        return makeError(ErrorCode::InvalidArgument,
                         "MSAA samples " + std::to_string(request.msaaSamples) + " is outside 2..64");
    GLint maxSamples = 0, maxIntegerSamples = 0;
    context.gl().GetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    context.gl().GetIntegerv(GL_MAX_INTEGER_SAMPLES, &maxIntegerSamples);
    c.samples = std::min({request.msaaSamples, int(maxSamples), int(maxIntegerSamples)});
    if (c.samples < 2) c.aa = AntiAlias::None, c.samples = 0;
    return c;
}

// The eye in the true local frame (the exaggeration is linear, so view rays stay lines):
// a point (w = 1, perspective) or the view direction (w = 0, profile).
glm::vec4 eyeUniform(const SliceRequest& request, const glm::dvec3& origin) {
    const VerticalExaggeration& ve = request.exaggeration;
    if (const auto* pv = std::get_if<PerspectiveCamera>(&request.view))
        return glm::vec4(glm::vec3(ve.toWorld(pv->eye) - origin), 1.0f);
    const glm::dvec3 n(normalizePlane(std::get<ProfileCamera>(request.view).plane).value());
    const glm::dvec3 dir(n.x, n.y, n.z / ve.factor);  // display direction +n back to the true frame
    return glm::vec4(glm::vec3(glm::normalize(dir)), 0.0f);
}

// Which clusters to draw at which level (renderer/lod/cluster_selection.hpp, CPU only). A
// convex cut keeps the clusters past its exit (see render()): only a plane with the eye on
// its removed side may cull (a fragment on its removed side is in front of the kept region,
// or on a ray that misses it); in a profile no plane culls.
ClusterFrame clusterFrame(const GpuModel& model, const SliceRequest& request, const glm::dmat4& viewProj,
                          const std::vector<glm::dvec4>& planes, bool unionMode, bool convexCut) {
    const VerticalExaggeration& ve = request.exaggeration;
    const auto* perspectiveView = std::get_if<PerspectiveCamera>(&request.view);
    ClusterFrame frame;
    frame.viewProj = viewProj;
    frame.planes = planes;
    if (perspectiveView) {
        const glm::dvec3 eyeLocal = ve.toWorld(perspectiveView->eye) - model.origin();
        frame.culls = cullingPlanes(planes, convexCut, &eyeLocal);
    } else {
        frame.culls = cullingPlanes(planes, convexCut, nullptr);
    }
    frame.unionMode = unionMode;
    frame.lod = model.hasLod() && (request.lod == SliceRequest::Lod::On ||
                                   (request.lod == SliceRequest::Lod::Auto && perspectiveView != nullptr));
    frame.exaggeration = ve.factor;
    frame.lodPixelError = request.lodPixelError;
    // Pixels per metre of error: orthographic from the frame, perspective at distance 1.
    if (perspectiveView) {
        frame.perspective = true;
        frame.perspPixelsPerMetre = 0.5 * request.height / std::tan(glm::radians(perspectiveView->fovYDegrees) * 0.5);
        frame.eyeDisplayLocal = perspectiveView->eye - ve.toDisplay(model.origin());
    } else {
        const ProfileCamera& pv = std::get<ProfileCamera>(request.view);
        frame.orthoPixelsPerMetre =
            std::max(request.width / (pv.rect.u1 - pv.rect.u0), request.height / (pv.rect.v1 - pv.rect.v0));
    }
    return frame;
}

// Depth, stencil and cull on, blending off, clip distances 0..planeCount-1 when they clip.
void setDrawState(const GlFunctions& gl, ClipMethod clip, int planeCount) {
    gl.Disablei(GL_BLEND, 0);
    gl.Disablei(GL_BLEND, 1);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    gl.DepthMask(GL_TRUE);
    gl.Enable(GL_STENCIL_TEST);
    gl.StencilMask(0xff);
    gl.Enable(GL_CULL_FACE);
    gl.FrontFace(GL_CCW);
    for (int i = 0; i < kMaxPlanes; ++i) {
        if (clip == ClipMethod::ClipDistance && i < planeCount)
            gl.Enable(GLenum(GL_CLIP_DISTANCE0 + i));
        else
            gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
    }
}

// The cut pass's input from the request (the caller adds the program and its uniforms).
CutPassInput cutPassInput(const SliceRequest& request, const std::vector<float>& budgets, bool allowGroups,
                          bool baked) {
    CutPassInput in;
    in.budgets = &budgets;
    in.allowGroups = allowGroups;
    in.exaggeration = request.exaggeration.factor;
    in.lodPixelError = request.lodPixelError;
    in.baked = baked;
    in.blockCaps = request.blockCaps;
    in.drawSurfaces = request.drawSurfaces;
    in.hidden = &request.hidden;
    in.cancel = request.cancel;
    return in;
}

// What the header promises render() leaves behind.
void resetState(const GlFunctions& gl) {
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.BindVertexArray(0);
    gl.UseProgram(0);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_STENCIL_TEST);
    gl.Disable(GL_CULL_FACE);
    for (int i = 0; i < kMaxPlanes; ++i) gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
}

}  // namespace

const char* antiAliasName(AntiAlias mode) {
    switch (mode) {
        case AntiAlias::None:
            return "none";
        case AntiAlias::Auto:
            return "auto";
        case AntiAlias::Fxaa:
            return "fxaa";
        case AntiAlias::Msaa:
            return "msaa";
    }
    return "none";
}

const char* clipMethodName(ClipMethod method) {
    return method == ClipMethod::ClipDistance ? "clip-distance" : "discard";
}

struct SliceRenderer::Impl {
    struct Variant {
        GlProgram program;
        SliceUniforms u;
    };
    Impl(GlContext& c, TracePass t, FxaaPass f) : context(c), trace(std::move(t)), fxaa(std::move(f)), target(c.gl()) {}

    // The target bound and cleared to `bg`, and the draw state of the slicing pass.
    void beginDraw(const SliceRequest& request, const float bg[4], bool cells, ClipMethod clip);
    // The per-view uniforms of `v` (the cut pass sets the per-part ones).
    void setViewUniforms(const Variant& v, const GpuModel& model, const SliceRequest& request,
                         const ViewTransform& view, const LocalPlanes& planes, bool unionMode, const float bg[4],
                         bool baked) const;
    // The cell pieces on the clipping bodies' caps (renderer/passes/block_caps.hpp).
    void drawBlockCaps(const BlockCaps& caps, const GpuModel& model, const glm::mat4& viewProj,
                       const LocalPlanes& planes, int planeCount, bool unionMode, const glm::vec4& eye) const;
    // MSAA resolve or FXAA, then the requested buffers into `image`.
    void antiAliasAndRead(const SliceRequest& request, const AaChoice& aa, bool cells, SliceImage& image);

    GlContext& context;
    std::vector<Variant> programs;  // variantIndex(): clip distance or discard, with or without blocks
    GlProgram capProgram;           // block-model cell pieces (renderer/passes/block_caps.hpp)
    TracePass trace;
    FxaaPass fxaa;
    RenderTarget target;
    ClusterSelection selection;  // reused by every part's draw
    float subpixelSteps = 0.0f;  // 2^GL_SUBPIXEL_BITS (shaders/slice.vert uSnap), 0: not snapped
};

void SliceRenderer::Impl::beginDraw(const SliceRequest& request, const float bg[4], bool cells, ClipMethod clip) {
    const GlFunctions& gl = context.gl();
    gl.BindFramebuffer(GL_FRAMEBUFFER, target.drawFramebuffer());
    gl.Viewport(0, 0, request.width, request.height);
    target.clear(bg, cells);
    // With block caps the bodies' program writes no cell: the caps pass fills the cell buffer.
    if (request.blockCaps) gl.ColorMaski(2, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    setDrawState(gl, clip, int(request.planes.size()));
}

void SliceRenderer::Impl::setViewUniforms(const Variant& v, const GpuModel& model, const SliceRequest& request,
                                          const ViewTransform& view, const LocalPlanes& planes, bool unionMode,
                                          const float bg[4], bool baked) const {
    const GlFunctions& gl = context.gl();
    const GLuint prog = v.program.id();
    const glm::mat4 viewProj(view.viewProj);
    const glm::vec3 light(view.lightDir);
    gl.UseProgram(prog);
    gl.ProgramUniformMatrix4fv(prog, v.u.viewProj, 1, GL_FALSE, glm::value_ptr(viewProj));
    gl.ProgramUniform4fv(prog, v.u.planes, kMaxPlanes, planes.f);
    gl.ProgramUniform1i(prog, v.u.planeCount, int(planes.d.size()));
    gl.ProgramUniform1i(prog, v.u.unionMode, unionMode ? 1 : 0);
    gl.ProgramUniform3fv(prog, v.u.lightDir, 1, glm::value_ptr(light));
    const float shadeScale[3] = {1.0f, 1.0f, float(request.exaggeration.factor)};
    gl.ProgramUniform3fv(prog, v.u.shadeScale, 1, shadeScale);
    const glm::vec4 eye = eyeUniform(request, model.origin());
    gl.ProgramUniform4fv(prog, v.u.eye, 1, glm::value_ptr(eye));
    gl.ProgramUniform4fv(prog, v.u.background, 1, bg);
    gl.ProgramUniform1f(prog, v.u.lodShift, 0.0f);
    const float snap[3] = {float(request.width), float(request.height), subpixelSteps};
    gl.ProgramUniform3fv(prog, v.u.snap, 1, snap);
    gl.ProgramUniform1i(prog, v.u.baked, baked ? 1 : 0);
    gl.ProgramUniform1i(prog, v.u.fetch, 0);
    if (baked) {
        gl.BindTextureUnit(0, model.idTexture());  // binding 0: uIdTexture (shaders/slice.frag)
        gl.BindTextureUnit(1, model.colourTable());
    }
    if (request.blocks) request.blocks->apply(prog, model.origin());
}

void SliceRenderer::Impl::drawBlockCaps(const BlockCaps& caps, const GpuModel& model, const glm::mat4& viewProj,
                                        const LocalPlanes& planes, int planeCount, bool unionMode,
                                        const glm::vec4& eye) const {
    const GlFunctions& gl = context.gl();
    const GLuint cp = capProgram.id();
    const GlProgram& c = capProgram;
    gl.ProgramUniformMatrix4fv(cp, c.uniform("uViewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
    gl.ProgramUniform4fv(cp, c.uniform("uPlanes"), kMaxPlanes, planes.f);
    gl.ProgramUniform1i(cp, c.uniform("uPlaneCount"), planeCount);
    gl.ProgramUniform1i(cp, c.uniform("uUnion"), unionMode ? 1 : 0);
    gl.ProgramUniform4fv(cp, c.uniform("uEye"), 1, glm::value_ptr(eye));
    for (int i = 0; i < kMaxPlanes; ++i) gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
    caps.draw(c);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthMask(GL_TRUE);
    gl.BindVertexArray(model.vertexArray());
}

void SliceRenderer::Impl::antiAliasAndRead(const SliceRequest& request, const AaChoice& aa, bool cells,
                                           SliceImage& image) {
    const GlFunctions& gl = context.gl();
    const auto tAa = std::chrono::steady_clock::now();
    if (aa.samples > 1) target.resolve();
    if (aa.aa == AntiAlias::Fxaa && request.readColour) fxaa.run(target, kMaxPlanes);
    if (aa.aa != AntiAlias::None) {
        gl.Finish();
        image.aaMs = msSince(tAa);
    }
    const auto t1 = std::chrono::steady_clock::now();
    if (request.readColour) target.readColour(aa.aa == AntiAlias::Fxaa, image.rgba);
    if (request.readIds) target.readIds(image.ids);
    if (request.readIds && cells) target.readCells(image.cells);
    if (request.readDepth) target.readDepth(image.depth);
    image.readbackMs = msSince(t1);
}

Result<std::unique_ptr<SliceRenderer>> SliceRenderer::create(GlContext& context) {
    const GlFunctions& gl = context.gl();
    std::vector<Impl::Variant> programs;
    for (int i = 0; i < kProgramCount; ++i) {
        const bool clipDistance = i % 2 == 0, blocks = i >= 2;
        auto p = GlProgram::build(gl, "slice.vert", "slice.frag",
                                  {std::string("GS_CLIP_DISTANCE ") + (clipDistance ? "1" : "0"),
                                   std::string("GS_BLOCKS ") + (blocks ? "1" : "0")});
        if (!p) return p.error();
        Impl::Variant v{std::move(p).value(), {}};
        v.u.viewProj = v.program.uniform("uViewProj");
        v.u.planes = v.program.uniform("uPlanes");
        v.u.planeCount = v.program.uniform("uPlaneCount");
        v.u.unionMode = v.program.uniform("uUnion");
        v.u.faceRole = v.program.uniform("uFaceRole");
        v.u.record = v.program.uniform("uRecord");
        v.u.colour = v.program.uniform("uColour");
        v.u.capRecord = v.program.uniform("uCapRecord");
        v.u.capColour = v.program.uniform("uCapColour");
        v.u.lightDir = v.program.uniform("uLightDir");
        v.u.shadeScale = v.program.uniform("uShadeScale");
        v.u.eye = v.program.uniform("uEye");
        v.u.lodShift = v.program.uniform("uLodShift");
        v.u.baked = v.program.uniform("uBaked");
        v.u.fetch = v.program.uniform("uFetch");
        v.u.background = v.program.uniform("uBackground");
        v.u.snap = v.program.uniform("uSnap");
        programs.push_back(std::move(v));
    }
    auto trace = TracePass::create(gl);
    if (!trace) return trace.error();
    auto fxaa = FxaaPass::create(gl);
    if (!fxaa) return fxaa.error();
    auto caps = GlProgram::build(gl, "block_cap.vert", "block_cap.frag", {});
    if (!caps) return caps.error();
    auto impl = std::make_unique<Impl>(context, std::move(trace).value(), std::move(fxaa).value());
    impl->programs = std::move(programs);
    impl->capProgram = std::move(caps).value();
    GLint subpixelBits = 0;
    gl.GetIntegerv(GL_SUBPIXEL_BITS, &subpixelBits);
    if (subpixelBits >= 1 && subpixelBits <= 12) impl->subpixelSteps = std::ldexp(1.0f, subpixelBits);
    return std::unique_ptr<SliceRenderer>(new SliceRenderer(std::move(impl)));
}

SliceRenderer::SliceRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

SliceRenderer::~SliceRenderer() = default;

const GlProgram& SliceRenderer::program(int index) const {
    GS_ASSERT(index >= 0 && index < kProgramCount, "program index out of range");
    return impl_->programs[std::size_t(index)].program;
}

const GlProgram& SliceRenderer::helperProgram(int index) const {
    GS_ASSERT(index >= 0 && index < kHelperProgramCount, "helper program index out of range");
    return index == 0 ? impl_->trace.program() : index == 1 ? impl_->fxaa.program() : impl_->capProgram;
}

void SliceRenderer::releaseTarget() { impl_->target.release(); }

Status SliceRenderer::checkSize(int width, int height) const {
    const GlContextInfo& info = impl_->context.info();
    int limitW = kMaxImageSide, limitH = kMaxImageSide;
    std::string why = "geoslice's limit " + std::to_string(kMaxImageSide);
    auto tighten = [&](int w, int h, const std::string& name) {
        if (w > 0 && w < limitW) limitW = w, why = name;
        if (h > 0 && h < limitH) limitH = h, why = name;
    };
    tighten(info.maxRenderbufferSize, info.maxRenderbufferSize,
            "GL_MAX_RENDERBUFFER_SIZE " + std::to_string(info.maxRenderbufferSize));
    tighten(
        info.maxViewportWidth, info.maxViewportHeight,
        "GL_MAX_VIEWPORT_DIMS " + std::to_string(info.maxViewportWidth) + "x" + std::to_string(info.maxViewportHeight));
    if (width < 1 || height < 1 || width > limitW || height > limitH)
        return makeError(ErrorCode::OutOfRange, "image size " + std::to_string(width) + "x" + std::to_string(height) +
                                                    " is outside 1x1.." + std::to_string(limitW) + "x" +
                                                    std::to_string(limitH) + " (" + why + ", on " + info.renderer +
                                                    ")");
    return {};
}

Result<SliceImage> SliceRenderer::render(const GpuModel& model, const SliceRequest& request) {
    if (auto s = checkSize(request.width, request.height); !s) return s.error();
    auto planes = localPlanes(request, model.origin());
    if (!planes) return planes.error();
    if (auto s = checkRequestValues(request); !s) return s.error();
    auto view = viewTransform(model, request);
    if (!view) return view.error();
    Impl& impl = *impl_;
    auto aa = chooseAntiAlias(impl.context, request);
    if (!aa) return aa.error();
    const GlFunctions& gl = impl.context.gl();
    const BlockCaps* caps = request.blockCaps;
    // Views coloured by a block model carry the cell of each pixel (colour attachment 2).
    const bool cells = request.blocks != nullptr || caps != nullptr;
    if (auto s = impl.target.ensure(request.width, request.height, aa->samples, aa->aa == AntiAlias::Fxaa, cells); !s)
        return s.error();

    SliceImage image;
    image.aaUsed = aa->aa;
    image.samples = std::max(aa->samples, 1);
    image.width = request.width;
    image.height = request.height;
    image.viewProj = view->viewProj;
    const int planeCount = int(request.planes.size());
    const bool unionMode = request.combine == PlaneCombine::Union && planeCount > 1;
    // Two or more planes keeping their intersection (a convex region): the fragment stage
    // judges each fragment by its view ray (shaders/slice.frag), so that a ray that leaves
    // the region inside a body still shows that body's cap; gl_ClipDistance would drop the
    // fragments past the exit that say which body that is.
    const bool convexCut = request.combine == PlaneCombine::Intersection && planeCount > 1;
    image.clipUsed = unionMode || convexCut ? ClipMethod::Discard : request.clip;
    const Impl::Variant& v =
        impl.programs[std::size_t((image.clipUsed == ClipMethod::ClipDistance ? 0 : 1) + (request.blocks ? 2 : 0))];

    const auto t0 = std::chrono::steady_clock::now();
    const float bg[4] = {request.background.r / 255.0f, request.background.g / 255.0f, request.background.b / 255.0f,
                         request.background.a / 255.0f};
    impl.beginDraw(request, bg, cells, image.clipUsed);
    const bool baked = model.hasIdTexture() && request.bakedIds;
    impl.setViewUniforms(v, model, request, *view, *planes, unionMode, bg, baked);
    gl.BindVertexArray(model.vertexArray());

    const ClusterFrame frame = clusterFrame(model, request, view->viewProj, planes->d, unionMode, convexCut);
    image.lodUsed = frame.lod;
    const std::vector<float> budgets = cellBudgets(model.cellBounds(), frame);
    CutPassInput cut = cutPassInput(request, budgets, !unionMode && !convexCut, baked);
    cut.program = v.program.id();
    cut.uniforms = &v.u;
    CutPassCounts counts;
    drawCutPass(gl, model, cut, impl.selection, counts);
    image.trianglesDrawn = counts.trianglesDrawn;
    image.clustersSkipped = counts.clustersSkipped;
    image.drawCalls = counts.drawCalls;
    if (baked) {
        gl.BindTextureUnit(0, 0);
        gl.BindTextureUnit(1, 0);
    }
    if (request.blocks) request.blocks->release();
    auto cancelled = [&] { return request.cancel && request.cancel->load(std::memory_order_relaxed); };
    const glm::mat4 viewProj(view->viewProj);
    if (caps && caps->triangleCount() > 0 && !cancelled())
        impl.drawBlockCaps(*caps, model, viewProj, *planes, planeCount, unionMode, eyeUniform(request, model.origin()));
    gl.ColorMaski(2, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (request.drawTraces && planeCount > 0 && !model.surfaceTriangles().empty()) {
        // Hidden surfaces leave no trace: the shown surfaces' triangles only.
        std::vector<glm::vec3> shown;
        const std::vector<glm::vec3>* traced = &model.surfaceTriangles();
        if (!request.hidden.empty()) {
            for (const auto& p : model.parts())
                if (!p.body && !std::binary_search(request.hidden.begin(), request.hidden.end(), p.record))
                    shown.insert(shown.end(), model.surfaceTriangles().begin() + std::ptrdiff_t(p.surfaceFirst),
                                 model.surfaceTriangles().begin() + std::ptrdiff_t(p.surfaceFirst + p.surfaceCount));
            traced = &shown;
        }
        if (!traced->empty())
            image.traceSegments = impl.trace.draw(*traced, planes->d, unionMode, viewProj, request.traceColour,
                                                  request.traceWidth, kMaxPlanes);
    }
    gl.Finish();
    image.drawMs = msSince(t0);
    if (cancelled())
        return makeError(ErrorCode::DeadlineExceeded, "cancelled: the deadline passed or the client went away");

    impl.antiAliasAndRead(request, *aa, cells, image);
    resetState(gl);
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR)
        return makeError(ErrorCode::Internal, "slicing pass " + std::to_string(request.width) + "x" +
                                                  std::to_string(request.height) + ": " + glErrorName(e));
    return image;
}

Status SliceRenderer::warmUp(const GpuModel& model) {
    SliceRequest r;
    r.width = r.height = 64;
    const Aabb& b = model.worldBounds();
    const WorldPlane plane(0.0, 1.0, 0.0, -b.centre().y);
    r.view = profileAround(plane, b, r.width, r.height);
    r.planes = {plane};
    for (ClipMethod m : {ClipMethod::ClipDistance, ClipMethod::Discard}) {
        r.clip = m;
        r.antiAlias = m == ClipMethod::ClipDistance ? AntiAlias::Auto : AntiAlias::None;
        auto img = render(model, r);
        if (!img) return img.error();
    }
    // The block caps' program, on one triangle of the plane across the model's middle.
    std::vector<RecordId> records;
    for (const auto& p : model.parts()) records.push_back(p.record);
    const glm::dvec3 c = b.centre() - model.origin();
    const glm::dvec3 s = b.size();
    const glm::vec3 tri[3] = {glm::vec3(c + glm::dvec3(-s.x, 0.0, -s.z)), glm::vec3(c + glm::dvec3(s.x, 0.0, -s.z)),
                              glm::vec3(c + glm::dvec3(0.0, 0.0, s.z))};
    const glm::uvec2 cells[3] = {{1u, 1u}, {1u, 1u}, {1u, 1u}};
    const BlockCaps::PlaneRange range{0, 3, 0};
    auto caps = BlockCaps::upload(impl_->context, tri, cells, std::span(&range, 1), {Rgba8{}}, records);
    if (!caps) return caps.error();
    r.blockCaps = caps.value().get();
    auto img = render(model, r);
    if (!img) return img.error();
    return {};
}

}  // namespace geoslice
