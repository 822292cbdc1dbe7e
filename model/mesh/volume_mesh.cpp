#include "model/mesh/volume_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <tuple>

namespace geoslice {
namespace {

using CellType = VolumeMesh::CellType;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// Faces of each cell type in VTK vertex order, every face counter-clockwise seen from
// outside a positively oriented cell (so the faces of one cell form a consistently
// oriented closed surface whatever the cell's actual orientation). -1 ends a triangle.
struct FaceTable {
    int count;
    std::array<std::array<int, 4>, 6> faces;
};
constexpr FaceTable kTetraFaces{4, {{{0, 1, 3, -1}, {1, 2, 3, -1}, {2, 0, 3, -1}, {0, 2, 1, -1}}}};
constexpr FaceTable kHexFaces{6,
                              {{{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}}}};
constexpr FaceTable kWedgeFaces{5, {{{0, 1, 2, -1}, {3, 5, 4, -1}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}}}};
constexpr FaceTable kPyramidFaces{5, {{{0, 3, 2, 1}, {0, 1, 4, -1}, {1, 2, 4, -1}, {2, 3, 4, -1}, {3, 0, 4, -1}}}};

const FaceTable& facesOf(CellType t) {
    switch (t) {
        case CellType::Tetra:
            return kTetraFaces;
        case CellType::Hexahedron:
            return kHexFaces;
        case CellType::Wedge:
            return kWedgeFaces;
        case CellType::Pyramid:
            return kPyramidFaces;
    }
    GS_ASSERT(false, "cell type checked before use");
    return kTetraFaces;
}

// Global vertex ids of face f of cell c, consecutive repeats removed (cyclically); n = 0
// when the face is degenerate (fewer than 3 distinct vertices, or a repeat that is not
// consecutive).
struct FacePolygon {
    std::array<std::uint32_t, 4> v{};
    int n = 0;
};

FacePolygon facePolygon(const VolumeMesh& m, std::size_t c, int f) {
    const std::uint32_t* cv = m.cellVertices.data() + m.cellOffsets[c];
    const auto& local = facesOf(m.cellTypes[c]).faces[static_cast<std::size_t>(f)];
    std::array<std::uint32_t, 4> raw{};
    int n = 0;
    for (int k : local)
        if (k >= 0) raw[static_cast<std::size_t>(n++)] = cv[k];
    FacePolygon p;
    for (int i = 0; i < n; ++i) {
        const std::uint32_t v = raw[static_cast<std::size_t>(i)];
        if (p.n > 0 && p.v[static_cast<std::size_t>(p.n - 1)] == v) continue;
        p.v[static_cast<std::size_t>(p.n++)] = v;
    }
    while (p.n > 1 && p.v[0] == p.v[static_cast<std::size_t>(p.n - 1)]) --p.n;
    for (int i = 0; i < p.n; ++i)
        for (int j = i + 1; j < p.n; ++j)
            if (p.v[static_cast<std::size_t>(i)] == p.v[static_cast<std::size_t>(j)]) p.n = 0;
    if (p.n < 3) p.n = 0;
    return p;
}

// Triangles of a face polygon: a quad is split along the diagonal through its smallest
// vertex id, so the two cells that share it split it alike.
int triangulate(const FacePolygon& p, std::array<std::array<std::uint32_t, 3>, 2>& out) {
    if (p.n == 3) {
        out[0] = {p.v[0], p.v[1], p.v[2]};
        return 1;
    }
    if (p.n != 4) return 0;
    std::size_t k = 0;
    for (std::size_t i = 1; i < 4; ++i)
        if (p.v[i] < p.v[k]) k = i;
    auto q = [&](std::size_t i) { return p.v[(k + i) % 4]; };
    out[0] = {q(0), q(1), q(2)};
    out[1] = {q(0), q(2), q(3)};
    return 2;
}

// A face of a cell, keyed by its sorted vertex ids (kNone-padded) and the cell's region.
struct FaceRec {
    std::array<std::uint32_t, 4> key;
    std::int32_t region;
    std::uint32_t cellFace;  // cell << 3 | face
    bool operator<(const FaceRec& o) const {
        for (std::size_t i = 0; i < 4; ++i)
            if (key[i] != o.key[i]) return key[i] < o.key[i];
        if (region != o.region) return region < o.region;
        return cellFace < o.cellFace;
    }
    bool sameFaceAndRegion(const FaceRec& o) const { return key == o.key && region == o.region; }
};

std::string cellName(std::size_t c) { return "cell " + std::to_string(c); }

std::string formatPoint(const glm::dvec3& p) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g)", p.x, p.y, p.z);
    return buf;
}

