// The slicing pass (paper section 2.1, made correct for nested bodies): one pass over a
// GpuModel into a framebuffer object with three attachments, read back on request:
//   colour  RGBA8   record colour, lit on exterior faces, flat on cut faces
//   ids     R32UI   attribute record id per pixel (never blended; 0 = background)
//   depth   32F     window depth in [0, 1] of the surface drawn (1 = background); for a cut
//                   face that is the depth of the surface behind the cut, see below
//
// Cut faces ("caps") without stencil parity: with every fragment on the removed side gone
// (gl_ClipDistance or discard), the nearest surviving surface along a pixel's ray tells
// which body the ray is in just after the cut:
//   - a back face of body X: the ray is inside X, and X is the innermost body there (a body
//     nested in X would have been exited first) -> cap of X;
//   - a front face of body D whose container (validation's nesting parent) is P: the ray,
//     just outside D, is inside P, and P's own front face must have been cut away -> cap of P;
//   - a front face of a top-level body: its exterior -> D, lit.
// Coincident faces of two bodies (partition models, shared horizons) tie; the back face
// must win (the point is in the body being exited), so front faces are drawn with a small
// polygon offset away from the viewer. The stencil buffer marks cap pixels (1) so that open
// surfaces (faults) never cover a cut face.
//
// Threads: create, use and destroy on the owning GlContext's thread. GL state: render()
// sets all the state it needs and, before returning, binds framebuffer 0, no program and no
// vertex array, and disables depth, stencil, cull, polygon offset and clip distances.
#pragma once

#include <memory>
#include <variant>
#include <vector>

#include "model/attributes.hpp"
#include "model/result.hpp"
#include "renderer/gl_context.hpp"
#include "renderer/gl_program.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/views.hpp"

namespace geoslice {

enum class ClipMethod {
    ClipDistance,  // gl_ClipDistance per plane (intersection of half-spaces only)
    Discard,       // the paper's fragment discard (eq. 5); needed for union
};
const char* clipMethodName(ClipMethod method);  // "clip-distance", "discard"

enum class PlaneCombine {
    Intersection,  // keep points on the positive side of every plane (slab, wedge kept)
    Union,         // keep points on the positive side of any plane (box or wedge cut out)
};

constexpr int kMaxPlanes = 6;
constexpr int kMaxImageSize = 8192;  // per side; the device may allow less

struct SliceRequest {
    std::vector<WorldPlane> planes;  // world (a,b,c,d); normalised by render(); up to kMaxPlanes
    PlaneCombine combine = PlaneCombine::Intersection;
    // ClipDistance with Union and more than one plane falls back to Discard (reported in
    // SliceImage::clipUsed): gl_ClipDistance can only intersect half-spaces.
    ClipMethod clip = ClipMethod::ClipDistance;
    std::variant<ProfileView, PerspectiveView> view = ProfileView{};
    int width = 512, height = 512;  // pixels
    Rgba8 background{0, 0, 0, 0};
    bool drawSurfaces = true;  // open surfaces (faults), never over a cut face
    bool readColour = true, readIds = true, readDepth = false;
};

struct SliceImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;  // 4 bytes per pixel, row 0 at the top (when read)
    std::vector<RecordId> ids;       // row 0 at the top (when read)
    std::vector<float> depth;        // window depth, row 0 at the top (when read)
    ClipMethod clipUsed = ClipMethod::ClipDistance;
    glm::dmat4 viewProj{1.0};  // local -> clip of this image
    double drawMs = 0.0;       // clear + draw + glFinish, wall clock
    double readbackMs = 0.0;   // glReadPixels of what was read, wall clock
    RecordId idAt(int column, int row) const {
        return ids[std::size_t(row) * std::size_t(width) + std::size_t(column)];
    }
};

class SliceRenderer {
public:
    // Compiles every program variant (errors carry the info log).
    static Result<std::unique_ptr<SliceRenderer>> create(GlContext& context);
    ~SliceRenderer();
    SliceRenderer(const SliceRenderer&) = delete;
    SliceRenderer& operator=(const SliceRenderer&) = delete;

    // OutOfRange when a side is < 1 or beyond min(kMaxImageSize, GL_MAX_RENDERBUFFER_SIZE,
    // GL_MAX_VIEWPORT_DIMS); the message names the limit that applies.
    Status checkSize(int width, int height) const;
    Result<SliceImage> render(const GpuModel& model, const SliceRequest& request);
    // Draws a small image with every program variant, so that the driver's shader JIT
    // (llvmpipe compiles on first draw) is not paid by the first real request.
    Status warmUp(const GpuModel& model);

    // Program variants: index 0 clip-distance, 1 discard.
    static constexpr int kProgramCount = 2;
    const GlProgram& program(int index) const { return programs_[std::size_t(index)].program; }

private:
    explicit SliceRenderer(GlContext& context) : context_(context) {}
    Status ensureTarget(int width, int height);
    void releaseTarget();

    struct Uniforms {
        GLint viewProj = -1, planes = -1, planeCount = -1, unionMode = -1, faceRole = -1, record = -1, colour = -1,
              capRecord = -1, capColour = -1, lightDir = -1;
    };
    struct Variant {
        GlProgram program;
        Uniforms u;
    };
    GlContext& context_;
    std::vector<Variant> programs_;
    GLuint fbo_ = 0, colourRb_ = 0, idRb_ = 0, depthRb_ = 0;
    int targetWidth_ = 0, targetHeight_ = 0;
};

}  // namespace geoslice
