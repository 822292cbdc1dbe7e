#include "section/plane_cut.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "section/partner_thread.hpp"

namespace geoslice {
namespace {

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}

// The arrays of one part, read straight by the cut (no pointer chase per triangle).
struct PartArrays {
    const glm::dvec3* positions = nullptr;
    const std::uint32_t* indices = nullptr;
    const std::uint32_t* canon = nullptr;  // null: identity weld
    std::uint32_t first = 0;               // global id of the part's triangle 0
    bool exitsOnly = false;                // a closed body cut with PlaneCut::exitsOnly
};

std::vector<PartArrays> partArrays(const SectionIndex& index, const PlaneCut& out) {
    std::vector<PartArrays> a(index.parts.size());
    for (std::size_t p = 0; p < a.size(); ++p) {
        const SectionPart& part = index.parts[p];
        const Mesh& mesh = part.part->mesh;
        a[p].positions = mesh.positions.data();
        a[p].indices = mesh.indices.data();
        a[p].canon = part.canon.empty() ? nullptr : part.canon.data();
        a[p].first = index.bvh.meshFirst[p];
        a[p].exitsOnly = out.exitsOnly && part.kind == PartKind::Body && part.closed;
    }
    return a;
}

// Global triangle id -> part, remembering the last two parts' id ranges: a leaf lists its
// ids in ascending order, so its triangles come in runs per part, and a leaf on the
// boundary of two bodies holds both bodies' copies of the shared faces. Two ranges turn the
// binary search of Bvh::meshOf from once per run (about 14k times per L4 section) into
// once per new pair of parts (about 1k).
struct PartCursor {
    const Bvh* bvh = nullptr;
    std::uint32_t part = 0, lo = 0, hi = 0;     // empty ranges until the first lookups
    std::uint32_t part2 = 0, lo2 = 0, hi2 = 0;  // the part before
    std::uint32_t operator()(std::uint32_t id) {
        if (id - lo < hi - lo) return part;  // unsigned: lo <= id < hi
        std::swap(part, part2);
        std::swap(lo, lo2);
        std::swap(hi, hi2);
        if (id - lo < hi - lo) return part;
        part = bvh->meshOf(id);
        lo = bvh->meshFirst[part];
        hi = bvh->meshFirst[part + 1];
        return part;
    }
};

// Cuts triangle t of part p; appends at most one segment.
inline __attribute__((always_inline)) void cutOne(const PartArrays& part, const glm::dvec3& origin, std::size_t p,
                                                  std::size_t t, PlaneCut& out) {
    const std::uint32_t* tri = part.indices + 3 * t;
    glm::dvec3 q[3];
    double s[3];
    int positive = 0;
    for (int k = 0; k < 3; ++k) {
        q[k] = part.positions[tri[k]] - origin;
        s[k] = out.plane.distance(q[k]);
        positive += s[k] >= 0.0;
    }
    if (positive == 0 || positive == 3) return;
    if (!std::isfinite(s[0] + s[1] + s[2])) return;  // left out of the BVH too
    std::uint32_t w[3] = {tri[0], tri[1], tri[2]};
    if (part.canon)
        for (auto& v : w) v = part.canon[v];
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) return;  // degenerate: no edges of its own
    if (part.exitsOnly) {
        ExitSegment e;
        for (int k = 0; k < 3; ++k) {
            const int k1 = k == 2 ? 0 : k + 1;
            const bool in = s[k] >= 0.0, in1 = s[k1] >= 0.0;
            if (in == in1) continue;
            if (!in) {
                e.keyA = edgeKey(w[k], w[k1]);
            } else {  // kept -> removed: the only point computed
                e.b = out.frame.toPlane(edgeCrossing(q[k], s[k], q[k1], s[k1]));
                e.keyB = edgeKey(w[k], w[k1]);
            }
        }
        e.triangle = part.first + static_cast<std::uint32_t>(t);
        out.exits[p].push_back(e);
        ++out.segments;
        return;
    }
    CutSegment seg;
    for (int k = 0; k < 3; ++k) {
        const int k1 = k == 2 ? 0 : k + 1;
        const bool in = s[k] >= 0.0, in1 = s[k1] >= 0.0;
        if (in == in1) continue;
        const glm::dvec2 uv = out.frame.toPlane(edgeCrossing(q[k], s[k], q[k1], s[k1]));
        if (!in) {  // removed -> kept: the segment starts here
            seg.a = uv;
            seg.keyA = edgeKey(w[k], w[k1]);
        } else {
            seg.b = uv;
            seg.keyB = edgeKey(w[k], w[k1]);
        }
    }
    out.parts[p].push_back(seg);
    ++out.segments;
}

// Units of the traversal (section/bvh.hpp queryPlaneUnits): enough for two threads to
// balance by taking them one at a time.
constexpr std::size_t kTraversalUnits = 32;
constexpr std::size_t kTwoThreadMinTriangles = 100000;

}  // namespace

