#include "section/cut/contours.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>

#include "model/clock.hpp"
#include "section/cut/partner_thread.hpp"

namespace geoslice {
namespace {

constexpr std::uint64_t kNoKey = ~0ull;  // edge keys have lo < hi, so never all ones
constexpr std::uint32_t kNone = 0xFFFFFFFFu;
// Below this many segments a second thread costs more than it saves.
constexpr std::size_t kTwoThreadMinSegments = 4096;

// Edge key -> the (up to) two segment ends on that edge; end = segment * 2 + (0: a, 1: b).
struct EndTable {
    struct Entry {
        std::uint64_t key;
        std::uint32_t e0, e1;
    };
    std::vector<Entry> slots;
    std::size_t mask = 0;
    std::size_t overfull = 0;  // ends beyond two on one edge (non-manifold)

    void reset(std::size_t ends) {
        std::size_t cap = 16;
        while (cap < 2 * ends) cap <<= 1;
        slots.assign(cap, Entry{kNoKey, kNone, kNone});
        mask = cap - 1;
        overfull = 0;
    }
    static std::size_t hash(std::uint64_t k) {
        k ^= k >> 33;
        k *= 0xff51afd7ed558ccdull;
        k ^= k >> 33;
        return static_cast<std::size_t>(k);
    }
    Entry& find(std::uint64_t key) {
        std::size_t h = hash(key) & mask;
        while (slots[h].key != key && slots[h].key != kNoKey) h = (h + 1) & mask;
        return slots[h];
    }
    void insert(std::uint64_t key, std::uint32_t end) {
        Entry& e = find(key);
        e.key = key;
        if (e.e0 == kNone)
            e.e0 = end;
        else if (e.e1 == kNone)
            e.e1 = end;
        else
            ++overfull;
    }
    // The other end on the same edge as `end`, or kNone.
    std::uint32_t partner(std::uint64_t key, std::uint32_t end) {
        const Entry& e = find(key);
        if (e.e0 == end) return e.e1;
        if (e.e1 == end) return e.e0;
        return kNone;
    }
};

// Closed, consistently oriented bodies: every crossed edge is the exit (b) of one segment
// and the entry (a) of one other, so a map from entry key to segment is the whole join.
struct EntryTable {
    std::vector<std::uint64_t> keys;
    std::vector<std::uint32_t> segs;
    std::size_t mask = 0;

