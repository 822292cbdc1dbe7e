// The whole-model bake: charts per part -> LSCM per chart (charts with flipped or degenerate
// UV triangles, or too large for a page, are split and flattened again) -> one shelf packing
// for all charts -> the conservative raster of record ids with one texel of seam padding.
// Parts and charts are processed by worker threads; every result lands in a slot fixed by its
// input position, so the output does not depend on the thread count.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "bake/bake_internal.hpp"

namespace geoslice::bake {
namespace bake_detail {

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

}  // namespace bake_detail

using namespace bake_detail;

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

}  // namespace geoslice::bake
