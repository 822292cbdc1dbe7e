// Shared helpers of the GL tests: a context per test process, small synthetic models.
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "renderer/gl/gl_context.hpp"
#include "tests/common/synthetic_model.hpp"

namespace geoslice::test {

// A context from `backend`; fails the test (with the backend's error) when none.
inline std::unique_ptr<GlContext> makeContext(GlBackend backend = GlBackend::Auto) {
    GlContextOptions o;
    o.backend = backend;
    auto c = GlContext::create(o);
    EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().message);
    return c.ok() ? std::move(c).value() : nullptr;
}

}  // namespace geoslice::test
