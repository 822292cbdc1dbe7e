// Which clusters of a GpuModel (renderer/gpu_model.hpp) a frame of the slicing pass draws, and
// at which level of detail. CPU only (no GL call, no context needed): unit-tested in
// tests/unit/cluster_selection_test.cpp.
//
// Per cell of the model's cluster grid a budget, the geometric error (metres) its clusters may
// have in this frame: -1 skip (every corner on the removed side of a plane that may cull, or
// beyond one clip-space plane: exact, they would give no fragment), 0 full detail (no level of
// detail, or a plane crosses the cell, or the cell lies past a convex cut's exit where the
// fragment stage reads which body a ray leaves the kept region in), else lodPixelError pixels
// in metres at the cell's distance (orthographic: the frame's scale; perspective: at the
// cell's nearest point to the eye), divided by the exaggeration factor when it is above 1.
// Then per part: each cluster at the coarsest level its cell's budget allows, groups
// (GpuModel::DrawPart::groups) in place of their members where every member allows the
// group's error, ranges batched for one glMultiDrawElementsBaseVertex per batch.
// Frames: local (world - Model::origin); display-local = local with z times the factor.
// Any thread.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "renderer/gpu_model.hpp"

namespace geoslice {

// What a frame needs to know to budget the cells.
struct ClusterFrame {
    glm::dmat4 viewProj{1.0};          // local -> clip, exaggeration included
    std::vector<glm::dvec4> planes;    // local (n, d), unit normals
    std::vector<std::uint8_t> culls;   // per plane: 1 if cells on its removed side may be skipped
    bool unionMode = false;            // kept = positive side of any plane (else of every plane)
    bool lod = false;                  // simplified levels allowed
    bool perspective = false;          // else orthographic
    double orthoPixelsPerMetre = 0.0;  // orthographic: pixels per display metre
    double perspPixelsPerMetre = 0.0;  // perspective: pixels per display metre at distance 1
    glm::dvec3 eyeDisplayLocal{0.0};   // perspective: the eye, display-local metres
    double exaggeration = 1.0;         // vertical factor (view/exaggeration.hpp)
    float lodPixelError = 1.0f;        // pixels, > 0
};

// Which planes may cull: every plane, except for a convex cut (intersection of two or more
// planes), which keeps the cells past its exit: there only a plane with the eye (local frame;
// nullptr for a profile) on its removed side culls.
std::vector<std::uint8_t> cullingPlanes(const std::vector<glm::dvec4>& planesLocal, bool convexCut,
                                        const glm::dvec3* eyeLocal);

// The budget of every cell (`cellBounds`, local frame; invalid boxes stay 0), see above.
std::vector<float> cellBudgets(const std::vector<Aabb>& cellBounds, const ClusterFrame& frame);

// Index ranges drawn by one glMultiDrawElementsBaseVertex. A range that continues the one
// before (same base vertex, next index) extends it.
struct DrawBatch {
    std::vector<GLsizei> counts;       // indices per range
    std::vector<const void*> offsets;  // byte offset of each range's first index (uint32 indices)
    std::vector<GLint> baseVertices;
    void add(std::size_t firstIndex, GLsizei count, GLint baseVertex);
    void clear() { counts.clear(), offsets.clear(), baseVertices.clear(); }
    bool empty() const { return counts.empty(); }
    std::size_t firstIndex(std::size_t range) const {
        return reinterpret_cast<std::uintptr_t>(offsets[range]) / sizeof(std::uint32_t);
    }
};

// The ranges of one part for one pass. Simplified ranges are sorted into buckets by how far
// their front faces are pushed back along the ray (2 x error x max(1, exaggeration), metres):
// bucket k holds pushes in (2^(k-9), 2^(k-8)], bucket 0 everything below, so that each bucket
// is one draw with one uniform value (shaders/slice.vert uLodShift = 2^(k-9)).
class ClusterSelection {
public:
    static constexpr int kShiftBuckets = 24;

    // Replaces the previous selection. `allowGroups`: not for a union or a convex cut (two or
    // more planes). With one plane every kept cell lies in its half-space, which is convex, so
    // a group (in the hull of its members) meets no plane; a union's kept region is not
    // convex, and a convex cut keeps cells past its exit too.
    void select(const GpuModel::DrawPart& part, const std::vector<float>& budgets, bool allowGroups,
                double exaggeration);

    DrawBatch full;                                   // full-detail ranges, index order
    std::array<DrawBatch, kShiftBuckets + 1> pushed;  // simplified ranges by push bucket
    bool anySimplified = false;
    std::size_t skipped = 0;  // clusters skipped in this selection

private:
    std::vector<std::uint8_t> handled_;  // per cluster: drawn by a group
};

}  // namespace geoslice