    void reset(std::size_t n) {
        std::size_t cap = 16;
        while (cap < 2 * n) cap <<= 1;
        keys.assign(cap, kNoKey);
        segs.resize(cap);
        mask = cap - 1;
    }
    // False when the key is already there (not a 2-manifold crossing: use EndTable).
    bool insert(std::uint64_t key, std::uint32_t seg) {
        std::size_t h = EndTable::hash(key) & mask;
        while (keys[h] != kNoKey) {
            if (keys[h] == key) return false;
            h = (h + 1) & mask;
        }
        keys[h] = key;
        segs[h] = seg;
        return true;
    }
    std::uint32_t find(std::uint64_t key) const {
        std::size_t h = EndTable::hash(key) & mask;
        while (keys[h] != key) {
            if (keys[h] == kNoKey) return kNone;
            h = (h + 1) & mask;
        }
        return segs[h];
    }
};

struct Chain {
    std::vector<glm::dvec2> points;
    bool closed = false;
};

void pushPoint(std::vector<glm::dvec2>& pts, const glm::dvec2& p) {
    if (pts.empty() || pts.back() != p) pts.push_back(p);
}

// Walks from segment `start`, entering it at its a end (forward) or b end.
Chain walk(const std::vector<CutSegment>& segs, EndTable& table, std::vector<char>& visited, std::uint32_t start,
           bool forward) {
    Chain c;
    std::uint32_t cur = start;
    for (;;) {
        visited[cur] = 1;
        const CutSegment& s = segs[cur];
        pushPoint(c.points, forward ? s.a : s.b);
        const std::uint32_t exitEnd = 2 * cur + (forward ? 1u : 0u);
        const std::uint32_t other = table.partner(forward ? s.keyB : s.keyA, exitEnd);
        if (other == kNone) {
            pushPoint(c.points, forward ? s.b : s.a);
            return c;
        }
        const std::uint32_t next = other >> 1;
        if (next == start) {
            c.closed = true;
            break;
        }
        if (visited[next]) {  // non-manifold tangle: stop here, open
            pushPoint(c.points, forward ? s.b : s.a);
            return c;
        }
        forward = (other & 1u) == 0;
        cur = next;
    }
    if (c.points.size() > 1 && c.points.back() == c.points.front()) c.points.pop_back();
    return c;
}

// walk() over an EntryTable, forward (a -> b). Returns false, leaving `c` unfinished, when
// the part's crossings are not a perfect matching of exits to entries (an exit with no
// entry, or an entry reached twice): the caller then chains the part with an EndTable.
// Otherwise the chain is walk()'s: each edge holds exactly one a end and one b end.
// Over exit segments (PlaneCut::exitsOnly) a segment's entry point is the exit point of the
// one before it, so the chain's points are the exits, the last one first, with the same
// repeats dropped: the same ring, point for point.
template <class Segment>
bool walkEntries(const std::vector<Segment>& segs, const EntryTable& table, std::vector<char>& state,
                 std::uint32_t start, Chain& c) {
    constexpr bool exits = std::is_same_v<Segment, ExitSegment>;
    constexpr char kVisited = 1, kEntered = 2;
    c.points.clear();
    if constexpr (exits) c.points.push_back(glm::dvec2(0.0));  // the first entry: the last exit, known at the end
    c.closed = false;
    std::uint32_t cur = start;
    for (;;) {
        state[cur] |= kVisited;
        const Segment& s = segs[cur];
        if constexpr (!exits) pushPoint(c.points, s.a);
        // The segment after (or before) this one in the cut's order is often the next on the
        // ring: its triangle is a neighbour in the same leaf. Entry keys are unique once the
        // table holds them all, so a match there is the table's answer without a probe.
        const std::uint32_t next = cur + 1 < segs.size() && segs[cur + 1].keyA == s.keyB ? cur + 1
                                   : cur > 0 && segs[cur - 1].keyA == s.keyB             ? cur - 1
                                                                                         : table.find(s.keyB);
        if (next == kNone || (state[next] & kEntered)) return false;
        state[next] |= kEntered;
        if (next == start) {
            if constexpr (exits) c.points[0] = s.b;
            break;
        }
        if (state[next] & kVisited) return false;  // entered a chain walked before: not a matching
        if constexpr (exits) {
            if (c.points.size() == 1)
                c.points.push_back(s.b);  // not compared with the slot, which is not known yet
            else
                pushPoint(c.points, s.b);
        }
        cur = next;
    }
    // The repeat pushPoint would have dropped after the first entry.
    if constexpr (exits)
        if (c.points.size() > 1 && c.points[1] == c.points[0]) c.points.erase(c.points.begin() + 1);
    c.closed = true;
    if (c.points.size() > 1 && c.points.back() == c.points.front()) c.points.pop_back();
    return true;
}

struct RingInfo {
    Ring ring;
    double area = 0.0;  // signed
    glm::dvec2 lo{0.0}, hi{0.0};
    glm::dvec2 probe{0.0};  // a point of the ring used for containment tests
    int depth = 0;
};

RingInfo makeRingInfo(Ring ring) {
    RingInfo r;
    r.area = ringArea(ring);
    r.lo = glm::dvec2(std::numeric_limits<double>::infinity());
    r.hi = -r.lo;
    for (const auto& p : ring) {
        r.lo = glm::min(r.lo, p);
        r.hi = glm::max(r.hi, p);
    }
    // Midpoint of the longest edge: away from the vertices where loops may touch.
    double best = -1.0;
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const glm::dvec2 &a = ring[i], &b = ring[(i + 1) % ring.size()];
        const double l = glm::dot(b - a, b - a);
        if (l > best) {
            best = l;
            r.probe = 0.5 * (a + b);
        }
    }
    r.ring = std::move(ring);
    return r;
}

bool boxInside(const RingInfo& inner, const RingInfo& outer) {
    return inner.lo.x >= outer.lo.x && inner.lo.y >= outer.lo.y && inner.hi.x <= outer.hi.x && inner.hi.y <= outer.hi.y;
}

// Even-odd assembly of a region's rings into polygons; returns the area.
double assemble(std::vector<RingInfo>& rings, std::vector<SectionPolygon>& out) {
    const std::size_t n = rings.size();
    std::vector<std::vector<std::uint32_t>> containers(n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (i != j && boxInside(rings[i], rings[j]) && pointInRing(rings[i].probe, rings[j].ring))
                containers[i].push_back(static_cast<std::uint32_t>(j));
    for (std::size_t i = 0; i < n; ++i) rings[i].depth = static_cast<int>(containers[i].size());
    std::vector<std::int64_t> polygonOf(n, -1);
    double area = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (rings[i].depth % 2 != 0) continue;
        if (rings[i].area < 0.0) std::reverse(rings[i].ring.begin(), rings[i].ring.end());
        polygonOf[i] = static_cast<std::int64_t>(out.size());
        area += std::abs(rings[i].area);
        out.push_back(SectionPolygon{std::move(rings[i].ring), {}});
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (rings[i].depth % 2 == 0) continue;
        std::int64_t host = -1;
        for (std::uint32_t j : containers[i])
            if (rings[j].depth == rings[i].depth - 1) host = polygonOf[j];
        if (host < 0) continue;  // cannot happen for non-crossing loops
        if (rings[i].area > 0.0) std::reverse(rings[i].ring.begin(), rings[i].ring.end());
        area -= std::abs(rings[i].area);
        out[static_cast<std::size_t>(host)].holes.push_back(std::move(rings[i].ring));
    }
    return area;
}

}  // namespace

