// Fault traces: where an open surface (fault, terrain sheet) crosses a cut plane on a
// visible cut face, a line (shaders/trace.vert|frag). The segments are cut on the CPU
// (traceSegments, no GL) and drawn as GL_LINES on the pixels the slicing pass marked as cut
// face (stencil bit 0: renderer/slice_renderer.cpp's cap codes), colour attachment 0 only.
// Threads: create, use and destroy on the owning GlContext's thread. GL state: draw() binds
// its program and vertex array, disables cull and clip distances 0..kClipDistances-1, and
// restores colour masks 1 and 2, depth mask on, depth func GL_LESS and line width 1; it leaves
// the stencil func GL_EQUAL 1 (mask 1) with op KEEP.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "model/attributes.hpp"
#include "model/result.hpp"
#include "renderer/gl/gl_objects.hpp"
#include "renderer/gl/gl_program.hpp"

namespace geoslice {

// The pieces of `triangles` (local frame, 3 vertices each) that lie on the cut face of each
// plane (local frame (n, d), unit normals), as line-segment end points appended to `out`. A
// triangle crosses plane i where its vertices' signed distances change sign (>= 0 counts as
// kept, so a vertex on the plane never yields a zero-length duplicate). The cut face of
// plane i is where every other plane keeps the point (intersection) or removes it
// (`unionMode`), so each segment is clipped by those half-spaces. Distances in double. Any thread.
void traceSegments(const std::vector<glm::vec3>& triangles, const std::vector<glm::dvec4>& planes, bool unionMode,
                   std::vector<glm::vec3>& out);

class TracePass {
public:
    static Result<TracePass> create(const GlFunctions& gl);
    // Draws the traces of `triangles` (local frame) with the slicing pass's local -> clip
    // `viewProj`, `width` pixels wide (clamped to GL_ALIASED_LINE_WIDTH_RANGE). Returns the
    // number of segments drawn. Target bound, depth and stencil tests on.
    std::size_t draw(const std::vector<glm::vec3>& triangles, const std::vector<glm::dvec4>& planes, bool unionMode,
                     const glm::mat4& viewProj, Rgba8 colour, float width, int clipDistances);
    const GlProgram& program() const { return program_; }

private:
    TracePass() = default;
    const GlFunctions* gl_ = nullptr;
    GlProgram program_;
    GLint viewProj_ = -1, colour_ = -1;
    GlVertexArray vao_;
    GlBuffer buffer_;
    std::size_t capacity_ = 0;  // vertices the buffer holds
    std::vector<glm::vec3> vertices_;
};

}  // namespace geoslice
