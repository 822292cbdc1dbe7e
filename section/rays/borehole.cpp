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

    // Clips origin + t dir, t in [t0, t1], to the model's bounds grown by 1 m (where the ray
    // can meet anything); false when nothing is left.
    bool clip(const glm::dvec3& o, const glm::dvec3& dir, double& t0, double& t1) const {
        for (int k = 0; k < 3; ++k) {
            const double lo = bounds.min[k] - 1.0, hi = bounds.max[k] + 1.0;
            if (dir[k] == 0.0) {
                if (o[k] < lo || o[k] > hi) return false;
                continue;
            }
            double a = (lo - o[k]) / dir[k], b = (hi - o[k]) / dir[k];
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a);
            t1 = std::min(t1, b);
        }
        return t0 <= t1;
    }

    // The depth of a boundary found on chord k at `sChord` (float32 cast), moved onto the hole:
    // where the chord's line (or path.exact, between the chord's ends) crosses the plane of the
    // triangle hit, in double. Kept at sChord when the triangle is degenerate, the hole runs
    // along its plane, or the crossing lies further than the cast's error allows (`tol`, plus
    // the chord's sagitta over the hit's cosine on a curved hole).
    double refine(const HolePolyline& path, std::size_t k, int part, unsigned prim, double sChord, double tol,
                  double sagitta, double cosine) const {
        const Mesh& mesh = part >= 0 ? model->bodies[static_cast<std::size_t>(part)].mesh
                                     : model->surfaces[static_cast<std::size_t>(-part - 1)].mesh;
        if (3 * std::size_t(prim) + 2 >= mesh.indices.size()) return sChord;
        const glm::dvec3 v0 = mesh.positions[mesh.indices[3 * std::size_t(prim)]];
        const glm::dvec3 v1 = mesh.positions[mesh.indices[3 * std::size_t(prim) + 1]];
        const glm::dvec3 v2 = mesh.positions[mesh.indices[3 * std::size_t(prim) + 2]];
        glm::dvec3 n = glm::cross(v1 - v0, v2 - v0);
        const double nl = glm::length(n);
        if (!(nl > 0.0) || !std::isfinite(nl)) return sChord;
        n /= nl;
        const glm::dvec3 p0 = path.points[k], p1 = path.points[k + 1];
        const double d0 = path.depth[k], d1 = path.depth[k + 1];
        double s = sChord;
        if (!path.exact) {
            const double denom = glm::dot(n, p1 - p0);
            if (!(std::abs(denom) > 1e-12 * glm::length(p1 - p0))) return sChord;
            s = d0 + (d1 - d0) * glm::dot(n, v0 - p0) / denom;
        } else {
            // Regula falsi (Illinois) on g(d) = n . (hole(d) - v0) within what the cast's error
            // and the chord's sagitta allow around the chord's crossing.
            const double grow = std::min(4.0 * tol + sagitta / std::max(cosine, 1e-3), d1 - d0);
            double a = sChord - grow, b = sChord + grow;
            double ga = glm::dot(n, path.exact(a) - v0), gb = glm::dot(n, path.exact(b) - v0);
            if (ga == 0.0) return a;
            if (gb == 0.0) return b;
            if ((ga < 0.0) == (gb < 0.0)) return sChord;
            int side = 0;
            for (int it = 0; it < 100 && b - a > 1e-13 * (1.0 + std::abs(a)); ++it) {
                const double c = (a * gb - b * ga) / (gb - ga);
                const double gc = glm::dot(n, path.exact(c) - v0);
                if (gc == 0.0) {
                    a = b = c;
                    break;
                }
                if ((gc < 0.0) == (ga < 0.0)) {
                    a = c;
                    ga = gc;
                    if (side == -1) gb *= 0.5;
                    side = -1;
                } else {
                    b = c;
                    gb = gc;
                    if (side == 1) ga *= 0.5;
                    side = 1;
                }
            }
            s = std::abs(ga) <= std::abs(gb) ? a : b;
        }
        const double allowed = 4.0 * tol + (path.exact ? sagitta / std::max(cosine, 1e-3) : 0.0);
        return std::isfinite(s) && std::abs(s - sChord) <= allowed ? s : sChord;
    }
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
    if (!im.bounds.valid()) return makeError(ErrorCode::OutOfRange, "the model has no finite vertices to drill");
    double t0 = 0.0, t1 = maxLength;
    if (!im.clip(origin, dir, t0, t1)) {
        std::snprintf(buf, sizeof buf,
                      "borehole ray from (%.3f, %.3f, %.3f) along (%.6f, %.6f, %.6f) misses the model: bounds "
                      "[%.3f, %.3f, %.3f] - [%.3f, %.3f, %.3f]",
                      origin.x, origin.y, origin.z, dir.x, dir.y, dir.z, im.bounds.min.x, im.bounds.min.y,
                      im.bounds.min.z, im.bounds.max.x, im.bounds.max.y, im.bounds.max.z);
        return makeError(ErrorCode::OutOfRange, buf);
    }
    // The ray is the one-chord polyline from its origin to where it leaves the model's box (or
    // ends); depth = distance from the origin.
    HolePolyline line;
    line.points = {origin, origin + t1 * dir};
    line.depth = {0.0, t1};
    auto bh = tracePath(line);
    if (!bh) return bh;
    bh.value().direction = dir;
    bh.value().length = std::isfinite(maxLength) ? maxLength : t1;
    return bh;
}

