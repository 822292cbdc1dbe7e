// A linked GL program built from embedded shaders (renderer/shader_sources.hpp), with
// "#define NAME VALUE" lines inserted after the "#version" line of each stage.
// Threads: the owning GlContext's thread only. GL state: build() leaves no program bound;
// the destructor deletes the program.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "model/result.hpp"
#include "renderer/gl/gl_functions.hpp"

namespace geoslice {

class GlProgram {
public:
    // Compiles and links. On failure the error (and stderr) carries the stage, the defines
    // and the driver's info log.
    static Result<GlProgram> build(const GlFunctions& gl, std::string_view vertexShader,
                                   std::string_view fragmentShader, const std::vector<std::string>& defines = {});
    // Inserts the defines into `source` after its first line (the #version line).
    static std::string withDefines(std::string_view source, const std::vector<std::string>& defines);

    GlProgram() = default;
    GlProgram(GlProgram&& other) noexcept;
    GlProgram& operator=(GlProgram&& other) noexcept;
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;
    ~GlProgram();

    GLuint id() const { return id_; }
    GLint uniform(const char* name) const;  // -1 when not active
    const std::string& label() const { return label_; }

private:
    const GlFunctions* gl_ = nullptr;
    GLuint id_ = 0;
    std::string label_;
};

}  // namespace geoslice
