#include "renderer/passes/cut_pass.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "renderer/passes/block_caps.hpp"

namespace geoslice {
namespace {

// Front faces are pushed this far away from the viewer so that a back face coincident with
// them wins (renderer/slice_renderer.hpp). Units are the depth buffer's resolution at that depth; the
// factor scales with the triangle's depth slope and covers interpolation rounding between
// two different triangulations of one surface (fault walls). Too large a factor lets a
// nested body's back face win through its own front face where it is thin along the ray
// (its rim). Measured against the oracle (tests/gl, 519k compared pixels, 50k triangles):
// factor/units 1/4: 107 disagree; 0/4: 2673; 0/16: 184; 0.25/4: 39; 0.1/4: 19; 0.05/8: 12.
constexpr float kFrontOffsetFactor = 0.05f;
constexpr float kFrontOffsetUnits = 8.0f;

class CutPass {
public:
    CutPass(const GlFunctions& gl, const GpuModel& model, const CutPassInput& in, ClusterSelection& selection,
            CutPassCounts& counts)
        : gl_(gl), in_(in), u_(*in.uniforms), selection_(selection), counts_(counts) {
        if (!in.hidden || in.hidden->empty()) return;
        for (const auto& p : model.parts())
            if (p.bodyIndex >= 0) {
                if (bodyPart_.size() <= std::size_t(p.bodyIndex))
                    bodyPart_.resize(std::size_t(p.bodyIndex) + 1, nullptr);
                bodyPart_[std::size_t(p.bodyIndex)] = &p;
            }
    }

    bool hidden(RecordId r) const {
        return in_.hidden && std::binary_search(in_.hidden->begin(), in_.hidden->end(), r);
    }

    // The container a nested body's front faces show the cap of: its own, or with bodies
    // hidden the nearest shown one up the nesting (null: none, the body is capped as a
    // top-level one).
    const GpuModel::DrawPart* shownContainer(const GpuModel::DrawPart& p) const {
        if (bodyPart_.empty()) return nullptr;
        for (int c = p.containerBody; c >= 0 && std::size_t(c) < bodyPart_.size();) {
            const GpuModel::DrawPart* cp = bodyPart_[std::size_t(c)];
            if (!cp) return nullptr;
            if (!hidden(cp->record)) return cp;
            c = cp->containerBody;
        }
        return nullptr;
    }

    bool cancelled() const { return in_.cancel && in_.cancel->load(std::memory_order_relaxed); }

    // fetch: the drawn surface's own texels hold the record to show (shaders/slice.frag); not
    // for a nested body's front faces, which show their container's cap.
    void setFace(int role, const GpuModel::DrawPart& p, RecordId capRecord, const glm::vec4& capColour,
                 bool fetch = true) const {
        const GLuint prog = in_.program;
        gl_.ProgramUniform1i(prog, u_.faceRole, role);
        if (in_.baked) gl_.ProgramUniform1i(prog, u_.fetch, fetch ? 1 : 0);
        gl_.ProgramUniform1ui(prog, u_.record, p.record);
        gl_.ProgramUniform4fv(prog, u_.colour, 1, glm::value_ptr(p.colour));
        gl_.ProgramUniform1ui(prog, u_.capRecord, capRecord);
        gl_.ProgramUniform4fv(prog, u_.capColour, 1, glm::value_ptr(capColour));
        const BlockCaps* caps = in_.blockCaps;
        const int code = role != 1 ? 0 : caps && caps->clips(capRecord) ? kStencilBlockCap : kStencilCap;
        gl_.StencilFunc(GL_ALWAYS, code, 0xff);
    }

    // Ranges of one part go out as one glMultiDrawElementsBaseVertex: llvmpipe pays its
    // per-draw validation once instead of per cluster (thousands of clusters at L4).
    void flush(const DrawBatch& batch) const {
        if (batch.empty()) return;
        gl_.MultiDrawElementsBaseVertex(GL_TRIANGLES, batch.counts.data(), GL_UNSIGNED_INT, batch.offsets.data(),
                                        GLsizei(batch.counts.size()), batch.baseVertices.data());
        for (GLsizei c : batch.counts) counts_.trianglesDrawn += std::size_t(c) / 3;
        ++counts_.drawCalls;
    }

    // Each cluster at the coarsest level its budget allows (-1: skipped).
    // shiftSign: 0 back faces (drawn where they are), +1 front faces and surfaces (away).
    // offsetBase: the pass draws with the front-face polygon offset on.
    void draw(const GpuModel::DrawPart& p, float shiftSign, bool offsetBase) const {
        if (cancelled()) return;
        selection_.select(p, *in_.budgets, in_.allowGroups, in_.exaggeration);
        counts_.clustersSkipped += selection_.skipped;
        flush(selection_.full);
        if (selection_.anySimplified) drawSimplified(shiftSign > 0.0f, offsetBase);
    }

