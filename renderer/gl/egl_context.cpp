// EGL backends: device platform (EGL_EXT_platform_device) and Mesa's surfaceless platform.
#include <cstring>
#include <map>
#include <mutex>
#include <string>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "renderer/gl/gl_context_backends.hpp"

namespace geoslice::detail {
namespace {

std::string eglErrorName(EGLint error) {
    switch (error) {
        case EGL_SUCCESS:
            return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED:
            return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS:
            return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC:
            return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE:
            return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG:
            return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT:
            return "EGL_BAD_CONTEXT";
        case EGL_BAD_CURRENT_SURFACE:
            return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY:
            return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH:
            return "EGL_BAD_MATCH";
        case EGL_BAD_NATIVE_PIXMAP:
            return "EGL_BAD_NATIVE_PIXMAP";
        case EGL_BAD_NATIVE_WINDOW:
            return "EGL_BAD_NATIVE_WINDOW";
        case EGL_BAD_PARAMETER:
            return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE:
            return "EGL_BAD_SURFACE";
        case EGL_CONTEXT_LOST:
            return "EGL_CONTEXT_LOST";
        case EGL_BAD_DEVICE_EXT:
            return "EGL_BAD_DEVICE_EXT";
        default: {
            char buf[32];
            std::snprintf(buf, sizeof buf, "EGL error 0x%04x", error);
            return buf;
        }
    }
}

Error eglFailure(const char* backend, const std::string& what) {
    return makeError(ErrorCode::Unsupported,
                     std::string(backend) + ": " + what + " failed: " + eglErrorName(eglGetError()));
}

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

template <class Fn>
Fn eglProc(const char* name) {
    return reinterpret_cast<Fn>(eglGetProcAddress(name));
}

void* eglGetProcForTable(const char* name, void*) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

// EGLDisplays are per process and per native display: two contexts on the same device share
// one, and eglTerminate would pull it from under the other. Count users; terminate at zero.
std::mutex gDisplayMutex;
std::map<EGLDisplay, int> gDisplayUsers;

Status acquireDisplay(EGLDisplay display, const char* backend, EGLint& major, EGLint& minor) {
    std::lock_guard<std::mutex> lock(gDisplayMutex);
    if (!eglInitialize(display, &major, &minor)) return eglFailure(backend, "eglInitialize");
    ++gDisplayUsers[display];
    return {};
}

void releaseDisplay(EGLDisplay display) {
    std::lock_guard<std::mutex> lock(gDisplayMutex);
    auto it = gDisplayUsers.find(display);
    if (it == gDisplayUsers.end()) return;
    if (--it->second == 0) {
        gDisplayUsers.erase(it);
        eglTerminate(display);
    }
}

class EglContext final : public GlContext {
public:
    ~EglContext() override {
        if (display_ == EGL_NO_DISPLAY) return;
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
        if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
        eglReleaseThread();
        releaseDisplay(display_);
    }

    Status makeCurrent() override {
        if (!eglMakeCurrent(display_, surface_, surface_, context_)) return eglFailure(backendName_, "eglMakeCurrent");
        return {};
    }
    void releaseCurrent() override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }

