// The render target and the FXAA pass on their own (Magnum's FooGLTest next to the CPU
// FooTest, tests/unit/cluster_selection_test.cpp): what is cleared is what is read back,
// through the single-sampled target, the MSAA resolve and the FXAA output; resizing keeps
// working. Colours compare exactly: a clear of an RGBA8 attachment stores the rounded
// value, a blit resolve of equal samples averages to the same byte, and FXAA leaves an image
// without contrast untouched (shaders/fxaa.frag: below kEdgeMin nothing is filtered).
#include <gtest/gtest.h>

#include "gl_test_util.hpp"
#include "renderer/gl/render_target.hpp"
#include "renderer/passes/fxaa_pass.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

void expectCleared(const RenderTarget& t, bool afterFxaa) {
    const std::size_t n = std::size_t(t.width()) * std::size_t(t.height());
    std::vector<std::uint8_t> rgba;
    t.readColour(afterFxaa, rgba);
    ASSERT_EQ(rgba.size(), n * 4);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < n; ++i)
        wrong += rgba[4 * i] != 51 || rgba[4 * i + 1] != 102 || rgba[4 * i + 2] != 153 || rgba[4 * i + 3] != 255;
    EXPECT_EQ(wrong, 0u) << "colour pixels not (51, 102, 153, 255)";
    std::vector<std::uint32_t> ids;
    t.readIds(ids);
    ASSERT_EQ(ids.size(), n);
    EXPECT_EQ(std::count(ids.begin(), ids.end(), 0u), std::ptrdiff_t(n));
    std::vector<float> depth;
    t.readDepth(depth);
    ASSERT_EQ(depth.size(), n);
    EXPECT_EQ(std::count(depth.begin(), depth.end(), 1.0f), std::ptrdiff_t(n));
}

}  // namespace

TEST(RenderTargetGl, ClearResolveFxaaAndReadBack) {
    auto ctx = makeContext();
    ASSERT_TRUE(ctx);
    const GlFunctions& gl = ctx->gl();
    const float bg[4] = {0.2f, 0.4f, 0.6f, 1.0f};  // bytes 51, 102, 153, 255
    RenderTarget target(gl);
    auto fxaa = FxaaPass::create(gl);
    ASSERT_TRUE(fxaa.ok()) << fxaa.error().message;

    ASSERT_TRUE(target.ensure(37, 21, 0, true).ok());  // odd sides: rows are not 4-byte aligned
    EXPECT_EQ(target.width(), 37);
    EXPECT_EQ(target.height(), 21);
    EXPECT_NE(target.drawFramebuffer(), 0u);
    EXPECT_NE(target.fxaaFramebuffer(), 0u);
    target.clear(bg);
    target.resolve();  // single-sampled: nothing to do
    expectCleared(target, false);
    fxaa->run(target, 6);
    expectCleared(target, true);

    GLint maxSamples = 0, maxIntegerSamples = 0;
    gl.GetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    gl.GetIntegerv(GL_MAX_INTEGER_SAMPLES, &maxIntegerSamples);
    if (std::min(maxSamples, maxIntegerSamples) >= 4) {
        ASSERT_TRUE(target.ensure(64, 48, 4, false).ok());
        EXPECT_EQ(target.fxaaFramebuffer(), 0u);
        target.clear(bg);
        target.resolve();
        expectCleared(target, false);
    }
    target.release();
    EXPECT_EQ(target.width(), 0);
    EXPECT_EQ(target.drawFramebuffer(), 0u);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    EXPECT_EQ(gl.GetError(), GLenum(GL_NO_ERROR));
}
