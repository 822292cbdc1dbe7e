#include "api/cut.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

#include "api/params.hpp"
#include "view/view_limits.hpp"

namespace geoslice::api {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double side(const Plane& p, const glm::dvec3& x) { return glm::dot(p.normal, x) + p.d; }

// The t >= 0 where origin + t * direction is on the kept side of `p`: [lo, hi] (empty when
// lo > hi).
RaySpan keptPart(const Plane& p, const glm::dvec3& origin, const glm::dvec3& direction) {
    const double s0 = side(p, origin), ds = glm::dot(p.normal, direction);
    if (ds > 0.0) return {std::max(0.0, -s0 / ds), kInf};
    if (ds < 0.0) return {0.0, -s0 / ds};
    return s0 >= 0.0 ? RaySpan{0.0, kInf} : RaySpan{1.0, 0.0};
}

}  // namespace

const char* cutModeName(CutMode mode) { return mode == CutMode::Union ? "union" : "intersection"; }

bool CutOut::keeps(const glm::dvec3& world) const {
    if (mode == CutMode::Union || planes.size() == 1) {
        for (const Plane& p : planes)
            if (side(p, world) < 0.0) return false;
        return true;
    }
    for (const Plane& p : planes)
        if (side(p, world) >= 0.0) return true;
    return false;
}

std::vector<RaySpan> CutOut::keptSpans(const glm::dvec3& origin, const glm::dvec3& direction) const {
    std::vector<RaySpan> out;
    if (mode == CutMode::Union || planes.size() == 1) {
        RaySpan k{0.0, kInf};
        for (const Plane& p : planes) {
            const RaySpan s = keptPart(p, origin, direction);
            k.from = std::max(k.from, s.from);
            k.to = std::min(k.to, s.to);
        }
        if (k.from < k.to) out.push_back(k);
        return out;
    }
    // The removed parts of the ray: each the complement of a kept part, a half-line (or
    // all, or nothing); their intersection is one span [a, b].
    double a = 0.0, b = kInf;
    for (const Plane& p : planes) {
        const double s0 = side(p, origin), ds = glm::dot(p.normal, direction);
        if (ds > 0.0) {
            b = std::min(b, -s0 / ds);  // removed for t < -s0/ds
        } else if (ds < 0.0) {
            a = std::max(a, -s0 / ds);  // removed for t > -s0/ds
        } else if (s0 >= 0.0) {
            b = -1.0;  // this plane keeps the whole ray
        }
    }
    if (!(a < b)) {
        out.push_back({0.0, kInf});
        return out;
    }
    if (a > 0.0) out.push_back({0.0, a});
    if (b < kInf) out.push_back({b, kInf});
    return out;
}

Result<Plane> parsePlane(std::string_view name, std::string_view text, std::string_view which) {
    const std::string what = "parameter '" + std::string(name) + "'" + std::string(which);
    auto v = parseNumberList(name, text, 4);
    if (!v) {
        // "parameter 'NAME': ..." from the list reader, with `which` put after the name.
        const std::string prefix = "parameter '" + std::string(name) + "': ";
        std::string message = v.error().message;
        if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
        return makeError(v.error().code, what + ": " + message);
    }
    const std::vector<double>& c = v.value();
    auto p = makePlane(c[0], c[1], c[2], c[3]);
    if (!p) return makeError(p.error().code, what + ": " + p.error().message);
    Plane plane = p.value();
    // A normal that is already unit to rounding is kept bit for bit, so that the canonical
    // text is a fixed point: parsing it again gives the same text (stateless section ids
    // decode to the key they were made from; found by fuzz_request).
    const double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (std::abs(len - 1.0) <= 1e-15) {
        plane.normal = {c[0], c[1], c[2]};
        plane.d = c[3];
    }
    if (auto s = checkCoordinate(what + ": offset d / |(a, b, c)|", plane.d); !s) return s.error();
    return plane;
}

Result<std::vector<Plane>> parsePlaneList(std::string_view name, std::string_view text) {
    const std::string param = "parameter '" + std::string(name) + "'";
    const std::size_t count = std::size_t(std::count(text.begin(), text.end(), ';')) + 1;
    if (count > kMaxCutPlanes)
        return makeError(ErrorCode::InvalidArgument, param + ": " + std::to_string(count) + " planes given, at most " +
                                                         std::to_string(kMaxCutPlanes));
    std::vector<Plane> planes;
    std::size_t start = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t end = std::min(text.find(';', start), text.size());
        auto p =
            parsePlane(name, text.substr(start, end - start), count == 1 ? "" : ": plane " + std::to_string(i + 1));
        if (!p) return p.error();
        for (std::size_t j = 0; j < planes.size(); ++j)
            if (glm::length(planes[j].normal - p.value().normal) <= 1e-12 &&
                std::abs(planes[j].d - p.value().d) <= 1e-9)
                return makeError(ErrorCode::InvalidArgument, param + ": planes " + std::to_string(j + 1) + " and " +
                                                                 std::to_string(i + 1) + " are the same plane (" +
                                                                 planeText(p.value()) + ")");
        planes.push_back(p.value());
        start = end + 1;
    }
    return planes;
}

