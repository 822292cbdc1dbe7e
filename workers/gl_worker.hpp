// One render worker's GL state (workers/ is the only library that holds GL state; the
// server only queues jobs): its context (created on, and only used by, that worker's
// thread), the slicing renderer and the models uploaded to it (keyed by id@version).
// Perspective views are drawn here; profile views and tiles never need GL.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <string>

#include "api/catalog.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "model/result.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/slice_renderer.hpp"
#include "workers/block_colouring.hpp"

namespace geoslice::workers {

struct GlWorker {
    std::unique_ptr<GlContext> context;
    std::unique_ptr<SliceRenderer> renderer;
    std::map<std::string, std::unique_ptr<GpuModel>> models;
    // Block-model colourings (workers/block_colouring.hpp), keyed by id@version and the
    // colouring (property, ramp, breaks): a box grid's class texture, or a grid's cell pieces
    // on one set of cut planes (a view turning about a fixed cut reuses them; a new plane set
    // replaces that colouring's pieces); dropped with their model's version.
    std::map<std::string, BlockColouring> colourings;
    // At most this many are kept (another is made by dropping one), so that requests with
    // ever new breaks cannot grow a worker's GPU memory without bound (a 1M-cell grid's
    // texture is 1 MB; a plane set's pieces of it up to ~10 MB).
    static constexpr std::size_t kMaxKeptColourings = 8;
    bool lod = false;  // simplified context geometry in 3D views (CPU backends)
    // How box-cell block models colour caps (workers/block_colouring.hpp).
    using BoxBlocks = workers::BoxBlocks;
    BoxBlocks boxBlocks = BoxBlocks::Auto;
    // Anti-aliasing of the colour of its views (the ID and cell buffers are never blended);
    // tests set None to compare colours exactly.
    AntiAlias antiAlias = AntiAlias::Auto;

    // Creates the context on the calling thread. Errors: the backend's, naming it.
    static Result<std::unique_ptr<GlWorker>> create(GlBackend backend, bool lod = false);
    ~GlWorker();

    // A perspective view of the plan's section (the half-space a.x + b.y + c.z + d >= 0 kept,
    // cut faces filled) with per-body record ids. Uploads the model on first use. With the
    // plan's colour= the clipping bodies' caps take their block cells' class colours (the
    // profile engine's rule; a box grid's class texture is uploaded on first use, a
    // curvilinear grid's cell pieces are cut for each new set of planes).
    // `cancel` (may be null): see SliceRequest::cancel.
    Result<api::ViewImage> renderPerspective(const api::CatalogModel& model, const api::ViewPlan& plan,
                                             const std::atomic<bool>* cancel = nullptr);
    // Frees the render targets and read-back buffers sized for the last image (the next
    // render makes them again): called after a large render so the worker does not keep
    // gigabytes for the rest of its life.
    void trim();
};

}  // namespace geoslice::workers
