// Block-model colouring of GL cut faces by exact cell pieces: the GL path for block models
// whose cells a 3D texture cannot address (curvilinear SGrid cells, CellShape::Hexahedron;
// box grids use renderer/passes/block_texture.hpp). The caller (api/view.hpp blockCapTriangles)
// cuts the cells with each plane of the view exactly as the profile engine does (a
// tetrahedron's cut is a triangle or a quadrilateral, section/blocks/block_section.hpp
// cellPolygons) and hands the pieces over as triangles in the model's local frame with their
// cell and class; this uploads them and draws them on the cut faces.
//
// Rule (the profile engine's, and the box texture's): a cap pixel of a clipping body takes the
// class colour of the cell holding the point where its view ray enters the kept region, and
// the cell + 1 goes to the cell buffer (cells with no value: the cell, the body's colour).
// How: the slicing pass marks the pixels whose visible fragment is a clipping body's cap
// (stencil code kStencilBlockCap); then the pieces of plane i are drawn with the stencil
// test, no depth test, where the ray crosses plane i towards its kept side and every other
// plane keeps the point (intersection) or removes it (union): that piece holds the ray's
// entry point (shaders/block_cap.frag). The rasteriser samples the exact pieces at pixel
// centres; neighbouring pieces share bit-identical vertices, so each pixel centre falls in one
// piece (GL's fill rule), and pixels near a cell face may take the neighbouring cell only by
// the float32 rounding of the vertices in the local frame.
//
// Threads: upload, draw and destroy on the GlContext's thread. GL state: draw() binds its
// program and vertex array and sets colour masks, depth, stencil and cull state as it
// documents; the caller restores what it needs.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "model/attributes.hpp"
#include "model/result.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/passes/block_texture.hpp"

namespace geoslice {

class GlProgram;

// Stencil codes of the slicing pass (renderer/slice_renderer.cpp): bit 0 a cap (fault traces
// test it), bit 1 a cap of a body whose pieces BlockCaps draws.
constexpr int kStencilCap = 1;
constexpr int kStencilBlockCap = 3;

class BlockCaps {
public:
    // One plane's triangles: `first` vertex, then `valued` vertices of cells with a value,
    // then `unvalued` vertices of cells without one (drawn into the cell buffer only).
    struct PlaneRange {
        std::uint32_t first = 0, valued = 0, unvalued = 0;
    };
    // `positions`: 3 per triangle, local frame (world - Model::origin) of the GpuModel it is
    // drawn with; `cellClass`: per vertex (cell + 1, class: 0 = no value, k + 1 = class k);
    // `planes`: per plane of the SliceRequest, in its order. Errors: InvalidArgument when the
    // sizes disagree, a range leaves the arrays, there are more than kMaxBlockClasses
    // (renderer/passes/block_texture.hpp) classes or a class index beyond them.
    static Result<std::unique_ptr<BlockCaps>> upload(GlContext& context, std::span<const glm::vec3> positions,
                                                     std::span<const glm::uvec2> cellClass,
                                                     std::span<const PlaneRange> planes,
                                                     const std::vector<Rgba8>& colours,
                                                     const std::vector<RecordId>& clipRecords);
    ~BlockCaps();
    BlockCaps(const BlockCaps&) = delete;
    BlockCaps& operator=(const BlockCaps&) = delete;

    // Whether `record` is a clipping body's (its caps get kStencilBlockCap).
    bool clips(RecordId record) const;
    std::size_t planeCount() const;
    std::size_t triangleCount() const;

    // Draws the pieces with `program` (shaders/block_cap.*, its uViewProj, uPlanes,
    // uPlaneCount, uUnion and uEye already set) on pixels of stencil kStencilBlockCap:
    // colour attachment 0 (class colours) and 2 (cells), not 1; no depth test or write, no
    // culling, pixel-centre coverage (GL_MULTISAMPLE off while drawing). Leaves colour masks
    // all on, GL_MULTISAMPLE on, depth test off, depth mask off, stencil op KEEP.
    void draw(const GlProgram& program) const;

private:
    struct Impl;
    explicit BlockCaps(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace geoslice
