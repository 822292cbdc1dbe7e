// Owning handles of GL objects (Magnum's RAII objects): a buffer, vertex array, texture,
// renderbuffer or framebuffer created with DSA (glCreate*) and deleted with its
// destructor. Move-only; a default-constructed handle owns nothing (id() 0).
// Threads: create, use and destroy on the thread of the GlContext whose GlFunctions made
// it, with that context current. GL state: creating or deleting binds nothing.
#pragma once

#include "renderer/gl/gl_functions.hpp"

namespace geoslice {

enum class GlObjectKind { Buffer, VertexArray, Texture, Renderbuffer, Framebuffer };

template <GlObjectKind Kind>
class GlObject {
public:
    GlObject() = default;
    // glCreate*; `textureTarget` is for textures only (GL_TEXTURE_2D, GL_TEXTURE_2D_ARRAY).
    static GlObject create(const GlFunctions& gl, GLenum textureTarget = GL_TEXTURE_2D);
    GlObject(GlObject&& other) noexcept : gl_(other.gl_), id_(other.id_) { other.id_ = 0; }
    GlObject& operator=(GlObject&& other) noexcept {
        if (this != &other) {
            reset();
            gl_ = other.gl_;
            id_ = other.id_;
            other.id_ = 0;
        }
        return *this;
    }
    GlObject(const GlObject&) = delete;
    GlObject& operator=(const GlObject&) = delete;
    ~GlObject() { reset(); }

    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    // Deletes the object now (context current); the handle then owns nothing.
    void reset();

private:
    const GlFunctions* gl_ = nullptr;
    GLuint id_ = 0;
};

using GlBuffer = GlObject<GlObjectKind::Buffer>;
using GlVertexArray = GlObject<GlObjectKind::VertexArray>;
using GlTexture = GlObject<GlObjectKind::Texture>;
using GlRenderbuffer = GlObject<GlObjectKind::Renderbuffer>;
using GlFramebuffer = GlObject<GlObjectKind::Framebuffer>;

extern template class GlObject<GlObjectKind::Buffer>;
extern template class GlObject<GlObjectKind::VertexArray>;
extern template class GlObject<GlObjectKind::Texture>;
extern template class GlObject<GlObjectKind::Renderbuffer>;
extern template class GlObject<GlObjectKind::Framebuffer>;

}  // namespace geoslice
