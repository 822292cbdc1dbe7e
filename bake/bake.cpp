// The whole-model bake: charts per part -> LSCM per chart (charts with flipped or degenerate
// UV triangles are split and flattened again) -> one shelf packing for all charts -> the
// conservative raster of record ids with one texel of seam padding. Parts and charts are
// processed by worker threads; every result lands in a slot fixed by its input position, so
// the output does not depend on the thread count.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>

#include "bake/bake.hpp"

namespace geoslice::bake {
namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// Runs fn(i) for i in [0, n) on `threads` workers; the calling thread reports progress.
template <class Fn>
void parallelFor(std::size_t n, unsigned threads, std::string_view stage, const ProgressFn& progress, Fn&& fn) {
    std::atomic<std::size_t> next{0}, done{0};
    auto work = [&] {
        for (std::size_t i; (i = next.fetch_add(1)) < n;) {
            fn(i);
            done.fetch_add(1);
        }
    };
    if (progress) progress(stage, 0.0);
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads && t < n; ++t) pool.emplace_back(work);
    while (done.load() < n) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        if (progress) progress(stage, double(done.load()) / double(n));
    }
    for (auto& th : pool) th.join();
    if (progress) progress(stage, 1.0);
}

struct PartWork {
    const Part* part = nullptr;
    std::vector<std::uint32_t> indices;  // welded
    Charts charts;
};

struct Flattened {
    std::uint32_t part = 0;
    std::vector<std::uint32_t> triangles;
    ChartUv uv;
    DistortionSums distortion;
    bool split = false;  // came from cutting a chart whose LSCM flipped triangles
};

Status checkOptions(const BakeOptions& o) {
    const auto& c = o.charts;
    if (!(c.maxDihedralDegrees > 0.0 && c.maxDihedralDegrees <= 180.0))
        return makeError(ErrorCode::InvalidArgument, "dihedral threshold must be in (0, 180] degrees");
    if (!(c.maxConeDegrees > 0.0 && c.maxConeDegrees <= 180.0))
        return makeError(ErrorCode::InvalidArgument, "chart normal cone must be in (0, 180] degrees");
    if (c.maxTriangles == 0) return makeError(ErrorCode::InvalidArgument, "charts need at least 1 triangle");
    if (!(o.pack.minDensity > 0.0) || !std::isfinite(o.pack.minDensity))
        return makeError(ErrorCode::InvalidArgument,
                         "minimum texel density must be a positive number of texels per metre");
    if (o.pack.width < 8 || o.pack.height < 8 || o.pack.width > 16384 || o.pack.height > 16384)
        return makeError(ErrorCode::InvalidArgument, "texture size " + std::to_string(o.pack.width) + "x" +
                                                         std::to_string(o.pack.height) + " is outside 8..16384");
    if (o.pack.margin < 2)
        return makeError(ErrorCode::InvalidArgument, "the chart margin must be at least 2 texels (seam padding)");
    return {};
}

}  // namespace

