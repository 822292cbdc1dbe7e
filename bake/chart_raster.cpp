// One placed chart's record ids into the index texture: the conservative raster of its
// triangles (raster.cpp) plus one texel of seam padding, with the part's record, or for a field
// bake the id of the block or property class at each texel's point on the chart.
#include <algorithm>
#include <cmath>
#include <limits>

#include "bake/bake_internal.hpp"

namespace geoslice::bake::bake_detail {
namespace {

// Closest point of a triangle to p (2D), as barycentric weights; returns the squared distance.
double closestBarycentric(const glm::dvec2 t[3], const glm::dvec2& p, glm::dvec3& bary) {
    const double area = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
    if (area != 0.0) {
        const double b1 = ((p.x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (p.y - t[0].y)) / area;
        const double b2 = ((t[1].x - t[0].x) * (p.y - t[0].y) - (p.x - t[0].x) * (t[1].y - t[0].y)) / area;
        if (b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0) {
            bary = {1.0 - b1 - b2, b1, b2};
            return 0.0;
        }
    }
    double best = std::numeric_limits<double>::infinity();
    for (int e = 0; e < 3; ++e) {
        const glm::dvec2 a = t[e], d = t[(e + 1) % 3] - a;
        const double len2 = glm::dot(d, d);
        const double u = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
        const glm::dvec2 q = a + u * d;
        const double dist = glm::dot(p - q, p - q);
        if (dist < best) {
            best = dist;
            bary = glm::dvec3(0.0);
            bary[e] = 1.0 - u;
            bary[(e + 1) % 3] = u;
        }
    }
    return best;
}

// Triangle k of a placed chart in the cells of its mask: mask cell (i, j) is texel
// (pl.x - 1 + i, pl.y - 1 + j); corners from the stored float UVs.
void chartTriangle(const Flattened& f, std::size_t k, const Placement& pl, const BakedPart& bp, std::uint32_t width,
                   std::uint32_t height, glm::dvec2 tri[3]) {
    for (int e = 0; e < 3; ++e) {
        const glm::vec2 uv = bp.uvs[bp.indices[3 * std::size_t(f.triangles[k]) + e]];
        tri[e] = {(double(uv.x) - double(pl.page)) * width - (double(pl.x) - 1.0),
                  double(uv.y) * height - (double(pl.y) - 1.0)};
    }
}

}  // namespace

void rasterChartField(const Flattened& f, const Placement& pl, const BakedPart& bp, const Mesh& mesh,
                      const FieldIds& field, int column, std::uint32_t width, std::uint32_t height,
                      std::uint32_t* texels) {
    const std::uint32_t mw = pl.w + 2, mh = pl.h + 2;
    const std::size_t cells = std::size_t(mw) * mh;
    std::vector<double> bestDist(cells, std::numeric_limits<double>::infinity());
    // Per cell: the nearest triangle (index into the chart's list) and the barycentric weights
    // of the cell centre's point on it.
    std::vector<glm::dvec3> bestBary(cells);
    std::vector<std::uint32_t> bestTriangle(cells, 0);
    std::vector<std::uint8_t> mask(cells, 0), local;
    for (std::size_t k = 0; k < f.triangles.size(); ++k) {
        glm::dvec2 tri[3];
        chartTriangle(f, k, pl, bp, width, height, tri);
        const glm::dvec2 lo = glm::min(tri[0], glm::min(tri[1], tri[2])),
                         hi = glm::max(tri[0], glm::max(tri[1], tri[2]));
        const long x0 = std::max(0L, long(std::ceil(lo.x)) - 1), y0 = std::max(0L, long(std::ceil(lo.y)) - 1);
        const long x1 = std::min(long(mw) - 1, long(std::floor(hi.x))),
                   y1 = std::min(long(mh) - 1, long(std::floor(hi.y)));
        if (x0 > x1 || y0 > y1) continue;
        const auto lw = std::uint32_t(x1 - x0 + 1), lh = std::uint32_t(y1 - y0 + 1);
        local.assign(std::size_t(lw) * lh, 0);
        const glm::dvec2 shift{double(x0), double(y0)};
        const glm::dvec2 moved[3] = {tri[0] - shift, tri[1] - shift, tri[2] - shift};
        rasterizeConservative(moved, local.data(), lw, lh);
        for (std::uint32_t j = 0; j < lh; ++j)
            for (std::uint32_t i = 0; i < lw; ++i) {
                if (!local[std::size_t(j) * lw + i]) continue;
                const std::size_t c = std::size_t(y0 + long(j)) * mw + std::size_t(x0 + long(i));
                glm::dvec3 b(1.0 / 3.0);
                const double d =
                    closestBarycentric(tri, glm::dvec2(double(x0 + long(i)) + 0.5, double(y0 + long(j)) + 0.5), b);
                mask[c] = 1;
                if (d < bestDist[c]) {
                    bestDist[c] = d;
                    bestBary[c] = b;
                    bestTriangle[c] = static_cast<std::uint32_t>(k);
                }
            }
    }
    std::vector<RecordId> ids(cells, kNoRecord);
    for (std::size_t c = 0; c < cells; ++c) {
        if (!mask[c]) continue;
        const std::size_t k = bestTriangle[c];
        const glm::dvec3& b = bestBary[c];
        if (column >= 0) {
            ids[c] = field.classRecord(bp.record, interpolateProperty(mesh, column, f.triangles[k], b));
        } else {
            glm::dvec3 world[3];
            for (int e = 0; e < 3; ++e) world[e] = mesh.positions[f.uv.vertices[f.uv.corners[3 * k + e]]];
            ids[c] = field.at(bp.record, b.x * world[0] + b.y * world[1] + b.z * world[2]);
        }
    }
    dilateMask(mask.data(), mw, mh);
    std::uint32_t* page = texels + std::size_t(pl.page) * height * width;
    for (std::uint32_t j = 0; j < mh; ++j) {
        const long ty = long(pl.y) - 1 + long(j);
        for (std::uint32_t i = 0; i < mw; ++i) {
            const std::size_t c = std::size_t(j) * mw + i;
            if (!mask[c]) continue;
            RecordId id = ids[c];
            for (int dy = -1; dy <= 1 && mask[c] == 2 && id == kNoRecord; ++dy)
                for (int dx = -1; dx <= 1 && id == kNoRecord; ++dx) {
                    const long ni = long(i) + dx, nj = long(j) + dy;
                    if (ni >= 0 && nj >= 0 && ni < long(mw) && nj < long(mh) &&
                        mask[std::size_t(nj) * mw + std::size_t(ni)] == 1)
                        id = ids[std::size_t(nj) * mw + std::size_t(ni)];
                }
            const long tx = long(pl.x) - 1 + long(i);
            if (tx < 0 || ty < 0 || tx >= long(width) || ty >= long(height)) continue;
            page[std::size_t(ty) * width + std::size_t(tx)] = id;
        }
    }
}

void rasterChart(const Flattened& f, const Placement& pl, const BakedPart& bp, std::uint32_t width,
                 std::uint32_t height, std::uint32_t* texels) {
    const std::uint32_t mw = pl.w + 2, mh = pl.h + 2;
    std::vector<std::uint8_t> mask(std::size_t(mw) * mh, 0);
    for (std::size_t k = 0; k < f.triangles.size(); ++k) {
        glm::dvec2 tri[3];
        chartTriangle(f, k, pl, bp, width, height, tri);
        rasterizeConservative(tri, mask.data(), mw, mh);
    }
    dilateMask(mask.data(), mw, mh);
    std::uint32_t* page = texels + std::size_t(pl.page) * height * width;
    for (std::uint32_t j = 0; j < mh; ++j) {
        const long ty = long(pl.y) - 1 + long(j);
        if (ty < 0 || ty >= long(height)) continue;
        for (std::uint32_t i = 0; i < mw; ++i) {
            const long tx = long(pl.x) - 1 + long(i);
            if (tx < 0 || tx >= long(width) || !mask[std::size_t(j) * mw + i]) continue;
            page[std::size_t(ty) * width + std::size_t(tx)] = bp.record;
        }
    }
}

}  // namespace geoslice::bake::bake_detail