// Checks cell c; an empty string when it is valid.
std::string checkCell(const VolumeMesh& m, std::size_t c, std::size_t regionCount) {
    const auto type = m.cellTypes[c];
    const std::size_t want = cellVertexCount(type);
    if (want == 0) return cellName(c) + ": unknown cell type " + std::to_string(static_cast<int>(type));
    const std::uint32_t begin = m.cellOffsets[c], end = m.cellOffsets[c + 1];
    if (end < begin || end > m.cellVertices.size())
        return cellName(c) + ": vertex offsets [" + std::to_string(begin) + ", " + std::to_string(end) +
               ") are out of order or past the " + std::to_string(m.cellVertices.size()) + " cell vertices";
    if (end - begin != want)
        return cellName(c) + ": " + std::to_string(end - begin) + " vertices for a cell type that has " +
               std::to_string(want);
    for (std::uint32_t i = begin; i < end; ++i) {
        const std::uint32_t v = m.cellVertices[i];
        if (v >= m.positions.size())
            return cellName(c) + ": vertex index " + std::to_string(v) + " is out of range (" +
                   std::to_string(m.positions.size()) + " vertices)";
        const glm::dvec3& p = m.positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return cellName(c) + ": vertex " + std::to_string(v) + " is not finite " + formatPoint(p);
    }
    const std::int32_t r = m.cellRegions[c];
    if (r < 0 || static_cast<std::size_t>(r) >= regionCount)
        return cellName(c) + ": region " + std::to_string(r) + " is outside [0, " + std::to_string(regionCount) + ")";
    return {};
}

}  // namespace

void VolumeMesh::addCell(CellType type, std::initializer_list<std::uint32_t> vertices, std::int32_t region) {
    if (cellOffsets.empty()) cellOffsets.push_back(static_cast<std::uint32_t>(cellVertices.size()));
    cellTypes.push_back(type);
    cellVertices.insert(cellVertices.end(), vertices.begin(), vertices.end());
    cellOffsets.push_back(static_cast<std::uint32_t>(cellVertices.size()));
    cellRegions.push_back(region);
}

std::size_t cellVertexCount(CellType type) {
    switch (type) {
        case CellType::Tetra:
            return 4;
        case CellType::Hexahedron:
            return 8;
        case CellType::Wedge:
            return 6;
        case CellType::Pyramid:
            return 5;
    }
    return 0;
}

double cellVolume(const VolumeMesh& m, std::size_t c) {
    // Divergence theorem over the split faces, relative to the cell's first vertex (faces
    // through it add nothing; for a tetrahedron this is the one determinant).
    const glm::dvec3 ref = m.positions[m.cellVertices[m.cellOffsets[c]]];
    double v = 0.0;
    const FaceTable& table = facesOf(m.cellTypes[c]);
    for (int f = 0; f < table.count; ++f) {
        std::array<std::array<std::uint32_t, 3>, 2> tris{};
        const int nt = triangulate(facePolygon(m, c, f), tris);
        for (int t = 0; t < nt; ++t) {
            const auto& tri = tris[static_cast<std::size_t>(t)];
            const glm::dvec3 a = m.positions[tri[0]] - ref, b = m.positions[tri[1]] - ref,
                             d = m.positions[tri[2]] - ref;
            v += glm::dot(a, glm::cross(b, d));
        }
    }
    return v / 6.0;
}

