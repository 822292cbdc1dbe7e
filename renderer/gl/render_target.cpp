#include "renderer/gl/render_target.hpp"

#include <algorithm>
#include <cstdio>

namespace geoslice {

void RenderTarget::release() {
    aaFbo_.reset();
    aaColour_.reset();
    for (Attachments* a : {&ms_, &single_}) {
        a->fbo.reset();
        a->colour.reset();
        a->ids.reset();
        a->depth.reset();
        a->cells.reset();
    }
    colourTex_.reset();
    width_ = height_ = samples_ = 0;
    fxaa_ = hasCells_ = cellsOn_ = false;
}

Status RenderTarget::ensure(int width, int height, int samples, bool fxaa, bool cells) {
    if (single_.fbo && width == width_ && height == height_ && samples == samples_ && (fxaa == fxaa_ || !fxaa) &&
        (cells == hasCells_ || !cells))
        return {};
    release();
    const GlFunctions& gl = *gl_;
    while (gl.GetError() != GL_NO_ERROR) {
    }
    const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    // Resolve target: colour is a texture so that the FXAA pass can sample it.
    colourTex_ = GlTexture::create(gl, GL_TEXTURE_2D);
    const GLuint tex = colourTex_.id();
    gl.TextureStorage2D(tex, 1, GL_RGBA8, width, height);
    gl.TextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl.TextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.TextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    single_.ids = GlRenderbuffer::create(gl);
    gl.NamedRenderbufferStorage(single_.ids.id(), GL_R32UI, width, height);
    single_.depth = GlRenderbuffer::create(gl);
    gl.NamedRenderbufferStorage(single_.depth.id(), GL_DEPTH32F_STENCIL8, width, height);
    single_.fbo = GlFramebuffer::create(gl);
    const GLuint fbo = single_.fbo.id();
    gl.NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    gl.NamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, single_.ids.id());
    gl.NamedFramebufferRenderbuffer(fbo, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, single_.depth.id());
    gl.NamedFramebufferDrawBuffers(fbo, 2, drawBuffers);
    if (cells) {
        single_.cells = GlRenderbuffer::create(gl);
        gl.NamedRenderbufferStorage(single_.cells.id(), GL_R32UI, width, height);
        gl.NamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT2, GL_RENDERBUFFER, single_.cells.id());
    }
    std::vector<GLuint> check = {fbo};
    if (samples > 1) {
        ms_.colour = GlRenderbuffer::create(gl);
        gl.NamedRenderbufferStorageMultisample(ms_.colour.id(), samples, GL_RGBA8, width, height);
        ms_.ids = GlRenderbuffer::create(gl);
        gl.NamedRenderbufferStorageMultisample(ms_.ids.id(), samples, GL_R32UI, width, height);
        ms_.depth = GlRenderbuffer::create(gl);
        gl.NamedRenderbufferStorageMultisample(ms_.depth.id(), samples, GL_DEPTH32F_STENCIL8, width, height);
        ms_.fbo = GlFramebuffer::create(gl);
        const GLuint msFbo = ms_.fbo.id();
        gl.NamedFramebufferRenderbuffer(msFbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ms_.colour.id());
        gl.NamedFramebufferRenderbuffer(msFbo, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, ms_.ids.id());
        gl.NamedFramebufferRenderbuffer(msFbo, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, ms_.depth.id());
        gl.NamedFramebufferDrawBuffers(msFbo, 2, drawBuffers);
        if (cells) {
            ms_.cells = GlRenderbuffer::create(gl);
            gl.NamedRenderbufferStorageMultisample(ms_.cells.id(), samples, GL_R32UI, width, height);
            gl.NamedFramebufferRenderbuffer(msFbo, GL_COLOR_ATTACHMENT2, GL_RENDERBUFFER, ms_.cells.id());
        }
        check.push_back(msFbo);
    }
    if (fxaa) {
        aaColour_ = GlRenderbuffer::create(gl);
        gl.NamedRenderbufferStorage(aaColour_.id(), GL_RGBA8, width, height);
        aaFbo_ = GlFramebuffer::create(gl);
        gl.NamedFramebufferRenderbuffer(aaFbo_.id(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, aaColour_.id());
        check.push_back(aaFbo_.id());
    }
    const GLenum error = gl.GetError();
    GLenum status = GL_FRAMEBUFFER_COMPLETE;
    for (GLuint f : check)
        if (status == GL_FRAMEBUFFER_COMPLETE) status = gl.CheckNamedFramebufferStatus(f, GL_FRAMEBUFFER);
    if (error != GL_NO_ERROR || status != GL_FRAMEBUFFER_COMPLETE) {
        release();
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "framebuffer %dx%d (RGBA8 + R32UI%s + DEPTH32F_STENCIL8, %d sample(s)%s): %s, status 0x%04x",
                      width, height, cells ? " + R32UI cells" : "", std::max(samples, 1), fxaa ? ", FXAA target" : "",
                      glErrorName(error).c_str(), status);
        return makeError(error == GL_OUT_OF_MEMORY ? ErrorCode::OutOfRange : ErrorCode::Internal, buf);
    }
    width_ = width;
    height_ = height;
    samples_ = samples;
    fxaa_ = fxaa;
    hasCells_ = cells;
    return {};
}

