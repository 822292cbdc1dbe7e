#include "section/rays/borehole.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <embree3/rtcore.h>

namespace geoslice {
namespace {

constexpr float kCosGrazing = 1e-4f;  // |cos(ray, face normal)| below this: the ray slides along the face

struct Hit {
    unsigned geom = 0;
    unsigned prim = 0;
    float t = 0.0f;
    float cosine = 0.0f;  // ray direction . unit geometric normal
};

struct HitsContext {
    RTCIntersectContext base;  // first member: Embree's own
    std::vector<Hit>* hits = nullptr;
};

// Records every hit and rejects it, so Embree keeps looking (all hits along the ray).
void collectFilter(const RTCFilterFunctionNArguments* a) {
    if (!a->valid[0]) return;
    auto* ctx = reinterpret_cast<HitsContext*>(a->context);
    const float nx = RTCHitN_Ng_x(a->hit, a->N, 0), ny = RTCHitN_Ng_y(a->hit, a->N, 0),
                nz = RTCHitN_Ng_z(a->hit, a->N, 0);
    const float len = std::sqrt(nx * nx + ny * ny + nz * nz);
    const float dot =
        RTCRayN_dir_x(a->ray, a->N, 0) * nx + RTCRayN_dir_y(a->ray, a->N, 0) * ny + RTCRayN_dir_z(a->ray, a->N, 0) * nz;
    ctx->hits->push_back(Hit{RTCHitN_geomID(a->hit, a->N, 0), RTCHitN_primID(a->hit, a->N, 0),
                             RTCRayN_tfar(a->ray, a->N, 0), len > 0.0f ? dot / len : 0.0f});
    a->valid[0] = 0;
}

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

struct BoreholeTracer::Impl {
    const Model* model = nullptr;
    std::shared_ptr<const RayScene> scene;
    glm::dvec3 origin{0.0};
    Aabb bounds;
    float maxLocalCoord = 0.0f;

