// Conservative rasterization of record ids (paper section 2.2: "every texel partially
// overlapping a triangle boundary is assigned the corresponding stratigraphic integer") by the
// separating axis theorem on each texel cell of the triangle's bounds (Akenine-Moller 2001,
// "Fast 3D triangle-box overlap testing", in 2D), and one texel of seam padding.
#include <algorithm>
#include <cmath>

#include "bake/bake.hpp"

namespace geoslice::bake {

void rasterizeConservative(const glm::dvec2 tri[3], std::uint8_t* mask, std::uint32_t w, std::uint32_t h) {
    if (w == 0 || h == 0) return;
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(tri[i].x) || !std::isfinite(tri[i].y)) return;
    const glm::dvec2 lo = glm::min(tri[0], glm::min(tri[1], tri[2]));
    const glm::dvec2 hi = glm::max(tri[0], glm::max(tri[1], tri[2]));
    // Closed cells: a triangle touching the line x = k touches cells k - 1 and k.
    const long x0 = std::max(0L, static_cast<long>(std::ceil(lo.x)) - 1);
    const long y0 = std::max(0L, static_cast<long>(std::ceil(lo.y)) - 1);
    const long x1 = std::min(long(w) - 1, static_cast<long>(std::floor(hi.x)));
    const long y1 = std::min(long(h) - 1, static_cast<long>(std::floor(hi.y)));
    if (x0 > x1 || y0 > y1) return;
    // Edge axes: normals of the three edges; for a cell to be separated along one of them, all
    // four corners lie strictly beyond the triangle's extent on that axis.
    glm::dvec2 axis[3];
    double tmin[3], tmax[3];
    for (int e = 0; e < 3; ++e) {
        const glm::dvec2 d = tri[(e + 1) % 3] - tri[e];
        axis[e] = {-d.y, d.x};
        tmin[e] = tmax[e] = glm::dot(axis[e], tri[0]);
        for (int k = 1; k < 3; ++k) {
            const double t = glm::dot(axis[e], tri[k]);
            tmin[e] = std::min(tmin[e], t);
            tmax[e] = std::max(tmax[e], t);
        }
    }
    for (long y = y0; y <= y1; ++y) {
        for (long x = x0; x <= x1; ++x) {
            bool separated = false;
            for (int e = 0; e < 3 && !separated; ++e) {
                // Box projection: centre +- half extent.
                const double c = axis[e].x * (double(x) + 0.5) + axis[e].y * (double(y) + 0.5);
                const double r = 0.5 * (std::abs(axis[e].x) + std::abs(axis[e].y));
                separated = c + r < tmin[e] || c - r > tmax[e];
            }
            if (!separated) mask[std::size_t(y) * w + std::size_t(x)] = 1;
        }
    }
}

void dilateMask(std::uint8_t* mask, std::uint32_t w, std::uint32_t h) {
    // 2 marks a cell set by this pass, so the dilation is by one texel only.
    for (std::uint32_t y = 0; y < h; ++y) {
        for (std::uint32_t x = 0; x < w; ++x) {
            if (mask[std::size_t(y) * w + x]) continue;
            bool near = false;
            for (int dy = -1; dy <= 1 && !near; ++dy) {
                for (int dx = -1; dx <= 1 && !near; ++dx) {
                    const long nx = long(x) + dx, ny = long(y) + dy;
                    if (nx < 0 || ny < 0 || nx >= long(w) || ny >= long(h)) continue;
                    near = mask[std::size_t(ny) * w + std::size_t(nx)] == 1;
                }
            }
            if (near) mask[std::size_t(y) * w + x] = 2;
        }
    }
}

RecordId fetchId(const std::uint32_t* texels, std::uint32_t width, std::uint32_t height, std::uint32_t pages,
                 glm::dvec2 uv) {
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y) || uv.x < 0.0 || uv.y < 0.0) return kNoRecord;
    const double page = std::floor(uv.x);
    if (page >= double(pages)) return kNoRecord;
    const double fx = std::floor((uv.x - page) * double(width)), fy = std::floor(uv.y * double(height));
    if (fx >= double(width) || fy >= double(height)) return kNoRecord;
    return texels[(std::size_t(page) * height + std::size_t(fy)) * width + std::size_t(fx)];
}

}  // namespace geoslice::bake
