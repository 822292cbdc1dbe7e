#include "section/adjacency.hpp"

#include <atomic>
#include <cmath>
#include <cstring>
#include <thread>

#include "section/section_index.hpp"

namespace geoslice {
namespace {

constexpr char kMagic[8] = {'G', 'S', 'A', 'D', 'J', '0', '0', '1'};
constexpr std::size_t kHeaderBytes = 32;
constexpr std::size_t kMaxWalkTriangles = std::size_t(1) << 30;  // 4 t' + k' fits in 32 bits

inline std::uint32_t nextCorner(std::uint32_t c) { return c % 3 == 2 ? c - 2 : c + 1; }

// Whether body `p` can be walked at all: closed, its indices its own 2-manifold (no weld),
// small enough for the encoding, no triangle with a repeated or non-finite vertex.
bool eligible(const SectionIndex& index, std::size_t p) {
    const SectionPart& sp = index.parts[p];
    if (sp.kind != PartKind::Body || !sp.closed || !sp.canon.empty()) return false;
    const Mesh& mesh = sp.part->mesh;
    const std::size_t m = mesh.triangleCount();
    if (m == 0 || m >= kMaxWalkTriangles) return false;
    for (const glm::dvec3& v : mesh.positions)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return false;
    const std::uint32_t* idx = mesh.indices.data();
    for (std::size_t t = 0; t < m; ++t)
        if (idx[3 * t] == idx[3 * t + 1] || idx[3 * t + 1] == idx[3 * t + 2] || idx[3 * t] == idx[3 * t + 2])
            return false;
    return true;
}

// Fills `out` (3 entries a triangle) for one part; false when some edge is not shared by
// exactly two triangles running it opposite ways.
bool buildPart(const Mesh& mesh, std::uint32_t* out) {
    const std::size_t n = mesh.positions.size(), corners = mesh.indices.size();
    const std::uint32_t* idx = mesh.indices.data();
    // Corners by vertex (counting sort).
    std::vector<std::uint32_t> start(n + 1, 0), byVertex(corners);
    for (std::size_t c = 0; c < corners; ++c) ++start[idx[c] + 1];
    for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t c = 0; c < corners; ++c) byVertex[fill[idx[c]]++] = static_cast<std::uint32_t>(c);
    }
    for (std::uint32_t c = 0; c < corners; ++c) {
        const std::uint32_t a = idx[c], b = idx[nextCorner(c)];
        std::uint32_t twin = kNoNeighbour;
        int found = 0;
        for (std::uint32_t i = start[b]; i < start[b + 1]; ++i) {
            const std::uint32_t d = byVertex[i];  // a corner at b: its edge runs b -> next
            if (idx[nextCorner(d)] == a) twin = d, ++found;
        }
        if (found != 1) return false;
        out[c] = 4 * (twin / 3) + twin % 3;
    }
    return true;
}

}  // namespace

TriangleAdjacency buildTriangleAdjacency(const SectionIndex& index, unsigned threads) {
    TriangleAdjacency adj;
    const std::size_t bodies = index.bodyCount;
    if (bodies == 0 || index.bvh.meshFirst.size() <= bodies) return adj;
    adj.walkable.assign(bodies, 0);
    adj.across.assign(3 * std::size_t(index.bvh.meshFirst[bodies]), kNoNeighbour);
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (std::size_t p = next++; p < bodies; p = next++) {
            if (!eligible(index, p)) continue;
            std::uint32_t* out = adj.across.data() + 3 * std::size_t(index.bvh.meshFirst[p]);
            if (buildPart(index.parts[p].part->mesh, out))
                adj.walkable[p] = 1;
            else
                std::fill(out, out + index.parts[p].part->mesh.indices.size(), kNoNeighbour);
        }
    };
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> helpers;
    for (unsigned i = 1; i < threads && i < bodies; ++i) helpers.emplace_back(work);
    work();
    for (auto& t : helpers) t.join();
    bool any = false;
    for (auto w : adj.walkable) any = any || w;
    if (!any) adj = TriangleAdjacency{};
    return adj;
}

std::vector<std::uint8_t> saveTriangleAdjacency(const TriangleAdjacency& adj) {
    const std::uint32_t bodies = static_cast<std::uint32_t>(adj.walkable.size());
    const std::uint64_t entries = adj.across.size();
    const std::size_t flagBytes = (bodies + 3) / 4 * 4;
    std::vector<std::uint8_t> out(kHeaderBytes + flagBytes + 4 * entries, 0);
    std::memcpy(out.data(), kMagic, 8);
    std::memcpy(out.data() + 8, &bodies, 4);
    std::memcpy(out.data() + 16, &entries, 8);
    std::memcpy(out.data() + kHeaderBytes, adj.walkable.data(), bodies);
    std::memcpy(out.data() + kHeaderBytes + flagBytes, adj.across.data(), 4 * entries);
    return out;
}

Result<TriangleAdjacency> loadTriangleAdjacency(std::span<const std::uint8_t> bytes, const SectionIndex& index,
                                                const std::string& source) {
    auto bad = [&](const std::string& what) {
        return makeError(ErrorCode::ParseError, source + ": triangle adjacency: " + what);
    };
    if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic, 8) != 0)
        return bad("not a GSADJ001 table (bad header)");
    std::uint32_t bodies = 0;
    std::uint64_t entries = 0;
    std::memcpy(&bodies, bytes.data() + 8, 4);
    std::memcpy(&entries, bytes.data() + 16, 8);
    if (bodies != index.bodyCount || index.bvh.meshFirst.size() <= bodies)
        return bad("made for " + std::to_string(bodies) + " bodies, the model has " + std::to_string(index.bodyCount));
    if (entries != 3 * std::uint64_t(index.bvh.meshFirst[bodies]))
        return bad(std::to_string(entries) + " entries for " + std::to_string(index.bvh.meshFirst[bodies]) +
                   " body triangles");
    const std::size_t flagBytes = (std::size_t(bodies) + 3) / 4 * 4;
    if (bytes.size() != kHeaderBytes + flagBytes + 4 * entries) return bad("size does not match its header");
    TriangleAdjacency adj;
    adj.walkable.assign(bytes.data() + kHeaderBytes, bytes.data() + kHeaderBytes + bodies);
    adj.across.resize(entries);
    std::memcpy(adj.across.data(), bytes.data() + kHeaderBytes + flagBytes, 4 * entries);
    for (std::size_t p = 0; p < bodies; ++p) {
        if (adj.walkable[p] > 1) return bad("body " + std::to_string(p) + ": walkable flag not 0 or 1");
        const SectionPart& sp = index.parts[p];
        if (adj.walkable[p] && (!sp.closed || !sp.canon.empty() || sp.part->mesh.triangleCount() >= kMaxWalkTriangles))
            return bad("body " + std::to_string(p) + " cannot be walked but is marked so");
    }
    return adj;
}

}  // namespace geoslice
