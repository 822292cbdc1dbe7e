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
#include "renderer/passes/fxaa_pass.hpp"
#include "renderer/passes/trace_pass.hpp"

namespace geoslice {
namespace {

// Front faces are pushed this far away from the viewer so that a back face coincident with
// them wins (see the header). Units are the depth buffer's resolution at that depth; the
// factor scales with the triangle's depth slope and covers interpolation rounding between
// two different triangulations of one surface (fault walls). Too large a factor lets a
// nested body's back face win through its own front face where it is thin along the ray
// (its rim). Measured against the oracle (tests/gl, 519k compared pixels, 50k triangles):
// factor/units 1/4: 107 disagree; 0/4: 2673; 0/16: 184; 0.25/4: 39; 0.1/4: 19; 0.05/8: 12.
constexpr float kFrontOffsetFactor = 0.05f;
constexpr float kFrontOffsetUnits = 8.0f;

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
    struct Uniforms {
        GLint viewProj = -1, planes = -1, planeCount = -1, unionMode = -1, faceRole = -1, record = -1, colour = -1,
              capRecord = -1, capColour = -1, lightDir = -1, shadeScale = -1, eye = -1, lodShift = -1, baked = -1,
              fetch = -1, background = -1, snap = -1;
    };
    struct Variant {
        GlProgram program;
        Uniforms u;
    };
    Impl(GlContext& c, TracePass t, FxaaPass f) : context(c), trace(std::move(t)), fxaa(std::move(f)), target(c.gl()) {}
    GlContext& context;
    std::vector<Variant> programs;  // variantIndex(): clip distance or discard, with or without blocks
    GlProgram capProgram;           // block-model cell pieces (renderer/passes/block_caps.hpp)
    TracePass trace;
    FxaaPass fxaa;
    RenderTarget target;
    ClusterSelection selection;  // reused by every part's draw
    float subpixelSteps = 0.0f;  // 2^GL_SUBPIXEL_BITS (shaders/slice.vert uSnap), 0: not snapped
};

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
    if (request.planes.size() > std::size_t(kMaxPlanes))
        return makeError(ErrorCode::InvalidArgument, std::to_string(request.planes.size()) + " planes given, at most " +
                                                         std::to_string(kMaxPlanes));
    float planesLocal[kMaxPlanes * 4] = {};
    std::vector<glm::dvec4> planesLocalD;
    for (std::size_t i = 0; i < request.planes.size(); ++i) {
        auto unit = normalizePlane(request.planes[i]);
        if (!unit)
            return makeError(ErrorCode::InvalidArgument, "plane " + std::to_string(i) + ": " + unit.error().message);
        const glm::dvec4 local = planeToLocal(*unit, model.origin());
        planesLocalD.push_back(local);
        for (int k = 0; k < 4; ++k) planesLocal[i * 4 + std::size_t(k)] = float(local[k]);
    }
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
    // The view is built in display space around the display image of the origin; local
    // positions q map to display-local as (q.x, q.y, f * q.z), so the exaggeration is one
    // diagonal matrix on the right. Planes stay in the true local frame.
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
    Impl& impl = *impl_;
    const GlFunctions& gl = impl.context.gl();
    AntiAlias aa = request.antiAlias;
    if (aa == AntiAlias::Auto) aa = impl.context.info().software ? AntiAlias::Fxaa : AntiAlias::Msaa;
    int samples = 0;
    if (aa == AntiAlias::Msaa) {
        if (request.msaaSamples < 2 || request.msaaSamples > 64)
            return makeError(ErrorCode::InvalidArgument,
                             "MSAA samples " + std::to_string(request.msaaSamples) + " is outside 2..64");
        GLint maxSamples = 0, maxIntegerSamples = 0;
        gl.GetIntegerv(GL_MAX_SAMPLES, &maxSamples);
        gl.GetIntegerv(GL_MAX_INTEGER_SAMPLES, &maxIntegerSamples);
        samples = std::min({request.msaaSamples, int(maxSamples), int(maxIntegerSamples)});
        if (samples < 2) aa = AntiAlias::None, samples = 0;
    }
    RenderTarget& target = impl.target;
    // Views coloured by a block model carry the cell of each pixel (colour attachment 2).
    const bool cells = request.blocks != nullptr || caps != nullptr;
    if (auto s = target.ensure(request.width, request.height, samples, aa == AntiAlias::Fxaa, cells); !s)
        return s.error();