double ringArea(const Ring& ring) {
    if (ring.size() < 3) return 0.0;
    const glm::dvec2 o = ring[0];
    double a = 0.0;
    for (std::size_t i = 1; i + 1 < ring.size(); ++i) {
        const glm::dvec2 p = ring[i] - o, q = ring[i + 1] - o;
        a += p.x * q.y - p.y * q.x;
    }
    return 0.5 * a;
}

bool pointInRing(const glm::dvec2& p, const Ring& ring) {
    bool inside = false;
    const std::size_t n = ring.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        const glm::dvec2 &a = ring[i], &b = ring[j];
        if ((a.y > p.y) != (b.y > p.y)) {
            const double x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if (p.x < x) inside = !inside;
        }
    }
    return inside;
}

void assembleContours(const SectionIndex& index, const PlaneCut& cut, Section& out, unsigned threads) {
    out.frame = cut.frame;
    out.bodies.clear();
    out.traces.clear();
    // Chaining is per part and region assembly per body, each into its own slot, so two
    // threads may take parts (then bodies) in any order: the output is collected in part
    // order afterwards and never depends on the thread count.
    const std::size_t partCount = index.parts.size();
    std::vector<std::vector<Ring>> loops(index.bodyCount);  // closed loops of every body
    std::vector<std::size_t> open(index.bodyCount, 0);
    std::vector<std::vector<SectionTrace>> partTraces(partCount);
    // A closed body's crossings pair each exit with one entry: one table of entries and one
    // probe per segment (an EndTable takes two inserts and a probe per segment). False when
    // they are not a perfect matching (loops[p] is then as before).
    auto chainByEntries = [&](std::size_t p, const auto& segs, std::vector<char>& visited) {
        thread_local EntryTable entries;
        entries.reset(segs.size());
        bool matching = true;
        for (std::uint32_t i = 0; i < segs.size() && matching; ++i) matching = entries.insert(segs[i].keyA, i);
        if (!matching) return false;
        visited.assign(segs.size(), 0);
        const std::size_t loopsBefore = loops[p].size();
        Chain c;
        for (std::uint32_t i = 0; i < segs.size() && matching; ++i) {
            if (visited[i]) continue;
            matching = walkEntries(segs, entries, visited, i, c);
            if (matching && c.points.size() >= 3) loops[p].push_back(std::move(c.points));
        }
        if (!matching) loops[p].resize(loopsBefore);
        return matching;
    };
    auto chainPart = [&](std::size_t p, EndTable& table, std::vector<char>& visited) {
        const std::vector<CutSegment>* partSegs = &cut.parts[p];
        if (p < cut.exits.size() && !cut.exits[p].empty()) {
            const std::vector<ExitSegment>& exits = cut.exits[p];
            if (chainByEntries(p, exits, visited)) return;
            // Not a matching (a body marked closed that is not): its triangles cut whole, then
            // chained as any other part's.
            thread_local PlaneCut whole;
            whole.frame = cut.frame;
            whole.plane = cut.plane;
            whole.exitsOnly = false;
            whole.parts.assign(index.parts.size(), {});
            whole.exits.assign(index.parts.size(), {});
            std::vector<std::uint32_t> ids(exits.size());
            for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = exits[i].triangle;
            cutTriangles(index, ids.data(), ids.size(), whole);
            partSegs = &whole.parts[p];
        } else if (index.parts[p].kind == PartKind::Body && index.parts[p].closed &&
                   chainByEntries(p, cut.parts[p], visited)) {
            return;
        }
        const std::vector<CutSegment>& segs = *partSegs;
        table.reset(2 * segs.size());
        for (std::uint32_t i = 0; i < segs.size(); ++i) {
            table.insert(segs[i].keyA, 2 * i);
            table.insert(segs[i].keyB, 2 * i + 1);
        }
        visited.assign(segs.size(), 0);
        const bool body = index.parts[p].kind == PartKind::Body;
        std::vector<SectionTrace>& traces = partTraces[p];
        if (!body) {
            // Open ends first, so each polyline is walked from one end.
            for (std::uint32_t i = 0; i < segs.size(); ++i) {
                if (visited[i]) continue;
                const bool freeA = table.partner(segs[i].keyA, 2 * i) == kNone;
                const bool freeB = table.partner(segs[i].keyB, 2 * i + 1) == kNone;
                if (!freeA && !freeB) continue;
                Chain c = walk(segs, table, visited, i, freeA);
                if (c.points.size() >= 2)
                    traces.push_back(
                        SectionTrace{static_cast<std::uint32_t>(p), index.parts[p].record, std::move(c.points), false});
            }
        }
        for (std::uint32_t i = 0; i < segs.size(); ++i) {
            if (visited[i]) continue;
            Chain c = walk(segs, table, visited, i, true);
            if (body) {
                if (!c.closed)
                    ++open[p];
                else if (c.points.size() >= 3)
                    loops[p].push_back(std::move(c.points));
            } else if (c.points.size() >= 2) {
                traces.push_back(
                    SectionTrace{static_cast<std::uint32_t>(p), index.parts[p].record, std::move(c.points), c.closed});
            }
        }
    };

    // Regions: a body's loops plus those of the bodies nested directly inside it.
    std::vector<std::vector<std::uint32_t>> children(index.bodyCount);
    std::vector<BodySection> bodies(index.bodyCount);
    std::vector<char> present(index.bodyCount, 0);
    auto assembleBody = [&](std::size_t b) {
        if (loops[b].empty() && open[b] == 0) return;
        std::vector<RingInfo> rings;
        for (const Ring& r : loops[b]) rings.push_back(makeRingInfo(r));
        if (!loops[b].empty())
            for (std::uint32_t c : children[b])
                for (const Ring& r : loops[c]) rings.push_back(makeRingInfo(r));
        BodySection& bs = bodies[b];
        bs.part = static_cast<std::uint32_t>(b);
        bs.record = index.parts[b].record;
        bs.openChains = open[b];
        bs.area = assemble(rings, bs.polygons);
        present[b] = 1;
    };

    // Work lists, largest first (balance for two threads).
    std::vector<std::uint32_t> partOrder;
    std::size_t segments = 0;
    auto partSize = [&](std::size_t p) {
        return cut.parts[p].size() + (p < cut.exits.size() ? cut.exits[p].size() : 0);
    };
    for (std::size_t p = 0; p < partCount; ++p)
        if (partSize(p) != 0) partOrder.push_back(static_cast<std::uint32_t>(p)), segments += partSize(p);
    std::stable_sort(partOrder.begin(), partOrder.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return partSize(a) > partSize(b); });
    std::atomic<std::size_t> nextPart{0}, nextBody{0};
    std::atomic<std::size_t> chained{0};  // parts chained
    auto linkChildren = [&] {
        for (std::size_t b = 0; b < index.bodyCount; ++b) {
            const int parent = index.parts[b].parent;
            if (parent >= 0 && static_cast<std::size_t>(parent) < index.bodyCount && !loops[b].empty())
                children[static_cast<std::size_t>(parent)].push_back(static_cast<std::uint32_t>(b));
        }
    };
    if (threads >= 2 && segments >= kTwoThreadMinSegments && partOrder.size() >= 2) {
        // The partner thread (section/cut/partner_thread.hpp) chains parts and then assembles
        // bodies, both taken from common counters; the caller chains, links the nesting once
        // every part is chained, then assembles alongside. The caller waits only for parts the
        // partner has taken (a partner that never started is withdrawn).
        std::atomic<int> linked{0};
        auto chainShare = [&] {
            EndTable table;
            std::vector<char> visited;
            for (std::size_t i = nextPart++; i < partOrder.size(); i = nextPart++) {
                chainPart(partOrder[i], table, visited);
                chained.fetch_add(1, std::memory_order_release);
                chained.notify_one();
            }
        };
        auto work = [&] {
            chainShare();
            linked.wait(0, std::memory_order_acquire);
            for (std::size_t b = nextBody++; b < index.bodyCount; b = nextBody++) assembleBody(b);
        };
        PartnerThread::Job worker = PartnerThread::forThisThread().run(work);
        chainShare();
        for (std::size_t c = chained.load(std::memory_order_acquire); c < partOrder.size();
             c = chained.load(std::memory_order_acquire))
            chained.wait(c, std::memory_order_acquire);
        linkChildren();
        linked.store(1, std::memory_order_release);
        linked.notify_one();
        for (std::size_t b = nextBody++; b < index.bodyCount; b = nextBody++) assembleBody(b);
        worker.wait();
    } else {
        thread_local EndTable table;  // kept between calls, as computeSection's segments
        thread_local std::vector<char> visited;
        for (std::uint32_t p : partOrder) chainPart(p, table, visited);
        linkChildren();
        for (std::size_t b = 0; b < index.bodyCount; ++b) assembleBody(b);
    }
    for (std::size_t b = 0; b < index.bodyCount; ++b)
        if (present[b]) out.bodies.push_back(std::move(bodies[b]));
    for (auto& t : partTraces)
        for (auto& tr : t) out.traces.push_back(std::move(tr));

    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const auto& b : out.bodies)
        for (const auto& poly : b.polygons)
            for (const auto& p : poly.outer) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
    for (const auto& t : out.traces)
        for (const auto& p : t.points) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    out.lo = lo.x <= hi.x ? lo : glm::dvec2(0.0);
    out.hi = lo.x <= hi.x ? hi : glm::dvec2(0.0);
}

