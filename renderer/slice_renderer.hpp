// The slicing pass (paper section 2.1, made correct for nested bodies): one pass over a
// GpuModel into a framebuffer object with three attachments, read back on request:
//   colour  RGBA8   record colour, lit on exterior faces, flat on cut faces
//   ids     R32UI   attribute record id per pixel (never blended; 0 = background)
//   cells   R32UI   views coloured by a block model only: the block cell + 1 whose class
//                   colours the pixel (caps of the clipping bodies; 0 = none), never blended
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
// polygon offset away from the viewer (not for nested bodies, which share no surface with
// their container: there the offset let a thin rim's back face win). The stencil buffer
// marks cap pixels (1) so that open surfaces (faults) never cover a cut face.
//
// Baked ids (GpuModel uploaded with a bake::BakedModel): every fragment, caps included, takes
// its record from the id texture at its UV (see shaders/slice.frag for which surface a cap's
// UV lies on), writes it to the ID buffer and is coloured by it.
//
// After the bodies: open surfaces where no cap is; fault traces (CPU-cut segments of the
// open surfaces, GL_LINES on cap pixels, colour only); then anti-aliasing of the colour
// (MSAA resolve or an FXAA pass). Clusters of the GpuModel on the removed side or outside
// the view are skipped; level of detail replaces clusters that no plane crosses by
// simplified copies (see SliceRequest::lod and renderer/gpu_model.hpp).
//
// The pieces, one file each: the render target (framebuffers, MSAA resolve, readback, row
// flip: renderer/gl/render_target.hpp), the trace pass (renderer/passes/trace_pass.hpp), the FXAA pass
// (renderer/passes/fxaa_pass.hpp) and the CPU-only cluster selection (renderer/lod/cluster_selection.hpp);
// render() is the cap algorithm above. GL objects are owned by RAII handles
// (renderer/gl/gl_objects.hpp) behind the private implementation: this header holds none.
//
// Threads: create, use and destroy on the owning GlContext's thread. GL state: render()
// sets all the state it needs and, before returning, binds framebuffer 0, no program and no
// vertex array, and disables depth, stencil, cull, polygon offset and clip distances.
#pragma once

#include <atomic>
#include <memory>
#include <variant>
#include <vector>

#include "model/attributes.hpp"
#include "model/result.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/views.hpp"
#include "view/view_limits.hpp"

