#include "renderer/gl/gl_context.hpp"

#include <cstring>

#include "renderer/gl/gl_context_backends.hpp"

namespace geoslice {

const char* glBackendName(GlBackend backend) {
    switch (backend) {
        case GlBackend::Auto:
            return "auto";
        case GlBackend::EglDevice:
            return "egl-device";
        case GlBackend::EglSurfaceless:
            return "egl-surfaceless";
        case GlBackend::OsMesa:
            return "osmesa";
    }
    return "?";
}

std::optional<GlBackend> parseGlBackend(std::string_view name) {
    for (GlBackend b : {GlBackend::Auto, GlBackend::EglDevice, GlBackend::EglSurfaceless, GlBackend::OsMesa})
        if (name == glBackendName(b)) return b;
    if (name == "egl") return GlBackend::EglDevice;
    return std::nullopt;
}

std::string GlContextInfo::describe() const {
    return std::string(glBackendName(backend)) + ": " + vendor + " | " + renderer + " | " + version;
}

GlContext::~GlContext() = default;

Status GlContext::finishCreation(GlBackend backend, GlFunctions::ProcAddressFn getProc, void* user,
                                 std::string platform) {
    std::vector<std::string> missing = gl_.load(getProc, user);
    if (!missing.empty()) {
        std::string list;
        for (std::size_t i = 0; i < missing.size() && i < 8; ++i) list += (i ? ", " : "") + missing[i];
        if (missing.size() > 8) list += ", ...";
        return makeError(ErrorCode::Unsupported, std::string(glBackendName(backend)) + ": " +
                                                     std::to_string(missing.size()) +
                                                     " GL 4.5 entry points missing: " + list);
    }
    auto str = [this](GLenum name) {
        const GLubyte* s = gl_.GetString(name);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    info_.backend = backend;
    info_.vendor = str(GL_VENDOR);
    info_.renderer = str(GL_RENDERER);
    info_.version = str(GL_VERSION);
    info_.glslVersion = str(GL_SHADING_LANGUAGE_VERSION);
    info_.platform = std::move(platform);
    for (const char* sw : {"llvmpipe", "softpipe", "swrast", "SwiftShader"})
        if (info_.renderer.find(sw) != std::string::npos) info_.software = true;
    GLint major = 0, minor = 0;
    gl_.GetIntegerv(GL_MAJOR_VERSION, &major);
    gl_.GetIntegerv(GL_MINOR_VERSION, &minor);
    if (major < 4 || (major == 4 && minor < 5))
        return makeError(ErrorCode::Unsupported, std::string(glBackendName(backend)) + ": need OpenGL 4.5 core, got " +
                                                     info_.version + " (" + info_.renderer + ")");
    gl_.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &info_.maxRenderbufferSize);
    GLint dims[2] = {0, 0};
    gl_.GetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
    info_.maxViewportWidth = dims[0];
    info_.maxViewportHeight = dims[1];
    while (gl_.GetError() != GL_NO_ERROR) {
    }
    return {};
}

Result<std::unique_ptr<GlContext>> GlContext::create(const GlContextOptions& options) {
    switch (options.backend) {
        case GlBackend::EglDevice:
            return detail::createEglDeviceContext(options, false);
        case GlBackend::EglSurfaceless:
            return detail::createEglSurfacelessContext(options);
        case GlBackend::OsMesa:
            return detail::createOsMesaContext(options);
        case GlBackend::Auto:
            break;
    }
    std::string tried;
    auto note = [&tried](const Error& e) { tried += (tried.empty() ? "" : "; ") + e.message; };
    auto hw = detail::createEglDeviceContext(options, true);
    if (hw) return hw;
    note(hw.error());
    auto sl = detail::createEglSurfacelessContext(options);
    if (sl) return sl;
    note(sl.error());
    auto dev = detail::createEglDeviceContext(options, false);
    if (dev) return dev;
    note(dev.error());
    auto os = detail::createOsMesaContext(options);
    if (os) return os;
    note(os.error());
    return makeError(ErrorCode::Unsupported, "no OpenGL 4.5 core context could be created (tried: " + tried + ")");
}

}  // namespace geoslice
