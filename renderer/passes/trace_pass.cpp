#include "renderer/passes/trace_pass.hpp"

#include <algorithm>

#include <glm/gtc/type_ptr.hpp>

namespace geoslice {

void traceSegments(const std::vector<glm::vec3>& tris, const std::vector<glm::dvec4>& planes, bool unionMode,
                   std::vector<glm::vec3>& out) {
    const int planeCount = int(planes.size());
    auto dist = [](const glm::dvec4& pl, const glm::dvec3& p) { return glm::dot(glm::dvec3(pl), p) + pl.w; };
    for (int i = 0; i < planeCount; ++i) {
        const glm::dvec4& pl = planes[std::size_t(i)];
        for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
            const glm::dvec3 v[3] = {tris[t], tris[t + 1], tris[t + 2]};
            const double d[3] = {dist(pl, v[0]), dist(pl, v[1]), dist(pl, v[2])};
            glm::dvec3 ends[2];
            int n = 0;
            for (int e = 0; e < 3; ++e) {
                const int a = e, b = (e + 1) % 3;
                if ((d[a] >= 0.0) == (d[b] >= 0.0)) continue;
                if (n < 2) ends[n] = v[a] + (v[b] - v[a]) * (d[a] / (d[a] - d[b]));
                ++n;
            }
            if (n != 2) continue;
            double t0 = 0.0, t1 = 1.0;
            for (int j = 0; j < planeCount && t0 <= t1; ++j) {
                if (j == i) continue;
                const double sign = unionMode ? -1.0 : 1.0;
                const double g0 = sign * dist(planes[std::size_t(j)], ends[0]);
                const double g1 = sign * dist(planes[std::size_t(j)], ends[1]);
                if (g0 < 0.0 && g1 < 0.0)
                    t0 = 2.0, t1 = -1.0;
                else if (g0 < 0.0)
                    t0 = std::max(t0, g0 / (g0 - g1));
                else if (g1 < 0.0)
                    t1 = std::min(t1, g0 / (g0 - g1));
            }
            if (!(t0 < t1)) continue;
            out.push_back(glm::vec3(ends[0] + (ends[1] - ends[0]) * t0));
            out.push_back(glm::vec3(ends[0] + (ends[1] - ends[0]) * t1));
        }
    }
}

Result<TracePass> TracePass::create(const GlFunctions& gl) {
    auto program = GlProgram::build(gl, "trace.vert", "trace.frag", {});
    if (!program) return program.error();
    TracePass pass;
    pass.gl_ = &gl;
    pass.program_ = std::move(program).value();
    pass.viewProj_ = pass.program_.uniform("uViewProj");
    pass.colour_ = pass.program_.uniform("uColour");
    return pass;
}

std::size_t TracePass::draw(const std::vector<glm::vec3>& triangles, const std::vector<glm::dvec4>& planes,
                            bool unionMode, const glm::mat4& viewProj, Rgba8 c, float width, int clipDistances) {
    vertices_.clear();
    traceSegments(triangles, planes, unionMode, vertices_);
    if (vertices_.empty()) return 0;
    const GlFunctions& gl = *gl_;
    if (vertices_.size() > capacity_) {
        capacity_ = std::max(vertices_.size(), 2 * capacity_);
        buffer_ = GlBuffer::create(gl);
        gl.NamedBufferStorage(buffer_.id(), GLsizeiptr(capacity_ * sizeof(glm::vec3)), nullptr, GL_DYNAMIC_STORAGE_BIT);
        if (!vao_) {
            vao_ = GlVertexArray::create(gl);
            gl.EnableVertexArrayAttrib(vao_.id(), 0);
            gl.VertexArrayAttribFormat(vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
            gl.VertexArrayAttribBinding(vao_.id(), 0, 0);
        }
        gl.VertexArrayVertexBuffer(vao_.id(), 0, buffer_.id(), 0, sizeof(glm::vec3));
    }
    gl.NamedBufferSubData(buffer_.id(), 0, GLsizeiptr(vertices_.size() * sizeof(glm::vec3)), vertices_.data());
    const GLuint prog = program_.id();
    gl.UseProgram(prog);
    gl.ProgramUniformMatrix4fv(prog, viewProj_, 1, GL_FALSE, glm::value_ptr(viewProj));
    const float colour[4] = {c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, c.a / 255.0f};
    gl.ProgramUniform4fv(prog, colour_, 1, colour);
    // Only on cut faces (stencil bit 0), at the plane's depth, which is in front of the surface
    // behind the cut that gave the cap its depth; ids, cells and depth untouched.
    gl.ColorMaski(1, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.ColorMaski(2, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.DepthMask(GL_FALSE);
    gl.DepthFunc(GL_LEQUAL);
    gl.StencilFunc(GL_EQUAL, 1, 0x1);
    gl.StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    gl.Disable(GL_CULL_FACE);
    for (int i = 0; i < clipDistances; ++i) gl.Disable(GLenum(GL_CLIP_DISTANCE0 + i));
    float range[2] = {1.0f, 1.0f};
    gl.GetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
    gl.LineWidth(std::clamp(width, std::max(range[0], 1.0f), std::max(range[1], 1.0f)));
    gl.BindVertexArray(vao_.id());
    gl.DrawArrays(GL_LINES, 0, GLsizei(vertices_.size()));
    gl.LineWidth(1.0f);
    gl.ColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.ColorMaski(2, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.DepthMask(GL_TRUE);
    gl.DepthFunc(GL_LESS);
    return vertices_.size() / 2;
}

}  // namespace geoslice
