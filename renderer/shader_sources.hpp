// GLSL 4.50 core sources from shaders/, embedded at build time by shaders/embed_shaders.cmake.
// Plain data: callable from any thread.
#pragma once

#include <span>
#include <string_view>

namespace geoslice {

struct EmbeddedShader {
    const char* name;    // file name in shaders/, e.g. "slice.vert"
    const char* source;  // full text; the first line is "#version 450 core"
};

std::span<const EmbeddedShader> embeddedShaders();

// The source of shaders/<name>, or nullptr.
inline const char* findEmbeddedShader(std::string_view name) {
    for (const EmbeddedShader& s : embeddedShaders())
        if (name == s.name) return s.source;
    return nullptr;
}

}  // namespace geoslice
