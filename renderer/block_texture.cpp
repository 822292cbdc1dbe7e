#include "renderer/block_texture.hpp"

#include <string>

#include "renderer/gl_objects.hpp"

namespace geoslice {

struct BlockTexture::Impl {
    const GlFunctions* gl = nullptr;
    GlTexture texture;
    glm::dvec3 origin{0.0};              // world
    std::array<glm::dvec3, 3> toGrid{};  // axis[a] / size[a]: world offset -> cell units
    std::array<int, 3> dims{0, 0, 0};
    std::vector<float> colours;  // 4 per class, straight alpha in [0, 1]
    std::vector<GLuint> clip;    // records
};

BlockTexture::BlockTexture(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
BlockTexture::~BlockTexture() = default;

Result<std::unique_ptr<BlockTexture>> BlockTexture::upload(GlContext& context, const BlockModel& blocks,
                                                           const std::vector<std::uint8_t>& cellClass,
                                                           const std::vector<Rgba8>& colours,
                                                           const std::vector<RecordId>& clipRecords) {
    const GlFunctions& gl = context.gl();
    if (cellClass.size() != blocks.cellCount() || blocks.cellCount() == 0)
        return makeError(ErrorCode::InvalidArgument, "block texture: " + std::to_string(cellClass.size()) +
                                                         " class bytes for " + std::to_string(blocks.cellCount()) +
                                                         " cells");
    if (colours.empty() || colours.size() > std::size_t(kMaxBlockClasses))
        return makeError(ErrorCode::InvalidArgument, "block texture: " + std::to_string(colours.size()) +
                                                         " classes (1.." + std::to_string(kMaxBlockClasses) + ")");
    if (clipRecords.size() > std::size_t(kMaxBlockClipRecords))
        return makeError(ErrorCode::InvalidArgument, "parameter 'colour': GL views colour at most " +
                                                         std::to_string(kMaxBlockClipRecords) +
                                                         " clipping bodies' records (the block model has " +
                                                         std::to_string(clipRecords.size()) + ")");
    GLint maxSide = 0;
    gl.GetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &maxSide);
    for (int a = 0; a < 3; ++a)
        if (blocks.dims[std::size_t(a)] > std::size_t(maxSide))
            return makeError(ErrorCode::OutOfRange,
                             "parameter 'colour': the block model's " + std::to_string(blocks.dims[std::size_t(a)]) +
                                 " cells along axis " + std::to_string(a) + " exceed the device's 3D texture side " +
                                 std::to_string(maxSide) + " (GL_MAX_3D_TEXTURE_SIZE)");
    auto impl = std::make_unique<Impl>();
    impl->gl = &gl;
    impl->origin = blocks.origin;
    for (int a = 0; a < 3; ++a) {
        impl->toGrid[std::size_t(a)] = blocks.axis[std::size_t(a)] / blocks.size[std::size_t(a)];
        impl->dims[std::size_t(a)] = int(blocks.dims[std::size_t(a)]);
    }
    for (const Rgba8& c : colours)
        impl->colours.insert(impl->colours.end(), {c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, c.a / 255.0f});
    impl->clip.assign(clipRecords.begin(), clipRecords.end());
    impl->texture = GlTexture::create(gl, GL_TEXTURE_3D);
    const GLuint tex = impl->texture.id();
    gl.TextureStorage3D(tex, 1, GL_R8UI, impl->dims[0], impl->dims[1], impl->dims[2]);
    gl.TextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.TextureSubImage3D(tex, 0, 0, 0, 0, impl->dims[0], impl->dims[1], impl->dims[2], GL_RED_INTEGER, GL_UNSIGNED_BYTE,
                         cellClass.data());
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR)
        return makeError(ErrorCode::Internal, "block texture upload failed (GL error " + std::to_string(e) + ")");
    return std::unique_ptr<BlockTexture>(new BlockTexture(std::move(impl)));
}

void BlockTexture::apply(GLuint program, const glm::dvec3& modelOrigin) const {
    const GlFunctions& gl = *impl_->gl;
    auto at = [&](const char* name) { return gl.GetUniformLocation(program, name); };
    gl.BindTextureUnit(2, impl_->texture.id());           // binding 2: uBlockClasses (shaders/slice.frag)
    const glm::vec3 origin(impl_->origin - modelOrigin);  // local frame
    gl.ProgramUniform3fv(program, at("uBlockOrigin"), 1, &origin.x);
    float rows[9];
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) rows[3 * a + c] = float(impl_->toGrid[std::size_t(a)][c]);
    gl.ProgramUniform3fv(program, at("uBlockToGrid"), 3, rows);
    gl.ProgramUniform3i(program, at("uBlockDims"), impl_->dims[0], impl_->dims[1], impl_->dims[2]);
    gl.ProgramUniform4fv(program, at("uBlockColours"), GLsizei(impl_->colours.size() / 4), impl_->colours.data());
    gl.ProgramUniform1i(program, at("uBlockClipCount"), GLint(impl_->clip.size()));
    if (!impl_->clip.empty())
        gl.ProgramUniform1uiv(program, at("uBlockClip"), GLsizei(impl_->clip.size()), impl_->clip.data());
}

void BlockTexture::release() const { impl_->gl->BindTextureUnit(2, 0); }

}  // namespace geoslice
