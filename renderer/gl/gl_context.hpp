// The GL platform seam (after Filament's OpenGLPlatform and Magnum's WindowlessEglContext):
// one headless OpenGL 4.5 core context, from one of three backends chosen at run time.
//
//   egl-device       EGL_EXT_platform_device: eglQueryDevicesEXT, then
//                    eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device). Picks the
//                    device by index, or (index -1) the first non-software device (NVIDIA on
//                    a GPU node), else the first device (Mesa's software device here).
//   egl-surfaceless  EGL_MESA_platform_surfaceless with EGL_KHR_no_config_context and
//                    EGL_KHR_surfaceless_context (Mesa; llvmpipe on a CPU machine).
//   osmesa           libOSMesa.so.8, loaded with dlopen (RTLD_LOCAL) so that its gl* symbols
//                    never meet libOpenGL's; made current on a 16x16 client buffer, which
//                    OSMesa needs even though geoslice renders to framebuffer objects only.
//   auto             egl-device when a non-software device exists, else egl-surfaceless,
//                    else egl-device (software), else osmesa.
//
// GL entry points come from the backend's getProcAddress into gl() (renderer/gl/gl_functions.hpp).
// Nothing here sets GALLIUM_DRIVER or LP_NUM_THREADS: llvmpipe picks its own thread count.
//
// Threads: a GlContext is created current on the calling thread and belongs to it. Call
// every member, gl() entry and every object that uses the context (GpuModel, SliceRenderer,
// GlProgram) on that thread only; destroy it there too. makeCurrent() re-binds it after
// another context was made current on the same thread. Different contexts may live on
// different threads at the same time (one per render worker).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "model/result.hpp"
#include "renderer/gl/gl_functions.hpp"

namespace geoslice {

enum class GlBackend { Auto, EglDevice, EglSurfaceless, OsMesa };

const char* glBackendName(GlBackend backend);  // "auto", "egl-device", "egl-surfaceless", "osmesa"
std::optional<GlBackend> parseGlBackend(std::string_view name);

struct GlContextOptions {
    GlBackend backend = GlBackend::Auto;
    int eglDeviceIndex = -1;   // egl-device: index into listEglDevices(); -1 = prefer hardware
    bool debugOutput = false;  // create a debug context (KHR_debug) where the backend allows
};

// What the context runs on, for logs and the health endpoint.
struct GlContextInfo {
    GlBackend backend = GlBackend::Auto;  // the backend actually used (never Auto)
    std::string vendor;                   // GL_VENDOR, e.g. "Mesa", "NVIDIA Corporation"
    std::string renderer;                 // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string version;                  // GL_VERSION
    std::string glslVersion;              // GL_SHADING_LANGUAGE_VERSION
    std::string platform;                 // e.g. "EGL 1.5 (Mesa Project) device 0 [EGL_MESA_device_software]"
    int eglDeviceIndex = -1;              // egl-device only
    bool software = false;                // llvmpipe / softpipe / swrast
    int maxRenderbufferSize = 0;          // GL_MAX_RENDERBUFFER_SIZE
    int maxViewportWidth = 0, maxViewportHeight = 0;  // GL_MAX_VIEWPORT_DIMS
    std::string describe() const;                     // one line: backend, vendor, renderer, version
};

// One EGL device as EGL_EXT_device_enumeration reports it (no context needed).
struct EglDeviceDesc {
    int index = 0;
    std::string extensions;  // eglQueryDeviceStringEXT(EGL_EXTENSIONS)
    std::string drmPath;     // EGL_DRM_DEVICE_FILE_EXT when the device has one
    bool software = false;   // EGL_MESA_device_software
};
Result<std::vector<EglDeviceDesc>> listEglDevices();

class GlContext {
public:
    // Creates the context, makes it current on the calling thread, loads gl() and checks
    // for GL >= 4.5 core. Errors name the backend and the EGL error (EGL_BAD_MATCH...) or
    // the OSMesa/dlopen failure; with Auto, every attempt is listed.
    static Result<std::unique_ptr<GlContext>> create(const GlContextOptions& options = {});

    virtual ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    // Makes this context current on the calling thread (which must be its own thread).
    virtual Status makeCurrent() = 0;
    // Releases it from the calling thread (no GL calls until makeCurrent()).
    virtual void releaseCurrent() = 0;

    const GlFunctions& gl() const { return gl_; }
    const GlContextInfo& info() const { return info_; }

protected:
    GlContext() = default;
    // Backends call this once the context is current: loads gl_, fills info_, checks 4.5.
    Status finishCreation(GlBackend backend, GlFunctions::ProcAddressFn getProc, void* user, std::string platform);

    GlFunctions gl_;
    GlContextInfo info_;
};

}  // namespace geoslice