    // Back faces of bodies: the ray is inside that body -> its cap.
    void backFaces(const GpuModel& model) const {
        gl_.StencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
        gl_.CullFace(GL_FRONT);
        gl_.Disable(GL_POLYGON_OFFSET_FILL);
        for (const auto& p : model.parts())
            if (p.body && !hidden(p.record)) {
                setFace(1, p, p.record, p.colour);
                draw(p, 0.0f, false);
            }
    }

    // Front faces of bodies, pushed back so that coincident back faces win: the exterior of
    // a top-level body, or the cap of the container of a nested one.
    void frontFaces(const GpuModel& model) const {
        gl_.CullFace(GL_BACK);
        gl_.Enable(GL_POLYGON_OFFSET_FILL);
        gl_.PolygonOffset(kFrontOffsetFactor, kFrontOffsetUnits);
        for (const auto& p : model.parts()) {
            if (!p.body || hidden(p.record)) continue;
            RecordId capRecord = p.containerRecord;
            glm::vec4 capColour = p.containerColour;
            if (capRecord != kNoRecord && hidden(capRecord)) {
                const GpuModel::DrawPart* c = shownContainer(p);
                capRecord = c ? c->record : kNoRecord;
                capColour = c ? c->colour : capColour;
            }
            if (capRecord == kNoRecord) {
                setFace(0, p, p.record, p.colour);
                draw(p, 1.0f, true);
                continue;
            }
            // A nested body shares no surface with its container, so its front faces need no
            // offset; with one, its own back face won through them where the body is thin
            // along the ray (specks of the nested body's cap at its rim).
            setFace(1, p, capRecord, capColour, false);
            gl_.Disable(GL_POLYGON_OFFSET_FILL);
            draw(p, 1.0f, false);
            gl_.Enable(GL_POLYGON_OFFSET_FILL);
            gl_.PolygonOffset(kFrontOffsetFactor, kFrontOffsetUnits);
        }
        gl_.Disable(GL_POLYGON_OFFSET_FILL);
    }

    // Open surfaces, both sides, never over a cut face (stencil 1).
    void surfaces(const GpuModel& model) const {
        gl_.Disable(GL_CULL_FACE);
        gl_.StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
        for (const auto& p : model.parts())
            if (!p.body && !hidden(p.record)) {
                setFace(0, p, p.record, p.colour);
                gl_.StencilFunc(GL_EQUAL, 0, 0xff);
                draw(p, 1.0f, false);
            }
    }

private:
    // Simplified clusters after the full-detail ones, so that the pass state changes twice
    // per part. Their front faces go back by twice the level's error: along the ray (shader)
    // for surfaces facing the viewer, and by a slope-scaled polygon offset for grazing ones
    // (the error projects to at most lodPixelError pixels, which moves depth by at most that
    // many depth slopes). Back faces stay: moving them would reorder back faces among
    // themselves. One offset per pass: llvmpipe compiles a setup variant per distinct
    // polygon offset.
    void drawSimplified(bool shift, bool offsetBase) const {
        const GLuint prog = in_.program;
        if (shift) {
            gl_.Enable(GL_POLYGON_OFFSET_FILL);
            gl_.PolygonOffset(3.0f * in_.lodPixelError + (offsetBase ? kFrontOffsetFactor : 0.0f),
                              offsetBase ? kFrontOffsetUnits : 0.0f);
        }
        for (int k = 0; k <= ClusterSelection::kShiftBuckets; ++k) {
            const DrawBatch& batch = selection_.pushed[std::size_t(k)];
            if (batch.empty()) continue;
            if (shift) gl_.ProgramUniform1f(prog, u_.lodShift, std::ldexp(1.0f, k - 9));
            flush(batch);
        }
        if (!shift) return;
        gl_.ProgramUniform1f(prog, u_.lodShift, 0.0f);
        if (offsetBase)
            gl_.PolygonOffset(kFrontOffsetFactor, kFrontOffsetUnits);
        else
            gl_.Disable(GL_POLYGON_OFFSET_FILL);
    }

    const GlFunctions& gl_;
    const CutPassInput& in_;
    const SliceUniforms& u_;
    ClusterSelection& selection_;
    CutPassCounts& counts_;
    std::vector<const GpuModel::DrawPart*> bodyPart_;  // by body index; only with bodies hidden
};

}  // namespace

void drawCutPass(const GlFunctions& gl, const GpuModel& model, const CutPassInput& in, ClusterSelection& selection,
                 CutPassCounts& counts) {
    const CutPass pass(gl, model, in, selection, counts);
    pass.backFaces(model);
    pass.frontFaces(model);
    if (in.drawSurfaces) pass.surfaces(model);
}

}  // namespace geoslice
