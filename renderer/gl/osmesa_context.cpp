// OSMesa backend: libOSMesa.so.8 is opened with dlopen(RTLD_LOCAL) and never linked, so its
// gl* exports cannot clash with libOpenGL/libGLdispatch (which EGL brings in).
#include <dlfcn.h>

#include <array>
#include <cstdint>
#include <mutex>
#include <string>

#include "renderer/gl/gl_context_backends.hpp"

namespace geoslice::detail {
namespace {

// From <GL/osmesa.h>, which cannot be included beside <GL/glcorearb.h> (it pulls in <GL/gl.h>).
using OSMesaContext = struct osmesa_context*;
using OSMesaCreateContextAttribsFn = OSMesaContext (*)(const int* attribList, OSMesaContext sharelist);
using OSMesaMakeCurrentFn = GLboolean (*)(OSMesaContext ctx, void* buffer, GLenum type, GLsizei width, GLsizei height);
using OSMesaDestroyContextFn = void (*)(OSMesaContext ctx);
using OSMesaGetProcAddressFn = void* (*)(const char* funcName);
constexpr int kOsMesaFormat = 0x22, kOsMesaDepthBits = 0x30, kOsMesaStencilBits = 0x31, kOsMesaAccumBits = 0x32,
              kOsMesaProfile = 0x33, kOsMesaCoreProfile = 0x34, kOsMesaContextMajor = 0x36, kOsMesaContextMinor = 0x37;
constexpr int kOsMesaRgba = GL_RGBA;
constexpr GLsizei kClientBufferSize = 16;  // OSMesa needs a bound buffer even when only FBOs are drawn

struct OsMesaLibrary {
    void* handle = nullptr;
    OSMesaCreateContextAttribsFn createContextAttribs = nullptr;
    OSMesaMakeCurrentFn makeCurrent = nullptr;
    OSMesaDestroyContextFn destroyContext = nullptr;
    OSMesaGetProcAddressFn getProcAddress = nullptr;
    std::string error;
};

// Opened once per process and kept open: Mesa does not support unloading it.
const OsMesaLibrary& osMesaLibrary() {
    static OsMesaLibrary lib = [] {
        OsMesaLibrary l;
        for (const char* name : {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}) {
            l.handle = dlopen(name, RTLD_NOW | RTLD_LOCAL);
            if (l.handle) break;
            const char* e = dlerror();
            l.error += std::string(l.error.empty() ? "" : "; ") + (e ? e : name);
        }
        if (!l.handle) return l;
        l.createContextAttribs =
            reinterpret_cast<OSMesaCreateContextAttribsFn>(dlsym(l.handle, "OSMesaCreateContextAttribs"));
        l.makeCurrent = reinterpret_cast<OSMesaMakeCurrentFn>(dlsym(l.handle, "OSMesaMakeCurrent"));
        l.destroyContext = reinterpret_cast<OSMesaDestroyContextFn>(dlsym(l.handle, "OSMesaDestroyContext"));
        l.getProcAddress = reinterpret_cast<OSMesaGetProcAddressFn>(dlsym(l.handle, "OSMesaGetProcAddress"));
        if (!l.createContextAttribs || !l.makeCurrent || !l.destroyContext || !l.getProcAddress) {
            l.error = "libOSMesa lacks OSMesaCreateContextAttribs/OSMesaMakeCurrent/OSMesaGetProcAddress";
            l.handle = nullptr;
        }
        return l;
    }();
    return lib;
}

void* osMesaProc(const char* name, void* user) { return static_cast<const OsMesaLibrary*>(user)->getProcAddress(name); }

class OsMesaGlContext final : public GlContext {
public:
    explicit OsMesaGlContext(const OsMesaLibrary& lib) : lib_(lib) {}
    ~OsMesaGlContext() override {
        if (ctx_) lib_.destroyContext(ctx_);
    }

    Status makeCurrent() override {
        if (!lib_.makeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, kClientBufferSize, kClientBufferSize))
            return makeError(ErrorCode::Internal, "osmesa: OSMesaMakeCurrent on a 16x16 RGBA buffer failed");
        return {};
    }
    void releaseCurrent() override { lib_.makeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0); }

    Status init() {
        const int attribs[] = {kOsMesaFormat,
                               kOsMesaRgba,
                               kOsMesaDepthBits,
                               0,
                               kOsMesaStencilBits,
                               0,
                               kOsMesaAccumBits,
                               0,
                               kOsMesaProfile,
                               kOsMesaCoreProfile,
                               kOsMesaContextMajor,
                               4,
                               kOsMesaContextMinor,
                               5,
                               0};
        ctx_ = lib_.createContextAttribs(attribs, nullptr);
        if (!ctx_)
            return makeError(ErrorCode::Unsupported,
                             "osmesa: OSMesaCreateContextAttribs(RGBA, core profile 4.5) failed (Mesa built without "
                             "gallium OSMesa, or no GL 4.5 core)");
        if (auto s = makeCurrent(); !s) return s;
        return finishCreation(GlBackend::OsMesa, &osMesaProc, const_cast<OsMesaLibrary*>(&lib_),
                              "OSMesa (dlopen libOSMesa.so.8), 16x16 client buffer");
    }

private:
    const OsMesaLibrary& lib_;
    OSMesaContext ctx_ = nullptr;
    std::array<std::uint8_t, kClientBufferSize * kClientBufferSize * 4> buffer_{};
};

}  // namespace

Result<std::unique_ptr<GlContext>> createOsMesaContext(const GlContextOptions&) {
    const OsMesaLibrary& lib = osMesaLibrary();
    if (!lib.handle) return makeError(ErrorCode::Unsupported, "osmesa: cannot load libOSMesa: " + lib.error);
    std::unique_ptr<OsMesaGlContext> ctx(new OsMesaGlContext(lib));
    if (auto s = ctx->init(); !s) return s.error();
    std::unique_ptr<GlContext> base = std::move(ctx);
    return base;
}

}  // namespace geoslice::detail
