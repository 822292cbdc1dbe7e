// Minimum curvature desurvey (model/drillholes/drillholes.hpp; Sawaryn & Thorogood, SPE 84246).
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "model/drillholes/drillholes.hpp"

namespace geoslice {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// The dogleg angle between unit vectors, stable for small and large angles (acos(t1.t2) loses
// half the digits near 0: 1 - cos(b) ~ b^2/2).
double dogleg(const glm::dvec3& t1, const glm::dvec3& t2) {
    return 2.0 * std::atan2(glm::length(t1 - t2), glm::length(t1 + t2));
}

// Position on the circular arc from t1 to t2 at fraction s of a segment of length `len`,
// relative to the segment's start: len * (a t1 + b t2), the integral of the slerp of the
// tangent from 0 to s*beta, divided by beta/len. At s = 1, a = b = tan(beta/2)/beta, which
// is the (MD2-MD1)/2 * RF of the method.
glm::dvec3 arcOffset(const glm::dvec3& t1, const glm::dvec3& t2, double len, double s) {
    const double beta = dogleg(t1, t2);
    double a, b;
    if (beta < 1e-9) {
        // The limit (error O(beta^2) relative): a straight segment.
        a = s * (2.0 - s) / 2.0;
        b = s * s / 2.0;
    } else if (beta > kPi - 1e-9) {
        // A hole that turns back on itself has no arc; the balanced tangent.
        a = b = s / 2.0;
    } else {
        // (cos(beta(1-s)) - cos(beta)) / (beta sin(beta)) and (1 - cos(s beta)) / (beta sin(beta)),
        // written with products of sines, which keep their digits for small angles.
        const double den = beta * std::sin(beta);
        a = 2.0 * std::sin(beta * (2.0 - s) / 2.0) * std::sin(beta * s / 2.0) / den;
        const double h = std::sin(beta * s / 2.0);
        b = 2.0 * h * h / den;
    }
    return len * (a * t1 + b * t2);
}

}  // namespace

const char* dipConventionName(DipConvention d) {
    return d == DipConvention::PositiveDown ? "positive_down" : "negative_down";
}

glm::dvec3 drillDirection(double azimuthDeg, double dipDeg) {
    const double az = azimuthDeg * kDeg, dip = dipDeg * kDeg;
    return {std::cos(dip) * std::sin(az), std::cos(dip) * std::cos(az), std::sin(dip)};
}

HolePath desurvey(const glm::dvec3& collar, const std::vector<SurveyStation>& stations, double totalDepth,
                  const glm::dvec3& collarDirection) {
    HolePath p;
    auto node = [&p](double depth, const glm::dvec3& dir) {
        p.depth.push_back(depth);
        p.direction.push_back(dir);
    };
    if (stations.empty()) {
        p.method = collarDirection == glm::dvec3(0.0, 0.0, -1.0)
                       ? "straight down (no survey)"
                       : "straight along the collar's azimuth/dip (no survey)";
        node(0.0, glm::normalize(collarDirection));
    } else {
        p.method = stations.size() == 1 ? "tangent (one station)" : "minimum curvature";
        const glm::dvec3 first = drillDirection(stations.front().azimuth, stations.front().dip);
        if (stations.front().depth > 0.0) node(0.0, first);
        for (const SurveyStation& s : stations) node(s.depth, drillDirection(s.azimuth, s.dip));
    }
    if (std::isfinite(totalDepth) && totalDepth > p.depth.back()) node(totalDepth, p.direction.back());

    p.position.resize(p.depth.size());
    // A station above the collar (negative depth) is refused by the loader; here the collar is
    // node 0 whenever depth[0] == 0, otherwise the first node is placed straight from it.
    p.position[0] = collar + p.depth[0] * p.direction[0];
    for (std::size_t i = 1; i < p.depth.size(); ++i)
        p.position[i] =
            p.position[i - 1] + arcOffset(p.direction[i - 1], p.direction[i], p.depth[i] - p.depth[i - 1], 1.0);
    return p;
}

glm::dvec3 HolePath::at(double d) const {
    if (depth.empty()) return glm::dvec3(0.0);
    if (d <= depth.front()) return position.front() + (d - depth.front()) * direction.front();
    if (d >= depth.back()) return position.back() + (d - depth.back()) * direction.back();
    const std::size_t i = std::size_t(std::upper_bound(depth.begin(), depth.end(), d) - depth.begin()) - 1;
    const double len = depth[i + 1] - depth[i];
    return position[i] + arcOffset(direction[i], direction[i + 1], len, (d - depth[i]) / len);
}

Status placeDrillholes(DrillholeDatabase& db, const Crs& modelCrs, const Aabb& modelBounds) {
    if (db.crs.empty()) return {};
    auto from = Crs::parse(db.crs);
    if (!from) return makeError(from.error().code, "drillholes \"crs\" '" + db.crs + "': " + from.error().message);
    if (from.value().isLocal() || from.value() == modelCrs) return {};
    if (modelCrs.isLocal()) {
        db.warnings.push_back(
            {db.source, 0, "",
             "the holes are in " + db.crs + " but the model has no CRS: their coordinates are taken as the model's"});
        return {};
    }
    auto area = lonLatBoxOf(modelCrs, {modelBounds.min.x, modelBounds.min.y}, {modelBounds.max.x, modelBounds.max.y});
    if (!area) return makeError(area.error().code, "the model's lon/lat extent: " + area.error().message);
    auto t = CrsTransform::forArea(from.value(), modelCrs, area.value());
    if (!t)
        return makeError(t.error().code, "no PROJ operation from the holes' " + db.crs + " to the model's " +
                                             modelCrs.id() + ": " + t.error().message);
    auto convert = [&](const glm::dvec3& p) -> Result<glm::dvec3> {
        auto q = t.value().apply(p);
        if (!q) return q.error();
        return glm::dvec3(q.value().x, q.value().y, p.z);
    };
    for (Drillhole& h : db.holes) {
        auto c = convert(h.collar);
        if (!c) return makeError(c.error().code, "hole '" + h.id + "': collar: " + c.error().message);
        h.collar = c.value();
        for (std::size_t i = 0; i < h.path.position.size(); ++i) {
            const glm::dvec3 p = h.path.position[i];
            auto q = convert(p);
            if (!q) return makeError(q.error().code, "hole '" + h.id + "': " + q.error().message);
            if (i < h.path.direction.size()) {
                auto ahead = convert(p + 10.0 * h.path.direction[i]);
                if (!ahead) return makeError(ahead.error().code, "hole '" + h.id + "': " + ahead.error().message);
                h.path.direction[i] = glm::normalize(ahead.value() - q.value());
            }
            h.path.position[i] = q.value();
        }
    }
    db.conversion = "from " + db.crs + " to " + modelCrs.id() + " by " + t.value().operationName() +
                    (t.value().isBallpark() ? " (a ballpark operation: no datum shift)" : "");
    return {};
}

}  // namespace geoslice