Result<std::vector<Mesh>> regionBoundaries(const VolumeMesh& m, std::size_t regionCount) {
    const std::size_t cells = m.cellTypes.size();
    if (cells > 0 && m.cellOffsets.size() != cells + 1)
        return makeError(ErrorCode::InvalidArgument, "volume mesh: " + std::to_string(m.cellOffsets.size()) +
                                                         " cell offsets for " + std::to_string(cells) +
                                                         " cells (want cells + 1)");
    if (m.cellRegions.size() != cells)
        return makeError(ErrorCode::InvalidArgument, "volume mesh: " + std::to_string(m.cellRegions.size()) +
                                                         " cell regions for " + std::to_string(cells) + " cells");
    if (cells >= (std::size_t(1) << 29))
        return makeError(ErrorCode::OutOfRange, "volume mesh: " + std::to_string(cells) + " cells is over 2^29");
    for (std::size_t c = 0; c < cells; ++c)
        if (std::string e = checkCell(m, c, regionCount); !e.empty()) return makeError(ErrorCode::InvalidArgument, e);

    // +1: the cell's faces as listed face outward; -1: the cell is inverted.
    std::vector<std::int8_t> sign(cells);
    for (std::size_t c = 0; c < cells; ++c) sign[c] = cellVolume(m, c) < 0.0 ? -1 : 1;

    // Every non-degenerate face, keyed by its sorted vertex ids, grouped by key then region.
    std::vector<FaceRec> faces;
    std::size_t total = 0;
    for (std::size_t c = 0; c < cells; ++c) total += static_cast<std::size_t>(facesOf(m.cellTypes[c]).count);
    faces.reserve(total);
    for (std::size_t c = 0; c < cells; ++c) {
        const int nf = facesOf(m.cellTypes[c]).count;
        for (int f = 0; f < nf; ++f) {
            FacePolygon p = facePolygon(m, c, f);
            if (p.n == 0) continue;
            FaceRec r{{kNone, kNone, kNone, kNone},
                      m.cellRegions[c],
                      static_cast<std::uint32_t>(c << 3 | static_cast<std::size_t>(f))};
            // Insertion sort of 3 or 4 ids (std::sort over n <= 4 trips GCC 12's -Warray-bounds).
            for (int a = 0; a < p.n; ++a) {
                std::uint32_t v = p.v[static_cast<std::size_t>(a)];
                int b = a;
                for (; b > 0 && r.key[static_cast<std::size_t>(b - 1)] > v; --b)
                    r.key[static_cast<std::size_t>(b)] = r.key[static_cast<std::size_t>(b - 1)];
                r.key[static_cast<std::size_t>(b)] = v;
            }
            faces.push_back(r);
        }
    }
    std::sort(faces.begin(), faces.end());

    // Triangles per region, in global vertex ids.
    std::vector<std::vector<std::uint32_t>> tris(regionCount);
    auto emit = [&](const FaceRec& r) {
        const std::size_t c = r.cellFace >> 3;
        std::array<std::array<std::uint32_t, 3>, 2> t{};
        const int nt = triangulate(facePolygon(m, c, static_cast<int>(r.cellFace & 7u)), t);
        auto& out = tris[static_cast<std::size_t>(m.cellRegions[c])];
        for (int i = 0; i < nt; ++i) {
            auto tri = t[static_cast<std::size_t>(i)];
            if (sign[c] < 0) std::swap(tri[1], tri[2]);
            out.insert(out.end(), tri.begin(), tri.end());
        }
    };
    for (std::size_t i = 0; i < faces.size();) {
        std::size_t j = i;
        while (j < faces.size() && faces[j].sameFaceAndRegion(faces[i])) ++j;
        // One cell of the region: a boundary face. Two: interior. More (a broken mesh):
        // keep them all, so validation reports the non-manifold edges it makes.
        if (j - i != 2)
            for (std::size_t k = i; k < j; ++k) emit(faces[k]);
        i = j;
    }

    std::vector<Mesh> out(regionCount);
    std::vector<std::uint32_t> localOf(m.positions.size(), kNone);
    for (std::size_t r = 0; r < regionCount; ++r) {
        Mesh& mesh = out[r];
        mesh.indices.reserve(tris[r].size());
        for (std::uint32_t v : tris[r]) {
            if (localOf[v] == kNone) {
                localOf[v] = static_cast<std::uint32_t>(mesh.positions.size());
                mesh.positions.push_back(m.positions[v]);
            }
            mesh.indices.push_back(localOf[v]);
        }
        for (std::uint32_t v : tris[r]) localOf[v] = kNone;
        std::vector<std::uint32_t>().swap(tris[r]);
    }
    return out;
}

}  // namespace geoslice
