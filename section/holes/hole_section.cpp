// Drillholes projected onto sections (section/holes/hole_section.hpp).
#include "section/holes/hole_section.hpp"

#include <algorithm>
#include <cmath>

namespace geoslice {
namespace {

// A linear function of the chord parameter t in [0, 1]: value(t) = at0 + t * (at1 - at0).
struct Linear {
    double at0 = 0.0, at1 = 0.0;
    double at(double t) const { return at0 + t * (at1 - at0); }
};

// Narrows [t0, t1] to where lo <= f(t) <= hi; false when nothing is left.
bool clipRange(const Linear& f, double lo, double hi, double& t0, double& t1) {
    const double df = f.at1 - f.at0;
    if (df == 0.0) return f.at0 >= lo && f.at0 <= hi;
    double a = (lo - f.at0) / df, b = (hi - f.at0) / df;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    return t0 < t1 || (t0 == t1 && f.at(t0) >= lo && f.at(t0) <= hi);
}

// Adds the pieces (and the pierce) of one chord clipped to [t0, t1]; `toSection` maps the
// chord parameter to section coordinates.
template <typename ToSection>
void addChord(HoleSection& out, const HoleSegment& s, const Linear& offset, double t0, double t1, std::uint32_t leg,
              const ToSection& toSection) {
    auto depthAt = [&](double t) { return s.from + t * (s.to - s.from); };
    auto piece = [&](double a, double b) {
        if (b <= a) return;
        HoleTracePiece p;
        p.hole = s.hole;
        p.from = depthAt(a);
        p.to = depthAt(b);
        p.a = toSection(a);
        p.b = toSection(b);
        p.offsetA = offset.at(a);
        p.offsetB = offset.at(b);
        p.front = offset.at(0.5 * (a + b)) < 0.0;
        p.leg = leg;
        out.pieces.push_back(p);
    };
    // The pierce: the sign changes between the chord's ends (0 counts as positive).
    const bool pierces = (offset.at0 < 0.0) != (offset.at1 < 0.0);
    const double tz = pierces ? -offset.at0 / (offset.at1 - offset.at0) : 0.0;
    if (pierces && tz > t0 && tz < t1) {
        piece(t0, tz);
        piece(tz, t1);
    } else {
        piece(t0, t1);
    }
    if (pierces && tz >= t0 && tz <= t1) out.pierces.push_back({s.hole, depthAt(tz), toSection(tz), leg});
}

void addLabels(HoleSection& out) {
    std::vector<HoleLabel> labels;
    for (const HoleTracePiece& p : out.pieces) {
        auto it = std::lower_bound(labels.begin(), labels.end(), p.hole,
                                   [](const HoleLabel& l, std::uint32_t h) { return l.hole < h; });
        if (it != labels.end() && it->hole == p.hole) {
            if (p.from < it->depth) *it = {p.hole, p.from, p.a, p.from == 0.0};
        } else {
            labels.insert(it, {p.hole, p.from, p.a, p.from == 0.0});
        }
    }
    out.labels = std::move(labels);
}

}  // namespace

HoleSection holesOnPlane(const HoleIndex& index, const SectionFrame& frame, double window) {
    HoleSection out;
    const glm::dvec3 n = frame.normal;
    const double d = -glm::dot(n, frame.originWorld());
    std::vector<std::uint32_t> near;
    index.segmentsNearPlane(n, d, window, near);
    for (std::uint32_t i : near) {
        const HoleSegment& s = index.segments()[i];
        // Distances and plane coordinates from local points (world - model origin), as the
        // section engine takes them.
        const glm::dvec3 la = s.a - frame.modelOrigin, lb = s.b - frame.modelOrigin;
        const Linear offset{glm::dot(n, la - frame.originLocal), glm::dot(n, lb - frame.originLocal)};
        double t0 = 0.0, t1 = 1.0;
        if (!clipRange(offset, -window, window, t0, t1)) continue;
        addChord(out, s, offset, t0, t1, 0, [&](double t) { return frame.toPlane(la + t * (lb - la)); });
    }
    addLabels(out);
    return out;
}

HoleSection holesOnLine(const HoleIndex& index, const SectionLine& line, double window) {
    HoleSection out;
    std::vector<std::uint32_t> near;
    for (std::size_t k = 0; k + 1 < line.points.size(); ++k) {
        const glm::dvec2 p0 = line.points[k];
        const glm::dvec2 t = glm::normalize(line.points[k + 1] - p0);
        const glm::dvec2 left(-t.y, t.x);  // the kept side of a leg is its left (section/cut/polyline.hpp)
        const glm::dvec3 n(left, 0.0);
        index.segmentsNearPlane(n, -glm::dot(left, p0), window, near);
        for (std::uint32_t i : near) {
            const HoleSegment& s = index.segments()[i];
            const glm::dvec2 ra = glm::dvec2(s.a) - p0, rb = glm::dvec2(s.b) - p0;
            const Linear offset{glm::dot(left, ra), glm::dot(left, rb)};
            const Linear chain{line.chainage[k] + glm::dot(t, ra), line.chainage[k] + glm::dot(t, rb)};
            double t0 = 0.0, t1 = 1.0;
            if (!clipRange(offset, -window, window, t0, t1)) continue;
            if (!clipRange(chain, line.chainage[k], line.chainage[k + 1], t0, t1)) continue;
            addChord(out, s, offset, t0, t1, std::uint32_t(k),
                     [&](double u) { return glm::dvec2(chain.at(u), s.a.z + u * (s.b.z - s.a.z)); });
        }
    }
    addLabels(out);
    return out;
}

}  // namespace geoslice