HolePolyline holePolyline(const HolePath& path, double toDepth, double maxSagitta) {
    HolePolyline out;
    const std::size_t n = path.depth.size();
    if (n == 0) return out;
    out.points.push_back(path.position[0]);
    out.depth.push_back(path.depth[0]);
    for (std::size_t i = 0; i + 1 < n; ++i) {
        const double len = path.depth[i + 1] - path.depth[i];
        const glm::dvec3 &t1 = path.direction[i], &t2 = path.direction[i + 1];
        const double beta = 2.0 * std::atan2(glm::length(t1 - t2), glm::length(t1 + t2));
        // Sagitta of a piece of length len/k on radius len/beta: <= len beta / (8 k^2).
        double pieces = 1.0;
        if (beta > 0.0 && maxSagitta > 0.0) pieces = std::ceil(std::sqrt(len * beta / (8.0 * maxSagitta)));
        const auto k = static_cast<std::size_t>(std::clamp(pieces, 1.0, 4096.0));
        for (std::size_t j = 1; j < k; ++j) {
            const double d = path.depth[i] + len * double(j) / double(k);
            out.points.push_back(path.at(d));
            out.depth.push_back(d);
        }
        out.points.push_back(path.position[i + 1]);
        out.depth.push_back(path.depth[i + 1]);
    }
    if (std::isfinite(toDepth) && toDepth > out.depth.back()) {
        out.points.push_back(path.at(toDepth));
        out.depth.push_back(toDepth);
    }
    if (out.points.size() == 1) {  // a path of one node: one metre straight along it
        out.points.push_back(path.at(path.depth[0] + 1.0));
        out.depth.push_back(path.depth[0] + 1.0);
    }
    const HolePath* p = &path;
    out.exact = [p](double d) { return p->at(d); };
    return out;
}

