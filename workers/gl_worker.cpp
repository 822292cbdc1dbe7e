#include "workers/gl_worker.hpp"

#include <chrono>
#include <cstdio>

#include "workers/render_pool.hpp"

namespace geoslice::workers {

GlWorker::~GlWorker() {
    // GPU objects die with the context: release them while it is current.
    if (context) (void)context->makeCurrent();
    models.clear();
    renderer.reset();
    context.reset();
}

Result<std::unique_ptr<GlWorker>> GlWorker::create(GlBackend backend, bool lod) {
    GlContextOptions options;
    options.backend = backend;
    auto context = GlContext::create(options);
    if (!context) return context.error();
    auto w = std::make_unique<GlWorker>();
    w->lod = lod;
    w->context = std::move(context.value());
    auto renderer = SliceRenderer::create(*w->context);
    if (!renderer) return renderer.error();
    w->renderer = std::move(renderer.value());
    return w;
}

Result<api::ViewImage> GlWorker::renderPerspective(const api::CatalogModel& model, const api::ViewPlan& plan,
                                                   const std::atomic<bool>* cancel) {
    const auto t0 = std::chrono::steady_clock::now();
    if (auto s = context->makeCurrent(); !s) return s.error();
    const std::string key = model.id + "@" + model.version;
    auto it = models.find(key);
    if (it == models.end()) {
        // One resident copy per model: drop other versions of the same id.
        for (auto m = models.begin(); m != models.end();)
            m = m->first.rfind(model.id + "@", 0) == 0 ? models.erase(m) : std::next(m);
        for (auto b = colourings.begin(); b != colourings.end();)
            b = b->first.rfind(model.id + "@", 0) == 0 ? colourings.erase(b) : std::next(b);
        GpuUploadOptions upload;
        upload.lod = lod ? GpuUploadOptions::Lod::Auto : GpuUploadOptions::Lod::Off;
        // A baked model draws its own mesh with UVs and fetches record ids from the
        // attribute-indexed texture (grade classes and all); a raw model has one record per part.
        auto gpu = model.package ? GpuModel::upload(*context, model.model, *model.package, upload)
                                 : GpuModel::upload(*context, model.model, upload);
        if (!gpu) return gpu.error();
        if (auto s = renderer->warmUp(*gpu.value()); !s) return s.error();
        it = models.emplace(key, std::move(gpu.value())).first;
    }
    // The request's removed sides combine by `cut` (api/cut.hpp); the renderer names what is
    // kept: cut=union keeps the intersection of the kept sides, cut=intersection their union.
    const api::CutOut cut = api::sectionCut(plan.section);
    SliceRequest req;
    for (const Plane& plane : cut.planes) req.planes.push_back(WorldPlane(plane.normal, plane.d));
    req.combine = cut.mode == api::CutMode::Union ? PlaneCombine::Intersection : PlaneCombine::Union;
    // Eye and target in display space (the exaggerated model), as the renderer expects.
    const VerticalExaggeration ds = api::exaggerationOf(plan.section, model.index->bounds);
    const PerspectiveCamera view = api::displayCamera(plan, model.index->bounds);
    // Level of detail is exact at the cut but may swap a thin layer just behind a cut face
    // (renderer/slice_renderer.hpp), so by default the server draws full detail and its
    // images agree with exact ray queries; --lod trades that for speed on CPU backends.
    req.lod = lod ? SliceRequest::Lod::Auto : SliceRequest::Lod::Off;
    req.exaggeration = ds;
    req.view = view;
    req.width = plan.width;
    req.height = plan.height;
    req.background = plan.section.background;
    req.readColour = true;
    req.readIds = true;
    req.antiAlias = antiAlias;
    req.hidden = plan.shown.hiddenOf(model.model);
    req.cancel = cancel;
    if (plan.section.colour) {
        auto classes = api::blockClasses(model, plan.section);
        if (!classes) return classes.error();
        const PropertyClasses& pc = *classes.value();
        const bool texture = colourWithTexture(*model.model.blocks, boxBlocks, *context);
        // A texture serves every plane set; pieces are per plane set, and one set per
        // colouring is kept (the others of that colouring are dropped when a new one is made).
        std::string colourKey = key + "|" + plan.section.colour->property + "|" + plan.section.colour->ramp + "|";
        for (double b : pc.breaks) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.17g,", b);
            colourKey += buf;
        }
        std::string fullKey = colourKey + (texture ? "|texture" : "|planes:");
        for (const Plane& plane : texture ? std::vector<Plane>() : cut.planes) {
            char buf[128];
            std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g;", plane.normal.x, plane.normal.y, plane.normal.z,
                          plane.d);
            fullKey += buf;
        }
        auto kept = colourings.find(fullKey);
        if (kept == colourings.end()) {
            for (auto b = colourings.begin(); b != colourings.end();)
                b = b->first.rfind(colourKey + "|", 0) == 0 ? colourings.erase(b) : std::next(b);
            auto made = uploadBlockColouring(*context, model.model, model.blockRecords, pc, cut.planes, texture);
            if (!made) return made.error();
            if (colourings.size() >= kMaxKeptColourings) colourings.erase(colourings.begin());
            kept = colourings.emplace(fullKey, std::move(made.value())).first;
        }
        kept->second.setOn(req);
    }
    auto image = renderer->render(*it->second, req);
    if (!image) return image.error();
    api::ViewImage v;
    v.width = plan.width;
    v.height = plan.height;
    v.rgba = std::move(image.value().rgba);
    v.ids = std::move(image.value().ids);
    v.cells = std::move(image.value().cells);  // coloured views: the cell + 1 of each cap pixel
    v.renderMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return v;
}

void GlWorker::trim() {
    if (context->makeCurrent().ok()) renderer->releaseTarget();
}

WorkerState::WorkerState(unsigned index, GlSettings gl) : index_(index), settings_(std::move(gl)) {}

WorkerState::~WorkerState() = default;

Result<std::string> WorkerState::openGl() {
    if (!gl_) {
        if (!settings_.enabled) return makeError(ErrorCode::Unsupported, "GL is disabled on this server (--gl none)");
        const auto backend = parseGlBackend(settings_.backend);
        if (!backend) return makeError(ErrorCode::InvalidArgument, "unknown GL backend '" + settings_.backend + "'");
        auto gl = GlWorker::create(*backend, settings_.lod);
        if (!gl) return gl.error();
        gl_ = std::move(gl.value());
    }
    return gl_->context->info().describe();
}

Result<api::ViewImage> WorkerState::renderPerspective(const api::CatalogModel& model, const api::ViewPlan& plan,
                                                      const std::atomic<bool>* cancel) {
    if (!gl_)
        if (auto opened = openGl(); !opened) return opened.error();
    return gl_->renderPerspective(model, plan, cancel);
}

void WorkerState::discardGl() { gl_.reset(); }

void WorkerState::trimGl() {
    if (gl_) gl_->trim();
}

}  // namespace geoslice::workers
