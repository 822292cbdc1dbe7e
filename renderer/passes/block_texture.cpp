#include "renderer/passes/block_texture.hpp"

#include <algorithm>
#include <string>

#include "renderer/gl/gl_objects.hpp"

namespace geoslice {

struct BlockTexture::Impl {
    const GlFunctions* gl = nullptr;
    GlTexture texture;
    GlTexture clipTexture;               // sorted records, rows of kBlockClipRow
    glm::dvec3 origin{0.0};              // world
    std::array<glm::dvec3, 3> toGrid{};  // axis[a] / size[a]: world offset -> cell units
    std::array<int, 3> dims{0, 0, 0};
    std::vector<float> colours;  // 4 per class, straight alpha in [0, 1]
    GLint clipCount = 0;
};

BlockTexture::BlockTexture(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
BlockTexture::~BlockTexture() = default;

Result<std::unique_ptr<BlockTexture>> BlockTexture::upload(GlContext& context, const BlockModel& blocks,
                                                           const std::vector<std::uint8_t>& cellClass,
                                                           const std::vector<Rgba8>& colours,
                                                           const std::vector<RecordId>& clipRecords) {
    const GlFunctions& gl = context.gl();
    if (blocks.shape != CellShape::Box)
        return makeError(ErrorCode::Unsupported,
                         "parameter 'colour': GL (perspective) views colour box-cell block models only (CSV, Voxet); " +
                             blocks.source +
                             " has curvilinear cells, which a 3D texture lookup cannot address (profile images, "
                             "tiles, vectors, print sheets, queries and reserves colour and use it)");
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
    std::vector<GLuint> clip(clipRecords.begin(), clipRecords.end());
    std::sort(clip.begin(), clip.end());
    clip.erase(std::unique(clip.begin(), clip.end()), clip.end());
    impl->clipCount = GLint(clip.size());
    const int rows = std::max(1, int((clip.size() + kBlockClipRow - 1) / kBlockClipRow));
    clip.resize(std::size_t(rows) * kBlockClipRow, 0u);
    impl->clipTexture = GlTexture::create(gl, GL_TEXTURE_2D);
    gl.TextureStorage2D(impl->clipTexture.id(), 1, GL_R32UI, kBlockClipRow, rows);
    gl.TextureParameteri(impl->clipTexture.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TextureParameteri(impl->clipTexture.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TextureSubImage2D(impl->clipTexture.id(), 0, 0, 0, kBlockClipRow, rows, GL_RED_INTEGER, GL_UNSIGNED_INT,
                         clip.data());
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
    gl.BindTextureUnit(3, impl_->clipTexture.id());  // binding 3: uBlockClip
    gl.ProgramUniform1i(program, at("uBlockClipCount"), impl_->clipCount);
}

void BlockTexture::release() const {
    impl_->gl->BindTextureUnit(2, 0);
    impl_->gl->BindTextureUnit(3, 0);
}

}  // namespace geoslice
