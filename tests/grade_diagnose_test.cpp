// raster grade's diagnosis (raster/tools/grade/diagnose.hpp) on hand-made pixel histories: each test
// builds the solution's trace of one pixel and a submission's that differs at one stage, and checks the
// stage named and the words and figures of the headline. And the trace's JSON carried from the lab
// runner (grade/trace_json.hpp) read back field for field.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "grade/diagnose.hpp"
#include "grade/trace_json.hpp"
#include "raster/check.hpp"

namespace {

using namespace raster;
using raster::grade::DiagnosisStage;

constexpr int32_t kX = 5, kY = 7;

BlendState additive() {
    return BlendState::additive();
}

// Draw 0: the occluder (no GS, primitive 0 covers the pixel); draw 1: particles through a GS, input
// primitive 3 emitting a 4-vertex strip set up as two triangles.
struct Frame {
    Trace trace{TraceOptions{.pixels = {kX, kY, kX, kY}}};
    std::vector<TraceFragment> fragments;

    Frame(const BlendState& blend, const DepthStencilState& depth, size_t gs_corners = 4,
          float corner_x = 10.0f) {
        TraceDraw& occluder = trace.beginDraw(16, 16);
        occluder.draw = 0;
        occluder.vertexShader = "VsBasic", occluder.pixelShader = "PsBasic";
        occluder.topology = Topology::TriangleList;
        occluder.primitives.push_back(triangle(0, 0.0f));
        TraceDraw& particles = trace.beginDraw(16, 16);
        particles.draw = 1;
        particles.vertexShader = "VsBillboard", particles.geometryShader = "GsBillboard";
        particles.pixelShader = "PsFire";
        particles.topology = Topology::PointList;
        particles.blend = blend;
        particles.depthStencil = depth;
        particles.gsFloats = 6;
        for (size_t k = 0; k < gs_corners; ++k)
            particles.gsVertices.push_back({3, k == 0, {float(k), 1, 0.5f, 1, float(k & 1), float(k >> 1)}});
        particles.primitives.push_back(triangle(3, corner_x));
        if (gs_corners == 4) particles.primitives.push_back(triangle(3, corner_x));
    }
    static TracePrimitive triangle(uint32_t primitive, float x0) {
        TracePrimitive p{};
        p.primitive = primitive, p.kind = PrimitiveKind::Triangle, p.fate = PrimitiveFate::Rasterized;
        p.vertexCount = 3;
        p.screen[0] = {x0, 0, 0.5f, 1}, p.screen[1] = {0, 12, 0.5f, 1}, p.screen[2] = {12, 12, 0.5f, 1};
        return p;
    }
    void add(uint32_t draw, uint32_t primitive, float depth, float before, float after, FragmentFate fate,
             glm::vec4 shader, glm::vec4 colour_before, glm::vec4 colour_after) {
        fragments.push_back(
            {draw, primitive, kX, kY, depth, before, after, fate, true, shader, colour_before, colour_after});
    }
    const Trace& done() {
        trace.addFragments(fragments);
        return trace;
    }
};

const glm::vec4 kBlack{0, 0, 0, 1}, kGrey{0.5f, 0.5f, 0.5f, 1}, kFire{1, 0.5f, 0.25f, 0.5f};

// The solution's history: the occluder written at depth 0.6, the particle in front at 0.4, added.
Frame solution() {
    Frame f(additive(), DepthStencilState::readOnly());
    f.add(0, 0, 0.6f, 1.0f, 0.6f, FragmentFate::Written, kGrey, kBlack, kGrey);
    f.add(1, 3, 0.4f, 0.6f, 0.6f, FragmentFate::Written, kFire, kGrey, {1.0f, 0.75f, 0.625f, 1.25f});
    return f;
}

TEST(GradeDiagnose, SameHistoriesNameNoStage) {
    Frame a = solution(), b = solution();
    const grade::Diagnosis d = grade::diagnosePixel(a.done(), b.done(), kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::None);
    EXPECT_NE(d.headline.find("the same"), std::string::npos) << d.headline;
}

TEST(GradeDiagnose, BlendFactorIsNamedWithBothValues) {
    BlendState wrong = additive();
    wrong.renderTarget[0].destBlend = Blend::InvSrcAlpha;
    Frame yours(wrong, DepthStencilState::readOnly()), theirs = solution();
    yours.add(0, 0, 0.6f, 1.0f, 0.6f, FragmentFate::Written, kGrey, kBlack, kGrey);
    yours.add(1, 3, 0.4f, 0.6f, 0.6f, FragmentFate::Written, kFire, kGrey, {0.75f, 0.5f, 0.375f, 0.75f});
    const grade::Diagnosis d = grade::diagnosePixel(yours.done(), theirs.done(), kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::Blend);
    EXPECT_NE(d.headline.find("draw 1, primitive 3: your destination factor is Blend::InvSrcAlpha where the "
                              "solution's is Blend::One"),
              std::string::npos)
        << d.headline;
}

TEST(GradeDiagnose, DepthWriteLeftOnIsNamedWithTheDepths) {
    Frame yours(additive(), DepthStencilState{}), theirs = solution();
    yours.add(0, 0, 0.6f, 1.0f, 0.6f, FragmentFate::Written, kGrey, kBlack, kGrey);
    yours.add(1, 3, 0.4f, 0.6f, 0.4f, FragmentFate::Written, kFire, kGrey, {1.0f, 0.75f, 0.625f, 1.25f});
    const grade::Diagnosis d = grade::diagnosePixel(yours.done(), theirs.done(), kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::DepthTest);
    EXPECT_NE(
        d.headline.find("your fragment wrote its depth 0.4 over a stored 0.6, the solution's left 0.6: is "
                        "depth write on?"),
        std::string::npos)
        << d.headline;
    ASSERT_FALSE(d.details.empty());
    EXPECT_EQ(d.details[0], "draw 1 depth-stencil: your depth write is on where the solution's is off");
}

TEST(GradeDiagnose, DepthTestOutcomeIsNamed) {
    Frame yours(additive(), DepthStencilState::readOnly()), theirs = solution();
    yours.add(0, 0, 0.6f, 1.0f, 0.6f, FragmentFate::Written, kGrey, kBlack, kGrey);
    yours.add(1, 3, 0.4f, 0.6f, 0.6f, FragmentFate::EarlyDepthFailed, kFire, kGrey, kGrey);
    const grade::Diagnosis d = grade::diagnosePixel(yours.done(), theirs.done(), kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::DepthTest);
    EXPECT_NE(d.headline.find(
                  "your fragment failed the depth test, the solution's passed (0.4 against a stored 0.6"),
              std::string::npos)
        << d.headline;
}

TEST(GradeDiagnose, GeometryShaderTriangleCountIsNamed) {
    Frame yours(additive(), DepthStencilState::readOnly(), 3), theirs = solution();
    yours.add(0, 0, 0.6f, 1.0f, 0.6f, FragmentFate::Written, kGrey, kBlack, kGrey);
    const grade::Diagnosis d = grade::diagnosePixel(yours.done(), theirs.done(), kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::GeometryShader);
    EXPECT_NE(
        d.headline.find("draw 1, primitive 3: the geometry shader emitted 1 triangle (3 vertices) for this "
                        "input primitive (solution: 2 triangles, 4 vertices)"),
        std::string::npos)
        << d.headline;
}

TEST(GradeDiagnose, PositionOffsetIsNamedInPixels) {
    Frame yours(additive(), DepthStencilState::readOnly(), 4, 10.5f), theirs = solution();
    yours.add(0, 0, 0.6f, 1.0f, 0.6f, FragmentFate::Written, kGrey, kBlack, kGrey);
    yours.add(1, 3, 0.4f, 0.6f, 0.6f, FragmentFate::Written, kFire, kGrey, {1.0f, 0.75f, 0.625f, 1.25f});
    const grade::Diagnosis d = grade::diagnosePixel(yours.done(), theirs.done(), kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::GeometryShader);
    EXPECT_NE(d.headline.find("x differs by +0.50 pixel"), std::string::npos) << d.headline;
}

TEST(GradeDiagnose, PixelShaderOutputIsNamed) {
    Frame yours(additive(), DepthStencilState::readOnly()), theirs = solution();
    yours.add(0, 0, 0.6f, 1.0f, 0.6f, FragmentFate::Written, kGrey, kBlack, kGrey);
    yours.add(1, 3, 0.4f, 0.6f, 0.6f, FragmentFate::Written, {1, 0.5f, 0.1f, 1}, kGrey, {1.5f, 1, 0.6f, 2});
    const grade::Diagnosis d = grade::diagnosePixel(yours.done(), theirs.done(), kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::PixelShader);
    EXPECT_NE(d.headline.find(
                  "your pixel shader returned (1.000, 0.500, 0.100, 1.000), the solution's (1.000, 0.500, "
                  "0.250, 0.500)"),
              std::string::npos)
        << d.headline;
}

// One draw of one triangle (screen positions in pixels, on the 16.8 grid) and, when `covered`, its
// fragment at pixel (kX, kY): a coverage difference, the same geometry on both sides.
Trace coverageFrame(const glm::vec2 (&corners)[3], bool covered, const RasterizerState& rs = {}) {
    Trace trace{TraceOptions{.pixels = {kX, kY, kX, kY}}};
    TraceDraw& d = trace.beginDraw(16, 16);
    d.draw = 0;
    d.vertexShader = "VsPassThrough", d.pixelShader = "PsColor";
    d.topology = Topology::TriangleList;
    d.rasterizer = rs;
    d.coverageTest = true;
    TracePrimitive p{};
    p.primitive = 0, p.kind = PrimitiveKind::Triangle, p.fate = PrimitiveFate::Rasterized, p.vertexCount = 3;
    for (int k = 0; k < 3; ++k) p.screen[k] = {corners[k].x, corners[k].y, 0.5f, 1};
    d.primitives.push_back(p);
    if (covered)
        trace.addFragments(
            {{0, 0, kX, kY, 0.5f, NAN, NAN, FragmentFate::Written, true, kFire, kBlack, kFire}});
    return trace;
}

TEST(GradeDiagnose, CentreOnAnEdgeNamesTheTopLeftRule) {
    // Pixel (5, 7)'s centre (5.5, 7.5) lies on the vertical edge x = 5.5, the triangle to its right: a
    // left edge, so the solution covers it; a bottom-right rule would not.
    const glm::vec2 corners[3] = {{5.5f, 0}, {5.5f, 16}, {12, 8}};
    const Trace yours = coverageFrame(corners, false), theirs = coverageFrame(corners, true);
    const grade::Diagnosis d = grade::diagnosePixel(yours, theirs, kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::Rasterizer) << d.headline;
    for (const char* words :
         {"your rasterizer did not cover pixel (5, 7) with primitive 0",
          "its centre (5.5, 7.5) lies exactly on the triangle's edge from (5.5, 16) to (5.5, 0)",
          "a left edge, which covers it", "check the top-left rule"})
        EXPECT_NE(d.headline.find(words), std::string::npos) << d.headline << "\nlacks: " << words;
    // Not every coverage difference is a tie: a centre well inside, missed, names neither cause.
    const glm::vec2 wide[3] = {{0, 0}, {16, 0}, {0, 16}};
    const grade::Diagnosis inside =
        grade::diagnosePixel(coverageFrame(wide, false), coverageFrame(wide, true), kX, kY);
    EXPECT_EQ(inside.stage, DiagnosisStage::Rasterizer);
    EXPECT_EQ(inside.headline.find("top-left"), std::string::npos) << inside.headline;
    EXPECT_NE(inside.headline.find("compare the rasterizer state"), std::string::npos) << inside.headline;
}

TEST(GradeDiagnose, CornerInsideCentreOutsideNamesTheHalfPixel) {
    // The right edge x = 5.25 leaves the centre (5.5, 7.5) outside and the corner (5, 7) inside.
    const glm::vec2 corners[3] = {{-20, -20}, {5.25f, -20}, {5.25f, 40}};
    const Trace yours = coverageFrame(corners, true), theirs = coverageFrame(corners, false);
    const grade::Diagnosis d = grade::diagnosePixel(yours, theirs, kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::Rasterizer) << d.headline;
    for (const char* words :
         {"your rasterizer covered pixel (5, 7) with primitive 0 1 time, the solution's 0",
          "its corner (5, 7) lies inside the triangle, and yours covered the pixel",
          "is coverage tested at the pixel's centre (x + 0.5, y + 0.5)?"})
        EXPECT_NE(d.headline.find(words), std::string::npos) << d.headline << "\nlacks: " << words;
}

TEST(GradeDiagnose, RasterizerStateDifferencesAreListed) {
    const glm::vec2 corners[3] = {{0, 0}, {16, 0}, {0, 16}};
    RasterizerState mine;
    mine.cullMode = CullMode::Back, mine.scissorEnable = true, mine.scissorRight = 8, mine.scissorBottom = 4;
    RasterizerState solution;
    solution.cullMode = CullMode::None, solution.depthClipEnable = false;
    const std::vector<std::string> lines = grade::drawStateDifferences(
        coverageFrame(corners, false, mine), coverageFrame(corners, true, solution), 0);
    const std::vector<std::string> expected = {
        "draw 0 rasterizer: your cull mode is CullMode::Back where the solution's is CullMode::None",
        "draw 0 rasterizer: your scissor is [0, 8) x [0, 4) where the solution's is off",
        "draw 0 rasterizer: your depth clip is on where the solution's is off"};
    EXPECT_EQ(lines, expected);
    EXPECT_TRUE(grade::drawStateDifferences(coverageFrame(corners, false, mine),
                                            coverageFrame(corners, true, mine), 0)
                    .empty());
}

TEST(GradeDiagnose, TraceJsonReadsBackFieldForField) {
    Frame f = solution();
    const Trace& trace = f.done();
    const Trace back = grade::traceFromJson(grade::traceToJson(trace), "test");
    ASSERT_EQ(back.draws().size(), 2u);
    EXPECT_EQ(back.draws()[1].geometryShader, "GsBillboard");
    EXPECT_EQ(back.draws()[1].blend.target(0).destBlend, Blend::One);
    EXPECT_FALSE(back.draws()[1].depthStencil.depthWriteMask);
    ASSERT_EQ(back.draws()[1].gsVertices.size(), 4u);
    EXPECT_EQ(back.draws()[1].gsVertices[3].values[5], 1.0f);
    EXPECT_EQ(back.draws()[1].primitives[0].screen[1].y, 12.0f);
    ASSERT_EQ(back.pixelHistory(kX, kY).size(), 2u);
    EXPECT_EQ(back.pixelHistory(kX, kY)[1].depth, 0.4f);
    EXPECT_EQ(back.pixelHistory(kX, kY)[1].fate, FragmentFate::Written);
    EXPECT_EQ(grade::diagnosePixel(back, trace, kX, kY).stage, DiagnosisStage::None);
}

TEST(GradeDiagnose, TraceJsonReadsBackTheRasterizerState) {
    RasterizerState rs;
    rs.fillMode = FillMode::Wireframe, rs.cullMode = CullMode::Front, rs.frontCounterClockwise = true;
    rs.depthClipEnable = false, rs.scissorEnable = true;
    rs.scissorLeft = 1, rs.scissorTop = 2, rs.scissorRight = 9, rs.scissorBottom = 11;
    const glm::vec2 corners[3] = {{0, 0}, {16, 0}, {0, 16}};
    const Trace trace = coverageFrame(corners, true, rs);
    const Trace back = grade::traceFromJson(grade::traceToJson(trace), "test");
    ASSERT_EQ(back.draws().size(), 1u);
    const RasterizerState& r = back.draws()[0].rasterizer;
    EXPECT_EQ(r.fillMode, FillMode::Wireframe);
    EXPECT_EQ(r.cullMode, CullMode::Front);
    EXPECT_TRUE(r.frontCounterClockwise);
    EXPECT_FALSE(r.depthClipEnable);
    EXPECT_TRUE(r.scissorEnable);
    EXPECT_EQ(glm::ivec4(r.scissorLeft, r.scissorTop, r.scissorRight, r.scissorBottom),
              glm::ivec4(1, 2, 9, 11));
    EXPECT_TRUE(back.draws()[0].coverageTest);
    EXPECT_TRUE(grade::drawStateDifferences(back, trace, 0).empty());
}

TEST(GradeDiagnose, TraceJsonRefusesForgedFields) {
    EXPECT_THROW(grade::traceFromJson("{", "t"), Error);
    EXPECT_THROW(grade::traceFromJson(
                     R"({"pixels": [0, 0, 0, 0], "size": [4, 4], "draws": [], "fragments": [[0]]})", "t"),
                 Error);
    EXPECT_THROW(
        grade::traceFromJson(
            R"({"pixels": [0, 0, 0, 0], "size": [4, 4], "draws": [], "fragments": [[0, 0, 0, 0, 1, 1, 1, 99, true,
                     [0,0,0,0], [0,0,0,0], [0,0,0,0]]]})",
            "t"),
        Error);
}

}  // namespace
