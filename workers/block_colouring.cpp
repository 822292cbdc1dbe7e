#include "workers/block_colouring.hpp"

#include "api/view.hpp"

namespace geoslice::workers {

bool colourWithTexture(const BlockModel& blocks, BoxBlocks mode, const GlContext& context) {
    return blocks.shape == CellShape::Box &&
           (mode == BoxBlocks::Texture || (mode == BoxBlocks::Auto && !context.info().software));
}

void BlockColouring::setOn(SliceRequest& request) const {
    request.blocks = texture.get();
    request.blockCaps = caps.get();
}

Result<BlockColouring> uploadBlockColouring(GlContext& context, const Model& model,
                                            const std::vector<RecordId>& clipRecords, const PropertyClasses& classes,
                                            const std::vector<Plane>& planes, bool texture) {
    if (!model.blocks) return makeError(ErrorCode::InvalidArgument, "the model has no block model");
    const BlockModel& blocks = *model.blocks;
    BlockColouring out;
    if (texture) {
        auto uploaded =
            BlockTexture::upload(context, blocks, cellClassIndex(blocks, classes), classes.colours, clipRecords);
        if (!uploaded) return uploaded.error();
        out.texture = std::move(uploaded.value());
        return out;
    }
    auto pieces = api::blockCapTriangles(model, classes, planes);
    if (!pieces) return pieces.error();
    std::vector<BlockCaps::PlaneRange> ranges;
    for (const auto& r : pieces->planes) ranges.push_back({r.first, r.valued, r.unvalued});
    auto uploaded =
        BlockCaps::upload(context, pieces->positions, pieces->cellClass, ranges, classes.colours, clipRecords);
    if (!uploaded) return uploaded.error();
    out.caps = std::move(uploaded.value());
    return out;
}

}  // namespace geoslice::workers
