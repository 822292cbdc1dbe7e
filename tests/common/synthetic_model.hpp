// Generated test models, shared by the unit and GL tests (GoogleTest reports failures).
#pragma once

#include <gtest/gtest.h>

#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"

namespace geoslice::test {

// A synthetic mine; validated (nesting parents filled in) unless `validated` is false,
// for tests that inspect what the generator itself produced.
inline Model syntheticModel(std::size_t triangles, OreVariant ore = OreVariant::Nested, std::uint64_t seed = 1,
                            const char* crs = nullptr, bool validated = true) {
    SyntheticOptions o;
    o.triangles = triangles;
    o.ore = ore;
    o.seed = seed;
    if (crs) {
        auto c = Crs::parse(crs);
        EXPECT_TRUE(c.ok()) << crs;
        if (c.ok()) o.crs = c.value();
    }
    auto m = generateSynthetic(o);
    EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().message);
    if (!m.ok()) return Model{};
    Model model = std::move(m).value();
    if (validated) validate(model);
    return model;
}

}  // namespace geoslice::test