Result<Borehole> BoreholeTracer::tracePath(const HolePolyline& path) const {
    const Impl& im = *impl_;
    const std::size_t np = path.points.size();
    if (np < 2 || path.depth.size() != np)
        return makeError(ErrorCode::InvalidArgument, "hole path: " + std::to_string(np) + " points and " +
                                                         std::to_string(path.depth.size()) +
                                                         " depths (at least two of each, as many depths as points)");
    for (std::size_t i = 0; i < np; ++i) {
        if (!finite3(path.points[i]) || !std::isfinite(path.depth[i]))
            return makeError(ErrorCode::InvalidArgument,
                             "hole path point " + std::to_string(i) + " has a non-finite coordinate or depth");
        if (i > 0 && !(path.depth[i] > path.depth[i - 1]))
            return makeError(ErrorCode::InvalidArgument, "hole path depths must increase (point " + std::to_string(i) +
                                                             ": " + std::to_string(path.depth[i]) + " after " +
                                                             std::to_string(path.depth[i - 1]) + ")");
    }
    if (!im.bounds.valid()) return makeError(ErrorCode::OutOfRange, "the model has no finite vertices to drill");
    const Model& model = *im.model;
    const double dBegin = path.depth.front(), dEnd = path.depth.back();

    // Position at a depth: the exact hole, else the chords.
    auto pointAt = [&](double d) {
        if (path.exact) return path.exact(d);
        const auto it = std::upper_bound(path.depth.begin(), path.depth.end(), d);
        std::size_t k = it == path.depth.begin() ? 0 : std::size_t(it - path.depth.begin()) - 1;
        k = std::min(k, np - 2);
        const double f = (d - path.depth[k]) / (path.depth[k + 1] - path.depth[k]);
        return path.points[k] + f * (path.points[k + 1] - path.points[k]);
    };

    struct Event {
        double s;    // depth along the hole
        double tol;  // the float tolerance where it was found
        int part;    // RayScene::partOf
        bool enter;
    };
    std::vector<Event> events, surfaceHits;
    const std::size_t nb = model.bodies.size();
    std::vector<char> inside(nb, 0);
    double collarDepth = std::numeric_limits<double>::quiet_NaN();
    double lastTol = im.tolerance(0.0);
    std::vector<Hit> hits;

    for (std::size_t k = 0; k + 1 < np; ++k) {
        const glm::dvec3 p0 = path.points[k], p1 = path.points[k + 1];
        const double d0 = path.depth[k], d1 = path.depth[k + 1];
        const double len = glm::length(p1 - p0);
        if (!(len > 0.0)) continue;
        const glm::dvec3 dir = (p1 - p0) / len;
        // Chords overlap by the float tolerance, so that a boundary at a joint is never lost
        // between two casts (found twice, it is one event: duplicates are merged below).
        const double eps = im.tolerance(len);
        const bool first = k == 0;
        double lo = first ? 0.0 : -eps;
        // The first chord looks on to the box's far side: the first hit of each body there
        // says whether the hole starts inside it.
        double hi = first ? std::numeric_limits<double>::infinity() : len + eps;
        if (!im.clip(p0, dir, lo, hi)) continue;
        const glm::dvec3 start = p0 + lo * dir - im.origin;
        hits.clear();
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
        rh.ray.tfar = float(hi - lo);
        rh.ray.mask = 0xFFFFFFFFu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(im.scene->scene(), &ctx.base, &rh);
        std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
            if (a.t != b.t) return a.t < b.t;
            if (a.geom != b.geom) return a.geom < b.geom;
            return a.prim < b.prim;
        });
        if (first) {
            std::vector<char> seen(nb, 0);
            for (const Hit& h : hits) {
                const int b = im.scene->partOf(h.geom);
                if (b < 0 || std::abs(h.cosine) < kCosGrazing) continue;
                const auto bi = static_cast<std::size_t>(b);
                if (!seen[bi]) inside[bi] = h.cosine > 0.0f;  // first hit exits: the hole starts inside
                seen[bi] = 1;
            }
        }
        // The chord's sagitta against the exact hole (0 without one): how far a refined
        // boundary may move from the chord's.
        const double sagitta = path.exact ? glm::length(path.exact(0.5 * (d0 + d1)) - 0.5 * (p0 + p1)) : 0.0;
        const double scale = (d1 - d0) / len;  // depth per metre of chord
        for (const Hit& h : hits) {
            const double t = lo + double(h.t);
            if (t > len + eps) break;
            const double tol = im.tolerance(double(h.t));
            lastTol = std::max(lastTol, tol);
            const double sChord = d0 + t * scale;
            const int part = im.scene->partOf(h.geom);
            const double s = im.refine(path, k, part, h.prim, sChord, tol, sagitta, std::abs(double(h.cosine)));
            if (t >= 0.0 && t <= len && !(collarDepth <= s)) collarDepth = s;
            if (part < 0) {
                surfaceHits.push_back(Event{s, tol, part, false});
                continue;
            }
            if (std::abs(h.cosine) < kCosGrazing) continue;
            events.push_back(Event{s, tol, part, h.cosine < 0.0f});
        }
    }

    Borehole bh;
    bh.origin = path.points.front();
    bh.direction = glm::length(path.points[1] - path.points[0]) > 0.0 ? glm::normalize(path.points[1] - path.points[0])
                                                                      : glm::dvec3(0.0, 0.0, -1.0);
    bh.length = dEnd;
    if (std::isfinite(collarDepth)) {
        bh.collarDepth = collarDepth;
        bh.collar = pointAt(collarDepth);
    }

    // Surfaces: one crossing per surface per distinct depth (a hit on a shared edge is
    // reported by both triangles; a joint's by both chords).
    std::stable_sort(surfaceHits.begin(), surfaceHits.end(), [](const Event& a, const Event& b) { return a.s < b.s; });
    for (const Event& e : surfaceHits) {
        const auto srf = static_cast<std::uint32_t>(-e.part - 1);
        bool dup = false;
        for (auto it = bh.crossings.rbegin(); it != bh.crossings.rend() && e.s - it->depth < e.tol; ++it)
            dup = dup || it->surface == srf;
        if (dup) continue;
        BoreholeCrossing c;
        c.surface = srf;
        c.record = model.surfaces[srf].record;
        c.depth = e.s;
        c.depthCollar = e.s - bh.collarDepth;
        c.world = pointAt(e.s);
        c.elevation = c.world.z;
        bh.crossings.push_back(c);
    }

    // Bodies: events in depth order, duplicates (shared edges, chord joints) merged.
    std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.s < b.s; });
    std::vector<Event> unique;
    for (const Event& e : events) {
        bool dup = false;
        for (auto it = unique.rbegin(); it != unique.rend() && e.s - it->s < e.tol; ++it)
            dup = dup || (it->part == e.part && it->enter == e.enter);
        if (!dup) unique.push_back(e);
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
        double from, to, tol;
        int body;
    };
    std::vector<Span> spans;
    double prev = dBegin;
    int current = innermost();
    auto close = [&](double s, double tol) {
        s = std::min(s, dEnd);
        if (current >= 0 && s > prev) spans.push_back(Span{prev, s, tol, current});
    };
    for (std::size_t i = 0; i < unique.size();) {
        const double s = unique[i].s;
        if (s > dEnd) break;
        close(s, unique[i].tol);
        // All events at (exactly) this depth change the state together.
        for (; i < unique.size() && unique[i].s == s; ++i)
            inside[static_cast<std::size_t>(unique[i].part)] = unique[i].enter;
        prev = std::max(prev, s);
        current = innermost();
    }
    close(dEnd, lastTol);
    // Drop slivers (coincident faces of neighbours), then merge what they separated.
    std::vector<Span> kept;
    for (const Span& s : spans) {
        if (s.to - s.from < s.tol) continue;
        if (!kept.empty() && kept.back().body == s.body && s.from - kept.back().to < s.tol) {
            kept.back().to = s.to;
            continue;
        }
        if (!kept.empty() && s.from - kept.back().to < s.tol) {
            // Close a sliver gap between neighbours at the midpoint: one shared boundary.
            const double mid = 0.5 * (s.from + kept.back().to);
            kept.back().to = mid;
            kept.push_back(Span{mid, s.to, s.tol, s.body});
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
