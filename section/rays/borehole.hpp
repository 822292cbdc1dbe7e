// Virtual boreholes: every geological interval along a ray through the model, plus the
// open surfaces (faults, horizons, terrain) the ray crosses.
//
// Frames and units: inputs and outputs are world coordinates (double, x east, y north,
// z elevation up, metres, the model's CRS). Rays are cast with Embree in the model's
// float32 local frame (world - Model::origin), so positions carry the float32 step of the
// local coordinates (about 0.5 mm for a 6 km model).
//
// Depths: every distance is metres measured along the ray.
//   - `from`/`to` are measured from the ray origin.
//   - `fromCollar`/`toCollar` are measured from the collar, the first surface of any part
//     (body face or open surface) the ray meets; NaN when the ray meets nothing.
// For a vertical hole at (x, y) (traceVertical) the ray starts 1 m above the model's top
// (bounds.max.z + 1) and points down (0, 0, -1), so the depth below the collar is the
// geological depth below the first surface hit (terrain when the model has one).
//
// Intervals (bodies): the ray is cut at every hit on a closed body's shell; an entering
// hit (ray . outward normal < 0) puts the ray inside that body, an exiting one takes it
// out, and between two hits the ray is in the innermost body it is inside (highest
// nesting depth from validation: nested bodies win over their host, like the oracle in
// section/rays/classify.hpp). A ray that starts inside a body (its first hit on that body
// exits it) starts in the body. Slivers shorter than the float tolerance (1e-6 x (model
// half-extent + distance from where the ray enters the model's box) + 0.1 mm, the
// classifier's) are dropped, so the coincident faces
// of two neighbouring bodies give one boundary, not a gap. Hits where the ray runs within
// 1e-4 (cosine) of a face's plane decide nothing (the ray slides along the face).
// Only closed bodies (validation's `closed`) give intervals; open surfaces give crossings.
//
// Thread-safety: build once; trace*() may be called from any number of threads.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "model/drillholes/drillholes.hpp"
#include "model/model.hpp"
#include "model/result.hpp"
#include "section/rays/ray_scene.hpp"

namespace geoslice {

struct BoreholeInterval {
    std::uint32_t body = 0;  // index into Model::bodies
    RecordId record = kNoRecord;
    double from = 0.0, to = 0.0;                    // metres along the ray from its origin, from < to
    double fromCollar = 0.0, toCollar = 0.0;        // metres along the ray from the collar
    double fromElevation = 0.0, toElevation = 0.0;  // world z, metres
    glm::dvec3 fromWorld{0.0}, toWorld{0.0};        // world points
};

struct BoreholeCrossing {
    std::uint32_t surface = 0;  // index into Model::surfaces
    RecordId record = kNoRecord;
    double depth = 0.0;        // metres along the ray from its origin
    double depthCollar = 0.0;  // metres along the ray from the collar
    double elevation = 0.0;    // world z, metres
    glm::dvec3 world{0.0};
};

struct Borehole {
    glm::dvec3 origin{0.0};     // world
    glm::dvec3 direction{0.0};  // world, unit
    double length = 0.0;        // metres traced (infinite rays stop where the model ends)
    double collarDepth = std::numeric_limits<double>::quiet_NaN();  // metres from the origin; NaN: no hit
    glm::dvec3 collar{std::numeric_limits<double>::quiet_NaN()};    // world point of the collar
    std::vector<BoreholeInterval> intervals;                        // ascending `from`, not overlapping
    std::vector<BoreholeCrossing> crossings;                        // ascending `depth`
};

// A hole as a polyline of chords: points[i] (world) at distance depth[i] along the hole
// (metres, strictly increasing). Each chord is cast as a ray; `exact`, when set, is the hole's
// true position at a depth (a minimum-curvature arc, HolePath::at): every boundary found on a
// chord is then moved onto the hole itself (below). Without `exact` the chords are the hole.
struct HolePolyline {
    std::vector<glm::dvec3> points;
    std::vector<double> depth;
    std::function<glm::dvec3(double)> exact;
};

// Largest distance (metres) between a minimum-curvature arc and the chords holePolyline()
// traces it with: each leg of dogleg beta and length L is cut into n = ceil(sqrt(L beta /
// (8 kHoleChordSagittaM))) equal chords, whose sagitta is at most L beta / (8 n^2).
constexpr double kHoleChordSagittaM = 0.01;

// The desurveyed hole as chords: every node of `path`, each leg subdivided as above, and the
// straight extension to `toDepth` when it is below the last node; `exact` = path.at. The path
// must outlive the polyline.
HolePolyline holePolyline(const HolePath& path, double toDepth, double maxSagitta = kHoleChordSagittaM);

class BoreholeTracer {
public:
    // Builds an Embree scene over the model's closed bodies and its open surfaces. The
    // model must be validated (closed flags, nesting depths) and must outlive the tracer.
    // Errors: Internal when Embree fails.
    static Result<std::unique_ptr<BoreholeTracer>> build(const Model& model);
    // The same over a scene built for this model and shared with other ray queries
    // (section/rays/ray_scene.hpp).
    static Result<std::unique_ptr<BoreholeTracer>> build(const Model& model, std::shared_ptr<const RayScene> scene);
    ~BoreholeTracer();
    BoreholeTracer(const BoreholeTracer&) = delete;
    BoreholeTracer& operator=(const BoreholeTracer&) = delete;

    // All intervals along the ray origin + t * direction, 0 <= t <= maxLength (metres;
    // infinity = to the end of the model). `direction` need not be unit.
    // Errors: InvalidArgument (non-finite input, zero direction, maxLength <= 0 or NaN);
    // OutOfRange when the ray misses the model's bounding box (names ray and bounds).
    Result<Borehole> traceRay(const glm::dvec3& origin, const glm::dvec3& direction,
                              double maxLength = std::numeric_limits<double>::infinity()) const;

    // A vertical hole at map point (x, y) (world metres), from 1 m above the model's top
    // down through its bottom. Errors: InvalidArgument (non-finite); OutOfRange when
    // (x, y) lies outside the model's map extent (names the point and the extent).
    Result<Borehole> traceVertical(double x, double y) const;

    // The same rule along a polyline (a drillhole): traceRay is its one-chord case. Depths
    // (`from`, `to`, `depth`) are distances along the hole from points[0] (depth[0] is added),
    // `collarDepth` the first hit's. Where the ray casts carry float32 error, every boundary is
    // moved onto the exact hole: the crossing, in double precision, of the hole (the chord's
    // line, or `exact` between the chord's ends by regula falsi) with the plane of the triangle
    // the chord hit. On planar faces the boundaries are then exact to about 1e-12 relative;
    // where a curved hole crosses a face next to the one its chord hit, the error is at most
    // the chord's sagitta over the sine of the angle between hole and face. Chords outside the
    // model's box are skipped; a state (inside which bodies) is carried from chord to chord,
    // the first chord's from the first hit of each body on the ray beyond it.
    // Errors: InvalidArgument (fewer than two points, sizes differ, non-finite, depths not
    // increasing).
    Result<Borehole> tracePath(const HolePolyline& path) const;

private:
    BoreholeTracer() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The borehole as JSON, the one format of `geoslice borehole --json` and the HTTP API:
// origin, direction, length_m, collar_depth_m, collar, and per interval from_m / to_m (from
// the ray origin), from_collar_m / to_collar_m (from the collar), elevations, world points,
// body, record and its attributes; per crossing the same for one depth. World coordinates
// as above; non-finite values (no collar) are null.
nlohmann::ordered_json boreholeJson(const Model& model, const Borehole& hole);

}  // namespace geoslice