    // Initialises `display` (already obtained from eglGetPlatformDisplayEXT) and creates a
    // GL 4.5 core context on it, current on this thread.
    Status init(EGLDisplay display, GlBackend backend, const GlContextOptions& options, std::string platform) {
        backendName_ = glBackendName(backend);
        EGLint major = 0, minor = 0;
        if (auto s = acquireDisplay(display, backendName_, major, minor); !s) return s;
        display_ = display;
        const char* displayExts = eglQueryString(display_, EGL_EXTENSIONS);
        if (!eglBindAPI(EGL_OPENGL_API)) return eglFailure(backendName_, "eglBindAPI(EGL_OPENGL_API)");

        EGLConfig config = EGL_NO_CONFIG_KHR;
        const bool noConfig = hasExtension(displayExts, "EGL_KHR_no_config_context");
        const bool surfaceless = hasExtension(displayExts, "EGL_KHR_surfaceless_context");
        if (!noConfig || !surfaceless) {
            const EGLint configAttribs[] = {EGL_SURFACE_TYPE,
                                            EGL_PBUFFER_BIT,
                                            EGL_RENDERABLE_TYPE,
                                            EGL_OPENGL_BIT,
                                            EGL_RED_SIZE,
                                            8,
                                            EGL_GREEN_SIZE,
                                            8,
                                            EGL_BLUE_SIZE,
                                            8,
                                            EGL_NONE};
            EGLint n = 0;
            if (!eglChooseConfig(display_, configAttribs, &config, 1, &n))
                return eglFailure(backendName_, "eglChooseConfig");
            if (n < 1)
                return makeError(ErrorCode::Unsupported,
                                 std::string(backendName_) + ": no EGL config with EGL_OPENGL_BIT and EGL_PBUFFER_BIT");
        }
        EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                   4,
                                   EGL_CONTEXT_MINOR_VERSION,
                                   5,
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                   EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                   EGL_CONTEXT_OPENGL_DEBUG,
                                   options.debugOutput ? EGL_TRUE : EGL_FALSE,
                                   EGL_NONE};
        context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, contextAttribs);
        if (context_ == EGL_NO_CONTEXT) return eglFailure(backendName_, "eglCreateContext(OpenGL 4.5 core)");
        if (!surfaceless) {
            const EGLint pbufferAttribs[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
            surface_ = eglCreatePbufferSurface(display_, config, pbufferAttribs);
            if (surface_ == EGL_NO_SURFACE) return eglFailure(backendName_, "eglCreatePbufferSurface(1x1)");
        }
        if (auto s = makeCurrent(); !s) return s;
        const char* vendor = eglQueryString(display_, EGL_VENDOR);
        platform = "EGL " + std::to_string(major) + "." + std::to_string(minor) + " (" + (vendor ? vendor : "?") +
                   ") " + platform + (noConfig ? "" : " [config]") + (surfaceless ? "" : " [pbuffer]");
        return finishCreation(backend, &eglGetProcForTable, nullptr, std::move(platform));
    }

private:
    const char* backendName_ = "egl";
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
    EGLSurface surface_ = EGL_NO_SURFACE;
};

struct DeviceApi {
    PFNEGLQUERYDEVICESEXTPROC queryDevices = nullptr;
    PFNEGLQUERYDEVICESTRINGEXTPROC queryDeviceString = nullptr;
    PFNEGLGETPLATFORMDISPLAYEXTPROC getPlatformDisplay = nullptr;
};

Result<DeviceApi> deviceApi(const char* backend) {
    const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    for (const char* ext : {"EGL_EXT_platform_base", "EGL_EXT_platform_device"})
        if (!hasExtension(clientExts, ext))
            return makeError(ErrorCode::Unsupported,
                             std::string(backend) + ": EGL client extension " + ext + " missing");
    if (!hasExtension(clientExts, "EGL_EXT_device_enumeration") && !hasExtension(clientExts, "EGL_EXT_device_base"))
        return makeError(ErrorCode::Unsupported, std::string(backend) + ": EGL_EXT_device_enumeration missing");
    DeviceApi api;
    api.queryDevices = eglProc<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
    api.queryDeviceString = eglProc<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");
    api.getPlatformDisplay = eglProc<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
    if (!api.queryDevices || !api.queryDeviceString || !api.getPlatformDisplay)
        return makeError(ErrorCode::Unsupported, std::string(backend) + ": EGL device functions not found");
    return api;
}

Result<std::vector<EGLDeviceEXT>> queryDevices(const DeviceApi& api, const char* backend) {
    EGLint n = 0;
    if (!api.queryDevices(0, nullptr, &n)) return eglFailure(backend, "eglQueryDevicesEXT");
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(n));
    if (n > 0 && !api.queryDevices(n, devices.data(), &n)) return eglFailure(backend, "eglQueryDevicesEXT");
    devices.resize(static_cast<std::size_t>(n));
    return devices;
}

