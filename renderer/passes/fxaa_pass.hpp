// The FXAA pass (shaders/fxaa.frag): anti-aliases the resolved colour of a RenderTarget into
// its FXAA output with one full-screen triangle. Colour only; ids and depth are untouched.
// Threads: create, use and destroy on the owning GlContext's thread. GL state: run() binds
// the target's FXAA framebuffer, sets the viewport, disables depth, stencil, cull and clip
// distances 0..kClipDistances-1, and leaves the FXAA program and its vertex array bound and
// texture unit 0 unbound.
#pragma once

#include "model/result.hpp"
#include "renderer/gl/gl_objects.hpp"
#include "renderer/gl/gl_program.hpp"
#include "renderer/gl/render_target.hpp"

namespace geoslice {

class FxaaPass {
public:
    static Result<FxaaPass> create(const GlFunctions& gl);
    // The target must have been made with its FXAA output (RenderTarget::ensure(..., fxaa)).
    void run(const RenderTarget& target, int clipDistances);
    const GlProgram& program() const { return program_; }

private:
    FxaaPass() = default;
    const GlFunctions* gl_ = nullptr;
    GlProgram program_;
    GLint texel_ = -1, colour_ = -1;
    GlVertexArray emptyVao_;  // attribute-less draw: the vertex shader makes the triangle
};

}  // namespace geoslice
