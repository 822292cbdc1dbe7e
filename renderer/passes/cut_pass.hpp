// The cut pass of the slicing pass (renderer/slice_renderer.cpp): the bodies' back faces
// (the ray is inside that body: its cap), their front faces pushed back by a polygon offset
// (the exterior, or the cap of a nested body's container), then the open surfaces, each part
// drawn cluster by cluster at the level of detail its budget allows (renderer/lod/). Writes
// colour, record id, depth and the stencil cap codes of renderer/passes/block_caps.hpp.
// Threads: the owning GlContext's thread. GL state: expects the slice program bound with its
// per-view uniforms set, the model's vertex array bound, depth and stencil tests on and cull
// face on; leaves polygon offset off, cull face on unless open surfaces were drawn, the
// stencil op KEEP when they were (else REPLACE), and uLodShift 0.
#pragma once

#include <atomic>
#include <cstddef>
#include <vector>

#include "renderer/gl/gl_functions.hpp"
#include "renderer/gpu_model.hpp"
#include "renderer/lod/cluster_selection.hpp"

namespace geoslice {

class BlockCaps;

// Uniform locations of a slice program variant (shaders/slice.vert|frag).
struct SliceUniforms {
    GLint viewProj = -1, planes = -1, planeCount = -1, unionMode = -1, faceRole = -1, record = -1, colour = -1,
          capRecord = -1, capColour = -1, lightDir = -1, shadeScale = -1, eye = -1, lodShift = -1, baked = -1,
          fetch = -1, background = -1, snap = -1;
};

struct CutPassInput {
    GLuint program = 0;
    const SliceUniforms* uniforms = nullptr;
    const std::vector<float>* budgets = nullptr;  // per cell (cellBudgets of cluster_selection.hpp)
    bool allowGroups = true;                      // LOD groups may replace clusters (no union or convex cut)
    double exaggeration = 1.0;                    // vertical, for the clusters' error along the ray
    float lodPixelError = 1.0f;
    bool baked = false;                    // records fetched from the model's id texture
    const BlockCaps* blockCaps = nullptr;  // caps of clipping bodies get kStencilBlockCap
    bool drawSurfaces = true;
    const std::vector<RecordId>* hidden = nullptr;  // sorted records not drawn (SliceRequest::hidden); null: none
    const std::atomic<bool>* cancel = nullptr;      // checked before each part
};

struct CutPassCounts {
    std::size_t trianglesDrawn = 0, clustersSkipped = 0, drawCalls = 0;
};

// Draws the pass; `selection` is scratch reused across parts (and calls).
void drawCutPass(const GlFunctions& gl, const GpuModel& model, const CutPassInput& in, ClusterSelection& selection,
                 CutPassCounts& counts);

}  // namespace geoslice