    SliceImage image;
    image.aaUsed = aa;
    image.samples = std::max(samples, 1);
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
    const GLuint prog = v.program.id();

    const auto t0 = std::chrono::steady_clock::now();
    gl.BindFramebuffer(GL_FRAMEBUFFER, target.drawFramebuffer());
    gl.Viewport(0, 0, request.width, request.height);
    const float bg[4] = {request.background.r / 255.0f, request.background.g / 255.0f, request.background.b / 255.0f,
                         request.background.a / 255.0f};
    target.clear(bg, cells);
    // With block caps the bodies' program writes no cell: the caps pass fills the cell buffer.
    if (caps) gl.ColorMaski(2, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);

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
        if (image.clipUsed == ClipMethod::ClipDistance && i < planeCount)
            gl.Enable(GLenum(GL_CLIP_DISTANCE0 + i));
        else
            gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
    }

    const glm::mat4 viewProj(view->viewProj);
    const glm::vec3 light(view->lightDir);
    gl.UseProgram(prog);
    gl.ProgramUniformMatrix4fv(prog, v.u.viewProj, 1, GL_FALSE, glm::value_ptr(viewProj));
    gl.ProgramUniform4fv(prog, v.u.planes, kMaxPlanes, planesLocal);
    gl.ProgramUniform1i(prog, v.u.planeCount, planeCount);
    gl.ProgramUniform1i(prog, v.u.unionMode, unionMode ? 1 : 0);
    gl.ProgramUniform3fv(prog, v.u.lightDir, 1, glm::value_ptr(light));
    const float shadeScale[3] = {1.0f, 1.0f, float(ve.factor)};
    gl.ProgramUniform3fv(prog, v.u.shadeScale, 1, shadeScale);
    // The eye in the true local frame (the exaggeration is linear, so view rays stay lines).
    glm::vec4 eyeUniform(0.0f);
    if (const auto* pv = std::get_if<PerspectiveCamera>(&request.view)) {
        eyeUniform = glm::vec4(glm::vec3(ve.toWorld(pv->eye) - model.origin()), 1.0f);
    } else {
        const glm::dvec3 n(normalizePlane(std::get<ProfileCamera>(request.view).plane).value());
        glm::dvec3 dir(n.x, n.y, n.z / ve.factor);  // display direction +n back to the true frame
        eyeUniform = glm::vec4(glm::vec3(glm::normalize(dir)), 0.0f);
    }
    gl.ProgramUniform4fv(prog, v.u.eye, 1, glm::value_ptr(eyeUniform));
    gl.ProgramUniform4fv(prog, v.u.background, 1, bg);
    gl.ProgramUniform1f(prog, v.u.lodShift, 0.0f);
    const float snap[3] = {float(request.width), float(request.height), impl.subpixelSteps};
    gl.ProgramUniform3fv(prog, v.u.snap, 1, snap);
    const bool baked = model.hasIdTexture() && request.bakedIds;
    gl.ProgramUniform1i(prog, v.u.baked, baked ? 1 : 0);
    gl.ProgramUniform1i(prog, v.u.fetch, 0);
    if (baked) {
        gl.BindTextureUnit(0, model.idTexture());  // binding 0: uIdTexture (shaders/slice.frag)
        gl.BindTextureUnit(1, model.colourTable());
    }
    if (request.blocks) request.blocks->apply(prog, model.origin());
    gl.BindVertexArray(model.vertexArray());

    // Which clusters to draw at which level (renderer/lod/cluster_selection.hpp, CPU only). A
    // convex cut keeps the clusters past its exit (see above): only a plane with the eye on
    // its removed side may cull (a fragment on its removed side is in front of the kept
    // region, or on a ray that misses it); in a profile no plane culls.
    const auto* perspectiveView = std::get_if<PerspectiveCamera>(&request.view);
    ClusterFrame frame;
    frame.viewProj = view->viewProj;
    frame.planes = planesLocalD;
    if (perspectiveView) {
        const glm::dvec3 eyeLocal = ve.toWorld(perspectiveView->eye) - model.origin();
        frame.culls = cullingPlanes(planesLocalD, convexCut, &eyeLocal);
    } else {
        frame.culls = cullingPlanes(planesLocalD, convexCut, nullptr);
    }
    frame.unionMode = unionMode;
    frame.lod = model.hasLod() && (request.lod == SliceRequest::Lod::On ||
                                   (request.lod == SliceRequest::Lod::Auto && perspectiveView != nullptr));
    image.lodUsed = frame.lod;
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
    const std::vector<float> allowed = cellBudgets(model.cellBounds(), frame);
    // Ranges of one part go out as one glMultiDrawElementsBaseVertex: llvmpipe pays its
    // per-draw validation once instead of per cluster (thousands of clusters at L4).
    auto flush = [&](const DrawBatch& batch) {
        if (batch.empty()) return;
        gl.MultiDrawElementsBaseVertex(GL_TRIANGLES, batch.counts.data(), GL_UNSIGNED_INT, batch.offsets.data(),
                                       GLsizei(batch.counts.size()), batch.baseVertices.data());
        for (GLsizei c : batch.counts) image.trianglesDrawn += std::size_t(c) / 3;
        ++image.drawCalls;
    };
    // Each cluster at the coarsest level its budget allows (-1: skipped).
    // shiftSign: 0 back faces (drawn where they are), +1 front faces and surfaces (away).
    // offsetBase: the pass draws with the front-face polygon offset on.
    ClusterSelection& selection = impl.selection;
    auto cancelled = [&] { return request.cancel && request.cancel->load(std::memory_order_relaxed); };
    auto draw = [&](const GpuModel::DrawPart& p, float shiftSign, bool offsetBase) {
        if (cancelled()) return;
        selection.select(p, allowed, !unionMode && !convexCut, ve.factor);
        image.clustersSkipped += selection.skipped;
        flush(selection.full);
        if (!selection.anySimplified) return;
        // Simplified clusters after the full-detail ones, so that the pass state changes
        // twice per part. Their front faces go back by twice the level's error: along the
        // ray (shader) for surfaces facing the viewer, and by a slope-scaled polygon offset
        // for grazing ones (the error projects to at most lodPixelError pixels, which moves
        // depth by at most that many depth slopes). Back faces stay: moving them would
        // reorder back faces among themselves. One offset per pass: llvmpipe compiles a
        // setup variant per distinct polygon offset.
        const bool shift = shiftSign > 0.0f;
        if (shift) {
            gl.Enable(GL_POLYGON_OFFSET_FILL);
            gl.PolygonOffset(3.0f * request.lodPixelError + (offsetBase ? kFrontOffsetFactor : 0.0f),
                             offsetBase ? kFrontOffsetUnits : 0.0f);
        }
        for (int k = 0; k <= ClusterSelection::kShiftBuckets; ++k) {
            const DrawBatch& batch = selection.pushed[std::size_t(k)];
            if (batch.empty()) continue;
            if (shift) gl.ProgramUniform1f(prog, v.u.lodShift, std::ldexp(1.0f, k - 9));
            flush(batch);
        }
        if (shift) {
            gl.ProgramUniform1f(prog, v.u.lodShift, 0.0f);
            if (offsetBase)
                gl.PolygonOffset(kFrontOffsetFactor, kFrontOffsetUnits);
            else
                gl.Disable(GL_POLYGON_OFFSET_FILL);
        }
    };
    // fetch: the drawn surface's own texels hold the record to show (shaders/slice.frag); not
    // for a nested body's front faces, which show their container's cap.
    auto setFace = [&](int role, const GpuModel::DrawPart& p, RecordId capRecord, const glm::vec4& capColour,
                       bool fetch = true) {
        gl.ProgramUniform1i(prog, v.u.faceRole, role);
        if (baked) gl.ProgramUniform1i(prog, v.u.fetch, fetch ? 1 : 0);
        gl.ProgramUniform1ui(prog, v.u.record, p.record);
        gl.ProgramUniform4fv(prog, v.u.colour, 1, glm::value_ptr(p.colour));
        gl.ProgramUniform1ui(prog, v.u.capRecord, capRecord);
        gl.ProgramUniform4fv(prog, v.u.capColour, 1, glm::value_ptr(capColour));
        const int code = role != 1 ? 0 : caps && caps->clips(capRecord) ? kStencilBlockCap : kStencilCap;
        gl.StencilFunc(GL_ALWAYS, code, 0xff);
    };
    // Back faces of bodies: the ray is inside that body -> its cap.
    gl.StencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    gl.CullFace(GL_FRONT);
    gl.Disable(GL_POLYGON_OFFSET_FILL);
    for (const auto& p : model.parts())
        if (p.body) {
            setFace(1, p, p.record, p.colour);
            draw(p, 0.0f, false);
        }
    // Front faces of bodies, pushed back so that coincident back faces win: the exterior of
    // a top-level body, or the cap of the container of a nested one.
    gl.CullFace(GL_BACK);
    gl.Enable(GL_POLYGON_OFFSET_FILL);
    gl.PolygonOffset(kFrontOffsetFactor, kFrontOffsetUnits);
    for (const auto& p : model.parts())
        if (p.body) {
            if (p.containerRecord != kNoRecord) {
                // A nested body shares no surface with its container, so its front faces
                // need no offset; with one, its own back face won through them where the
                // body is thin along the ray (specks of the nested body's cap at its rim).
                setFace(1, p, p.containerRecord, p.containerColour, false);
                gl.Disable(GL_POLYGON_OFFSET_FILL);
                draw(p, 1.0f, false);
                gl.Enable(GL_POLYGON_OFFSET_FILL);
                gl.PolygonOffset(kFrontOffsetFactor, kFrontOffsetUnits);
            } else {
                setFace(0, p, p.record, p.colour);
                draw(p, 1.0f, true);
            }
        }
    gl.Disable(GL_POLYGON_OFFSET_FILL);
    // Open surfaces, both sides, never over a cut face (stencil 1).
    if (request.drawSurfaces) {
        gl.Disable(GL_CULL_FACE);
        gl.StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
        for (const auto& p : model.parts())
            if (!p.body) {
                setFace(0, p, p.record, p.colour);
                gl.StencilFunc(GL_EQUAL, 0, 0xff);
                draw(p, 1.0f, false);
            }
    }
    if (baked) {
        gl.BindTextureUnit(0, 0);
        gl.BindTextureUnit(1, 0);
    }
    if (request.blocks) request.blocks->release();
    if (caps && caps->triangleCount() > 0 && !cancelled()) {
        // The cell pieces on the clipping bodies' caps (renderer/passes/block_caps.hpp).
        const GLuint cp = impl.capProgram.id();
        const GlProgram& c = impl.capProgram;
        gl.ProgramUniformMatrix4fv(cp, c.uniform("uViewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
        gl.ProgramUniform4fv(cp, c.uniform("uPlanes"), kMaxPlanes, planesLocal);
        gl.ProgramUniform1i(cp, c.uniform("uPlaneCount"), planeCount);
        gl.ProgramUniform1i(cp, c.uniform("uUnion"), unionMode ? 1 : 0);
        gl.ProgramUniform4fv(cp, c.uniform("uEye"), 1, glm::value_ptr(eyeUniform));
        for (int i = 0; i < kMaxPlanes; ++i) gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
        caps->draw(c);
        gl.Enable(GL_DEPTH_TEST);
        gl.DepthMask(GL_TRUE);
        gl.BindVertexArray(model.vertexArray());
    }
    gl.ColorMaski(2, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (request.drawTraces && planeCount > 0 && !model.surfaceTriangles().empty())
        image.traceSegments = impl.trace.draw(model.surfaceTriangles(), planesLocalD, unionMode, viewProj,
                                              request.traceColour, request.traceWidth, kMaxPlanes);
    gl.Finish();
    image.drawMs = msSince(t0);
    if (cancelled())
        return makeError(ErrorCode::DeadlineExceeded, "cancelled: the deadline passed or the client went away");

    const auto tAa = std::chrono::steady_clock::now();
    if (samples > 1) target.resolve();
    if (aa == AntiAlias::Fxaa && request.readColour) impl.fxaa.run(target, kMaxPlanes);
    if (aa != AntiAlias::None) {
        gl.Finish();
        image.aaMs = msSince(tAa);
    }

    const auto t1 = std::chrono::steady_clock::now();
    if (request.readColour) target.readColour(aa == AntiAlias::Fxaa, image.rgba);
    if (request.readIds) target.readIds(image.ids);
    if (request.readIds && cells) target.readCells(image.cells);
    if (request.readDepth) target.readDepth(image.depth);
    image.readbackMs = msSince(t1);

    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.BindVertexArray(0);
    gl.UseProgram(0);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_STENCIL_TEST);
    gl.Disable(GL_CULL_FACE);
    for (int i = 0; i < kMaxPlanes; ++i) gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
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
