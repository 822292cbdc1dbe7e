// The whole-model bake: charts per part -> LSCM per chart (charts with flipped or degenerate
// UV triangles, or too large for a page, are split and flattened again) -> one shelf packing
// for all charts -> the conservative raster of record ids with one texel of seam padding.
// Parts and charts are processed by worker threads; every result lands in a slot fixed by its
// input position, so the output does not depend on the thread count. Also the incremental
// re-bake of one part into the free space of an existing bake.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>

#include "bake/bake.hpp"
#include "bake/field.hpp"

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
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (progress) progress(stage, double(done.load()) / double(n));
    }
    for (auto& th : pool) th.join();
    if (progress) progress(stage, 1.0);
}

struct PartWork {
    const Part* part = nullptr;
    std::size_t source = 0;
    std::vector<std::uint32_t> indices;  // welded
    Charts charts;
};

struct Flattened {
    std::uint32_t part = 0;
    std::vector<std::uint32_t> triangles;
    ChartUv uv;
    DistortionSums distortion;
    glm::dvec2 extent{0.0};  // metres; uv starts at (0, 0)
    bool split = false;      // came from cutting a chart (flips or size)
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
    if (o.field.blocks && !o.field.vertexProperty.empty())
        return makeError(ErrorCode::InvalidArgument, "a field is either a block model or the per-vertex property \"" +
                                                         o.field.vertexProperty + "\", not both");
    if (o.field.blocks && o.field.blocks->values.empty())
        return makeError(ErrorCode::InvalidArgument, "the block model has no blocks");
    if (o.field.enabled()) {
        for (std::size_t i = 0; i < o.field.breaks.size(); ++i)
            if (!std::isfinite(o.field.breaks[i]) || (i && !(o.field.breaks[i] > o.field.breaks[i - 1])))
                return makeError(ErrorCode::InvalidArgument, "field class breaks must be finite and increasing");
    }
    if (o.pack.margin < 2 || o.pack.margin > 64)
        return makeError(ErrorCode::InvalidArgument, "the chart margin must be 2..64 texels (seam padding needs 2)");
    return {};
}

