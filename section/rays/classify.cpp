#include "section/rays/classify.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <thread>

namespace geoslice {
namespace {

constexpr std::array<glm::vec3, 6> kDirections = {
    glm::vec3(0.5316705f, 0.2876141f, 0.7966510f),   glm::vec3(-0.3120954f, 0.8231507f, -0.4743921f),
    glm::vec3(0.7071421f, -0.6011239f, 0.3723344f),  glm::vec3(-0.6432120f, -0.2213412f, 0.7329412f),
    glm::vec3(0.2953311f, -0.3187654f, -0.9006543f), glm::vec3(0.9112873f, 0.1012345f, -0.3991234f)};
constexpr float kBaryEps = 1e-5f;     // hits this close (barycentric) to an edge re-cast the ray
constexpr float kCosGrazing = 1e-4f;  // |cos| between ray and face below this re-casts the ray

// Context passed through Embree to the filter callback (first member: Embree's own).
struct AllHitsContext {
    RTCIntersectContext base;
    const RayScene* scene = nullptr;
    std::vector<std::pair<unsigned, float>>* hits = nullptr;
    bool grazing = false;
};

bool isGrazing(const RTCFilterFunctionNArguments* a, float dot) {
    float u = RTCHitN_u(a->hit, a->N, 0), v = RTCHitN_v(a->hit, a->N, 0);
    float nx = RTCHitN_Ng_x(a->hit, a->N, 0), ny = RTCHitN_Ng_y(a->hit, a->N, 0), nz = RTCHitN_Ng_z(a->hit, a->N, 0);
    float len = std::sqrt(nx * nx + ny * ny + nz * nz);
    return u < kBaryEps || v < kBaryEps || u + v > 1.0f - kBaryEps || std::abs(dot) < kCosGrazing * len;
}

float facing(const RTCFilterFunctionNArguments* a) {
    return RTCRayN_dir_x(a->ray, a->N, 0) * RTCHitN_Ng_x(a->hit, a->N, 0) +
           RTCRayN_dir_y(a->ray, a->N, 0) * RTCHitN_Ng_y(a->hit, a->N, 0) +
           RTCRayN_dir_z(a->ray, a->N, 0) * RTCHitN_Ng_z(a->hit, a->N, 0);
}

void allHitsFilter(const RTCFilterFunctionNArguments* a) {
    if (!a->valid[0]) return;
    auto* ctx = reinterpret_cast<AllHitsContext*>(a->context);
    a->valid[0] = 0;  // rejected: Embree keeps looking (all hits along the ray)
    const unsigned geom = RTCHitN_geomID(a->hit, a->N, 0);
    if (ctx->scene->partOf(geom) < 0) return;  // an open surface: no part of the classification
    if (isGrazing(a, facing(a))) ctx->grazing = true;
    ctx->hits->emplace_back(geom, RTCRayN_tfar(a->ray, a->N, 0));
}

RTCRayHit makeRay(const glm::vec3& org, const glm::vec3& dir) {
    RTCRayHit rh{};
    rh.ray.org_x = org.x;
    rh.ray.org_y = org.y;
    rh.ray.org_z = org.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

}  // namespace

struct Classifier::Impl {
    std::shared_ptr<const RayScene> scene;
    std::vector<int> depth;  // by body
    std::vector<RecordId> records;
    glm::dvec3 origin{0.0};
    float maxLocalCoord = 0.0f;  // largest |local coordinate| of the bodies, m: sets the float tolerance
};

Classifier::~Classifier() = default;

Result<std::unique_ptr<Classifier>> Classifier::build(const Model& model) {
    auto scene = RayScene::build(model);
    if (!scene) return scene.error();
    return build(model, std::move(scene.value()));
}

Result<std::unique_ptr<Classifier>> Classifier::build(const Model& model, std::shared_ptr<const RayScene> scene) {
    if (!scene || &scene->model() != &model)
        return makeError(ErrorCode::InvalidArgument, "classifier: the ray scene was built for another model");
    std::unique_ptr<Classifier> c(new Classifier());
    c->impl_ = std::make_unique<Impl>();
    Impl& im = *c->impl_;
    im.origin = model.origin;
    for (const Part& part : model.bodies) {
        im.depth.push_back(part.report.nestingDepth);
        im.records.push_back(part.record);
    }
    im.maxLocalCoord = scene->maxLocalCoordBodies();
    c->triangles_ = scene->bodyTriangles();
    im.scene = std::move(scene);
    return c;
}

int Classifier::classifyBody(const glm::dvec3& world) const {
    const Impl& im = *impl_;
    if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) return -1;
    const glm::vec3 org(world - im.origin);
    // No body's box holds p: nothing to cast for.
    bool anyBox = false;
    for (const auto& box : im.scene->bodyBoxes())
        anyBox = anyBox || (org.x >= box[0].x && org.y >= box[0].y && org.z >= box[0].z && org.x <= box[1].x &&
                            org.y <= box[1].y && org.z <= box[1].z);
    if (!anyBox) return -1;
    std::vector<std::pair<unsigned, float>> hits;
    std::vector<int> counts(im.records.size());
    for (std::size_t attempt = 0; attempt < kDirections.size(); ++attempt) {
        hits.clear();
        AllHitsContext ctx;
        ctx.scene = im.scene.get();
        ctx.hits = &hits;
        rtcInitIntersectContext(&ctx.base);
        ctx.base.filter = allHitsFilter;
        RTCRayHit rh = makeRay(org, kDirections[attempt]);
        rtcIntersect1(im.scene->scene(), &ctx.base, &rh);
        if (ctx.grazing && attempt + 1 < kDirections.size()) continue;
        // Parity per body; of the bodies that hold p, the section engine's winner.
        std::fill(counts.begin(), counts.end(), 0);
        for (const auto& [geom, t] : hits) ++counts[static_cast<std::size_t>(im.scene->partOf(geom))];
        int best = -1;
        for (std::size_t b = 0; b < counts.size(); ++b)
            if (counts[b] % 2 == 1 && (best < 0 || im.depth[b] >= im.depth[static_cast<std::size_t>(best)]))
                best = static_cast<int>(b);
        return best;
    }
    return -1;
}

double Classifier::tolerance() const { return 1e-6 * double(impl_->maxLocalCoord) + 1e-4; }

RecordId Classifier::classify(const glm::dvec3& world) const {
    int b = classifyBody(world);
    return b < 0 ? kNoRecord : impl_->records[static_cast<std::size_t>(b)];
}

void Classifier::classifyBatch(const glm::dvec3* world, std::size_t n, RecordId* out, unsigned threads) const {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(1, n / 1024)));
    auto run = [&](std::size_t lo, std::size_t hi) {
        for (std::size_t i = lo; i < hi; ++i) out[i] = classify(world[i]);
    };
    std::vector<std::thread> pool;
    std::size_t chunk = (n + threads - 1) / std::max(1u, threads);
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(run, std::min(n, t * chunk), std::min(n, (t + 1) * chunk));
    run(0, std::min(n, chunk));
    for (auto& th : pool) th.join();
}

}  // namespace geoslice
