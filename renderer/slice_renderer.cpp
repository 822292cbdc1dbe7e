#include "renderer/slice_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <glm/gtc/type_ptr.hpp>

namespace geoslice {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Front faces are pushed this far away from the viewer so that a back face coincident with
// them wins (see the header). Units are the depth buffer's resolution at that depth; the
// factor scales with the triangle's depth slope and covers interpolation rounding between
// two different triangulations of one surface (fault walls). Too large a factor lets a
// nested body's back face win through its own front face where it is thin along the ray
// (its rim). Measured against the oracle (tests/gl, 519k compared pixels, 50k triangles):
// factor/units 1/4: 107 disagree; 0/4: 2673; 0/16: 184; 0.25/4: 39; 0.1/4: 19; 0.05/8: 12.
constexpr float kFrontOffsetFactor = 0.05f;
constexpr float kFrontOffsetUnits = 8.0f;

// Flips rows (GL reads bottom-up) into `out`, row 0 at the top.
template <class T>
void flipRows(const std::vector<T>& in, std::vector<T>& out, int width, int height, int channels) {
    const std::size_t row = std::size_t(width) * std::size_t(channels);
    out.resize(in.size());
    for (int y = 0; y < height; ++y)
        std::memcpy(out.data() + std::size_t(height - 1 - y) * row, in.data() + std::size_t(y) * row, row * sizeof(T));
}

// The pieces of `tris` (local frame, 3 vertices each) that lie on the cut face of each plane
// (local frame, unit normals), as line-segment end points appended to `out`. A triangle
// crosses plane i where its vertices' signed distances change sign (>= 0 counts as kept, so
// a vertex on the plane never yields a zero-length duplicate). The cut face of plane i is
// where every other plane keeps the point (intersection) or removes it (union), so each
// segment is clipped by those half-spaces. Distances in double.
void appendTraces(const std::vector<glm::vec3>& tris, const std::vector<glm::dvec4>& planes, bool unionMode,
                  std::vector<glm::vec3>& out) {
    const int planeCount = int(planes.size());
    auto dist = [](const glm::dvec4& pl, const glm::dvec3& p) { return glm::dot(glm::dvec3(pl), p) + pl.w; };
    for (int i = 0; i < planeCount; ++i) {
        const glm::dvec4& pl = planes[std::size_t(i)];
        for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
            const glm::dvec3 v[3] = {tris[t], tris[t + 1], tris[t + 2]};
            const double d[3] = {dist(pl, v[0]), dist(pl, v[1]), dist(pl, v[2])};
            glm::dvec3 ends[2];
            int n = 0;
            for (int e = 0; e < 3; ++e) {
                const int a = e, b = (e + 1) % 3;
                if ((d[a] >= 0.0) == (d[b] >= 0.0)) continue;
                if (n < 2) ends[n] = v[a] + (v[b] - v[a]) * (d[a] / (d[a] - d[b]));
                ++n;
            }
            if (n != 2) continue;
            double t0 = 0.0, t1 = 1.0;
            for (int j = 0; j < planeCount && t0 <= t1; ++j) {
                if (j == i) continue;
                const double sign = unionMode ? -1.0 : 1.0;
                const double g0 = sign * dist(planes[std::size_t(j)], ends[0]);
                const double g1 = sign * dist(planes[std::size_t(j)], ends[1]);
                if (g0 < 0.0 && g1 < 0.0)
                    t0 = 2.0, t1 = -1.0;
                else if (g0 < 0.0)
                    t0 = std::max(t0, g0 / (g0 - g1));
                else if (g1 < 0.0)
                    t1 = std::min(t1, g0 / (g0 - g1));
            }
            if (!(t0 < t1)) continue;
            out.push_back(glm::vec3(ends[0] + (ends[1] - ends[0]) * t0));
            out.push_back(glm::vec3(ends[0] + (ends[1] - ends[0]) * t1));
        }
    }
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

Result<std::unique_ptr<SliceRenderer>> SliceRenderer::create(GlContext& context) {
    std::unique_ptr<SliceRenderer> r(new SliceRenderer(context));
    for (int i = 0; i < kProgramCount; ++i) {
        auto p = GlProgram::build(context.gl(), "slice.vert", "slice.frag",
                                  {std::string("GS_CLIP_DISTANCE ") + (i == 0 ? "1" : "0")});
        if (!p) return p.error();
        Variant v{std::move(p).value(), {}};
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
        r->programs_.push_back(std::move(v));
    }
    auto trace = GlProgram::build(context.gl(), "trace.vert", "trace.frag", {});
    if (!trace) return trace.error();
    r->traceProgram_ = std::make_unique<GlProgram>(std::move(trace).value());
    r->traceViewProj_ = r->traceProgram_->uniform("uViewProj");
    r->traceColour_ = r->traceProgram_->uniform("uColour");
    auto fxaa = GlProgram::build(context.gl(), "fxaa.vert", "fxaa.frag", {});
    if (!fxaa) return fxaa.error();
    r->fxaaProgram_ = std::make_unique<GlProgram>(std::move(fxaa).value());
    r->fxaaTexel_ = r->fxaaProgram_->uniform("uTexel");
    r->fxaaColour_ = r->fxaaProgram_->uniform("uColour");
    return r;
}

SliceRenderer::~SliceRenderer() {
    releaseTarget();
    const GlFunctions& gl = context_.gl();
    if (traceVao_) gl.DeleteVertexArrays(1, &traceVao_);
    if (traceBuffer_) gl.DeleteBuffers(1, &traceBuffer_);
    if (emptyVao_) gl.DeleteVertexArrays(1, &emptyVao_);
}

Status SliceRenderer::drawTraces(const SliceRequest& request, const GpuModel& model,
                                 const std::vector<glm::dvec4>& planesLocal, const glm::mat4& viewProj,
                                 std::size_t& segments) {
    std::vector<glm::vec3> verts;
    appendTraces(model.surfaceTriangles(), planesLocal,
                 request.combine == PlaneCombine::Union && planesLocal.size() > 1, verts);
    segments = verts.size() / 2;
    if (verts.empty()) return {};
    const GlFunctions& gl = context_.gl();
    if (verts.size() > traceCapacity_) {
        if (traceBuffer_) gl.DeleteBuffers(1, &traceBuffer_);
        traceCapacity_ = std::max(verts.size(), 2 * traceCapacity_);
        gl.CreateBuffers(1, &traceBuffer_);
        gl.NamedBufferStorage(traceBuffer_, GLsizeiptr(traceCapacity_ * sizeof(glm::vec3)), nullptr,
                              GL_DYNAMIC_STORAGE_BIT);
        if (!traceVao_) {
            gl.CreateVertexArrays(1, &traceVao_);
            gl.EnableVertexArrayAttrib(traceVao_, 0);
            gl.VertexArrayAttribFormat(traceVao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
            gl.VertexArrayAttribBinding(traceVao_, 0, 0);
        }
        gl.VertexArrayVertexBuffer(traceVao_, 0, traceBuffer_, 0, sizeof(glm::vec3));
    }
    gl.NamedBufferSubData(traceBuffer_, 0, GLsizeiptr(verts.size() * sizeof(glm::vec3)), verts.data());
    const GLuint prog = traceProgram_->id();
    gl.UseProgram(prog);
    gl.ProgramUniformMatrix4fv(prog, traceViewProj_, 1, GL_FALSE, glm::value_ptr(viewProj));
    const Rgba8 c = request.traceColour;
    const float colour[4] = {c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, c.a / 255.0f};
    gl.ProgramUniform4fv(prog, traceColour_, 1, colour);
    // Only on cut faces (stencil 1), at the plane's depth, which is in front of the surface
    // behind the cut that gave the cap its depth; ids and depth untouched.
    gl.ColorMaski(1, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.DepthMask(GL_FALSE);
    gl.DepthFunc(GL_LEQUAL);
    gl.StencilFunc(GL_EQUAL, 1, 0xff);
    gl.StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    gl.Disable(GL_CULL_FACE);
    for (int i = 0; i < kMaxPlanes; ++i) gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
    float range[2] = {1.0f, 1.0f};
    gl.GetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
    gl.LineWidth(std::clamp(request.traceWidth, std::max(range[0], 1.0f), std::max(range[1], 1.0f)));
    gl.BindVertexArray(traceVao_);
    gl.DrawArrays(GL_LINES, 0, GLsizei(verts.size()));
    gl.LineWidth(1.0f);
    gl.ColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.DepthMask(GL_TRUE);
    gl.DepthFunc(GL_LESS);
    return {};
}

void SliceRenderer::releaseTarget() {
    const GlFunctions& gl = context_.gl();
    GLuint fbos[] = {fbo_, msFbo_, aaFbo_};
    for (GLuint f : fbos)
        if (f) gl.DeleteFramebuffers(1, &f);
    GLuint rbs[] = {idRb_, depthRb_, msColourRb_, msIdRb_, msDepthRb_, aaRb_};
    for (GLuint rb : rbs)
        if (rb) gl.DeleteRenderbuffers(1, &rb);
    if (colourTex_) gl.DeleteTextures(1, &colourTex_);
    fbo_ = msFbo_ = aaFbo_ = colourTex_ = idRb_ = depthRb_ = msColourRb_ = msIdRb_ = msDepthRb_ = aaRb_ = 0;
    targetWidth_ = targetHeight_ = targetSamples_ = 0;
    targetAa_ = false;
}

Status SliceRenderer::checkSize(int width, int height) const {
    const GlContextInfo& info = context_.info();
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

Status SliceRenderer::ensureTarget(int width, int height, int samples, bool fxaa) {
    if (fbo_ && width == targetWidth_ && height == targetHeight_ && samples == targetSamples_ &&
        (fxaa == targetAa_ || !fxaa))
        return {};
    releaseTarget();
    const GlFunctions& gl = context_.gl();
    while (gl.GetError() != GL_NO_ERROR) {
    }
    const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    // Single-sample target: what is read back. Colour is a texture so that the FXAA pass can
    // sample it; ids and depth are renderbuffers.
    gl.CreateTextures(GL_TEXTURE_2D, 1, &colourTex_);
    gl.TextureStorage2D(colourTex_, 1, GL_RGBA8, width, height);
    gl.TextureParameteri(colourTex_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl.TextureParameteri(colourTex_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.TextureParameteri(colourTex_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TextureParameteri(colourTex_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl.CreateRenderbuffers(1, &idRb_);
    gl.NamedRenderbufferStorage(idRb_, GL_R32UI, width, height);
    gl.CreateRenderbuffers(1, &depthRb_);
    gl.NamedRenderbufferStorage(depthRb_, GL_DEPTH32F_STENCIL8, width, height);
    gl.CreateFramebuffers(1, &fbo_);
    gl.NamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, colourTex_, 0);
    gl.NamedFramebufferRenderbuffer(fbo_, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, idRb_);
    gl.NamedFramebufferRenderbuffer(fbo_, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depthRb_);
    gl.NamedFramebufferDrawBuffers(fbo_, 2, drawBuffers);
    std::vector<GLuint> check = {fbo_};
    if (samples > 1) {
        // Multisampled draw target, resolved into fbo_ after the pass (colour averaged; ids
        // and depth take one sample's value, GL 4.5 section 18.3.1: never blended).
        gl.CreateRenderbuffers(1, &msColourRb_);
        gl.NamedRenderbufferStorageMultisample(msColourRb_, samples, GL_RGBA8, width, height);
        gl.CreateRenderbuffers(1, &msIdRb_);
        gl.NamedRenderbufferStorageMultisample(msIdRb_, samples, GL_R32UI, width, height);
        gl.CreateRenderbuffers(1, &msDepthRb_);
        gl.NamedRenderbufferStorageMultisample(msDepthRb_, samples, GL_DEPTH32F_STENCIL8, width, height);
        gl.CreateFramebuffers(1, &msFbo_);
        gl.NamedFramebufferRenderbuffer(msFbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msColourRb_);
        gl.NamedFramebufferRenderbuffer(msFbo_, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, msIdRb_);
        gl.NamedFramebufferRenderbuffer(msFbo_, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, msDepthRb_);
        gl.NamedFramebufferDrawBuffers(msFbo_, 2, drawBuffers);
        check.push_back(msFbo_);
    }
    if (fxaa) {
        gl.CreateRenderbuffers(1, &aaRb_);
        gl.NamedRenderbufferStorage(aaRb_, GL_RGBA8, width, height);
        gl.CreateFramebuffers(1, &aaFbo_);
        gl.NamedFramebufferRenderbuffer(aaFbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, aaRb_);
        check.push_back(aaFbo_);
    }
    GLenum error = gl.GetError();
    GLenum status = GL_FRAMEBUFFER_COMPLETE;
    for (GLuint f : check)
        if (status == GL_FRAMEBUFFER_COMPLETE) status = gl.CheckNamedFramebufferStatus(f, GL_FRAMEBUFFER);
    if (error != GL_NO_ERROR || status != GL_FRAMEBUFFER_COMPLETE) {
        releaseTarget();
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "framebuffer %dx%d (RGBA8 + R32UI + DEPTH32F_STENCIL8, %d sample(s)%s): %s, status 0x%04x", width,
                      height, std::max(samples, 1), fxaa ? ", FXAA target" : "", glErrorName(error).c_str(), status);
        return makeError(error == GL_OUT_OF_MEMORY ? ErrorCode::OutOfRange : ErrorCode::Internal, buf);
    }
    targetWidth_ = width;
    targetHeight_ = height;
    targetSamples_ = samples;
    targetAa_ = fxaa;
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
        std::holds_alternative<ProfileView>(request.view)
            ? profileTransform(std::get<ProfileView>(request.view), displayOrigin, displayBounds)
            : perspectiveTransform(std::get<PerspectiveView>(request.view), displayOrigin, displayBounds, request.width,
                                   request.height);
    if (!view) return view.error();
    if (!ve.identity()) {
        glm::dmat4 stretch(1.0);
        stretch[2][2] = ve.factor;
        view->viewProj = view->viewProj * stretch;
    }
    const GlFunctions& gl = context_.gl();
    AntiAlias aa = request.antiAlias;
    if (aa == AntiAlias::Auto) aa = context_.info().software ? AntiAlias::Fxaa : AntiAlias::Msaa;
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
    if (auto s = ensureTarget(request.width, request.height, samples, aa == AntiAlias::Fxaa); !s) return s.error();
    const GLuint drawFbo = samples > 1 ? msFbo_ : fbo_;

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
    const Variant& v = programs_[image.clipUsed == ClipMethod::ClipDistance ? 0 : 1];
    const GLuint prog = v.program.id();

    const auto t0 = std::chrono::steady_clock::now();
    gl.BindFramebuffer(GL_FRAMEBUFFER, drawFbo);
    gl.Viewport(0, 0, request.width, request.height);
    const float bg[4] = {request.background.r / 255.0f, request.background.g / 255.0f, request.background.b / 255.0f,
                         request.background.a / 255.0f};
    const GLuint noId[4] = {0, 0, 0, 0};
    gl.ClearNamedFramebufferfv(drawFbo, GL_COLOR, 0, bg);
    gl.ClearNamedFramebufferuiv(drawFbo, GL_COLOR, 1, noId);
    gl.ClearNamedFramebufferfi(drawFbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);

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
    if (const auto* pv = std::get_if<PerspectiveView>(&request.view)) {
        eyeUniform = glm::vec4(glm::vec3(ve.toWorld(pv->eye) - model.origin()), 1.0f);
    } else {
        const glm::dvec3 n(normalizePlane(std::get<ProfileView>(request.view).plane).value());
        glm::dvec3 dir(n.x, n.y, n.z / ve.factor);  // display direction +n back to the true frame
        eyeUniform = glm::vec4(glm::vec3(glm::normalize(dir)), 0.0f);
    }
    gl.ProgramUniform4fv(prog, v.u.eye, 1, glm::value_ptr(eyeUniform));
    gl.ProgramUniform4fv(prog, v.u.background, 1, bg);
    gl.ProgramUniform1f(prog, v.u.lodShift, 0.0f);
    const bool baked = model.hasIdTexture() && request.bakedIds;
    gl.ProgramUniform1i(prog, v.u.baked, baked ? 1 : 0);
    gl.ProgramUniform1i(prog, v.u.fetch, 0);
    if (baked) {
        gl.BindTextureUnit(0, model.idTexture());  // binding 0: uIdTexture (shaders/slice.frag)
        gl.BindTextureUnit(1, model.colourTable());
    }
    gl.BindVertexArray(model.vertexArray());

    // A convex cut keeps the clusters past its exit (see above): only a plane with the eye on
    // its removed side may cull (a fragment on its removed side is in front of the kept
    // region, or on a ray that misses it); in a profile no plane culls.
    std::vector<std::uint8_t> culls(planesLocalD.size(), 1);
    if (convexCut)
        for (std::size_t i = 0; i < planesLocalD.size(); ++i) {
            const glm::dvec4& pl = planesLocalD[i];
            const auto* pv = std::get_if<PerspectiveView>(&request.view);
            culls[i] = pv && glm::dot(glm::dvec3(pl), ve.toWorld(pv->eye) - model.origin()) + pl.w < 0.0;
        }
    const std::vector<float> allowed = clusterBudget(model, request, *view, unionMode, planesLocalD, culls, image);
    // Ranges of one part go out as one glMultiDrawElementsBaseVertex: llvmpipe pays its
    // per-draw validation once instead of per cluster (thousands of clusters at L4).
    struct Batch {
        std::vector<GLsizei> counts;
        std::vector<const void*> offsets;
        std::vector<GLint> baseVertices;
        void add(std::size_t first, GLsizei count, GLint baseVertex) {
            if (count == 0) return;
            const void* offset = reinterpret_cast<const void*>(first * sizeof(std::uint32_t));
            // Contiguous with the previous range (full-detail clusters in index order): extend.
            if (!counts.empty() && baseVertices.back() == baseVertex &&
                static_cast<const char*>(offsets.back()) + std::size_t(counts.back()) * sizeof(std::uint32_t) ==
                    static_cast<const char*>(offset)) {
                counts.back() += count;
                return;
            }
            counts.push_back(count);
            offsets.push_back(offset);
            baseVertices.push_back(baseVertex);
        }
        void clear() { counts.clear(), offsets.clear(), baseVertices.clear(); }
    };
    auto flush = [&](Batch& batch) {
        if (batch.counts.empty()) return;
        gl.MultiDrawElementsBaseVertex(GL_TRIANGLES, batch.counts.data(), GL_UNSIGNED_INT, batch.offsets.data(),
                                       GLsizei(batch.counts.size()), batch.baseVertices.data());
        for (GLsizei c : batch.counts) image.trianglesDrawn += std::size_t(c) / 3;
        ++image.drawCalls;
        batch.clear();
    };
    // Each cluster at the coarsest level its budget allows (-1: skipped).
    // shiftSign: 0 back faces (drawn where they are), +1 front faces and surfaces (away).
    // offsetBase: the pass draws with the front-face polygon offset on.
    const double shiftScale = std::max(1.0, request.exaggeration.factor);
    // Simplified clusters are grouped by their push rounded up to a power of two (at most
    // twice what they need), so that each group is one draw with one uniform value.
    constexpr int kShiftBuckets = 24;
    Batch full;
    std::vector<Batch> pushed(kShiftBuckets + 1);
    std::vector<std::uint8_t> handled;  // per cluster of the part being drawn: in a group
    auto cancelled = [&] { return request.cancel && request.cancel->load(std::memory_order_relaxed); };
    auto draw = [&](const GpuModel::DrawPart& p, float shiftSign, bool offsetBase) {
        if (cancelled()) return;
        bool anySimplified = false;
        auto addSimplified = [&](std::size_t first, GLsizei count, float error) {
            // Bucket k holds pushes in (2^(k-9), 2^(k-8)] metres; bucket 0 everything below.
            const double push = 2.0 * error * shiftScale;
            const int k = push <= 0.0 ? 0 : std::clamp(int(std::ceil(std::log2(push))) + 9, 0, kShiftBuckets);
            pushed[std::size_t(k)].add(first, count, p.baseVertex);
            anySimplified = true;
        };
        // A group replaces its members when every one of them may have its error and none is
        // at full detail for a cut (budget 0) or skipped; coarsest first (the model stores
        // them finest first), and a group with a member already drawn by a coarser one stays.
        // One plane only: then every member cell lies in the kept half-space, which is
        // convex, so the group (in the hull of its members) meets no plane; a union's kept
        // region is not convex, and a convex cut keeps cells past its exit too.
        handled.assign(p.clusters.size(), 0);
        for (auto it = p.groups.rbegin(); it != p.groups.rend() && !unionMode && !convexCut; ++it) {
            bool ok = true;
            for (std::uint32_t m : it->members) {
                const float budget = allowed[p.clusters[m].cell];
                ok = ok && !handled[m] && budget > 0.0f && budget >= it->error;
            }
            if (!ok) continue;
            for (std::uint32_t m : it->members) handled[m] = 1;
            addSimplified(it->first, it->count, it->error);
        }
        for (std::size_t ci = 0; ci < p.clusters.size(); ++ci) {
            if (handled[ci]) continue;
            const GpuModel::DrawPart::Cluster& c = p.clusters[ci];
            const float budget = allowed[c.cell];
            int level = budget < 0.0f ? -1 : 0;
            while (level >= 0 && level + 1 < c.levels && c.error[level + 1] <= budget) ++level;
            if (level < 0) {
                ++image.clustersSkipped;
            } else if (level == 0) {
                full.add(c.first[0], c.count[0], p.baseVertex);
            } else {
                addSimplified(c.first[level], c.count[level], c.error[level]);
            }
        }
        flush(full);
        if (!anySimplified) return;
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
        for (int k = 0; k <= kShiftBuckets; ++k) {
            Batch& batch = pushed[std::size_t(k)];
            if (batch.counts.empty()) continue;
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
        gl.StencilFunc(GL_ALWAYS, role == 1 ? 1 : 0, 0xff);
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
    if (request.drawTraces && planeCount > 0 && !model.surfaceTriangles().empty())
        if (auto s = drawTraces(request, model, planesLocalD, viewProj, image.traceSegments); !s) return s.error();
    gl.Finish();
    image.drawMs = msSince(t0);
    if (cancelled())
        return makeError(ErrorCode::DeadlineExceeded, "cancelled: the deadline passed or the client went away");

    const auto tAa = std::chrono::steady_clock::now();
    if (samples > 1) resolveMultisample(request.width, request.height);
    if (aa == AntiAlias::Fxaa && request.readColour) runFxaa(request.width, request.height);
    if (aa != AntiAlias::None) {
        gl.Finish();
        image.aaMs = msSince(tAa);
    }

    const auto t1 = std::chrono::steady_clock::now();
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    const std::size_t n = std::size_t(request.width) * std::size_t(request.height);
    if (request.readColour) {
        std::vector<std::uint8_t> raw(n * 4);
        const GLuint colourFbo = aa == AntiAlias::Fxaa ? aaFbo_ : fbo_;
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, colourFbo);
        gl.NamedFramebufferReadBuffer(colourFbo, GL_COLOR_ATTACHMENT0);
        gl.ReadPixels(0, 0, request.width, request.height, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
        flipRows(raw, image.rgba, request.width, request.height, 4);
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    }
    if (request.readIds) {
        std::vector<RecordId> raw(n);
        gl.NamedFramebufferReadBuffer(fbo_, GL_COLOR_ATTACHMENT1);
        gl.ReadPixels(0, 0, request.width, request.height, GL_RED_INTEGER, GL_UNSIGNED_INT, raw.data());
        flipRows(raw, image.ids, request.width, request.height, 1);
    }
    if (request.readDepth) {
        std::vector<float> raw(n);
        gl.ReadPixels(0, 0, request.width, request.height, GL_DEPTH_COMPONENT, GL_FLOAT, raw.data());
        flipRows(raw, image.depth, request.width, request.height, 1);
    }
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

std::vector<float> SliceRenderer::clusterBudget(const GpuModel& model, const SliceRequest& request,
                                                const ViewTransform& view, bool unionMode,
                                                const std::vector<glm::dvec4>& planesLocal,
                                                const std::vector<std::uint8_t>& culls, SliceImage& image) const {
    const std::vector<Aabb>& cells = model.cellBounds();
    std::vector<float> allowed(cells.size(), 0.0f);
    const bool perspective = std::holds_alternative<PerspectiveView>(request.view);
    const bool lod = model.hasLod() &&
                     (request.lod == SliceRequest::Lod::On || (request.lod == SliceRequest::Lod::Auto && perspective));
    image.lodUsed = lod;
    const double f = request.exaggeration.factor;
    // Pixels per metre of error: orthographic from the frame, perspective at distance 1.
    double orthoScale = 0.0, perspScale = 0.0;
    glm::dvec3 eye(0.0);
    if (perspective) {
        const PerspectiveView& pv = std::get<PerspectiveView>(request.view);
        perspScale = 0.5 * request.height / std::tan(glm::radians(pv.fovYDegrees) * 0.5);
        eye = pv.eye - request.exaggeration.toDisplay(model.origin());  // display-local
    } else {
        const ProfileView& pv = std::get<ProfileView>(request.view);
        orthoScale = std::max(request.width / (pv.uMax - pv.uMin), request.height / (pv.vMax - pv.vMin));
    }
    for (std::size_t c = 0; c < cells.size(); ++c) {
        const Aabb& b = cells[c];
        if (!b.valid()) continue;
        glm::dvec3 corner[8];
        for (int i = 0; i < 8; ++i)
            corner[i] = {i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z};
        // Slack for float32 positions and plane coefficients on the GPU.
        const double tol = 1e-3 + 1e-6 * glm::length(b.size()) + 1e-7 * glm::length(b.max);
        // witness: past a convex cut's exit (a plane that does not cull), where the fragment
        // stage reads which body a ray leaves the kept region in: full detail, like a cut.
        bool removed = unionMode && !planesLocal.empty(), crossing = false, witness = false;
        for (std::size_t i = 0; i < planesLocal.size(); ++i) {
            const glm::dvec4& pl = planesLocal[i];
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (const glm::dvec3& q : corner) {
                const double d = glm::dot(glm::dvec3(pl), q) + pl.w;
                lo = std::min(lo, d);
                hi = std::max(hi, d);
            }
            const bool outside = hi < -tol && culls[i];
            witness = witness || (hi < -tol && !culls[i]);
            removed = unionMode ? (removed && outside) : (removed || outside);
            crossing = crossing || (lo <= tol && hi >= -tol);
        }
        // Outside the view: every corner beyond one clip-space plane.
        bool culled = false;
        for (int axis = 0; axis < 3 && !culled; ++axis)
            for (double side : {-1.0, 1.0}) {
                bool allOut = true;
                for (const glm::dvec3& q : corner) {
                    const glm::dvec4 clip = view.viewProj * glm::dvec4(q, 1.0);
                    allOut = allOut && side * clip[axis] > clip.w;
                }
                culled = culled || allOut;
            }
        if (removed || culled) {
            allowed[c] = -1.0f;
            continue;
        }
        if (!lod || crossing || witness) continue;  // full detail: the cut stays exact
        double pixelsPerMetre = orthoScale;
        if (perspective) {
            const glm::dvec3 lo(b.min.x, b.min.y, f * b.min.z), hi(b.max.x, b.max.y, f * b.max.z);
            const double dist = glm::length(glm::max(glm::max(lo - eye, eye - hi), glm::dvec3(0.0)));
            if (dist <= 0.0) continue;
            pixelsPerMetre = perspScale / dist;
        }
        // Exaggeration stretches an error along z by up to f.
        allowed[c] = float(request.lodPixelError / (pixelsPerMetre * std::max(1.0, f)));
    }
    return allowed;
}

void SliceRenderer::resolveMultisample(int width, int height) {
    const GlFunctions& gl = context_.gl();
    // One attachment at a time: float and integer colour buffers cannot share a blit.
    const GLenum colourOnly[] = {GL_COLOR_ATTACHMENT0, GL_NONE};
    const GLenum idsOnly[] = {GL_NONE, GL_COLOR_ATTACHMENT1};
    const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    gl.NamedFramebufferReadBuffer(msFbo_, GL_COLOR_ATTACHMENT0);
    gl.NamedFramebufferDrawBuffers(fbo_, 2, colourOnly);
    gl.BlitNamedFramebuffer(msFbo_, fbo_, 0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl.NamedFramebufferReadBuffer(msFbo_, GL_COLOR_ATTACHMENT1);
    gl.NamedFramebufferDrawBuffers(fbo_, 2, idsOnly);
    gl.BlitNamedFramebuffer(msFbo_, fbo_, 0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl.BlitNamedFramebuffer(msFbo_, fbo_, 0, 0, width, height, 0, 0, width, height,
                            GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, GL_NEAREST);
    gl.NamedFramebufferDrawBuffers(fbo_, 2, both);
    gl.NamedFramebufferReadBuffer(msFbo_, GL_COLOR_ATTACHMENT0);
}

void SliceRenderer::runFxaa(int width, int height) {
    const GlFunctions& gl = context_.gl();
    gl.BindFramebuffer(GL_FRAMEBUFFER, aaFbo_);
    gl.Viewport(0, 0, width, height);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_STENCIL_TEST);
    gl.Disable(GL_CULL_FACE);
    for (int i = 0; i < kMaxPlanes; ++i) gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
    const GLuint prog = fxaaProgram_->id();
    gl.UseProgram(prog);
    const float texel[2] = {1.0f / float(width), 1.0f / float(height)};
    gl.ProgramUniform2fv(prog, fxaaTexel_, 1, texel);
    gl.ProgramUniform1i(prog, fxaaColour_, 0);
    gl.BindTextureUnit(0, colourTex_);
    if (!emptyVao_) gl.CreateVertexArrays(1, &emptyVao_);
    gl.BindVertexArray(emptyVao_);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    gl.BindTextureUnit(0, 0);
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
    return {};
}

}  // namespace geoslice