Result<BakedModel> bakeModel(const Model& model, const BakeOptions& options, const ProgressFn& progress) {
    if (auto s = checkOptions(options); !s) return s.error();
    const unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    std::vector<PartWork> parts;
    std::size_t triangles = 0;
    for (const auto* list : {&model.bodies, &model.surfaces}) {
        for (const Part& p : *list) {
            const Mesh& m = p.mesh;
            if (m.indices.size() % 3)
                return makeError(ErrorCode::InvalidArgument,
                                 "part \"" + p.name + "\": index count is not a multiple of 3");
            if (m.triangleCount() == 0) continue;
            if (m.positions.size() >= 0xFFFFFFFFu || m.triangleCount() >= 0x3FFFFFFFu)
                return makeError(ErrorCode::OutOfRange, "part \"" + p.name + "\" has too many vertices or triangles");
            for (std::size_t i = 0; i < m.indices.size(); ++i)
                if (m.indices[i] >= m.positions.size())
                    return makeError(ErrorCode::InvalidArgument,
                                     "part \"" + p.name + "\": index " + std::to_string(i) + " refers to vertex " +
                                         std::to_string(m.indices[i]) + " of " + std::to_string(m.positions.size()));
            for (std::size_t v = 0; v < m.positions.size(); ++v) {
                const glm::dvec3& q = m.positions[v];
                if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
                    return makeError(
                        ErrorCode::InvalidArgument,
                        "part \"" + p.name + "\": vertex " + std::to_string(v) + " has a non-finite coordinate");
            }
            parts.push_back({&p, {}, {}});
            triangles += m.triangleCount();
        }
    }
    if (parts.empty())
        return makeError(ErrorCode::InvalidArgument, "model \"" + model.name + "\" has no triangles to bake");

    BakedModel out;
    out.stats.triangles = triangles;

    // 1. Charts, per part (largest parts first for balance; results stay in part order).
    double t0 = now();
    std::vector<std::size_t> partOrder(parts.size());
    for (std::size_t i = 0; i < parts.size(); ++i) partOrder[i] = i;
    std::stable_sort(partOrder.begin(), partOrder.end(), [&](std::size_t a, std::size_t b) {
        return parts[a].part->mesh.triangleCount() > parts[b].part->mesh.triangleCount();
    });
    parallelFor(parts.size(), threads, "charts", progress, [&](std::size_t k) {
        PartWork& w = parts[partOrder[k]];
        const Mesh& m = w.part->mesh;
        const std::vector<std::uint32_t> weld = weldVertices(m.positions.data(), m.positions.size());
        w.indices.resize(m.indices.size());
        for (std::size_t i = 0; i < m.indices.size(); ++i) w.indices[i] = weld[m.indices[i]];
        w.charts =
            buildCharts(m.positions.data(), m.positions.size(), w.indices.data(), m.triangleCount(), options.charts);
    });
    out.stats.secondsCharts = now() - t0;

    // 2. LSCM per chart; a chart with flipped or collapsed triangles is cut and flattened again.
    t0 = now();
    struct ChartRef {
        std::uint32_t part, chart;
    };
    std::vector<ChartRef> refs;
    for (std::size_t p = 0; p < parts.size(); ++p)
        for (std::size_t c = 0; c < parts[p].charts.count(); ++c)
            refs.push_back({static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(c)});
    std::vector<std::vector<Flattened>> flatSlots(refs.size());
    // A chart that could not fit a page at the minimum density is cut as well.
    const double maxExtent =
        (double(std::min(options.pack.width, options.pack.height)) - 2.0 * options.pack.margin - 2.0) /
        options.pack.minDensity;
    auto tooLarge = [maxExtent](const ChartUv& uv) {
        glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (const auto& q : uv.uv) {
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        return hi.x - lo.x > maxExtent || hi.y - lo.y > maxExtent;
    };
    parallelFor(refs.size(), threads, "lscm", progress, [&](std::size_t i) {
        const PartWork& w = parts[refs[i].part];
        const glm::dvec3* pos = w.part->mesh.positions.data();
        const std::uint32_t* idx = w.indices.data();
        std::vector<std::pair<std::vector<std::uint32_t>, bool>> stack;
        const std::uint32_t b = w.charts.offsets[refs[i].chart], e = w.charts.offsets[refs[i].chart + 1];
        stack.push_back(
            {std::vector<std::uint32_t>(w.charts.triangles.begin() + b, w.charts.triangles.begin() + e), false});
        std::vector<std::vector<std::uint32_t>> pieces;
        while (!stack.empty()) {
            auto [tris, split] = std::move(stack.back());
            stack.pop_back();
            ChartUv uv = lscmChart(pos, idx, tris.data(), tris.size());
            if ((uv.badTriangles || tooLarge(uv)) && tris.size() > 1) {
                pieces.clear();
                splitTriangles(pos, idx, tris.data(), tris.size(), pieces);
                // Pieces that are not disks are cut further before they are flattened.
                for (auto it = pieces.rbegin(); it != pieces.rend(); ++it) {
                    if (it->size() > 1 && !isTopologicalDisk(idx, it->data(), it->size())) {
                        std::vector<std::vector<std::uint32_t>> sub;
                        splitTriangles(pos, idx, it->data(), it->size(), sub);
                        for (auto s = sub.rbegin(); s != sub.rend(); ++s) stack.push_back({std::move(*s), true});
                    } else {
                        stack.push_back({std::move(*it), true});
                    }
                }
                continue;
            }
            Flattened f;
            f.part = refs[i].part;
            f.distortion = measureDistortion(pos, idx, tris.data(), tris.size(), uv);
            f.triangles = std::move(tris);
            f.uv = std::move(uv);
            f.split = split;
            flatSlots[i].push_back(std::move(f));
        }
    });
    std::vector<Flattened> charts;
    for (auto& slot : flatSlots)
        for (auto& f : slot) charts.push_back(std::move(f));
    flatSlots.clear();
    out.stats.secondsLscm = now() - t0;

    // 3. Packing: chart UVs moved to start at (0, 0), extents in metres.
    t0 = now();
    if (progress) progress("pack", 0.0);
    std::vector<glm::dvec2> extents(charts.size());
    DistortionSums distortion;
    for (std::size_t c = 0; c < charts.size(); ++c) {
        glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (const auto& q : charts[c].uv.uv) {
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        for (auto& q : charts[c].uv.uv) q -= lo;
        extents[c] = hi - lo;
        distortion.add(charts[c].distortion);
        out.stats.splitCharts += charts[c].split ? 1 : 0;
    }
    auto packing = packCharts(extents.data(), extents.size(), options.pack);
    if (!packing) return makeError(packing.error().code, "model \"" + model.name + "\": " + packing.error().message);
    // The texture is allocated whole: refuse sizes no machine here holds (4 GiB).
    const std::uint64_t textureBytes = std::uint64_t(packing->pages) * options.pack.width * options.pack.height * 4;
    if (textureBytes > (std::uint64_t(4) << 30))
        return makeError(ErrorCode::OutOfRange, "model \"" + model.name + "\" does not fit the texture budget: " +
                                                    std::to_string(packing->pages) + " pages of " +
                                                    std::to_string(options.pack.width) + "x" +
                                                    std::to_string(options.pack.height) + " need " +
                                                    std::to_string(textureBytes >> 20) + " MiB, over 4096 MiB");
    out.width = options.pack.width;
    out.height = options.pack.height;
    out.pages = packing->pages;
    out.density = packing->density;
    out.stats.charts = charts.size();
    out.stats.distortion = distortion.result();

    // Output mesh: per part, one vertex per (chart, vertex); triangles keep their source order.
    const double s = out.density, W = out.width, H = out.height;
    std::vector<std::uint32_t> vertexBase(charts.size());
    out.parts.resize(parts.size());
    for (std::size_t p = 0; p < parts.size(); ++p) {
        out.parts[p].name = parts[p].part->name;
        out.parts[p].kind = parts[p].part->kind;
        out.parts[p].record = parts[p].part->record;
        out.parts[p].indices.resize(parts[p].indices.size());
    }
    for (std::size_t c = 0; c < charts.size(); ++c) {
        const Flattened& f = charts[c];
        BakedPart& bp = out.parts[f.part];
        const Mesh& mesh = parts[f.part].part->mesh;
        const Placement& pl = packing->placements[c];
        vertexBase[c] = static_cast<std::uint32_t>(bp.positions.size());
        for (std::size_t v = 0; v < f.uv.vertices.size(); ++v) {
            bp.positions.emplace_back(mesh.positions[f.uv.vertices[v]] - model.origin);
            const glm::dvec2 q = f.uv.uv[v];
            bp.uvs.emplace_back(static_cast<float>(double(pl.page) + (pl.x + 0.5 + q.x * s) / W),
                                static_cast<float>((pl.y + 0.5 + q.y * s) / H));
        }
        for (std::size_t k = 0; k < f.triangles.size(); ++k)
            for (int e = 0; e < 3; ++e)
                bp.indices[3 * std::size_t(f.triangles[k]) + e] = vertexBase[c] + f.uv.corners[3 * k + e];
        out.stats.vertices += f.uv.vertices.size();
    }
    out.stats.secondsPack = now() - t0;
    if (progress) progress("pack", 1.0);

    // 4. Raster: each chart into its own cell rectangle plus one texel of padding; rectangles
    // are at least `margin` (>= 2) apart, so the padded ones never overlap and charts can be
    // written concurrently.
    t0 = now();
    out.texels.assign(std::size_t(out.pages) * out.height * out.width, kNoRecord);
    parallelFor(charts.size(), threads, "raster", progress, [&](std::size_t c) {
        const Flattened& f = charts[c];
        const BakedPart& bp = out.parts[f.part];
        const Placement& pl = packing->placements[c];
        const std::uint32_t mw = pl.w + 2, mh = pl.h + 2;
        std::vector<std::uint8_t> mask(std::size_t(mw) * mh, 0);
        // Mask cell (i, j) is texel (pl.x - 1 + i, pl.y - 1 + j); corners from the stored float UVs.
        for (std::size_t k = 0; k < f.triangles.size(); ++k) {
            glm::dvec2 tri[3];
            for (int e = 0; e < 3; ++e) {
                const glm::vec2 uv = bp.uvs[bp.indices[3 * std::size_t(f.triangles[k]) + e]];
                tri[e] = {(double(uv.x) - double(pl.page)) * W - (double(pl.x) - 1.0),
                          double(uv.y) * H - (double(pl.y) - 1.0)};
            }
            rasterizeConservative(tri, mask.data(), mw, mh);
        }
        dilateMask(mask.data(), mw, mh);
        std::uint32_t* page = out.texels.data() + std::size_t(pl.page) * out.height * out.width;
        for (std::uint32_t j = 0; j < mh; ++j) {
            const long ty = long(pl.y) - 1 + long(j);
            if (ty < 0 || ty >= long(out.height)) continue;
            for (std::uint32_t i = 0; i < mw; ++i) {
                const long tx = long(pl.x) - 1 + long(i);
                if (tx < 0 || tx >= long(out.width) || !mask[std::size_t(j) * mw + i]) continue;
                page[std::size_t(ty) * out.width + std::size_t(tx)] = bp.record;
            }
        }
    });
    std::size_t used = 0;
    for (std::uint32_t v : out.texels) used += v != kNoRecord;
    out.stats.texelUtilisation = out.texels.empty() ? 0.0 : double(used) / double(out.texels.size());
    out.stats.secondsRaster = now() - t0;
    return out;
}

}  // namespace geoslice::bake