Status checkPart(const Part& p) {
    const Mesh& m = p.mesh;
    if (m.indices.size() % 3)
        return makeError(ErrorCode::InvalidArgument, "part \"" + p.name + "\": index count is not a multiple of 3");
    if (m.positions.size() >= 0xFFFFFFFFu || m.triangleCount() >= 0x3FFFFFFFu)
        return makeError(ErrorCode::OutOfRange, "part \"" + p.name + "\" has too many vertices or triangles");
    for (std::size_t i = 0; i < m.indices.size(); ++i)
        if (m.indices[i] >= m.positions.size())
            return makeError(ErrorCode::InvalidArgument, "part \"" + p.name + "\": index " + std::to_string(i) +
                                                             " refers to vertex " + std::to_string(m.indices[i]) +
                                                             " of " + std::to_string(m.positions.size()));
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const glm::dvec3& q = m.positions[v];
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
            return makeError(ErrorCode::InvalidArgument,
                             "part \"" + p.name + "\": vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
    return {};
}

void chartPart(PartWork& w, const ChartOptions& options) {
    const Mesh& m = w.part->mesh;
    const std::vector<std::uint32_t> weld = weldVertices(m.positions.data(), m.positions.size());
    w.indices.resize(m.indices.size());
    for (std::size_t i = 0; i < m.indices.size(); ++i) w.indices[i] = weld[m.indices[i]];
    w.charts = buildCharts(m.positions.data(), m.positions.size(), w.indices.data(), m.triangleCount(), options);
}

// The largest chart extent (metres) that fits a page at `density`.
double maxExtentAt(double density, const PackOptions& o) {
    return (double(std::min(o.width, o.height)) - 2.0 * o.margin - 2.0) / density;
}

// Flattens chart `chart` of a part; pieces are cut and flattened again while LSCM flips or
// collapses a triangle or the chart exceeds maxExtent. Appends to `out` in a fixed order.
void flattenChart(const PartWork& w, std::uint32_t partIndex, std::size_t chart, double maxExtent,
                  std::vector<Flattened>& out) {
    const glm::dvec3* pos = w.part->mesh.positions.data();
    const std::uint32_t* idx = w.indices.data();
    std::vector<std::pair<std::vector<std::uint32_t>, bool>> stack;
    const std::uint32_t b = w.charts.offsets[chart], e = w.charts.offsets[chart + 1];
    stack.push_back(
        {std::vector<std::uint32_t>(w.charts.triangles.begin() + b, w.charts.triangles.begin() + e), false});
    std::vector<std::vector<std::uint32_t>> pieces;
    while (!stack.empty()) {
        auto [tris, split] = std::move(stack.back());
        stack.pop_back();
        ChartUv uv = lscmChart(pos, idx, tris.data(), tris.size());
        glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (const auto& q : uv.uv) {
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        const bool tooLarge = hi.x - lo.x > maxExtent || hi.y - lo.y > maxExtent;
        if ((uv.badTriangles || tooLarge) && tris.size() > 1) {
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
        for (auto& q : uv.uv) q -= lo;
        Flattened f;
        f.part = partIndex;
        f.distortion = measureDistortion(pos, idx, tris.data(), tris.size(), uv);
        f.extent = uv.uv.empty() ? glm::dvec2(0.0) : hi - lo;
        f.triangles = std::move(tris);
        f.uv = std::move(uv);
        f.split = split;
        out.push_back(std::move(f));
    }
}

// What float32 lost of a local position: local - hi, in double, rounded to float. The
// volatile is needed: GCC 12 at -O3 vectorised (SLP) the x and y of local - double(hi) and
// folded double(float(x)) back to x, so the residual came out 0 (seen in the assembly).
glm::vec3 residual(const glm::dvec3& local) {
    glm::vec3 r;
    for (int k = 0; k < 3; ++k) {
        volatile float hi = static_cast<float>(local[k]);
        r[k] = static_cast<float>(local[k] - static_cast<double>(hi));
    }
    return r;
}

// Appends a chart's vertices to its part (positions in the local frame, UVs on the page) and
// points the chart's triangles at them.
void emitChart(const Flattened& f, const Placement& pl, const Mesh& mesh, const glm::dvec3& origin, double density,
               std::uint32_t width, std::uint32_t height, BakedPart& bp) {
    const auto base = static_cast<std::uint32_t>(bp.positions.size());
    for (std::size_t v = 0; v < f.uv.vertices.size(); ++v) {
        const glm::dvec3 local = mesh.positions[f.uv.vertices[v]] - origin;
        const glm::vec3 hi(local);
        bp.positions.push_back(hi);
        bp.positionsLo.push_back(residual(local));
        const glm::dvec2 q = f.uv.uv[v];
        bp.uvs.emplace_back(static_cast<float>(double(pl.page) + (pl.x + 0.5 + q.x * density) / width),
                            static_cast<float>((pl.y + 0.5 + q.y * density) / height));
    }
    for (std::size_t k = 0; k < f.triangles.size(); ++k)
        for (int e = 0; e < 3; ++e) bp.indices[3 * std::size_t(f.triangles[k]) + e] = base + f.uv.corners[3 * k + e];
}

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

// The field variant of rasterChart: each covered cell's centre is mapped back onto its nearest
// triangle of the chart (texel space -> barycentric) and takes the id of that point: for a block
// field, of the block holding the world point; for a vertex property (column >= 0 of the part's
// mesh), of the class of the value interpolated with those barycentric weights. Padding cells
// copy the id of their first covered neighbour (row by row, left to right).
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
        for (int e = 0; e < 3; ++e) {
            const glm::vec2 uv = bp.uvs[bp.indices[3 * std::size_t(f.triangles[k]) + e]];
            tri[e] = {(double(uv.x) - double(pl.page)) * width - (double(pl.x) - 1.0),
                      double(uv.y) * height - (double(pl.y) - 1.0)};
        }
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

// Rasterizes one emitted chart into its cell rectangle plus one texel of padding. Rectangles
// are at least `margin` (>= 2) apart, so padded ones never overlap: charts may be written
// concurrently.
void rasterChart(const Flattened& f, const Placement& pl, const BakedPart& bp, std::uint32_t width,
                 std::uint32_t height, std::uint32_t* texels) {
    const std::uint32_t mw = pl.w + 2, mh = pl.h + 2;
    std::vector<std::uint8_t> mask(std::size_t(mw) * mh, 0);
    // Mask cell (i, j) is texel (pl.x - 1 + i, pl.y - 1 + j); corners from the stored float UVs.
    for (std::size_t k = 0; k < f.triangles.size(); ++k) {
        glm::dvec2 tri[3];
        for (int e = 0; e < 3; ++e) {
            const glm::vec2 uv = bp.uvs[bp.indices[3 * std::size_t(f.triangles[k]) + e]];
            tri[e] = {(double(uv.x) - double(pl.page)) * width - (double(pl.x) - 1.0),
                      double(uv.y) * height - (double(pl.y) - 1.0)};
        }
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

void finishStats(BakedModel& b) {
    std::size_t used = 0;
    for (std::uint32_t v : b.texels) used += v != kNoRecord;
    b.stats.texelUtilisation = b.texels.empty() ? 0.0 : double(used) / double(b.texels.size());
    DistortionSums d;
    for (const auto& c : b.charts) d.add(c.distortion);
    b.stats.distortion = d.result();
    b.stats.charts = b.charts.size();
    b.stats.vertices = b.stats.triangles = 0;
    for (const auto& p : b.parts) {
        b.stats.vertices += p.positions.size();
        b.stats.triangles += p.indices.size() / 3;
    }
}

const Part* sourcePart(const Model& model, std::size_t source) {
    if (source < model.bodies.size()) return &model.bodies[source];
    if (source - model.bodies.size() < model.surfaces.size()) return &model.surfaces[source - model.bodies.size()];
    return nullptr;
}

}  // namespace

Result<BakedModel> bakeModel(const Model& model, const BakeOptions& options, const ProgressFn& progress) {
    if (auto s = checkOptions(options); !s) return s.error();
    const unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    std::vector<PartWork> parts;
    for (std::size_t source = 0; source < model.bodies.size() + model.surfaces.size(); ++source) {
        const Part& p = *sourcePart(model, source);
        if (auto s = checkPart(p); !s) return s.error();
        if (p.mesh.triangleCount()) parts.push_back({&p, source, {}, {}});
    }
    if (parts.empty())
        return makeError(ErrorCode::InvalidArgument, "model \"" + model.name + "\" has no triangles to bake");
    // Vertex-property field: the property's column per part (-1: the part does not have it).
    std::vector<int> columns(parts.size(), -1);
    if (!options.field.vertexProperty.empty()) {
        const std::string& name = options.field.vertexProperty;
        std::vector<std::string> known;
        bool found = false;
        for (std::size_t p = 0; p < parts.size(); ++p) {
            const Mesh& m = parts[p].part->mesh;
            for (const auto& n : m.propertyNames)
                if (std::find(known.begin(), known.end(), n) == known.end()) known.push_back(n);
            columns[p] = propertyColumn(m, name);
            if (columns[p] < 0) continue;
            found = true;
            if (m.propertyValues.size() != m.positions.size() * m.propertyNames.size())
                return makeError(ErrorCode::InvalidArgument,
                                 "part \"" + parts[p].part->name + "\": " + std::to_string(m.propertyValues.size()) +
                                     " per-vertex property values for " + std::to_string(m.positions.size()) +
                                     " vertices x " + std::to_string(m.propertyNames.size()) + " properties");
        }
        if (!found) {
            std::string list;
            for (const auto& n : known) list += (list.empty() ? "\"" : ", \"") + n + "\"";
            return makeError(ErrorCode::InvalidArgument,
                             "model \"" + model.name + "\" has no per-vertex property \"" + name + "\" (" +
                                 (known.empty() ? std::string("it has no per-vertex properties") : "known: " + list) +
                                 ")");
        }
    }
    BakedModel out;
    out.pack = options.pack;

    // 1. Charts, per part (largest parts first for balance; results stay in part order).
    double t0 = now();
    std::vector<std::size_t> partOrder(parts.size());
    for (std::size_t i = 0; i < parts.size(); ++i) partOrder[i] = i;
    std::stable_sort(partOrder.begin(), partOrder.end(), [&](std::size_t a, std::size_t b) {
        return parts[a].part->mesh.triangleCount() > parts[b].part->mesh.triangleCount();
    });
    parallelFor(parts.size(), threads, "charts", progress,
                [&](std::size_t k) { chartPart(parts[partOrder[k]], options.charts); });
    out.stats.secondsCharts = now() - t0;

    // 2. LSCM per chart. A chart too large for a page at the minimum density is cut as well.
    t0 = now();
    std::vector<std::pair<std::uint32_t, std::uint32_t>> refs;  // (part, chart)
    for (std::size_t p = 0; p < parts.size(); ++p)
        for (std::size_t c = 0; c < parts[p].charts.count(); ++c)
            refs.emplace_back(static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(c));
    std::vector<std::vector<Flattened>> slots(refs.size());
    const double maxExtent = maxExtentAt(options.pack.minDensity, options.pack);
    parallelFor(refs.size(), threads, "lscm", progress, [&](std::size_t i) {
        flattenChart(parts[refs[i].first], refs[i].first, refs[i].second, maxExtent, slots[i]);
    });
    std::vector<Flattened> charts;
    for (auto& slot : slots)
        for (auto& f : slot) charts.push_back(std::move(f));
    slots.clear();
    out.stats.secondsLscm = now() - t0;

    // 3. Packing at one uniform density.
    t0 = now();
    if (progress) progress("pack", 0.0);
    std::vector<glm::dvec2> extents(charts.size());
    for (std::size_t c = 0; c < charts.size(); ++c) {
        extents[c] = charts[c].extent;
        out.stats.splitCharts += charts[c].split ? 1 : 0;
    }
    auto packing = packCharts(extents.data(), extents.size(), options.pack);
    if (!packing) return makeError(packing.error().code, "model \"" + model.name + "\": " + packing.error().message);
    // The texture is allocated whole: refuse sizes no machine here holds (4 GiB).
    const std::uint64_t textureBytes = std::uint64_t(packing->pages) * options.pack.width * options.pack.height * 4;
    if (textureBytes > (std::uint64_t(4) << 30))
        return makeError(ErrorCode::OutOfRange,
                         "model \"" + model.name +
                             "\" does not fit the texture budget: " + std::to_string(packing->pages) + " pages of " +
                             std::to_string(options.pack.width) + "x" + std::to_string(options.pack.height) + " need " +
                             std::to_string(textureBytes >> 20) + " MiB, over 4096 MiB");
    out.width = options.pack.width;
    out.height = options.pack.height;
    out.pages = packing->pages;
    out.density = packing->density;

    // Output mesh: per part, one vertex per (chart, vertex); triangles keep their source order.
    out.parts.resize(parts.size());
    for (std::size_t p = 0; p < parts.size(); ++p) {
        BakedPart& bp = out.parts[p];
        bp.source = parts[p].source;
        bp.name = parts[p].part->name;
        bp.kind = parts[p].part->kind;
        bp.record = parts[p].part->record;
        bp.indices.resize(parts[p].indices.size());
    }
    out.charts.resize(charts.size());
    for (std::size_t c = 0; c < charts.size(); ++c) {
        const Flattened& f = charts[c];
        emitChart(f, packing->placements[c], parts[f.part].part->mesh, model.origin, out.density, out.width, out.height,
                  out.parts[f.part]);
        out.charts[c] = {f.part, packing->placements[c], f.distortion};
    }
    out.stats.secondsPack = now() - t0;
    if (progress) progress("pack", 1.0);

    // 4. Raster.
    t0 = now();
    out.texels.assign(std::size_t(out.pages) * out.height * out.width, kNoRecord);
    std::optional<BlockIndex> blockIndex;
    FieldIds field;
    if (options.field.enabled()) {
        if (options.field.blocks) {
            blockIndex.emplace(*options.field.blocks);
            field.index = &*blockIndex;
        }
        field.options = &options.field;
        // A vertex property gives classes only to the records of parts that have it.
        for (std::size_t p = 0; p < out.parts.size(); ++p)
            if (out.parts[p].record != kNoRecord && (options.field.blocks || columns[p] >= 0))
                field.partRecords.push_back(out.parts[p].record);
        std::sort(field.partRecords.begin(), field.partRecords.end());
        field.partRecords.erase(std::unique(field.partRecords.begin(), field.partRecords.end()),
                                field.partRecords.end());
        field.base = model.attributes.nextId();
        out.fieldRecords = fieldClassRecords(model.attributes, field);
    }
    parallelFor(charts.size(), threads, "raster", progress, [&](std::size_t c) {
        const BakedPart& bp = out.parts[charts[c].part];
        const int column = columns[charts[c].part];
        if (field.index || column >= 0)
            rasterChartField(charts[c], packing->placements[c], bp, parts[charts[c].part].part->mesh, field, column,
                             out.width, out.height, out.texels.data());
        else
            rasterChart(charts[c], packing->placements[c], bp, out.width, out.height, out.texels.data());
    });
    finishStats(out);
    out.stats.secondsRaster = now() - t0;
    return out;
}

Status rebakePart(const Model& model, std::size_t part, BakedModel& baked, const BakeOptions& options) {
    if (auto s = checkOptions(options); !s) return s.error();
    if (options.field.enabled() || !baked.fieldRecords.empty())
        return makeError(ErrorCode::Unsupported,
                         "re-bake of a bake with a field (block model or vertex property) is not supported: bake in "
                         "full");
    if (part >= baked.parts.size())
        return makeError(ErrorCode::InvalidArgument, "re-bake: part " + std::to_string(part) + " of " +
                                                         std::to_string(baked.parts.size()) + " baked parts");
    const Part* source = sourcePart(model, baked.parts[part].source);
    if (!source)
        return makeError(ErrorCode::InvalidArgument, "re-bake: the model no longer has part " + baked.parts[part].name);
    if (auto s = checkPart(*source); !s) return s.error();
    if (source->mesh.triangleCount() == 0)
        return makeError(ErrorCode::InvalidArgument, "re-bake: part \"" + source->name + "\" has no triangles");
    const unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    const PackOptions& po = baked.pack;
    const auto p32 = static_cast<std::uint32_t>(part);

    PartWork w{source, baked.parts[part].source, {}, {}};
    chartPart(w, options.charts);
    std::vector<std::vector<Flattened>> slots(w.charts.count());
    const double maxExtent = maxExtentAt(baked.density, po);
    parallelFor(w.charts.count(), threads, "lscm", {},
                [&](std::size_t c) { flattenChart(w, p32, c, maxExtent, slots[c]); });
    std::vector<Flattened> charts;
    for (auto& s : slots)
        for (auto& f : s) charts.push_back(std::move(f));

    std::vector<Placement> placed(baked.charts.size());
    std::vector<std::uint8_t> replaced(baked.charts.size());
    for (std::size_t c = 0; c < baked.charts.size(); ++c) {
        placed[c] = baked.charts[c].rect;
        replaced[c] = baked.charts[c].part == p32;
    }
    std::vector<glm::dvec2> extents(charts.size());
    for (std::size_t c = 0; c < charts.size(); ++c) extents[c] = charts[c].extent;
    auto packing = packIntoFreeSpace(placed.data(), replaced.data(), placed.size(), baked.pages, extents.data(),
                                     extents.size(), baked.density, po);
    if (!packing)
        return makeError(packing.error().code, "re-bake of \"" + source->name + "\": " + packing.error().message);
    const std::vector<Placement>& placements = packing->placements;
    const std::uint32_t pages = packing->pages;

    if (pages > baked.pages) {
        const std::uint64_t bytes = std::uint64_t(pages) * baked.width * baked.height * 4;
        if (bytes > (std::uint64_t(4) << 30))
            return makeError(ErrorCode::OutOfRange, "re-bake of \"" + source->name + "\" needs " +
                                                        std::to_string(pages) + " texture pages, over 4096 MiB");
        baked.texels.resize(std::size_t(pages) * baked.height * baked.width, kNoRecord);
        baked.pages = pages;
    }
    // Commit: clear the part's old texels (its padded rectangles are its own), replace its
    // charts, mesh and texels.
    for (const auto& c : baked.charts) {
        if (c.part != p32) continue;
        std::uint32_t* page = baked.texels.data() + std::size_t(c.rect.page) * baked.height * baked.width;
        for (long y = long(c.rect.y) - 1; y <= long(c.rect.y + c.rect.h); ++y)
            for (long x = long(c.rect.x) - 1; x <= long(c.rect.x + c.rect.w); ++x)
                if (x >= 0 && y >= 0 && x < long(baked.width) && y < long(baked.height))
                    page[std::size_t(y) * baked.width + std::size_t(x)] = kNoRecord;
    }
    baked.charts.erase(
        std::remove_if(baked.charts.begin(), baked.charts.end(), [&](const ChartSlot& c) { return c.part == p32; }),
        baked.charts.end());
    BakedPart& bp = baked.parts[part];
    bp.name = source->name;
    bp.kind = source->kind;
    bp.record = source->record;
    bp.positions.clear();
    bp.positionsLo.clear();
    bp.uvs.clear();
    bp.indices.assign(source->mesh.indices.size(), 0);
    for (std::size_t c = 0; c < charts.size(); ++c) {
        emitChart(charts[c], placements[c], source->mesh, model.origin, baked.density, baked.width, baked.height, bp);
        baked.charts.push_back({p32, placements[c], charts[c].distortion});
    }
    for (std::size_t c = 0; c < charts.size(); ++c)
        rasterChart(charts[c], placements[c], bp, baked.width, baked.height, baked.texels.data());
    finishStats(baked);
    return {};
}

}  // namespace geoslice::bake
