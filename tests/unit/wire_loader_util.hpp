// Helpers of the STL, PLY, DXF and Surpac loader tests (tests/unit/{stl,ply,dxf,surpac}_loader_test.cpp):
// committed test files, parts by name, closed-form volume and section-area checks.
//
// Tolerances: volumes and section areas 1e-9 relative (the test shapes have coordinates
// exact in double and in float32 where a format stores float32; the divergence-theorem sum
// and the contour shoelace round at ~1e-13 relative of 24000 m3 at easting 500,000).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "section/cut/contours.hpp"
#include "section/index/section_index.hpp"

namespace geoslice::test {

constexpr double kWireRelTol = 1e-9;

inline std::string wireData(const std::string& rel) { return std::string(GEOSLICE_TEST_DATA_DIR) + "/" + rel; }

inline std::string wireBytes(const std::string& rel) {
    auto r = readFile(wireData(rel));
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? r.value() : std::string();
}

inline const Part* wirePart(const Model& m, const std::string& name) {
    for (const auto* list : {&m.bodies, &m.surfaces})
        for (const Part& p : *list)
            if (p.name == name) return &p;
    return nullptr;
}

inline const Polyline* wireLine(const Model& m, const std::string& name) {
    for (const Polyline& l : m.lines)
        if (l.name == name) return &l;
    return nullptr;
}

// The part is a closed body of the given volume (m³, 1e-9 relative).
inline void expectBody(const Model& m, const std::string& name, double volume) {
    const Part* p = wirePart(m, name);
    ASSERT_NE(p, nullptr) << "no part " << name;
    EXPECT_EQ(p->kind, PartKind::Body) << name;
    EXPECT_TRUE(p->report.closed) << name;
    EXPECT_NEAR(std::fabs(signedVolume(p->mesh)), volume, volume * kWireRelTol) << name;
}

inline void expectSurface(const Model& m, const std::string& name) {
    const Part* p = wirePart(m, name);
    ASSERT_NE(p, nullptr) << "no part " << name;
    EXPECT_EQ(p->kind, PartKind::Surface) << name;
}

// The section area (m²) of the body `name` on the plane dot(n, p) + d = 0, by the section engine.
inline double wireSectionArea(const Model& m, const std::string& name, const Plane& plane) {
    auto idx = buildSectionIndex(m);
    EXPECT_TRUE(idx.ok()) << (idx.ok() ? "" : idx.error().message);
    if (!idx.ok()) return -1.0;
    auto s = computeSection(*idx.value(), plane);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    if (!s.ok()) return -1.0;
    for (std::size_t i = 0; i < m.bodies.size(); ++i) {
        if (m.bodies[i].name != name) continue;
        for (const BodySection& b : s->bodies)
            if (b.part == i) {
                EXPECT_EQ(b.openChains, 0u) << name;
                return b.area;
            }
        return 0.0;
    }
    ADD_FAILURE() << "no body " << name;
    return -1.0;
}

// An error that names the source and contains every one of `parts`.
inline void expectWireError(const Result<Model>& r, const std::string& source,
                            std::initializer_list<std::string> parts) {
    ASSERT_FALSE(r.ok()) << "expected an error from " << source;
    const std::string& msg = r.error().message;
    EXPECT_NE(msg.find(source), std::string::npos) << msg;
    for (const std::string& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << "expected '" << p << "' in: " << msg;
}

}  // namespace geoslice::test
