// The incremental re-bake: one part charted and flattened again, packed into the free space of
// an existing bake (pack.cpp, packIntoFreeSpace), and its old texels, charts and mesh replaced.
#include <algorithm>
#include <string>

#include "bake/bake_internal.hpp"

namespace geoslice::bake {

using namespace bake_detail;

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
