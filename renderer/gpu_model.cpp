#include "renderer/gpu_model.hpp"

#include <limits>

namespace geoslice {
namespace {

glm::vec4 recordColour(const Model& model, RecordId id) {
    Rgba8 c;
    if (const AttributeRecord* r = model.attributes.find(id)) c = r->colour;
    return glm::vec4(c.r, c.g, c.b, c.a) / 255.0f;
}

}  // namespace

Result<std::unique_ptr<GpuModel>> GpuModel::upload(GlContext& context, const Model& model) {
    const GlFunctions& gl = context.gl();
    std::unique_ptr<GpuModel> g(new GpuModel(context));
    g->origin_ = model.origin;
    g->bounds_ = model.bounds();
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    auto add = [&](const Part& part, bool body) -> Status {
        const Mesh& mesh = part.mesh;
        if (mesh.indices.empty()) return {};
        if (positions.size() > std::size_t(std::numeric_limits<GLint>::max()) ||
            indices.size() + mesh.indices.size() > std::size_t(std::numeric_limits<GLsizei>::max()))
            return makeError(ErrorCode::OutOfRange, "model " + model.name + " is too large for one GL buffer");
        DrawPart d;
        d.baseVertex = GLint(positions.size());
        d.firstIndex = indices.size();
        d.indexCount = GLsizei(mesh.indices.size());
        d.body = body;
        d.record = part.record;
        d.colour = recordColour(model, part.record);
        if (body && part.report.parent >= 0 && std::size_t(part.report.parent) < model.bodies.size()) {
            d.containerRecord = model.bodies[std::size_t(part.report.parent)].record;
            d.containerColour = recordColour(model, d.containerRecord);
        }
        std::vector<glm::vec3> local = model.localPositions(mesh);
        positions.insert(positions.end(), local.begin(), local.end());
        indices.insert(indices.end(), mesh.indices.begin(), mesh.indices.end());
        g->parts_.push_back(d);
        g->triangles_ += mesh.triangleCount();
        return {};
    };
    for (const Part& p : model.bodies)
        if (auto s = add(p, true); !s) return s.error();
    for (const Part& p : model.surfaces)
        if (auto s = add(p, false); !s) return s.error();
    if (positions.empty())
        return makeError(ErrorCode::InvalidArgument, "model " + model.name + " has no triangles to draw");

    gl.CreateBuffers(1, &g->vertexBuffer_);
    gl.NamedBufferStorage(g->vertexBuffer_, GLsizeiptr(positions.size() * sizeof(glm::vec3)), positions.data(), 0);
    gl.CreateBuffers(1, &g->indexBuffer_);
    gl.NamedBufferStorage(g->indexBuffer_, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(), 0);
    gl.CreateVertexArrays(1, &g->vao_);
    gl.VertexArrayVertexBuffer(g->vao_, 0, g->vertexBuffer_, 0, sizeof(glm::vec3));
    gl.VertexArrayElementBuffer(g->vao_, g->indexBuffer_);
    gl.EnableVertexArrayAttrib(g->vao_, 0);
    gl.VertexArrayAttribFormat(g->vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl.VertexArrayAttribBinding(g->vao_, 0, 0);
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR)
        return makeError(
            e == GL_OUT_OF_MEMORY ? ErrorCode::OutOfRange : ErrorCode::Internal,
            "uploading model " + model.name + " (" + std::to_string(g->triangles_) + " triangles): " + glErrorName(e));
    return g;
}

GpuModel::~GpuModel() {
    const GlFunctions& gl = context_.gl();
    if (vao_) gl.DeleteVertexArrays(1, &vao_);
    if (vertexBuffer_) gl.DeleteBuffers(1, &vertexBuffer_);
    if (indexBuffer_) gl.DeleteBuffers(1, &indexBuffer_);
}

}  // namespace geoslice
