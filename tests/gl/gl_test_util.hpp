// Shared helpers of the GL tests: a context per test process, small synthetic models.
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "model/synthetic.hpp"
#include "model/validate.hpp"
#include "renderer/gl_context.hpp"

namespace geoslice::test {

// A context from `backend`; fails the test (with the backend's error) when none.
inline std::unique_ptr<GlContext> makeContext(GlBackend backend = GlBackend::Auto) {
    GlContextOptions o;
    o.backend = backend;
    auto c = GlContext::create(o);
    EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().message);
    return c.ok() ? std::move(c).value() : nullptr;
}

// A validated synthetic mine (nesting parents filled in).
inline Model makeMine(std::size_t triangles, std::uint64_t seed, OreVariant ore = OreVariant::Nested,
                      const char* crs = nullptr) {
    SyntheticOptions o;
    o.triangles = triangles;
    o.seed = seed;
    o.ore = ore;
    if (crs) {
        auto c = Crs::parse(crs);
        EXPECT_TRUE(c.ok());
        if (c.ok()) o.crs = *c;
    }
    auto m = generateSynthetic(o);
    EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().message);
    Model model = std::move(m).value();
    validate(model);
    return model;
}

}  // namespace geoslice::test
