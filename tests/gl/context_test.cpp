// GlContext backends: each one that exists here creates a GL 4.5 core context and reports
// what it runs on; EGL and OSMesa contexts coexist in one process.
#include <gtest/gtest.h>

#include <cstdio>

#include "gl_test_util.hpp"
#include "renderer/gl/gl_context.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

void report(const GlContextInfo& info) {
    std::printf("[ backend  ] %s\n[ platform ] %s\n[ glsl     ] %s, max renderbuffer %d, viewport %dx%d\n",
                info.describe().c_str(), info.platform.c_str(), info.glslVersion.c_str(), info.maxRenderbufferSize,
                info.maxViewportWidth, info.maxViewportHeight);
    ::testing::Test::RecordProperty("gl_renderer", info.renderer);
}

void expectUsable(GlContext& ctx, GlBackend backend) {
    const GlContextInfo& info = ctx.info();
    EXPECT_EQ(info.backend, backend);
    EXPECT_FALSE(info.vendor.empty());
    EXPECT_FALSE(info.renderer.empty());
    EXPECT_NE(info.version.find("4."), std::string::npos) << info.version;
    EXPECT_GE(info.maxRenderbufferSize, 1024);
    // One GL call through the loaded table: clear colour round trip.
    const GlFunctions& gl = ctx.gl();
    GLint major = 0;
    gl.GetIntegerv(GL_MAJOR_VERSION, &major);
    EXPECT_GE(major, 4);
    EXPECT_EQ(gl.GetError(), GLenum(GL_NO_ERROR));
    report(info);
}

}  // namespace

TEST(GlContext, BackendNames) {
    for (GlBackend b : {GlBackend::Auto, GlBackend::EglDevice, GlBackend::EglSurfaceless, GlBackend::OsMesa})
        EXPECT_EQ(parseGlBackend(glBackendName(b)), b);
    EXPECT_FALSE(parseGlBackend("vulkan").has_value());
    EXPECT_GE(GlFunctions::count(), 60u);
}

TEST(GlContext, EglDevice) {
    auto devices = listEglDevices();
    if (!devices.ok() || devices->empty())
        GTEST_SKIP() << "no EGL device here: " << (devices.ok() ? "none listed" : devices.error().message);
    for (const EglDeviceDesc& d : *devices)
        std::printf("[ device %d ] %s%s %s\n", d.index, d.software ? "software " : "", d.drmPath.c_str(),
                    d.extensions.c_str());
    // Every listed device either gives a context or a named failure (a DRM node we may not open).
    for (const EglDeviceDesc& d : *devices) {
        GlContextOptions o;
        o.backend = GlBackend::EglDevice;
        o.eglDeviceIndex = d.index;
        auto c = GlContext::create(o);
        if (!c) {
            EXPECT_NE(c.error().message.find("egl-device"), std::string::npos) << c.error().message;
            std::printf("[ device %d ] no context: %s\n", d.index, c.error().message.c_str());
            EXPECT_FALSE(d.software) << "the software device must work: " << c.error().message;
            continue;
        }
        expectUsable(**c, GlBackend::EglDevice);
        EXPECT_EQ((*c)->info().software, d.software);
    }
}

TEST(GlContext, EglDeviceIndexOutOfRange) {
    auto devices = listEglDevices();
    if (!devices.ok()) GTEST_SKIP() << devices.error().message;
    GlContextOptions o;
    o.backend = GlBackend::EglDevice;
    o.eglDeviceIndex = int(devices->size()) + 3;
    auto c = GlContext::create(o);
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(c.error().message.find("out of range"), std::string::npos) << c.error().message;
}

TEST(GlContext, EglSurfaceless) {
    auto c = makeContext(GlBackend::EglSurfaceless);
    ASSERT_TRUE(c);
    expectUsable(*c, GlBackend::EglSurfaceless);
}

TEST(GlContext, OsMesa) {
    auto c = makeContext(GlBackend::OsMesa);
    ASSERT_TRUE(c);
    expectUsable(*c, GlBackend::OsMesa);
}

TEST(GlContext, AutoPicksABackend) {
    auto c = makeContext(GlBackend::Auto);
    ASSERT_TRUE(c);
    EXPECT_NE(c->info().backend, GlBackend::Auto);
    report(c->info());
}

// Two EGL contexts (one display, reference counted) and an OSMesa context in one process,
// made current in turn on this thread: each keeps working after the others.
TEST(GlContext, BackendsCoexistInOneProcess) {
    auto a = makeContext(GlBackend::EglSurfaceless);
    auto b = makeContext(GlBackend::EglSurfaceless);
    auto m = makeContext(GlBackend::OsMesa);
    ASSERT_TRUE(a && b && m);
    for (int round = 0; round < 2; ++round)
        for (GlContext* ctx : {a.get(), m.get(), b.get()}) {
            ASSERT_TRUE(ctx->makeCurrent().ok());
            const GlFunctions& gl = ctx->gl();
            GLuint fbo = 0, rb = 0;
            gl.CreateRenderbuffers(1, &rb);
            gl.NamedRenderbufferStorage(rb, GL_RGBA8, 4, 4);
            gl.CreateFramebuffers(1, &fbo);
            gl.NamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb);
            const float colour[4] = {0.0f, 1.0f, 0.0f, 1.0f};
            gl.ClearNamedFramebufferfv(fbo, GL_COLOR, 0, colour);
            unsigned char px[4] = {};
            gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
            gl.NamedFramebufferReadBuffer(fbo, GL_COLOR_ATTACHMENT0);
            gl.ReadPixels(1, 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, px);
            gl.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
            gl.DeleteFramebuffers(1, &fbo);
            gl.DeleteRenderbuffers(1, &rb);
            EXPECT_EQ(px[1], 255) << glBackendName(ctx->info().backend);
            EXPECT_EQ(gl.GetError(), GLenum(GL_NO_ERROR));
        }
    a.reset();  // the shared EGL display must survive for b
    ASSERT_TRUE(b->makeCurrent().ok());
    GLint major = 0;
    b->gl().GetIntegerv(GL_MAJOR_VERSION, &major);
    EXPECT_GE(major, 4);
}