Result<Plane> checkSectionPlane(const SectionIndex& index, const Plane& plane) {
    return checkPlaneMeetsBounds(plane, index.bounds, index.origin);
}

Result<Section> computeSection(const SectionIndex& index, const Plane& plane, const SectionOptions& options,
                               SectionTimings* timings) {
    auto checked = checkSectionPlane(index, plane);
    if (!checked) return checked.error();
    // The segments live only until assembly: each thread keeps its buffers between calls
    // (about 1 MiB at L4), so a section allocates and faults in none of them again.
    thread_local PlaneCut cut;
    beginCut(index, checked.value(), cut, options.exitsOnly);
    CutStats cs;
    // Decided once per section: both steps run with the same help (kThreadsWhenIdle: a partner
    // only while a core is idle).
    const unsigned threads = PartnerThread::resolve(options.threads);
    cutWithBvh(index, nullptr, cut, threads, &cs);
    const auto t2 = std::chrono::steady_clock::now();
    Section s;
    s.plane = checked.value();
    assembleContours(index, cut, s, threads);
    if (timings) {
        timings->queryMs = cs.queryMs;
        timings->cutMs = cs.cutMs;
        timings->contourMs = msSince(t2);
        timings->trianglesTested = cs.trianglesTested;
        timings->segments = cut.segments;
    }
    return s;
}

}  // namespace geoslice
