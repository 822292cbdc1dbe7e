#include "section/classify.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <thread>

#include <embree3/rtcore.h>

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
    if (isGrazing(a, facing(a))) ctx->grazing = true;
    ctx->hits->emplace_back(RTCHitN_geomID(a->hit, a->N, 0), RTCRayN_tfar(a->ray, a->N, 0));
    a->valid[0] = 0;
}

}  // namespace

struct Classifier::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;                      // one BVH; the filter comes with each query's context
    std::vector<std::vector<glm::vec4>> vertices;  // local frame, 16-byte stride for Embree
    std::vector<int> geomToBody;
    std::vector<std::array<glm::vec3, 2>> boxes;  // local bounds of each closed body (empty box otherwise)
    std::vector<int> parentBody;
    std::vector<int> depth;
    std::vector<RecordId> records;
    glm::dvec3 origin{0.0};
    float maxLocalCoord = 0.0f;  // largest |local coordinate|, m: sets the float tolerance

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    RTCRayHit makeRay(const glm::vec3& org, const glm::vec3& dir) const {
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
};

Classifier::~Classifier() = default;

Result<std::unique_ptr<Classifier>> Classifier::build(const Model& model) {
    std::unique_ptr<Classifier> c(new Classifier());
    c->impl_ = std::make_unique<Impl>();
    Impl& im = *c->impl_;
    im.origin = model.origin;
    im.device = rtcNewDevice("verbose=0");
    if (!im.device)
        return makeError(ErrorCode::Internal,
                         "Embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
    im.scene = rtcNewScene(im.device);
    rtcSetSceneFlags(im.scene, RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
    rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_MEDIUM);
    for (std::size_t b = 0; b < model.bodies.size(); ++b) {
        const Part& part = model.bodies[b];
        im.parentBody.push_back(part.report.parent);
        im.depth.push_back(part.report.nestingDepth);
        im.records.push_back(part.record);
        im.boxes.push_back(
            {glm::vec3(std::numeric_limits<float>::infinity()), glm::vec3(-std::numeric_limits<float>::infinity())});
        if (part.mesh.triangleCount() == 0 || !part.report.closed) continue;
        auto& verts = im.vertices.emplace_back(part.mesh.positions.size());
        for (std::size_t i = 0; i < verts.size(); ++i) {
            verts[i] = glm::vec4(glm::vec3(part.mesh.positions[i] - model.origin), 0.0f);
            im.boxes.back()[0] = glm::min(im.boxes.back()[0], glm::vec3(verts[i]));
            im.boxes.back()[1] = glm::max(im.boxes.back()[1], glm::vec3(verts[i]));
            im.maxLocalCoord =
                std::max({im.maxLocalCoord, std::abs(verts[i].x), std::abs(verts[i].y), std::abs(verts[i].z)});
        }
        c->triangles_ += part.mesh.triangleCount();
        RTCGeometry g = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, verts.data(), 0, sizeof(glm::vec4),
                                   verts.size());
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, part.mesh.indices.data(), 0,
                                   3 * sizeof(std::uint32_t), part.mesh.triangleCount());
        rtcCommitGeometry(g);
        unsigned id = rtcAttachGeometry(im.scene, g);
        rtcReleaseGeometry(g);
        if (im.geomToBody.size() <= id) im.geomToBody.resize(id + 1, -1);
        im.geomToBody[id] = static_cast<int>(b);
    }
    rtcCommitScene(im.scene);
    if (RTCError e = rtcGetDeviceError(im.device); e != RTC_ERROR_NONE)
        return makeError(ErrorCode::Internal, "Embree: scene build failed (error " + std::to_string(e) + ")");
    // The index buffers are shared with the model: it must outlive the classifier.
    return c;
}

int Classifier::classifyBody(const glm::dvec3& world) const {
    const Impl& im = *impl_;
    if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) return -1;
    const glm::vec3 org(world - im.origin);
    // No body's box holds p: nothing to cast for.
    bool anyBox = false;
    for (const auto& box : im.boxes)
        anyBox = anyBox || (org.x >= box[0].x && org.y >= box[0].y && org.z >= box[0].z && org.x <= box[1].x &&
                            org.y <= box[1].y && org.z <= box[1].z);
    if (!anyBox) return -1;
    std::vector<std::pair<unsigned, float>> hits;
    std::vector<int> counts(im.records.size());
    for (std::size_t attempt = 0; attempt < kDirections.size(); ++attempt) {
        hits.clear();
        AllHitsContext ctx;
        ctx.hits = &hits;
        rtcInitIntersectContext(&ctx.base);
        ctx.base.filter = allHitsFilter;
        RTCRayHit rh = im.makeRay(org, kDirections[attempt]);
        rtcIntersect1(im.scene, &ctx.base, &rh);
        if (ctx.grazing && attempt + 1 < kDirections.size()) continue;
        // Parity per body; of the bodies that hold p, the section engine's winner.
        std::fill(counts.begin(), counts.end(), 0);
        for (const auto& [geom, t] : hits) ++counts[static_cast<std::size_t>(im.geomToBody[geom])];
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
