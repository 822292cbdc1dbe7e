// Every embedded shader compiles and links in every variant; failures print the info log.
#include <gtest/gtest.h>

#include <string>

#include "gl_test_util.hpp"
#include "renderer/gl/gl_program.hpp"
#include "renderer/shader_sources.hpp"
#include "renderer/slice_renderer.hpp"

using namespace geoslice;
using namespace geoslice::test;

TEST(Shaders, EmbeddedSourcesAreGlsl450Core) {
    ASSERT_FALSE(embeddedShaders().empty());
    for (const EmbeddedShader& s : embeddedShaders())
        EXPECT_EQ(std::string(s.source).rfind("#version 450 core\n", 0), 0u) << s.name;
    EXPECT_NE(findEmbeddedShader("slice.vert"), nullptr);
    EXPECT_EQ(findEmbeddedShader("missing.frag"), nullptr);
}

TEST(Shaders, DefinesGoAfterTheVersionLine) {
    std::string s = GlProgram::withDefines("#version 450 core\nvoid main() {}\n", {"A 1", "B"});
    EXPECT_EQ(s, "#version 450 core\n#define A 1\n#define B\n#line 2\nvoid main() {}\n");
}

TEST(Shaders, EveryProgramVariantCompiles) {
    auto ctx = makeContext();
    ASSERT_TRUE(ctx);
    auto r = SliceRenderer::create(*ctx);  // compiles and links every variant
    ASSERT_TRUE(r.ok()) << r.error().message;
    for (int i = 0; i < SliceRenderer::kProgramCount; ++i) {
        EXPECT_NE((*r)->program(i).id(), 0u);
        EXPECT_GE((*r)->program(i).uniform("uViewProj"), 0) << (*r)->program(i).label();
        EXPECT_GE((*r)->program(i).uniform("uCapRecord"), 0) << (*r)->program(i).label();
    }
    for (int i = 0; i < SliceRenderer::kHelperProgramCount; ++i) EXPECT_NE((*r)->helperProgram(i).id(), 0u);
    EXPECT_GE((*r)->helperProgram(0).uniform("uViewProj"), 0) << (*r)->helperProgram(0).label();
    EXPECT_GE((*r)->helperProgram(1).uniform("uTexel"), 0) << (*r)->helperProgram(1).label();
}

TEST(Shaders, CompileErrorCarriesTheInfoLog) {
    auto ctx = makeContext();
    ASSERT_TRUE(ctx);
    auto p = GlProgram::build(ctx->gl(), "slice.vert", "slice.frag", {"GS_CLIP_DISTANCE 1", "uniform not_a_type"});
    ASSERT_FALSE(p.ok());
    EXPECT_NE(p.error().message.find("slice.vert"), std::string::npos) << p.error().message;
    EXPECT_GT(p.error().message.size(), 60u) << p.error().message;  // the driver's log is included
    auto missing = GlProgram::build(ctx->gl(), "slice.vert", "nothing.frag");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::NotFound);
}
