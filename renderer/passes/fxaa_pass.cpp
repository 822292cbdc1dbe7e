#include "renderer/passes/fxaa_pass.hpp"

namespace geoslice {

Result<FxaaPass> FxaaPass::create(const GlFunctions& gl) {
    auto program = GlProgram::build(gl, "fxaa.vert", "fxaa.frag", {});
    if (!program) return program.error();
    FxaaPass pass;
    pass.gl_ = &gl;
    pass.program_ = std::move(program).value();
    pass.texel_ = pass.program_.uniform("uTexel");
    pass.colour_ = pass.program_.uniform("uColour");
    return pass;
}

void FxaaPass::run(const RenderTarget& target, int clipDistances) {
    const GlFunctions& gl = *gl_;
    const int width = target.width(), height = target.height();
    gl.BindFramebuffer(GL_FRAMEBUFFER, target.fxaaFramebuffer());
    gl.Viewport(0, 0, width, height);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_STENCIL_TEST);
    gl.Disable(GL_CULL_FACE);
    for (int i = 0; i < clipDistances; ++i) gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
    const GLuint prog = program_.id();
    gl.UseProgram(prog);
    const float texel[2] = {1.0f / float(width), 1.0f / float(height)};
    gl.ProgramUniform2fv(prog, texel_, 1, texel);
    gl.ProgramUniform1i(prog, colour_, 0);
    gl.BindTextureUnit(0, target.colourTexture());
    if (!emptyVao_) emptyVao_ = GlVertexArray::create(gl);
    gl.BindVertexArray(emptyVao_.id());
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    gl.BindTextureUnit(0, 0);
}

}  // namespace geoslice