    // Float32 tolerance at distance `t` along a ray cast from near the model (its float
    // origin is the box entry point, so t is measured from there, not from the caller's origin).
    double tolerance(double t) const { return 1e-6 * (double(maxLocalCoord) + std::abs(t)) + 1e-4; }
};

BoreholeTracer::~BoreholeTracer() = default;

Result<std::unique_ptr<BoreholeTracer>> BoreholeTracer::build(const Model& model) {
    auto scene = RayScene::build(model);
    if (!scene) return scene.error();
    return build(model, std::move(scene.value()));
}

Result<std::unique_ptr<BoreholeTracer>> BoreholeTracer::build(const Model& model,
                                                              std::shared_ptr<const RayScene> scene) {
    if (!scene || &scene->model() != &model)
        return makeError(ErrorCode::InvalidArgument, "borehole tracer: the ray scene was built for another model");
    std::unique_ptr<BoreholeTracer> tracer(new BoreholeTracer());
    tracer->impl_ = std::make_unique<Impl>();
    Impl& im = *tracer->impl_;
    im.model = &model;
    im.origin = model.origin;
    im.bounds = model.bounds();
    im.maxLocalCoord = scene->maxLocalCoordAll();
    im.scene = std::move(scene);
    return tracer;
}

Result<Borehole> BoreholeTracer::traceRay(const glm::dvec3& origin, const glm::dvec3& direction,
                                          double maxLength) const {
    const Impl& im = *impl_;
    char buf[512];
    if (!finite3(origin) || !finite3(direction))
        return makeError(ErrorCode::InvalidArgument, "borehole ray origin or direction has a non-finite coordinate");
    const double dlen = glm::length(direction);
    if (!(dlen > 0.0) || !std::isfinite(dlen))
        return makeError(ErrorCode::InvalidArgument, "borehole ray direction is zero");
    if (!(maxLength > 0.0))
        return makeError(ErrorCode::InvalidArgument,
                         "borehole length must be > 0 (got " + std::to_string(maxLength) + ")");
    const glm::dvec3 dir = direction / dlen;

    Borehole bh;
    bh.origin = origin;
    bh.direction = dir;
    // Slab test against the model bounds grown by 1 m: where the ray can meet anything.
    if (!im.bounds.valid()) return makeError(ErrorCode::OutOfRange, "the model has no finite vertices to drill");
    double t0 = 0.0, t1 = maxLength;
    for (int k = 0; k < 3; ++k) {
        const double lo = im.bounds.min[k] - 1.0, hi = im.bounds.max[k] + 1.0;
        if (dir[k] == 0.0) {
            if (origin[k] < lo || origin[k] > hi) t1 = -1.0;
            continue;
        }
        double a = (lo - origin[k]) / dir[k], b = (hi - origin[k]) / dir[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    if (!(t0 <= t1)) {
        std::snprintf(buf, sizeof buf,
                      "borehole ray from (%.3f, %.3f, %.3f) along (%.6f, %.6f, %.6f) misses the model: bounds "
                      "[%.3f, %.3f, %.3f] - [%.3f, %.3f, %.3f]",
                      origin.x, origin.y, origin.z, dir.x, dir.y, dir.z, im.bounds.min.x, im.bounds.min.y,
                      im.bounds.min.z, im.bounds.max.x, im.bounds.max.y, im.bounds.max.z);
        return makeError(ErrorCode::OutOfRange, buf);
    }
    bh.length = std::isfinite(maxLength) ? maxLength : t1;

    // Cast from the box entry (float32 local frame near the model), add t0 back in double.
    const glm::dvec3 start = origin + t0 * dir - im.origin;
    std::vector<Hit> hits;
    HitsContext ctx;
    ctx.hits = &hits;
    rtcInitIntersectContext(&ctx.base);
    ctx.base.filter = collectFilter;
    RTCRayHit rh{};
    rh.ray.org_x = float(start.x);
    rh.ray.org_y = float(start.y);
    rh.ray.org_z = float(start.z);
    rh.ray.dir_x = float(dir.x);
    rh.ray.dir_y = float(dir.y);
    rh.ray.dir_z = float(dir.z);
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = float(t1 - t0);
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(im.scene->scene(), &ctx.base, &rh);
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
        if (a.t != b.t) return a.t < b.t;
        if (a.geom != b.geom) return a.geom < b.geom;
        return a.prim < b.prim;
    });

    const Model& model = *im.model;
    auto pointAt = [&](double t) { return origin + t * dir; };
    // Collar: the first hit of anything.
    if (!hits.empty()) {
        bh.collarDepth = t0 + double(hits.front().t);
        bh.collar = pointAt(bh.collarDepth);
    }

    // Surfaces: one crossing per surface per distinct distance (a hit on a shared edge
    // is reported by both triangles).
    for (const Hit& h : hits) {
        const int tag = im.scene->partOf(h.geom);
        if (tag >= 0) continue;
        const auto s = static_cast<std::uint32_t>(-tag - 1);
        const double t = t0 + double(h.t);
        bool dup = false;
        for (auto it = bh.crossings.rbegin(); it != bh.crossings.rend() && t - it->depth < im.tolerance(t - t0); ++it)
            dup = dup || it->surface == s;
        if (dup) continue;
        BoreholeCrossing c;
        c.surface = s;
        c.record = model.surfaces[s].record;
        c.depth = t;
        c.depthCollar = t - bh.collarDepth;
        c.world = pointAt(t);
        c.elevation = c.world.z;
        bh.crossings.push_back(c);
    }

    // Bodies: events (distance, body, enters?).
    struct Event {
        double t;
        int body;
        bool enter;
    };
    std::vector<Event> events;
    for (const Hit& h : hits) {
        const int b = im.scene->partOf(h.geom);
        if (b < 0 || std::abs(h.cosine) < kCosGrazing) continue;
        const double t = t0 + double(h.t);
        const bool enter = h.cosine < 0.0f;
        bool dup = false;
        for (auto it = events.rbegin(); it != events.rend() && t - it->t < im.tolerance(t - t0); ++it)
            dup = dup || (it->body == b && it->enter == enter);
        if (!dup) events.push_back(Event{t, b, enter});
    }
    const std::size_t nb = model.bodies.size();
    std::vector<char> inside(nb, 0), seen(nb, 0);
    for (const Event& e : events) {
        const auto b = static_cast<std::size_t>(e.body);
        if (!seen[b]) inside[b] = !e.enter;  // first hit exits: the ray started inside
        seen[b] = 1;
    }
    auto innermost = [&]() {
        int best = -1;
        for (std::size_t b = 0; b < nb; ++b)
            if (inside[b] && (best < 0 || model.bodies[b].report.nestingDepth >
                                              model.bodies[static_cast<std::size_t>(best)].report.nestingDepth))
                best = static_cast<int>(b);
        return best;
    };
    struct Span {
        double from, to;
        int body;
    };
    std::vector<Span> spans;
    double prevT = t0;
    int current = innermost();
    auto close = [&](double t) {
        if (current >= 0 && t > prevT) spans.push_back(Span{prevT, t, current});
    };
    for (std::size_t i = 0; i < events.size();) {
        const double t = events[i].t;
        close(t);
        // All events at (exactly) this distance change the state together.
        for (; i < events.size() && events[i].t == t; ++i)
            inside[static_cast<std::size_t>(events[i].body)] = events[i].enter;
        prevT = t;
        current = innermost();
    }
    close(t0 + std::min(double(rh.ray.tfar), t1 - t0));
    // Drop slivers (coincident faces of neighbours), then merge what they separated.
    std::vector<Span> kept;
    for (const Span& s : spans) {
        if (s.to - s.from < im.tolerance(s.to - t0)) continue;
        if (!kept.empty() && kept.back().body == s.body && s.from - kept.back().to < im.tolerance(s.from - t0)) {
            kept.back().to = s.to;
            continue;
        }
        if (!kept.empty() && s.from - kept.back().to < im.tolerance(s.from - t0)) {
            // Close a sliver gap between neighbours at the midpoint: one shared boundary.
            const double mid = 0.5 * (s.from + kept.back().to);
            kept.back().to = mid;
            kept.push_back(Span{mid, s.to, s.body});
            continue;
        }
        kept.push_back(s);
    }
    for (const Span& s : kept) {
        BoreholeInterval iv;
        iv.body = static_cast<std::uint32_t>(s.body);
        iv.record = model.bodies[iv.body].record;
        iv.from = s.from;
        iv.to = s.to;
        iv.fromCollar = s.from - bh.collarDepth;
        iv.toCollar = s.to - bh.collarDepth;
        iv.fromWorld = pointAt(s.from);
        iv.toWorld = pointAt(s.to);
        iv.fromElevation = iv.fromWorld.z;
        iv.toElevation = iv.toWorld.z;
        bh.intervals.push_back(iv);
    }
    return bh;
}

Result<Borehole> BoreholeTracer::traceVertical(double x, double y) const {
    const Impl& im = *impl_;
    if (!std::isfinite(x) || !std::isfinite(y))
        return makeError(ErrorCode::InvalidArgument, "borehole position has a non-finite coordinate");
    const Aabb& b = im.bounds;
    if (!b.valid()) return makeError(ErrorCode::OutOfRange, "the model has no finite vertices to drill");
    if (x < b.min.x || x > b.max.x || y < b.min.y || y > b.max.y) {
        char buf[400];
        std::snprintf(buf, sizeof buf,
                      "borehole at (%.3f, %.3f) lies outside the model's map extent x %.3f..%.3f, y %.3f..%.3f", x, y,
                      b.min.x, b.max.x, b.min.y, b.max.y);
        return makeError(ErrorCode::OutOfRange, buf);
    }
    const double top = b.max.z + 1.0;
    return traceRay(glm::dvec3(x, y, top), glm::dvec3(0.0, 0.0, -1.0), top - b.min.z + 1.0);
}

nlohmann::ordered_json boreholeJson(const Model& model, const Borehole& b) {
    using json = nlohmann::ordered_json;
    auto vec3 = [](const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); };
    auto number = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
    auto attributes = [&](RecordId id) {
        const AttributeRecord* r = model.attributes.find(id);
        return r ? r->toJson() : json(nullptr);
    };
    json intervals = json::array(), crossings = json::array();
    for (const auto& iv : b.intervals)
        intervals.push_back({{"from_m", iv.from},
                             {"to_m", iv.to},
                             {"from_collar_m", number(iv.fromCollar)},
                             {"to_collar_m", number(iv.toCollar)},
                             {"from_elevation_m", iv.fromElevation},
                             {"to_elevation_m", iv.toElevation},
                             {"from_world", vec3(iv.fromWorld)},
                             {"to_world", vec3(iv.toWorld)},
                             {"body", model.bodies[iv.body].name},
                             {"record", iv.record},
                             {"attributes", attributes(iv.record)}});
    for (const auto& c : b.crossings)
        crossings.push_back({{"depth_m", c.depth},
                             {"depth_collar_m", number(c.depthCollar)},
                             {"elevation_m", c.elevation},
                             {"world", vec3(c.world)},
                             {"surface", model.surfaces[c.surface].name},
                             {"record", c.record},
                             {"attributes", attributes(c.record)}});
    return {{"axes", "world: x easting, y northing, z elevation, metres; depths in metres along the hole"},
            {"origin", vec3(b.origin)},
            {"direction", vec3(b.direction)},
            {"length_m", b.length},
            {"collar_depth_m", number(b.collarDepth)},
            {"collar", std::isfinite(b.collarDepth) ? vec3(b.collar) : json(nullptr)},
            {"depths", "*_m: from the ray origin; *_collar_m: from the collar (first surface hit)"},
            {"intervals", std::move(intervals)},
            {"crossings", std::move(crossings)}};
}

}  // namespace geoslice
