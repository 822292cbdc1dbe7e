#include "renderer/gl/gl_program.hpp"

#include <cstdio>
#include <utility>

#include "renderer/shader_sources.hpp"

namespace geoslice {
namespace {

std::string shaderLog(const GlFunctions& gl, GLuint shader) {
    GLint len = 0;
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(len > 0 ? len : 0), '\0');
    if (len > 0) gl.GetShaderInfoLog(shader, len, nullptr, log.data());
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
    return log;
}

std::string programLog(const GlFunctions& gl, GLuint program) {
    GLint len = 0;
    gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(len > 0 ? len : 0), '\0');
    if (len > 0) gl.GetProgramInfoLog(program, len, nullptr, log.data());
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
    return log;
}

Result<GLuint> compile(const GlFunctions& gl, GLenum stage, std::string_view name, const std::string& label,
                       const std::vector<std::string>& defines) {
    const char* text = findEmbeddedShader(name);
    if (!text) return makeError(ErrorCode::NotFound, "shader " + std::string(name) + " is not embedded (shaders/)");
    std::string source = GlProgram::withDefines(text, defines);
    GLuint shader = gl.CreateShader(stage);
    const char* src = source.c_str();
    gl.ShaderSource(shader, 1, &src, nullptr);
    gl.CompileShader(shader);
    GLint ok = GL_FALSE;
    gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::string log = shaderLog(gl, shader);
        gl.DeleteShader(shader);
        std::string message = "compiling " + std::string(name) + " for program " + label + " failed:\n" + log;
        std::fprintf(stderr, "geoslice: %s\n", message.c_str());
        return makeError(ErrorCode::Internal, message);
    }
    return shader;
}

}  // namespace

std::string GlProgram::withDefines(std::string_view source, const std::vector<std::string>& defines) {
    std::size_t eol = source.find('\n');
    std::string out(source.substr(0, eol == std::string_view::npos ? source.size() : eol + 1));
    if (eol == std::string_view::npos) out += '\n';
    for (const std::string& d : defines) out += "#define " + d + "\n";
    out += "#line 2\n";
    if (eol != std::string_view::npos) out += source.substr(eol + 1);
    return out;
}

Result<GlProgram> GlProgram::build(const GlFunctions& gl, std::string_view vertexShader,
                                   std::string_view fragmentShader, const std::vector<std::string>& defines) {
    std::string label = std::string(vertexShader) + "+" + std::string(fragmentShader);
    for (const std::string& d : defines) label += " -D" + d;
    auto vs = compile(gl, GL_VERTEX_SHADER, vertexShader, label, defines);
    if (!vs) return vs.error();
    auto fs = compile(gl, GL_FRAGMENT_SHADER, fragmentShader, label, defines);
    if (!fs) {
        gl.DeleteShader(*vs);
        return fs.error();
    }
    GlProgram p;
    p.gl_ = &gl;
    p.label_ = label;
    p.id_ = gl.CreateProgram();
    gl.AttachShader(p.id_, *vs);
    gl.AttachShader(p.id_, *fs);
    gl.LinkProgram(p.id_);
    gl.DetachShader(p.id_, *vs);
    gl.DetachShader(p.id_, *fs);
    gl.DeleteShader(*vs);
    gl.DeleteShader(*fs);
    GLint ok = GL_FALSE;
    gl.GetProgramiv(p.id_, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::string message = "linking program " + label + " failed:\n" + programLog(gl, p.id_);
        std::fprintf(stderr, "geoslice: %s\n", message.c_str());
        return makeError(ErrorCode::Internal, message);
    }
    return p;
}

GlProgram::GlProgram(GlProgram&& other) noexcept
    : gl_(other.gl_), id_(std::exchange(other.id_, 0)), label_(std::move(other.label_)) {}

GlProgram& GlProgram::operator=(GlProgram&& other) noexcept {
    if (this != &other) {
        if (id_) gl_->DeleteProgram(id_);
        gl_ = other.gl_;
        id_ = std::exchange(other.id_, 0);
        label_ = std::move(other.label_);
    }
    return *this;
}

GlProgram::~GlProgram() {
    if (id_) gl_->DeleteProgram(id_);
}

GLint GlProgram::uniform(const char* name) const { return id_ ? gl_->GetUniformLocation(id_, name) : -1; }

}  // namespace geoslice
