// A model uploaded to one GL context, in its local frame: float32 positions = world -
// Model::origin, computed in double on the CPU (Model::localPositions), so nothing reaches
// the GPU at a Gauss-Kruger magnitude. One vertex buffer and one index buffer for all parts;
// each part is a range drawn with glDrawElementsBaseVertex.
// Threads: create, use and destroy on the owning GlContext's thread. GL state: upload()
// creates buffers and a vertex array with DSA and leaves no binding changed.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"
#include "renderer/gl_context.hpp"

namespace geoslice {

class GpuModel {
public:
    struct DrawPart {
        GLint baseVertex = 0;
        GLsizei indexCount = 0;
        std::size_t firstIndex = 0;
        bool body = true;  // closed body (caps) or open surface
        RecordId record = kNoRecord;
        glm::vec4 colour{0.6f};                // attribute record colour, 0..1
        RecordId containerRecord = kNoRecord;  // innermost containing body (validation's parent)
        glm::vec4 containerColour{0.6f};
    };

    // Uploads every body and surface. Nesting comes from Part::report.parent, so the model
    // should have been validated (loaders do; generateSynthetic callers run validate()).
    static Result<std::unique_ptr<GpuModel>> upload(GlContext& context, const Model& model);
    ~GpuModel();
    GpuModel(const GpuModel&) = delete;
    GpuModel& operator=(const GpuModel&) = delete;

    GLuint vertexArray() const { return vao_; }
    const std::vector<DrawPart>& parts() const { return parts_; }
    const glm::dvec3& origin() const { return origin_; }
    const Aabb& worldBounds() const { return bounds_; }
    std::size_t triangleCount() const { return triangles_; }

private:
    explicit GpuModel(GlContext& context) : context_(context) {}
    GlContext& context_;
    GLuint vao_ = 0, vertexBuffer_ = 0, indexBuffer_ = 0;
    std::vector<DrawPart> parts_;
    glm::dvec3 origin_{0.0};
    Aabb bounds_;
    std::size_t triangles_ = 0;
};

}  // namespace geoslice
