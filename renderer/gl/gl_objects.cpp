#include "renderer/gl/gl_objects.hpp"

namespace geoslice {

template <GlObjectKind Kind>
GlObject<Kind> GlObject<Kind>::create(const GlFunctions& gl, GLenum textureTarget) {
    GlObject o;
    o.gl_ = &gl;
    if constexpr (Kind == GlObjectKind::Buffer)
        gl.CreateBuffers(1, &o.id_);
    else if constexpr (Kind == GlObjectKind::VertexArray)
        gl.CreateVertexArrays(1, &o.id_);
    else if constexpr (Kind == GlObjectKind::Texture)
        gl.CreateTextures(textureTarget, 1, &o.id_);
    else if constexpr (Kind == GlObjectKind::Renderbuffer)
        gl.CreateRenderbuffers(1, &o.id_);
    else
        gl.CreateFramebuffers(1, &o.id_);
    return o;
}

template <GlObjectKind Kind>
void GlObject<Kind>::reset() {
    if (!id_) return;
    if constexpr (Kind == GlObjectKind::Buffer)
        gl_->DeleteBuffers(1, &id_);
    else if constexpr (Kind == GlObjectKind::VertexArray)
        gl_->DeleteVertexArrays(1, &id_);
    else if constexpr (Kind == GlObjectKind::Texture)
        gl_->DeleteTextures(1, &id_);
    else if constexpr (Kind == GlObjectKind::Renderbuffer)
        gl_->DeleteRenderbuffers(1, &id_);
    else
        gl_->DeleteFramebuffers(1, &id_);
    id_ = 0;
}

template class GlObject<GlObjectKind::Buffer>;
template class GlObject<GlObjectKind::VertexArray>;
template class GlObject<GlObjectKind::Texture>;
template class GlObject<GlObjectKind::Renderbuffer>;
template class GlObject<GlObjectKind::Framebuffer>;

}  // namespace geoslice
