// The GPU colouring of a view's cut faces by a block-model property (issue 15): the one place
// that turns a colouring's classes into what SliceRequest::blocks or ::blockCaps point at,
// for the render workers (which keep what it makes, workers/gl_worker.hpp) and for
// `geoslice render --colour` (cli/cmd_render.cpp).
//
// Threads: on the GlContext's thread, as the renderer objects it makes.
#pragma once

#include <memory>
#include <vector>

#include "model/model.hpp"
#include "model/result.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/passes/block_caps.hpp"
#include "renderer/passes/block_texture.hpp"
#include "renderer/slice_renderer.hpp"
#include "section/blocks/block_section.hpp"
#include "view/plane.hpp"

namespace geoslice::workers {

// How box-cell block models colour caps: Texture, a class texture looked up per fragment
// (renderer/passes/block_texture.hpp; no CPU work for a new plane), or Pieces, the cells' exact
// pieces per plane as for curvilinear grids (renderer/passes/block_caps.hpp; a CPU cut per new
// plane set, then about the cost of the plain frame). Auto: Pieces on a software
// rasteriser (llvmpipe, L4 1024x1024, CPU time: texture 1.24-1.43x the plain frame,
// pieces 0.99-1.03x), Texture on a GPU. Curvilinear grids always use Pieces.
enum class BoxBlocks { Auto, Texture, Pieces };

// Whether `blocks` is coloured through a class texture on `context` under `mode` (then the
// colouring does not depend on the planes); otherwise through the pieces of the planes.
bool colourWithTexture(const BlockModel& blocks, BoxBlocks mode, const GlContext& context);

// What colours one view's caps: a class texture, or the exact cell pieces of its planes.
struct BlockColouring {
    std::unique_ptr<BlockTexture> texture;
    std::unique_ptr<BlockCaps> caps;
    // Points the request at it (it must outlive the render).
    void setOn(SliceRequest& request) const;
};

// Uploads the colouring of `model`'s block model (model.blocks set) by `classes`:
// `texture` (colourWithTexture) a class texture, else the pieces of `planes` (world, in the
// request's order; api/view.hpp blockCapTriangles). `clipRecords`: the clipping bodies'
// records, sorted (section/blocks/block_section.hpp blockClipRecords). Errors: the cut's (a plane
// crossing too many cells, named) and the upload's.
Result<BlockColouring> uploadBlockColouring(GlContext& context, const Model& model,
                                            const std::vector<RecordId>& clipRecords, const PropertyClasses& classes,
                                            const std::vector<Plane>& planes, bool texture);

}  // namespace geoslice::workers
