#include "renderer/gl/gl_functions.hpp"

#include <cstdio>

namespace geoslice {

std::vector<std::string> GlFunctions::load(ProcAddressFn getProc, void* user) {
    std::vector<std::string> missing;
#define GEOSLICE_GL_LOAD(type, name)                          \
    name = reinterpret_cast<type>(getProc("gl" #name, user)); \
    if (!name) missing.emplace_back("gl" #name);
    GEOSLICE_GL_FUNCTIONS(GEOSLICE_GL_LOAD)
#undef GEOSLICE_GL_LOAD
    return missing;
}

std::size_t GlFunctions::count() {
    std::size_t n = 0;
#define GEOSLICE_GL_COUNT(type, name) ++n;
    GEOSLICE_GL_FUNCTIONS(GEOSLICE_GL_COUNT)
#undef GEOSLICE_GL_COUNT
    return n;
}

std::string glErrorName(GLenum error) {
    switch (error) {
        case GL_NO_ERROR:
            return "GL_NO_ERROR";
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION:
            return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        case GL_STACK_OVERFLOW:
            return "GL_STACK_OVERFLOW";
        case GL_STACK_UNDERFLOW:
            return "GL_STACK_UNDERFLOW";
        default: {
            char buf[32];
            std::snprintf(buf, sizeof buf, "GL error 0x%04x", error);
            return buf;
        }
    }
}

}  // namespace geoslice