Result<CutMode> parseCutMode(std::string_view name, std::string_view text) {
    if (text == "union") return CutMode::Union;
    if (text == "intersection") return CutMode::Intersection;
    return makeError(ErrorCode::InvalidArgument,
                     "parameter '" + std::string(name) + "': '" + std::string(text.substr(0, 64)) +
                         "' is not 'union' (remove the union of the planes' removed sides: keep what is on the kept "
                         "side of every plane) or 'intersection' (remove what is on the removed side of every "
                         "plane: a wedge, an octant or a box taken out)");
}

void sortPlanes(std::vector<Plane>& planes) {
    std::sort(planes.begin(), planes.end(), [](const Plane& a, const Plane& b) {
        return std::tie(a.normal.x, a.normal.y, a.normal.z, a.d) < std::tie(b.normal.x, b.normal.y, b.normal.z, b.d);
    });
}

std::string planeText(const Plane& p) {
    return formatNumber(p.normal.x) + "," + formatNumber(p.normal.y) + "," + formatNumber(p.normal.z) + "," +
           formatNumber(p.d);
}

Status checkCutKeepsSomething(std::string_view name, const CutOut& cut, const Aabb& bounds) {
    if (!bounds.valid()) return {};
    // Coordinates relative to the box centre (Gauss-Kruger eastings keep 1e-8 m in double).
    const glm::dvec3 centre = bounds.centre(), half = 0.5 * bounds.size();
    std::vector<Plane> planes;
    for (const Plane& p : cut.planes) planes.push_back({p.normal, p.d + glm::dot(p.normal, centre)});
    const double tol = 1e-9 * (1.0 + glm::length(half));
    std::array<glm::dvec3, 8> corners;
    for (int i = 0; i < 8; ++i)
        corners[std::size_t(i)] = {i & 1 ? half.x : -half.x, i & 2 ? half.y : -half.y, i & 4 ? half.z : -half.z};
    CutOut local{planes, cut.mode};
    bool kept = false;
    for (const glm::dvec3& c : corners) kept = kept || local.keeps(c);
    if (!kept && cut.mode == CutMode::Union && planes.size() > 1) {
        // The kept region (convex) may meet the box with no corner inside it: then the
        // polytope box ∩ kept has a vertex where three of its faces meet. Try every triple
        // of the planes and the box's six faces (at most C(12, 3) = 220 small solves).
        std::vector<Plane> all = planes;
        for (int axis = 0; axis < 3; ++axis)
            for (double s : {1.0, -1.0}) {
                glm::dvec3 n(0.0);
                n[axis] = s;
                all.push_back({n, half[axis]});  // s * x[axis] + half >= 0
            }
        for (std::size_t i = 0; i < all.size() && !kept; ++i)
            for (std::size_t j = i + 1; j < all.size() && !kept; ++j)
                for (std::size_t k = j + 1; k < all.size() && !kept; ++k) {
                    const glm::dmat3 m = glm::transpose(glm::dmat3(all[i].normal, all[j].normal, all[k].normal));
                    const double det = glm::determinant(m);
                    if (std::abs(det) < 1e-12) continue;
                    const glm::dvec3 x = glm::inverse(m) * glm::dvec3(-all[i].d, -all[j].d, -all[k].d);
                    bool inside = true;
                    for (const Plane& p : all) inside = inside && side(p, x) >= -tol;
                    kept = inside;
                }
    }
    if (kept) return {};
    const std::string param = "parameter '" + std::string(name) + "'";
    char box[256];
    std::snprintf(box, sizeof box, "[%.3f, %.3f, %.3f] - [%.3f, %.3f, %.3f]", bounds.min.x, bounds.min.y, bounds.min.z,
                  bounds.max.x, bounds.max.y, bounds.max.z);
    return makeError(ErrorCode::InvalidArgument,
                     param + ": the cut removes the whole model: no point of its bounds " + box + " is kept" +
                         (cut.planes.size() > 1 ? std::string(" (cut=") + cutModeName(cut.mode) + ")" : ""));
}

}  // namespace geoslice::api
