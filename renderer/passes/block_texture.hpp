// Block-model colouring of GL cut faces (issue 15 item 1, GL views): the block model's class
// index per cell (section/blocks/block_section.hpp cellClassIndex: 0 = no value, k + 1 = class k) in
// a 3D integer texture (R8UI, one texel per cell, texelFetch = nearest), with the grid's
// frame, the class colours and the records of the clipping bodies as uniforms of the slicing
// program (shaders/slice.frag).
//
// Rule (the profile engine's, section/blocks/block_section.hpp colourPixelsByBlocks): a cap
// fragment (the section face drawn where the cut opens a body) whose record is a clipping
// body's takes the colour of the class of the cell holding the point where its view ray
// crosses the cut plane (the cap lies on the plane; the fragment's own position is on the
// body's far surface behind it). With several planes that point is where the ray enters the
// kept region: the last plane crossed for an intersection, the first for a union. Cells are
// half-open boxes, as BlockModel::cellAt; cells with no value keep the body's colour.
// The point is computed in float in the local frame (world - Model::origin): within about
// 1e-5 m of the exact one for models of a few km, so pixels whose point lies that close to a
// cell face may take the neighbouring cell.
// The cell + 1 goes to the cell buffer (colour attachment 2, shaders/slice.frag oCell).
// Curvilinear block models (SGrid, CellShape::Hexahedron) are refused by upload() with a
// named reason: a texel per cell addresses box cells only; their GL views draw the cells'
// exact pieces instead (renderer/passes/block_caps.hpp).
//
// Threads: upload, apply and destroy on the GlContext's thread. GL state: upload() binds
// nothing (DSA; sets GL_UNPACK_ALIGNMENT to 1 and back to 4); apply() binds the class texture
// to unit 2, the clip records' texture to unit 3, and sets the program's uBlock* uniforms (the
// GS_BLOCKS variants of shaders/slice.frag).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "model/attributes.hpp"
#include "model/blocks/block_model.hpp"
#include "model/result.hpp"
#include "renderer/gl/gl_context.hpp"

namespace geoslice {

constexpr int kMaxBlockClasses = 65;  // 64 breaks
// Clipping bodies' records a GL view can tell apart: sorted in an R32UI texture of rows of
// kBlockClipRow texels (unit 3), found by binary search in the shader (16 steps at most).
constexpr int kBlockClipRow = 1024;  // shaders/slice.frag's row length
constexpr int kMaxBlockClipRecords = 1 << 16;

class BlockTexture {
public:
    // Uploads the grid of `blocks` with `cellClass` (one byte per cell, linear index),
    // `colours` (one per class) and the clipping records. Errors: InvalidArgument when the
    // sizes disagree or there are more than kMaxBlockClasses classes or kMaxBlockClipRecords
    // records; OutOfRange when a side exceeds GL_MAX_3D_TEXTURE_SIZE (named).
    static Result<std::unique_ptr<BlockTexture>> upload(GlContext& context, const BlockModel& blocks,
                                                        const std::vector<std::uint8_t>& cellClass,
                                                        const std::vector<Rgba8>& colours,
                                                        const std::vector<RecordId>& clipRecords);
    ~BlockTexture();
    BlockTexture(const BlockTexture&) = delete;
    BlockTexture& operator=(const BlockTexture&) = delete;

    // Binds the textures (units 2 and 3) and sets the uniforms of `program` for a model whose
    // local frame has origin `modelOrigin` (world).
    void apply(GLuint program, const glm::dvec3& modelOrigin) const;
    // Unbinds units 2 and 3.
    void release() const;

private:
    struct Impl;
    explicit BlockTexture(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace geoslice
