#include "renderer/passes/block_caps.hpp"

#include <algorithm>
#include <string>

#include "renderer/gl/gl_objects.hpp"
#include "renderer/gl/gl_program.hpp"

namespace geoslice {

struct BlockCaps::Impl {
    const GlFunctions* gl = nullptr;
    GlBuffer positions, cells;
    GlVertexArray vao;
    std::vector<PlaneRange> planes;
    std::vector<float> colours;         // 4 per class, straight alpha in [0, 1]
    std::vector<RecordId> clipRecords;  // sorted
    std::size_t vertices = 0;
};

BlockCaps::BlockCaps(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
BlockCaps::~BlockCaps() = default;

Result<std::unique_ptr<BlockCaps>> BlockCaps::upload(GlContext& context, std::span<const glm::vec3> positions,
                                                     std::span<const glm::uvec2> cellClass,
                                                     std::span<const PlaneRange> planes,
                                                     const std::vector<Rgba8>& colours,
                                                     const std::vector<RecordId>& clipRecords) {
    if (positions.size() != cellClass.size() || positions.size() % 3 != 0)
        return makeError(ErrorCode::InvalidArgument, "block caps: " + std::to_string(positions.size()) +
                                                         " positions and " + std::to_string(cellClass.size()) +
                                                         " cell/class pairs (3 per triangle, one per position)");
    if (colours.empty() || colours.size() > std::size_t(kMaxBlockClasses))
        return makeError(ErrorCode::InvalidArgument, "block caps: " + std::to_string(colours.size()) + " classes (1.." +
                                                         std::to_string(kMaxBlockClasses) + ")");
    for (const PlaneRange& r : planes)
        if (std::size_t(r.first) + r.valued + r.unvalued > positions.size() || r.valued % 3 != 0 || r.unvalued % 3 != 0)
            return makeError(ErrorCode::InvalidArgument, "block caps: a plane's range [" + std::to_string(r.first) +
                                                             ", +" + std::to_string(r.valued + r.unvalued) +
                                                             ") leaves the " + std::to_string(positions.size()) +
                                                             " vertices or splits a triangle");
    for (const glm::uvec2& c : cellClass)
        if (c.y > colours.size())
            return makeError(ErrorCode::InvalidArgument, "block caps: class index " + std::to_string(c.y) +
                                                             " beyond the " + std::to_string(colours.size()) +
                                                             " classes");
    const GlFunctions& gl = context.gl();
    auto impl = std::make_unique<Impl>();
    impl->gl = &gl;
    impl->planes.assign(planes.begin(), planes.end());
    for (const Rgba8& c : colours)
        impl->colours.insert(impl->colours.end(), {c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, c.a / 255.0f});
    impl->clipRecords = clipRecords;
    std::sort(impl->clipRecords.begin(), impl->clipRecords.end());
    impl->vertices = positions.size();
    impl->vao = GlVertexArray::create(gl);
    const GLuint vao = impl->vao.id();
    if (!positions.empty()) {
        impl->positions = GlBuffer::create(gl);
        gl.NamedBufferStorage(impl->positions.id(), GLsizeiptr(positions.size_bytes()), positions.data(), 0);
        impl->cells = GlBuffer::create(gl);
        gl.NamedBufferStorage(impl->cells.id(), GLsizeiptr(cellClass.size_bytes()), cellClass.data(), 0);
        gl.EnableVertexArrayAttrib(vao, 0);
        gl.VertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
        gl.VertexArrayAttribBinding(vao, 0, 0);
        gl.VertexArrayVertexBuffer(vao, 0, impl->positions.id(), 0, sizeof(glm::vec3));
        gl.EnableVertexArrayAttrib(vao, 1);
        gl.VertexArrayAttribIFormat(vao, 1, 2, GL_UNSIGNED_INT, 0);
        gl.VertexArrayAttribBinding(vao, 1, 1);
        gl.VertexArrayVertexBuffer(vao, 1, impl->cells.id(), 0, sizeof(glm::uvec2));
    }
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR)
        return makeError(e == GL_OUT_OF_MEMORY ? ErrorCode::OutOfRange : ErrorCode::Internal,
                         "block caps: uploading " + std::to_string(positions.size() / 3) +
                             " triangles failed (GL error " + glErrorName(e) + ")");
    return std::unique_ptr<BlockCaps>(new BlockCaps(std::move(impl)));
}

bool BlockCaps::clips(RecordId record) const {
    return std::binary_search(impl_->clipRecords.begin(), impl_->clipRecords.end(), record);
}

std::size_t BlockCaps::planeCount() const { return impl_->planes.size(); }

std::size_t BlockCaps::triangleCount() const { return impl_->vertices / 3; }

void BlockCaps::draw(const GlProgram& program) const {
    const GlFunctions& gl = *impl_->gl;
    const GLuint prog = program.id();
    gl.ProgramUniform4fv(prog, program.uniform("uBlockColours"), GLsizei(impl_->colours.size() / 4),
                         impl_->colours.data());
    const GLint planeAt = program.uniform("uPlane");
    gl.Disable(GL_DEPTH_TEST);
    gl.DepthMask(GL_FALSE);
    gl.Disable(GL_CULL_FACE);
    // Pixel-centre coverage on a multisampled target too (every covered pixel's samples get
    // the centre's piece), as the box texture's per-pixel shader does: the cell is the one
    // at the pixel centre wherever a sample of the pixel is kept.
    gl.Disable(GL_MULTISAMPLE);
    gl.Enable(GL_STENCIL_TEST);
    gl.StencilFunc(GL_EQUAL, kStencilBlockCap, 0xff);
    gl.StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    gl.ColorMaski(1, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.ColorMaski(2, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.UseProgram(prog);
    gl.BindVertexArray(impl_->vao.id());
    for (std::size_t i = 0; i < impl_->planes.size(); ++i) {
        const PlaneRange& r = impl_->planes[i];
        if (r.valued + r.unvalued == 0) continue;
        gl.ProgramUniform1i(prog, planeAt, GLint(i));
        gl.ColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        if (r.valued) gl.DrawArrays(GL_TRIANGLES, GLint(r.first), GLsizei(r.valued));
        // Cells with no value: the cell buffer only; the cap keeps the body's colour.
        gl.ColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        if (r.unvalued) gl.DrawArrays(GL_TRIANGLES, GLint(r.first + r.valued), GLsizei(r.unvalued));
    }
    for (GLuint b = 0; b < 3; ++b) gl.ColorMaski(b, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.Enable(GL_MULTISAMPLE);
}

}  // namespace geoslice