void beginCut(const SectionIndex& index, const Plane& plane, PlaneCut& out, bool exitsOnly) {
    out.frame = makeSectionFrame(plane, index.origin);
    out.plane = toLocal(plane, index.origin);
    out.parts.resize(index.parts.size());
    for (auto& v : out.parts) v.clear();
    out.exits.resize(index.parts.size());
    for (auto& v : out.exits) v.clear();
    out.exitsOnly = exitsOnly;
    out.segments = 0;
}

void cutTriangles(const SectionIndex& index, const std::uint32_t* triangles, std::size_t count, PlaneCut& out) {
    const Bvh& bvh = index.bvh;
    const std::vector<PartArrays> arrays = partArrays(index, out);
    PartCursor cursor{&bvh};
    for (std::size_t i = 0; i < count; ++i) {
        const std::uint32_t id = triangles[i];
        const std::uint32_t p = cursor(id);
        cutOne(arrays[p], index.origin, p, id - bvh.meshFirst[p], out);
    }
}

void cutWithBvh(const SectionIndex& index, const PlaneRect* rect, PlaneCut& out, unsigned threads, CutStats* stats) {
    const auto t0 = std::chrono::steady_clock::now();
    const Bvh& bvh = index.bvh;
    if (rect) out.exitsOnly = false;  // rings cut off by the rectangle have first entries of their own
    // The traversal runs in units (subtrees near the root) so that two threads can share it;
    // the leaves are taken unit by unit in unit order whatever the thread count, so the
    // output never depends on it.
    std::vector<std::uint32_t> units;
    BvhQueryStats qs;
    queryPlaneUnits(bvh, out.plane, rect, kTraversalUnits, units, &qs);
    std::vector<std::vector<std::uint32_t>> unitLeaves(threads >= 2 ? units.size() : 0);
    std::atomic<std::size_t> nextUnit{0}, unitsDone{0};
    auto traverseUnits = [&](BvhQueryStats& st) {
        for (std::size_t u = nextUnit++; u < units.size(); u = nextUnit++) {
            queryPlaneLeavesUnder(bvh, units[u], out.plane, rect, unitLeaves[u], &st);
            unitsDone.fetch_add(1, std::memory_order_release);
            unitsDone.notify_one();
        }
    };
    // A second thread costs a thread start (tens of microseconds): small models cut on one.
    const bool two = threads >= 2 && units.size() >= 2 && bvh.triangles.size() >= kTwoThreadMinTriangles;
    std::vector<std::uint32_t> leaves;
    auto gatherLeaves = [&] {
        std::size_t n = 0;
        for (const auto& l : unitLeaves) n += l.size();
        leaves.reserve(n);
        for (const auto& l : unitLeaves) leaves.insert(leaves.end(), l.begin(), l.end());
    };
    std::chrono::steady_clock::time_point t1;
    const std::vector<PartArrays> arrays = partArrays(index, out);
    // The cut is bound by memory latency along a chain of four dependent loads per leaf:
    // node -> its triangle ids -> their vertex indices -> the vertices. Each link is
    // prefetched in its own stage, kGap leaves apart (node 8 leaves ahead, ids 6, indices
    // 4, vertices 2), so every load a stage needs was requested kGap leaves earlier (gaps
    // of 3 and 4 measured the same on L4).
    constexpr std::size_t kGap = 2;  // leaves between stages
    auto prefetchIndices = [&](std::size_t l, PartCursor& cursor) {
        const BvhNode& nd = bvh.nodes[leaves[l]];
        for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
            const std::uint32_t id = bvh.triangles[i];
            const std::uint32_t p = cursor(id);
            __builtin_prefetch(arrays[p].indices + 3 * std::size_t(id - bvh.meshFirst[p]));
        }
    };
    auto prefetchVertices = [&](std::size_t l, PartCursor& cursor) {
        const BvhNode& nd = bvh.nodes[leaves[l]];
        for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
            const std::uint32_t id = bvh.triangles[i];
            const std::uint32_t p = cursor(id);
            const PartArrays& a = arrays[p];
            const std::uint32_t* tri = a.indices + 3 * std::size_t(id - bvh.meshFirst[p]);
            for (int k = 0; k < 3; ++k) __builtin_prefetch(&a.positions[tri[k]]);
        }
    };
    // Cuts leaves [lo, hi) into dst; the prefetch stages run on past hi (into a range the
    // other thread may be cutting: reads only), so a range starts with its pipeline full.
    auto cutRange = [&](std::size_t lo, std::size_t hi, PlaneCut& dst) {
        PartCursor cut{&bvh}, ahead4{&bvh}, ahead2{&bvh};
        const std::size_t end = leaves.size();
        for (std::size_t l = lo; l < hi; ++l) {
            if (l + 4 * kGap < end) __builtin_prefetch(&bvh.nodes[leaves[l + 4 * kGap]]);
            if (l + 3 * kGap < end) {
                const BvhNode& nd = bvh.nodes[leaves[l + 3 * kGap]];
                __builtin_prefetch(&bvh.triangles[nd.first]);
                __builtin_prefetch(&bvh.triangles[nd.first + nd.count - 1]);
            }
            if (l + 2 * kGap < end) prefetchIndices(l + 2 * kGap, ahead4);
            if (l + kGap < end) prefetchVertices(l + kGap, ahead2);
            const BvhNode& nd = bvh.nodes[leaves[l]];
            for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
                const std::uint32_t id = bvh.triangles[i];
                const std::uint32_t p = cut(id);
                cutOne(arrays[p], index.origin, p, id - bvh.meshFirst[p], dst);
            }
        }
    };
    if (two) {
        // Partner (section/partner_thread.hpp): units of the traversal, then chunks of the
        // cut, each taken from a common counter, so a partner that starts late (the cores
        // are busy) takes less and one that never starts is withdrawn: the caller never
        // waits for it to take a share. Leaves go in kChunks ranges of equal triangle
        // counts; the caller takes them from the front, straight into `out`, the partner
        // from the back into buffers of its own, appended after the caller's in chunk order.
        // Hand-offs through atomic wait/notify (futex), not spinning.
        constexpr std::size_t kChunks = 16;
        std::size_t chunkStart[kChunks + 1] = {};
        std::atomic<int> chunksKnown{0};
        std::atomic<std::size_t> claimed{0};
        std::size_t partnerChunks = 0;  // the partner's, the last ones (written by it alone)
        BvhQueryStats workerStats;
        // The partner's chunk buffers, kept per calling thread between calls (as computeSection
        // keeps the caller's), so the partner writes into memory already mapped. (A reference:
        // a lambda names a thread_local directly, and the partner's would be its own.)
        thread_local std::vector<PlaneCut> kept(kChunks);
        std::vector<PlaneCut>& chunkCut = kept;
        auto work = [&] {
            traverseUnits(workerStats);
            chunksKnown.wait(0, std::memory_order_acquire);
            while (claimed.fetch_add(1) < kChunks) {
                const std::size_t c = kChunks - 1 - partnerChunks++;
                PlaneCut& dst = chunkCut[c];
                dst.frame = out.frame;
                dst.plane = out.plane;
                dst.parts.resize(out.parts.size());
                for (auto& v : dst.parts) v.clear();
                dst.exits.resize(out.exits.size());
                for (auto& v : dst.exits) v.clear();
                dst.segments = 0;
                cutRange(chunkStart[c], chunkStart[c + 1], dst);
            }
        };
        PartnerThread::Job worker = PartnerThread::forThisThread().run(work);
        traverseUnits(qs);
        // Units the partner took and has not finished yet (none when it has not started).
        for (std::size_t d = unitsDone.load(std::memory_order_acquire); d < units.size();
             d = unitsDone.load(std::memory_order_acquire))
            unitsDone.wait(d, std::memory_order_acquire);
        gatherLeaves();
        std::size_t total = 0;
        for (std::uint32_t l : leaves) total += bvh.nodes[l].count;
        qs.trianglesTested = total;
        {
            std::size_t acc = 0, l = 0;
            for (std::size_t c = 1; c < kChunks; ++c) {
                while (l < leaves.size() && acc * kChunks < total * c) acc += bvh.nodes[leaves[l++]].count;
                chunkStart[c] = l;
            }
            chunkStart[kChunks] = leaves.size();
        }
        t1 = std::chrono::steady_clock::now();
        chunksKnown.store(1, std::memory_order_release);
        chunksKnown.notify_one();
        std::size_t mine = 0;
        while (claimed.fetch_add(1) < kChunks) {
            cutRange(chunkStart[mine], chunkStart[mine + 1], out);
            ++mine;
        }
        if (worker.wait()) {
            qs.nodesVisited += workerStats.nodesVisited;
            for (std::size_t c = mine; c < kChunks; ++c) {
                for (std::size_t p = 0; p < out.parts.size(); ++p) {
                    out.parts[p].insert(out.parts[p].end(), chunkCut[c].parts[p].begin(), chunkCut[c].parts[p].end());
                    out.exits[p].insert(out.exits[p].end(), chunkCut[c].exits[p].begin(), chunkCut[c].exits[p].end());
                }
                out.segments += chunkCut[c].segments;
            }
        }
    } else {
        // Unit by unit straight into the leaf list (the same order as gathering per unit).
        for (std::uint32_t u : units) queryPlaneLeavesUnder(bvh, u, out.plane, rect, leaves, &qs);
        t1 = std::chrono::steady_clock::now();
        cutRange(0, leaves.size(), out);
    }
    if (stats) {
        stats->nodesVisited = qs.nodesVisited;
        stats->leaves = leaves.size();
        stats->trianglesTested = qs.trianglesTested;
        stats->queryMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
        stats->cutMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
    }
}

void cutAllTriangles(const SectionIndex& index, PlaneCut& out) {
    const std::vector<PartArrays> arrays = partArrays(index, out);
    for (std::size_t p = 0; p < index.parts.size(); ++p) {
        const std::size_t n = index.parts[p].part->mesh.triangleCount();
        for (std::size_t t = 0; t < n; ++t) cutOne(arrays[p], index.origin, p, t, out);
    }
}

}  // namespace geoslice