namespace geoslice {

class GlProgram;
class BlockTexture;
class BlockCaps;

enum class ClipMethod {
    ClipDistance,  // gl_ClipDistance per plane (intersection of half-spaces only)
    Discard,       // the paper's fragment discard (eq. 5); needed for union
};
const char* clipMethodName(ClipMethod method);  // "clip-distance", "discard"

// Anti-aliasing of the colour output. The ID buffer is never blended: with MSAA it takes one
// sample's id per pixel; FXAA reads and writes colour only.
enum class AntiAlias {
    None,
    Auto,  // Msaa on a hardware device, Fxaa on a software rasteriser (llvmpipe: MSAA costs 3.5-5x)
    Fxaa,  // a post pass on colour (shaders/fxaa.frag)
    Msaa,  // multisampled draw target, resolved before readback
};
const char* antiAliasName(AntiAlias mode);  // "none", "auto", "fxaa", "msaa"

enum class PlaneCombine {
    Intersection,  // keep points on the positive side of every plane (slab, wedge kept)
    Union,         // keep points on the positive side of any plane (box or wedge cut out)
};

constexpr int kMaxPlanes = 6;
// Image sides: kMaxImageSide (view/view_limits.hpp); the device may allow less.

struct SliceRequest {
    std::vector<WorldPlane> planes;  // world (a,b,c,d); normalised by render(); up to kMaxPlanes
    PlaneCombine combine = PlaneCombine::Intersection;
    // ClipDistance with more than one plane falls back to Discard (reported in
    // SliceImage::clipUsed): gl_ClipDistance can only intersect half-spaces, and with an
    // intersection the fragment stage must see the fragments past the kept region's exit
    // to fill the caps of rays that leave it inside a body (shaders/slice.frag).
    ClipMethod clip = ClipMethod::ClipDistance;
    // The view is in display space (see VerticalExaggeration): for a profile of a cut plane
    // P use exaggeration.planeToDisplay(P) and boundsToDisplay(bounds); eye and target of a
    // perspective view are display points (toDisplay of world points).
    std::variant<ProfileCamera, PerspectiveCamera> view = ProfileCamera{};
    VerticalExaggeration exaggeration;  // factor 1: none
    int width = 512, height = 512;      // pixels
    Rgba8 background{0, 0, 0, 0};
    bool drawSurfaces = true;  // open surfaces (faults), never over a cut face
    // Records not drawn (sorted): the picture of the model without those bodies and surfaces.
    // A shown body nested in a hidden one is capped as if the hidden one were not in the model
    // (its nearest shown container's cap, or its own exterior); a hidden surface leaves no
    // trace. Empty: everything drawn.
    std::vector<RecordId> hidden;
    // Traces: where an open surface (fault, terrain sheet) crosses a plane on a visible cut
    // face, a line of `traceColour`, `traceWidth` pixels wide (clamped to the driver's line
    // width range). Colour only: the ID buffer keeps the body's record under a trace.
    bool drawTraces = true;
    Rgba8 traceColour{25, 25, 25, 255};
    float traceWidth = 1.5f;
    bool readColour = true, readIds = true, readDepth = false;
    AntiAlias antiAlias = AntiAlias::Auto;
    // Level of detail (renderer/gpu_model.hpp): clusters that no plane crosses may be drawn
    // simplified when their geometric error projects to at most lodPixelError pixels. Auto:
    // for perspective views of a model uploaded with LOD (software backends). Profiles are
    // exact sections and stay at full detail under Auto. Clusters on the removed side or
    // outside the view are skipped in every mode (exact).
    enum class Lod { Off, Auto, On };
    Lod lod = Lod::Auto;
    float lodPixelError = 1.0f;  // pixels, > 0
    int msaaSamples = 4;         // for Msaa: 2..64, clamped to GL_MAX_SAMPLES / GL_MAX_INTEGER_SAMPLES
    // A GpuModel uploaded with a bake: ids (and colours) per fragment from its id texture
    // (issue 4 item 8, shaders/slice.frag). false: one record per part, as without a bake
    // (same geometry: the bake's mesh).
    bool bakedIds = true;
    // Cancellation (any thread may set it): read before every part's draw call, every
    // pass and the read-back; when set, the draw calls left are skipped and render()
    // returns DeadlineExceeded. A single draw call already submitted is not interrupted.
    const std::atomic<bool>* cancel = nullptr;
    // Caps of the clipping bodies coloured by block-model class (renderer/passes/block_texture.hpp);
    // null: none. Must outlive the call. With it, SliceImage::cells holds each pixel's cell.
    const BlockTexture* blocks = nullptr;
    // Or (not both) the exact cell pieces of each plane (renderer/passes/block_caps.hpp: block models
    // with curvilinear cells), cut by `planes` in their order; null: none. Must outlive the call.
    const BlockCaps* blockCaps = nullptr;
};

struct SliceImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;  // 4 bytes per pixel, row 0 at the top (when read)
    std::vector<RecordId> ids;       // row 0 at the top (when read)
    // With SliceRequest::blocks or blockCaps, read with the ids: BlockModel linear cell index + 1 of the
    // cell whose class colours each pixel (0: none), row 0 at the top; empty otherwise.
    std::vector<std::uint32_t> cells;
    std::vector<float> depth;  // window depth, row 0 at the top (when read)
    ClipMethod clipUsed = ClipMethod::ClipDistance;
    glm::dmat4 viewProj{1.0};            // true local frame -> clip of this image (exaggeration included)
    double drawMs = 0.0;                 // clear + draw + glFinish, wall clock
    double readbackMs = 0.0;             // glReadPixels of what was read, wall clock
    std::size_t traceSegments = 0;       // fault-trace segments drawn
    AntiAlias aaUsed = AntiAlias::None;  // what Auto resolved to (None when MSAA is unavailable)
    int samples = 1;                     // samples per pixel of the draw target
    double aaMs = 0.0;                   // MSAA resolve or FXAA pass + glFinish, wall clock
    bool lodUsed = false;
    std::size_t trianglesDrawn = 0;   // over all passes (bodies twice: back and front faces)
    std::size_t clustersSkipped = 0;  // (part, cell) clusters culled, over all passes
    std::size_t drawCalls = 0;
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

    // OutOfRange when a side is < 1 or beyond min(kMaxImageSide, GL_MAX_RENDERBUFFER_SIZE,
    // GL_MAX_VIEWPORT_DIMS); the message names the limit that applies.
    Status checkSize(int width, int height) const;
    Result<SliceImage> render(const GpuModel& model, const SliceRequest& request);
    // Draws a small image with every program variant, so that the driver's shader JIT
    // (llvmpipe compiles on first draw) is not paid by the first real request.
    Status warmUp(const GpuModel& model);
    // Deletes the render targets sized for the last image (render() makes them again):
    // a worker calls it after a large image so as not to keep its memory. Context current.
    void releaseTarget();

    // Program variants: index 0 clip-distance, 1 discard; 2 and 3 the same with block-model
    // colouring of caps (GS_BLOCKS, used only when SliceRequest::blocks is set).
    static constexpr int kProgramCount = 4;
    const GlProgram& program(int index) const;
    // Helper programs: index 0 fault traces, 1 FXAA, 2 block-model cell pieces.
    static constexpr int kHelperProgramCount = 3;
    const GlProgram& helperProgram(int index) const;

private:
    struct Impl;  // programs, passes and the render target (slice_renderer.cpp)
    explicit SliceRenderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace geoslice
