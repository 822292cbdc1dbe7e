#include "section/cut/plane_cut.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "section/cut/partner_thread.hpp"

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

// Appends the segment of triangle t of part p, crossed by the plane (corners' local
// positions q, distances s and welded ids w, in the triangle's vertex order).
inline __attribute__((always_inline)) void emitSegment(const PartArrays& part, std::size_t p, std::size_t t,
                                                       const glm::dvec3* const q[3], const double s[3],
                                                       const std::uint32_t w[3], PlaneCut& out) {
    if (part.exitsOnly) {
        ExitSegment e;
        for (int k = 0; k < 3; ++k) {
            const int k1 = k == 2 ? 0 : k + 1;
            const bool in = s[k] >= 0.0, in1 = s[k1] >= 0.0;
            if (in == in1) continue;
            if (!in) {
                e.keyA = edgeKey(w[k], w[k1]);
            } else {  // kept -> removed: the only point computed
                e.b = out.frame.toPlane(edgeCrossing(*q[k], s[k], *q[k1], s[k1]));
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
        const glm::dvec2 uv = out.frame.toPlane(edgeCrossing(*q[k], s[k], *q[k1], s[k1]));
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

// Cuts triangle t of part p; appends at most one segment.
inline void cutOne(const PartArrays& part, const glm::dvec3& origin, std::size_t p, std::size_t t, PlaneCut& out) {
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
    const glm::dvec3* const corners[3] = {&q[0], &q[1], &q[2]};
    emitSegment(part, p, t, corners, s, w, out);
}

// Cuts one leaf from its table (section/index/leaf_tables.hpp): each distinct vertex is loaded
// and measured once, each triangle tested through its corner bytes. The same segments in
// the same order as cutOne over the leaf's triangles: a welded vertex has the position of
// the vertices welded to it, and degenerate triangles are not in the table.
inline __attribute__((always_inline)) void cutLeaf(const LeafTable& table, const PartArrays* arrays,
                                                   const glm::dvec3& origin, PlaneCut& out) {
    glm::dvec3 q[LeafTables::kMaxVertices];
    double s[LeafTables::kMaxVertices];
    std::uint32_t v0 = 0, c = 0;  // the run's first vertex and corner in the leaf
    for (std::uint32_t r = 0; r < table.runs; ++r) {
        const LeafTable::Run run = table.run(r);
        const PartArrays& part = arrays[run.part];
        std::uint32_t positive = 0;
        for (std::uint32_t k = v0; k < v0 + run.vertices; ++k) {
            q[k] = part.positions[table.vertices[k]] - origin;
            s[k] = out.plane.distance(q[k]);
            positive += s[k] >= 0.0;
        }
        v0 += run.vertices;
        if (positive == 0 || positive == run.vertices) {  // the run's triangles all on one side
            c += 3 * run.triangles;
            continue;
        }
        for (std::uint32_t t = 0; t < run.triangles; ++t) {
            std::uint32_t k[3];
            for (int j = 0; j < 3; ++j, ++c) k[j] = table.corner(c);
            const double d[3] = {s[k[0]], s[k[1]], s[k[2]]};
            const int in = int(d[0] >= 0.0) + int(d[1] >= 0.0) + int(d[2] >= 0.0);
            if (in == 0 || in == 3) continue;
            if (!std::isfinite(d[0] + d[1] + d[2])) continue;  // left out of the BVH too
            const glm::dvec3* const corners[3] = {&q[k[0]], &q[k[1]], &q[k[2]]};
            const std::uint32_t w[3] = {table.vertices[k[0]], table.vertices[k[1]], table.vertices[k[2]]};
            emitSegment(part, run.part, run.first + t, corners, d, w, out);
        }
    }
}

// A software prefetch the optimiser keeps: GCC 12 deletes a loop whose only effect is
// __builtin_prefetch (it has no effect on the program's behaviour), which is what a loop
// over a leaf's vertices is.
inline void prefetch(const void* p) {
#if defined(__x86_64__) || defined(__i386__)
    asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#else
    asm volatile("" : : "r"(p));  // keeps the loop; the hint itself is the compiler's
    __builtin_prefetch(p);
#endif
}

// Units of the traversal (section/index/bvh.hpp queryPlaneUnits): enough for two threads to
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
    BvhMeshCursor cursor{&bvh};
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
    // The cut is bound by memory latency along a chain of three dependent loads per leaf:
    // its table's offset -> the table -> the table's vertices. Each link is prefetched in its
    // own stage, kGap leaves apart (offset 3 kGap leaves ahead, the table's first
    // kTableLines cache lines 2 kGap, its vertices and the rest of it kGap), so every load a
    // stage needs was requested kGap leaves earlier. L4 (leaves of <= 64, tables of about 300
    // bytes): prefetching 2 lines of a table instead of all of it cost 0.1 ms a plane; gaps
    // of 2 and 3 measured the same.
    constexpr std::size_t kGap = 2;  // leaves between stages
    constexpr std::size_t kTableLines = 4;
    const LeafTables& tables = index.leafTables;
    auto tableOf = [&](std::size_t l) { return tables.table(leaves[l]); };
    auto prefetchVertices = [&](std::size_t l) {
        const std::uint32_t* words = tableOf(l);
        const LeafTable table(words);
        // The rest of the table (its corner bytes), beyond the lines the stage before took.
        for (std::size_t w = 16 * kTableLines; w < table.words(); w += 16) prefetch(words + w);
        const std::uint32_t* vertex = table.vertices;
        for (std::uint32_t r = 0; r < table.runs; ++r) {
            const LeafTable::Run run = table.run(r);
            const glm::dvec3* positions = arrays[run.part].positions;
            for (std::uint32_t k = 0; k < run.vertices; ++k, ++vertex) {
                // Both ends: 3 vertices in 8 straddle two cache lines.
                prefetch(&positions[*vertex].x);
                prefetch(&positions[*vertex].z);
            }
        }
    };
    // Cuts leaves [lo, hi) into dst; the prefetch stages run on past hi (into a range the
    // other thread may be cutting: reads only), so a range starts with its pipeline full.
    auto cutRange = [&](std::size_t lo, std::size_t hi, PlaneCut& dst) {
        const std::size_t end = leaves.size();
        for (std::size_t l = lo; l < hi; ++l) {
            if (l + 3 * kGap < end) __builtin_prefetch(&tables.tableOf[leaves[l + 3 * kGap]]);
            if (l + 2 * kGap < end) {
                const std::uint32_t* table = tableOf(l + 2 * kGap);
                for (std::size_t line = 0; line < kTableLines; ++line) prefetch(table + 16 * line);
            }
            if (l + kGap < end) prefetchVertices(l + kGap);
            cutLeaf(LeafTable(tableOf(l)), arrays.data(), index.origin, dst);
        }
    };
    if (two) {
        // Partner (section/cut/partner_thread.hpp): units of the traversal, then chunks of the
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