EglDeviceDesc describeDevice(const DeviceApi& api, EGLDeviceEXT device, int index) {
    EglDeviceDesc d;
    d.index = index;
    const char* exts = api.queryDeviceString(device, EGL_EXTENSIONS);
    d.extensions = exts ? exts : "";
    d.software = hasExtension(exts, "EGL_MESA_device_software");
    if (hasExtension(exts, "EGL_EXT_device_drm")) {
        const char* path = api.queryDeviceString(device, EGL_DRM_DEVICE_FILE_EXT);
        if (path) d.drmPath = path;
    }
    eglGetError();  // a device without the string leaves an error behind
    return d;
}

}  // namespace

Result<std::unique_ptr<GlContext>> createEglDeviceContext(const GlContextOptions& options, bool requireHardware) {
    const char* backend = "egl-device";
    auto api = deviceApi(backend);
    if (!api) return api.error();
    auto devices = queryDevices(*api, backend);
    if (!devices) return devices.error();
    if (devices->empty()) return makeError(ErrorCode::Unsupported, "egl-device: eglQueryDevicesEXT found no device");
    std::vector<EglDeviceDesc> descs;
    for (std::size_t i = 0; i < devices->size(); ++i) descs.push_back(describeDevice(*api, (*devices)[i], int(i)));
    int pick = -1;
    if (options.eglDeviceIndex >= 0) {
        if (options.eglDeviceIndex >= int(descs.size()))
            return makeError(ErrorCode::InvalidArgument,
                             "egl-device: device index " + std::to_string(options.eglDeviceIndex) + " out of range (" +
                                 std::to_string(descs.size()) + " devices)");
        pick = options.eglDeviceIndex;
    } else {
        for (const auto& d : descs)
            if (!d.software) {
                pick = d.index;
                break;
            }
        if (pick < 0 && !requireHardware) pick = 0;
        if (pick < 0)
            return makeError(ErrorCode::Unsupported, "egl-device: no hardware device among " +
                                                         std::to_string(descs.size()) +
                                                         " EGL device(s) (software only)");
    }
    EGLDisplay display = api->getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, (*devices)[std::size_t(pick)], nullptr);
    if (display == EGL_NO_DISPLAY) return eglFailure(backend, "eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT)");
    const EglDeviceDesc& d = descs[std::size_t(pick)];
    std::string platform = "device " + std::to_string(pick) + "/" + std::to_string(descs.size()) +
                           (d.drmPath.empty() ? "" : " " + d.drmPath) + (d.software ? " [software]" : "");
    std::unique_ptr<EglContext> ctx(new EglContext());
    if (auto s = ctx->init(display, GlBackend::EglDevice, options, std::move(platform)); !s) return s.error();
    std::unique_ptr<GlContext> base = std::move(ctx);
    return base;
}

Result<std::unique_ptr<GlContext>> createEglSurfacelessContext(const GlContextOptions& options) {
    const char* backend = "egl-surfaceless";
    const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    for (const char* ext : {"EGL_EXT_platform_base", "EGL_MESA_platform_surfaceless"})
        if (!hasExtension(clientExts, ext))
            return makeError(ErrorCode::Unsupported,
                             std::string(backend) + ": EGL client extension " + ext + " missing");
    auto getPlatformDisplay = eglProc<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
    if (!getPlatformDisplay)
        return makeError(ErrorCode::Unsupported, "egl-surfaceless: eglGetPlatformDisplayEXT not found");
    EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY)
        return eglFailure(backend, "eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
    std::unique_ptr<EglContext> ctx(new EglContext());
    if (auto s = ctx->init(display, GlBackend::EglSurfaceless, options, "surfaceless"); !s) return s.error();
    std::unique_ptr<GlContext> base = std::move(ctx);
    return base;
}

}  // namespace geoslice::detail

namespace geoslice {

Result<std::vector<EglDeviceDesc>> listEglDevices() {
    auto api = detail::deviceApi("egl-device");
    if (!api) return api.error();
    auto devices = detail::queryDevices(*api, "egl-device");
    if (!devices) return devices.error();
    std::vector<EglDeviceDesc> out;
    for (std::size_t i = 0; i < devices->size(); ++i)
        out.push_back(detail::describeDevice(*api, (*devices)[i], int(i)));
    return out;
}

}  // namespace geoslice