void RenderTarget::selectDrawBuffers(GLuint fbo, bool cells) const {
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    gl_->NamedFramebufferDrawBuffers(fbo, cells ? 3 : 2, buffers);
}

void RenderTarget::clear(const float background[4], bool cells) {
    const GlFunctions& gl = *gl_;
    const GLuint fbo = drawFramebuffer();
    const GLuint noId[4] = {0, 0, 0, 0};
    cellsOn_ = cells && hasCells_;
    if (hasCells_) selectDrawBuffers(fbo, cellsOn_);
    gl.ClearNamedFramebufferfv(fbo, GL_COLOR, 0, background);
    gl.ClearNamedFramebufferuiv(fbo, GL_COLOR, 1, noId);
    if (cellsOn_) gl.ClearNamedFramebufferuiv(fbo, GL_COLOR, 2, noId);
    gl.ClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
}

void RenderTarget::resolve() const {
    if (!ms_.fbo) return;
    const GlFunctions& gl = *gl_;
    const GLuint from = ms_.fbo.id(), to = single_.fbo.id();
    const int w = width_, h = height_;
    // One attachment at a time: float and integer colour buffers cannot share a blit.
    const GLenum colourOnly[] = {GL_COLOR_ATTACHMENT0, GL_NONE, GL_NONE};
    const GLenum idsOnly[] = {GL_NONE, GL_COLOR_ATTACHMENT1, GL_NONE};
    const GLenum cellsOnly[] = {GL_NONE, GL_NONE, GL_COLOR_ATTACHMENT2};
    gl.NamedFramebufferReadBuffer(from, GL_COLOR_ATTACHMENT0);
    gl.NamedFramebufferDrawBuffers(to, 2, colourOnly);
    gl.BlitNamedFramebuffer(from, to, 0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl.NamedFramebufferReadBuffer(from, GL_COLOR_ATTACHMENT1);
    gl.NamedFramebufferDrawBuffers(to, 2, idsOnly);
    gl.BlitNamedFramebuffer(from, to, 0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    if (cellsOn_) {
        gl.NamedFramebufferReadBuffer(from, GL_COLOR_ATTACHMENT2);
        gl.NamedFramebufferDrawBuffers(to, 3, cellsOnly);
        gl.BlitNamedFramebuffer(from, to, 0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    gl.BlitNamedFramebuffer(from, to, 0, 0, w, h, 0, 0, w, h, GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, GL_NEAREST);
    selectDrawBuffers(to, cellsOn_);
    gl.NamedFramebufferReadBuffer(from, GL_COLOR_ATTACHMENT0);
}

void RenderTarget::readColour(bool afterFxaa, std::vector<std::uint8_t>& rgba) const {
    const GlFunctions& gl = *gl_;
    const GLuint fbo = afterFxaa ? aaFbo_.id() : single_.fbo.id();
    std::vector<std::uint8_t> raw(std::size_t(width_) * std::size_t(height_) * 4);
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.NamedFramebufferReadBuffer(fbo, GL_COLOR_ATTACHMENT0);
    gl.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
    flipRows(raw, rgba, width_, height_, 4);
}

void RenderTarget::readInteger(GLenum attachment, std::vector<std::uint32_t>& out) const {
    const GlFunctions& gl = *gl_;
    const GLuint fbo = single_.fbo.id();
    std::vector<std::uint32_t> raw(std::size_t(width_) * std::size_t(height_));
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.NamedFramebufferReadBuffer(fbo, attachment);
    gl.ReadPixels(0, 0, width_, height_, GL_RED_INTEGER, GL_UNSIGNED_INT, raw.data());
    flipRows(raw, out, width_, height_, 1);
}

void RenderTarget::readIds(std::vector<std::uint32_t>& ids) const { readInteger(GL_COLOR_ATTACHMENT1, ids); }

void RenderTarget::readCells(std::vector<std::uint32_t>& cells) const {
    if (cellsOn_)
        readInteger(GL_COLOR_ATTACHMENT2, cells);
    else
        cells.clear();
}

void RenderTarget::readDepth(std::vector<float>& depth) const {
    const GlFunctions& gl = *gl_;
    std::vector<float> raw(std::size_t(width_) * std::size_t(height_));
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, single_.fbo.id());
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.ReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT, raw.data());
    flipRows(raw, depth, width_, height_, 1);
}

}  // namespace geoslice
