// Internal to renderer/: the backend factories behind GlContext::create().
#pragma once

#include <memory>

#include "renderer/gl/gl_context.hpp"

namespace geoslice::detail {

Result<std::unique_ptr<GlContext>> createEglDeviceContext(const GlContextOptions& options, bool requireHardware);
Result<std::unique_ptr<GlContext>> createEglSurfacelessContext(const GlContextOptions& options);
Result<std::unique_ptr<GlContext>> createOsMesaContext(const GlContextOptions& options);

}  // namespace geoslice::detail
