// The render target of the slicing pass (Filament's render target, Magnum's RAII objects):
// the framebuffers an image is drawn into and read back from.
//   resolve target (always)  colour RGBA8 texture (FXAA samples it), ids R32UI, depth
//                            DEPTH32F_STENCIL8 renderbuffers: what is read back
//   cells (on request)       R32UI at colour attachment 2: the block cell + 1 per pixel
//                            (0 = none) of views coloured by a block model; made by the
//                            first ensure() that asks for it, and written only while
//                            clear(.., cells = true) selected it, so views without a block
//                            model draw into two colour buffers as before
//   multisampled (samples>1) the same attachments as multisampled renderbuffers, the
//                            draw target; resolve() blits it into the resolve target
//                            (colour averaged; ids, cells and depth one sample's value,
//                            GL 4.5 section 18.3.1: never blended)
//   FXAA output (fxaa)       colour RGBA8 renderbuffer written by FxaaPass
// Readback flips rows: images are row 0 at the top, GL reads bottom-up.
// Threads: create, use and destroy on the owning GlContext's thread, context current.
// GL state: clear() and resolve() change draw/read buffer selections of the target's own
// framebuffers only; read*() bind GL_READ_FRAMEBUFFER and set GL_PACK_ALIGNMENT 1.
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include "model/result.hpp"
#include "renderer/gl/gl_objects.hpp"

namespace geoslice {

// Rows of `in` (width x height x channels, row 0 at the bottom) into `out` with row 0 at the
// top; `out` is resized to in.size().
template <class T>
void flipRows(const std::vector<T>& in, std::vector<T>& out, int width, int height, int channels) {
    const std::size_t row = std::size_t(width) * std::size_t(channels);
    out.resize(in.size());
    for (int y = 0; y < height; ++y)
        std::memcpy(out.data() + std::size_t(height - 1 - y) * row, in.data() + std::size_t(y) * row, row * sizeof(T));
}

class RenderTarget {
public:
    explicit RenderTarget(const GlFunctions& gl) : gl_(&gl) {}

    // Makes the target width x height pixels (sides checked by the caller) with `samples`
    // samples per pixel (<= 1: single-sampled) and, with `fxaa`, the FXAA output, with
    // `cells` the cell attachment; keeps the current one when it already fits. Errors: OutOfRange for GL_OUT_OF_MEMORY,
    // Internal for an incomplete framebuffer, both naming the size, formats and samples.
    Status ensure(int width, int height, int samples, bool fxaa, bool cells = false);
    // Deletes every attachment (ensure() makes them again): not to keep a large image's memory.
    void release();

    int width() const { return width_; }
    int height() const { return height_; }
    // Where the pass draws: the multisampled framebuffer, or the resolve target.
    GLuint drawFramebuffer() const { return ms_.fbo ? ms_.fbo.id() : single_.fbo.id(); }
    GLuint colourTexture() const { return colourTex_.id(); }  // resolved colour, for FXAA
    GLuint fxaaFramebuffer() const { return aaFbo_.id(); }    // 0 without the FXAA output

    // Clears the draw framebuffer: colour to `background` (RGBA 0..1), ids to 0, depth to 1,
    // stencil to 0; with `cells` (ensure() made them) selects the cell attachment as draw
    // buffer 2 and clears it to 0, without deselects it.
    void clear(const float background[4], bool cells = false);
    // Multisampled colour, ids, cells (when selected), depth and stencil into the resolve
    // target (no-op when single-sampled).
    void resolve() const;
    // Row 0 at the top. Colour from the FXAA output when `afterFxaa`, else the resolve target.
    void readColour(bool afterFxaa, std::vector<std::uint8_t>& rgba) const;
    void readIds(std::vector<std::uint32_t>& ids) const;
    void readCells(std::vector<std::uint32_t>& cells) const;  // after clear(.., true)
    void readDepth(std::vector<float>& depth) const;

private:
    struct Attachments {
        GlFramebuffer fbo;
        GlRenderbuffer colour, ids, depth, cells;
    };
    void selectDrawBuffers(GLuint fbo, bool cells) const;
    void readInteger(GLenum attachment, std::vector<std::uint32_t>& out) const;
    const GlFunctions* gl_;
    GlTexture colourTex_;  // resolve target's colour (single_.colour stays empty)
    Attachments single_, ms_;
    GlFramebuffer aaFbo_;
    GlRenderbuffer aaColour_;
    int width_ = 0, height_ = 0, samples_ = 0;
    bool fxaa_ = false;
    bool hasCells_ = false, cellsOn_ = false;
};

}  // namespace geoslice
