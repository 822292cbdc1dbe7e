// The segment BVH of a drillhole database (model/drillholes/hole_index.hpp): median splits on
// the longest axis of the centroids' box, leaves of up to kLeafSize chords.
#include "model/drillholes/hole_index.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace geoslice {
namespace {

constexpr std::uint32_t kLeafSize = 4;

double dogleg(const glm::dvec3& t1, const glm::dvec3& t2) {
    return 2.0 * std::atan2(glm::length(t1 - t2), glm::length(t1 + t2));
}

}  // namespace

HoleIndex::HoleIndex(const DrillholeDatabase& db) {
    endDepth_.assign(db.holes.size(), 0.0);
    for (std::size_t h = 0; h < db.holes.size(); ++h) {
        const Drillhole& hole = db.holes[h];
        double end = hole.path.depth.empty() ? 0.0 : hole.path.depth.back();
        if (std::isfinite(hole.totalDepth)) end = std::max(end, hole.totalDepth);
        endDepth_[h] = end;
    }
    for (const IntervalTable& t : db.intervals)
        for (std::size_t i = 0; i < t.size(); ++i) endDepth_[t.hole[i]] = std::max(endDepth_[t.hole[i]], t.to[i]);

    for (std::size_t h = 0; h < db.holes.size(); ++h) {
        const HolePath& p = db.holes[h].path;
        if (p.depth.empty()) continue;
        // Breakpoints: the nodes (each arc split for the chord bound), then the end of the hole.
        std::vector<double> cuts{0.0};
        for (std::size_t i = 0; i + 1 < p.depth.size(); ++i) {
            const double len = p.depth[i + 1] - p.depth[i];
            if (len <= 0.0) continue;
            const double beta = dogleg(p.direction[i], p.direction[i + 1]);
            const int k = std::max(1, int(std::ceil(std::sqrt(len * beta / (8.0 * kMaxChordError)))));
            for (int j = 1; j <= k; ++j) cuts.push_back(p.depth[i] + len * j / k);
        }
        if (endDepth_[h] > cuts.back()) cuts.push_back(endDepth_[h]);
        cuts.erase(std::remove_if(cuts.begin(), cuts.end(), [&](double d) { return d > endDepth_[h]; }), cuts.end());
        if (cuts.back() < endDepth_[h]) cuts.push_back(endDepth_[h]);
        glm::dvec3 prev = p.at(cuts[0]);
        for (std::size_t j = 1; j < cuts.size(); ++j) {
            if (cuts[j] <= cuts[j - 1]) continue;
            const glm::dvec3 next = p.at(cuts[j]);
            segments_.push_back({std::uint32_t(h), cuts[j - 1], cuts[j], prev, next});
            prev = next;
        }
    }
    order_.resize(segments_.size());
    for (std::uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
    if (!segments_.empty()) {
        nodes_.reserve(2 * segments_.size() / kLeafSize + 2);
        buildNode(0, std::uint32_t(order_.size()));
    }
}

std::uint32_t HoleIndex::buildNode(std::uint32_t begin, std::uint32_t end) {
    const std::uint32_t self = std::uint32_t(nodes_.size());
    nodes_.push_back({});
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    glm::dvec3 clo = lo, chi = hi;
    for (std::uint32_t i = begin; i < end; ++i) {
        const HoleSegment& s = segments_[order_[i]];
        lo = glm::min(lo, glm::min(s.a, s.b));
        hi = glm::max(hi, glm::max(s.a, s.b));
        const glm::dvec3 c = 0.5 * (s.a + s.b);
        clo = glm::min(clo, c);
        chi = glm::max(chi, c);
    }
    nodes_[self].lo = lo;
    nodes_[self].hi = hi;
    if (end - begin <= kLeafSize) {
        nodes_[self].first = begin;
        nodes_[self].count = end - begin;
        return self;
    }
    const glm::dvec3 ext = chi - clo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(
        order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](std::uint32_t x, std::uint32_t y) {
            return segments_[x].a[axis] + segments_[x].b[axis] < segments_[y].a[axis] + segments_[y].b[axis];
        });
    buildNode(begin, mid);
    const std::uint32_t right = buildNode(mid, end);
    nodes_[self].first = right;
    nodes_[self].count = 0;
    return self;
}

template <typename Visit>
void HoleIndex::visitNearPlane(const glm::dvec3& n, double d, double window, const Visit& visit) const {
    if (nodes_.empty() || !(window >= 0.0)) return;
    const glm::dvec3 an = glm::abs(n);
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const std::uint32_t at = stack[--top];
        const Node& node = nodes_[at];
        const glm::dvec3 c = 0.5 * (node.lo + node.hi), h = 0.5 * (node.hi - node.lo);
        if (std::abs(glm::dot(n, c) + d) > window + glm::dot(an, h)) continue;
        if (node.count > 0) {
            for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
                const HoleSegment& s = segments_[order_[i]];
                const double sa = glm::dot(n, s.a) + d, sb = glm::dot(n, s.b) + d;
                if (std::min(sa, sb) <= window && std::max(sa, sb) >= -window) visit(order_[i]);
            }
        } else {
            // Depth is bounded by the median split: log2(segments) + 1 < 64.
            stack[top++] = node.first;
            stack[top++] = at + 1;
        }
    }
}

void HoleIndex::segmentsNearPlane(const glm::dvec3& n, double d, double window, std::vector<std::uint32_t>& out) const {
    out.clear();
    visitNearPlane(n, d, window, [&out](std::uint32_t i) { out.push_back(i); });
    std::sort(out.begin(), out.end());
}

std::vector<std::uint32_t> HoleIndex::holesNearPlane(const glm::dvec3& normal, double d, double window) const {
    // A mark per hole instead of sorting every segment found.
    std::vector<unsigned char> seen(endDepth_.size(), 0);
    visitNearPlane(normal, d, window, [&](std::uint32_t i) { seen[segments_[i].hole] = 1; });
    std::vector<std::uint32_t> holes;
    for (std::uint32_t h = 0; h < seen.size(); ++h)
        if (seen[h]) holes.push_back(h);
    return holes;
}

}  // namespace geoslice
