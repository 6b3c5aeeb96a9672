// raster grade's diagnosis (raster/tools/grade/diagnose.hpp) on hand-made pixel histories: each test
// builds the solution's trace of one pixel and a submission's that differs at one stage, and checks the
// stage named and the words and figures of the headline. And the trace's JSON carried from the lab
// runner (grade/trace_json.hpp) read back field for field.
#include <gtest/gtest.h>

#include <algorithm>
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

// The same two fragments of one draw in the other order (an index buffer sorted front to back): named
// as the order, with both directions, not as the geometry of the primitive that now comes first.
TEST(GradeDiagnose, DrawOrderIsNamedWithBothDirections) {
    const glm::vec4 near{1, 0.75f, 0.1f, 0.75f}, far{0.1f, 0.3f, 1, 0.75f};
    Frame yours(BlendState::alphaBlend(), DepthStencilState::readOnly()),
        theirs(BlendState::alphaBlend(), DepthStencilState::readOnly());
    for (Frame* f : {&yours, &theirs})
        f->add(0, 0, 0.6f, 1.0f, 0.6f, FragmentFate::Written, kGrey, kBlack, kGrey);
    theirs.add(1, 3, 0.5f, 0.6f, 0.6f, FragmentFate::Written, far, kGrey, kGrey);
    theirs.add(1, 4, 0.4f, 0.6f, 0.6f, FragmentFate::Written, near, kGrey, kGrey);
    yours.add(1, 3, 0.4f, 0.6f, 0.6f, FragmentFate::Written, near, kGrey, kGrey);
    yours.add(1, 4, 0.5f, 0.6f, 0.6f, FragmentFate::Written, far, kGrey, kGrey);
    const grade::Diagnosis d = grade::diagnosePixel(yours.done(), theirs.done(), kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::Blend);
    EXPECT_NE(d.headline.find(
                  "draw 1: your draw 1 brings the solution's 2 fragments in another order: yours "
                  "from depth 0.4 to 0.5 (near to far), the solution's from depth 0.5 to 0.4 (far to near)"),
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

// One indexed draw of particles, two triangles each (vertices 4k .. 4k + 3), in `order`; the triangle
// (4k, 4k + 1, 4k + 2) of each particle in `at_pixel` covers the pixel, in the draw's order. Particle k
// lies at depth kQuadDepth[k] with colour kQuadColour[k]; each fragment written with the draw's states.
struct QuadFrame {
    static constexpr float kQuadDepth[3] = {0.5f, 0.7f, 0.3f};  // middle, far, near
    static inline const glm::vec4 kQuadColour[3] = {
        {0.5f, 0.5f, 0.5f, 0.75f}, {0.1f, 0.3f, 1, 0.75f}, {1, 0.75f, 0.1f, 0.75f}};
    Trace trace{TraceOptions{.pixels = {kX, kY, kX, kY}}};

    QuadFrame(const BlendState& blend, const DepthStencilState& depth, const std::vector<uint32_t>& order,
              const std::vector<uint32_t>& at_pixel) {
        TraceDraw& d = trace.beginDraw(16, 16);
        d.draw = 1;
        d.vertexShader = "VsQuad", d.pixelShader = "PsDisc";
        d.topology = Topology::TriangleList;
        d.blend = blend, d.depthStencil = depth;
        d.verticesPerPrimitive = 3, d.primitivesPerInstance = uint32_t(2 * order.size());
        for (const uint32_t k : order)
            for (const uint32_t corner : {0u, 1u, 2u, 0u, 2u, 3u})
                d.primitiveVertices.push_back(4 * k + corner);
        std::vector<TraceFragment> fragments;
        glm::vec4 colour = kBlack;
        float stored = 1.0f;
        for (size_t position = 0; position < order.size(); ++position) {
            const uint32_t k = order[position];
            if (std::find(at_pixel.begin(), at_pixel.end(), k) == at_pixel.end()) continue;
            const bool passed = !depth.depthEnable || kQuadDepth[k] < stored;
            const glm::vec4 before = colour, src = kQuadColour[k];
            const float keep = blend.target(0).destBlend == Blend::One ? 1.0f : 1.0f - src.a;
            if (passed) colour = blend.target(0).blendEnable ? src * src.a + before * keep : src;
            const float depth_before = stored;
            if (passed && depth.depthEnable && depth.depthWriteMask) stored = kQuadDepth[k];
            fragments.push_back({1, uint32_t(2 * position), kX, kY, kQuadDepth[k], depth_before, stored,
                                 passed ? FragmentFate::Written : FragmentFate::EarlyDepthFailed, passed,
                                 passed ? src : glm::vec4(NAN), before, colour});
        }
        trace.addFragments(fragments);
    }
};

// The solution's: "over", depth test without write, back to front (particle 1, 0, 2).
QuadFrame sortedSolution() {
    return QuadFrame(BlendState::alphaBlend(), DepthStencilState::readOnly(), {1, 0, 2}, {0, 1, 2});
}

// A half-done lab: blending off, depth write on (other fates, other outputs) and the storage order: its
// primitive k is not the solution's primitive k. Aligned by the primitives' vertices, the diagnosis is
// the order, not the geometry of whichever particle comes first.
TEST(GradeDiagnose, PrimitivesInAnotherOrderAreNamedByTheirVertices) {
    const QuadFrame yours(BlendState{}, DepthStencilState{}, {0, 1, 2}, {0, 1, 2});
    const QuadFrame theirs = sortedSolution();
    const grade::Diagnosis d = grade::diagnosePixel(yours.trace, theirs.trace, kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::Blend) << d.headline;
    for (const char* words :
         {"pixel (5, 7), draw 1: your draw 1 brings the solution's 3 fragments in another order: yours from "
          "depth 0.5 to 0.3 (far to near), the solution's from depth 0.7 to 0.3 (far to near): yours takes "
          "them in the vertex buffer's order, as stored, the solution's not: are they sorted at all",
          "the same primitives, by their vertices: your 0, 2, 4 in your order are the solution's 2, 0, 4",
          "; besides, your blending is off where the solution's is on"})
        EXPECT_NE(d.headline.find(words), std::string::npos) << d.headline << "\nlacks: " << words;
    EXPECT_NE(std::find(d.details.begin(), d.details.end(),
                        "draw 1 depth-stencil: your depth write is on where the solution's is off"),
              d.details.end());
    // Front to back, the states right: the other way round.
    const QuadFrame reversed(BlendState::alphaBlend(), DepthStencilState::readOnly(), {2, 0, 1}, {0, 1, 2});
    const grade::Diagnosis r = grade::diagnosePixel(reversed.trace, theirs.trace, kX, kY);
    EXPECT_EQ(r.stage, DiagnosisStage::Blend) << r.headline;
    for (const char* words :
         {"yours from depth 0.3 to 0.7 (near to far), the solution's from depth 0.7 to 0.3 "
          "(far to near): yours is the solution's order reversed: is the comparator's "
          "comparison the wrong way round",
          "your 0, 2, 4 in your order are the solution's 4, 2, 0"})
        EXPECT_NE(r.headline.find(words), std::string::npos) << r.headline << "\nlacks: " << words;
    EXPECT_EQ(r.headline.find("besides"), std::string::npos) << r.headline;
    // The solution against itself: nothing.
    EXPECT_EQ(grade::diagnosePixel(theirs.trace, theirs.trace, kX, kY).stage, DiagnosisStage::None);
}

// Another order elsewhere, one particle at the pixel: your primitive 4 is compared with the solution's
// primitive 2 (the same vertices), and the blend that differs is named on it.
TEST(GradeDiagnose, RenumberedPrimitiveIsComparedWithTheSolutionsSame) {
    BlendState wrong = BlendState::alphaBlend();
    wrong.renderTarget[0].destBlend = Blend::One;
    const QuadFrame yours(wrong, DepthStencilState::readOnly(), {1, 2, 0}, {0});
    const QuadFrame theirs(BlendState::alphaBlend(), DepthStencilState::readOnly(), {1, 0, 2}, {0});
    const grade::Diagnosis d = grade::diagnosePixel(yours.trace, theirs.trace, kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::Blend) << d.headline;
    EXPECT_NE(
        d.headline.find("pixel (5, 7), draw 1, your primitive 4 (the solution's 2): your destination factor "
                        "is Blend::One where the solution's is Blend::InvSrcAlpha"),
        std::string::npos)
        << d.headline;
}

// A particle drawn twice and another left out: named as primitives your draw lacks or repeats.
TEST(GradeDiagnose, PrimitiveTheSolutionLacksIsNamedWithItsVertices) {
    const QuadFrame yours(BlendState::alphaBlend(), DepthStencilState::readOnly(), {0, 0, 2}, {0, 2});
    const QuadFrame theirs(BlendState::alphaBlend(), DepthStencilState::readOnly(), {0, 1, 2}, {0, 1, 2});
    const grade::Diagnosis d = grade::diagnosePixel(yours.trace, theirs.trace, kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::InputAssembler) << d.headline;
    EXPECT_NE(d.headline.find("draw 1: the solution's primitive 2, with the vertices "
                              "(4, 5, 6), is not in your draw: your draw's index buffer (or its range) holds "
                              "other primitives than the solution's"),
              std::string::npos)
        << d.headline;
    const QuadFrame twice(BlendState::alphaBlend(), DepthStencilState::readOnly(), {0, 0, 1}, {0, 1});
    const QuadFrame once(BlendState::alphaBlend(), DepthStencilState::readOnly(), {0, 1, 2}, {0, 1});
    const grade::Diagnosis t = grade::diagnosePixel(twice.trace, once.trace, kX, kY);
    EXPECT_EQ(t.stage, DiagnosisStage::InputAssembler) << t.headline;
    EXPECT_NE(
        t.headline.find("your primitive 2 has the vertices (0, 1, 2), which your draw has 2 times and the "
                        "solution's 1"),
        std::string::npos)
        << t.headline;
}

TEST(GradeDiagnose, TraceJsonCarriesThePrimitivesVertices) {
    const QuadFrame f = sortedSolution();
    std::string json = grade::traceToJson(f.trace);
    const Trace back = grade::traceFromJson(json, "test");
    ASSERT_EQ(back.draws().size(), 1u);
    EXPECT_EQ(back.draws()[0].primitiveVertices, f.trace.draws()[0].primitiveVertices);
    EXPECT_EQ(back.draws()[0].verticesPerPrimitive, 3u);
    EXPECT_EQ(back.draws()[0].primitivesPerInstance, 6u);
    // A trace without them (written before they were recorded) reads, with none.
    const std::string field = "\"primitiveVertices\":[3,6,[";
    const size_t at = json.find(field);
    ASSERT_NE(at, std::string::npos) << json;
    std::string old = json;
    old.erase(at - 1, json.find("]]", at) + 2 - (at - 1));  // with the comma before it
    const Trace without = grade::traceFromJson(old, "test");
    EXPECT_TRUE(without.draws()[0].primitiveVertices.empty()) << old;
    EXPECT_EQ(without.draws()[0].verticesPerPrimitive, 0u);
    // Not a whole number of primitives: refused.
    json.replace(at, field.size(), "\"primitiveVertices\":[3,6,[7,");
    EXPECT_THROW(grade::traceFromJson(json, "test"), Error);
}

// A point-list draw without a geometry shader, as the input-layout lab draws: primitive 2 is vertex 2,
// whose input (POSITION, LIFESPAN, AGE, COLOR) and output (SV_Position, colour) are recorded.
struct PointFrame {
    Trace trace{TraceOptions{.pixels = {kX, kY, kX, kY}}};

    // input: position (3), lifespan, age, colour (4); output: SV_Position (4), colour (4).
    PointFrame(std::vector<float> input, std::vector<float> output) {
        TraceDraw& d = trace.beginDraw(16, 16);
        d.draw = 1;
        d.vertexShader = "VsParticle", d.pixelShader = "PsParticle";
        d.topology = Topology::PointList;
        d.inputFields = {{"POSITION", 0, 3}, {"LIFESPAN", 3, 1}, {"AGE", 4, 1}, {"COLOR", 5, 4}};
        d.vsFloats = 8;
        for (uint32_t i = 0; i < 3; ++i) d.vertices.push_back({0, i, kInput, kOutput});
        d.vertices[2] = {0, 2, std::move(input), std::move(output)};
        TracePrimitive p{};
        p.primitive = 2, p.kind = PrimitiveKind::Point, p.fate = PrimitiveFate::Rasterized, p.vertexCount = 1;
        p.screen[0] = {kX + 0.5f, kY + 0.5f, 0.5f, 1};
        d.primitives.push_back(p);
        trace.addFragments(
            {{1, 2, kX, kY, 0.5f, 1.0f, 0.5f, FragmentFate::Written, true, kFire, kBlack, kFire}});
    }
    static inline const std::vector<float> kInput = {0.1f, 0.2f, 0.3f, 2.0f, 0.5f, 1.0f, 0.5f, 0.25f, 0.75f};
    static inline const std::vector<float> kOutput = {0.1f, 0.2f, 0.3f, 1.0f, 0.65f, 0.325f, 0.1625f, 1.0f};
};

TEST(GradeDiagnose, InputAssemblerOffsetOfAnotherFieldIsNamed) {
    std::vector<float> input = PointFrame::kInput;
    input[4] = input[3];  // AGE read at LIFESPAN's offset
    const PointFrame yours(input, PointFrame::kOutput), theirs(PointFrame::kInput, PointFrame::kOutput);
    const grade::Diagnosis d = grade::diagnosePixel(yours.trace, theirs.trace, kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::InputAssembler);
    EXPECT_EQ(std::string(grade::stageName(d.stage)), "input assembler");
    EXPECT_NE(
        d.headline.find("draw 1, primitive 2: the input assembler fetched vertex 2 (instance 0) with AGE = 2 "
                        "where the solution's is 0.5: yours holds what the solution reads as LIFESPAN"),
        std::string::npos)
        << d.headline;
}

TEST(GradeDiagnose, InputAssemblerFormatTooNarrowIsNamed) {
    std::vector<float> input = PointFrame::kInput;
    input[8] = 1.0f;  // COLOR as R32G32B32_FLOAT: the fourth component is the default 1
    const PointFrame yours(input, PointFrame::kOutput), theirs(PointFrame::kInput, PointFrame::kOutput);
    const grade::Diagnosis d = grade::diagnosePixel(yours.trace, theirs.trace, kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::InputAssembler);
    EXPECT_NE(
        d.headline.find("with COLOR = (1, 0.5, 0.25, 1) where the solution's is (1, 0.5, 0.25, 0.75): yours "
                        "has the first 3 components and the defaults (0, 0, 0, 1) after them"),
        std::string::npos)
        << d.headline;
}

TEST(GradeDiagnose, VertexShaderOutputFromTheSameInputIsNamed) {
    std::vector<float> moved = PointFrame::kOutput, dimmer = PointFrame::kOutput;
    moved[0] = 0.15f;  // x in clip space: 0.05 * 16 / 2 = +0.4 pixel
    dimmer[5] = 0.5f;
    const PointFrame theirs(PointFrame::kInput, PointFrame::kOutput);
    const PointFrame yours_moved(PointFrame::kInput, moved), yours_dimmer(PointFrame::kInput, dimmer);
    grade::Diagnosis d = grade::diagnosePixel(yours_moved.trace, theirs.trace, kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::VertexShader);
    EXPECT_NE(
        d.headline.find("the vertex shader's output for vertex 2 (instance 0), from the same input: its "
                        "SV_Position is (0.15, 0.2, 0.3, 1) where the solution's is (0.1, 0.2, 0.3, 1)"),
        std::string::npos)
        << d.headline;
    EXPECT_NE(d.headline.find("x differs by +0.40 pixel"), std::string::npos) << d.headline;
    d = grade::diagnosePixel(yours_dimmer.trace, theirs.trace, kX, kY);
    EXPECT_EQ(d.stage, DiagnosisStage::VertexShader);
    EXPECT_NE(d.headline.find("differs in float 5: 0.5 where the solution's is 0.325"), std::string::npos)
        << d.headline;
    // The same draw, the same records: nothing to name.
    EXPECT_EQ(grade::diagnosePixel(theirs.trace, theirs.trace, kX, kY).stage, DiagnosisStage::None);
}

TEST(GradeDiagnose, TraceJsonCarriesTheVertexShadersInputs) {
    const PointFrame f(PointFrame::kInput, PointFrame::kOutput);
    const Trace back = grade::traceFromJson(grade::traceToJson(f.trace), "test");
    ASSERT_EQ(back.draws().size(), 1u);
    const TraceDraw& d = back.draws()[0];
    ASSERT_EQ(d.inputFields.size(), 4u);
    EXPECT_EQ(d.inputFields[3].name, "COLOR");
    EXPECT_EQ(d.inputFields[3].offset, 5u);
    EXPECT_EQ(d.inputFields[3].components, 4u);
    ASSERT_EQ(d.vertices.size(), 3u);
    EXPECT_EQ(d.vertices[2].input, PointFrame::kInput);
    EXPECT_EQ(d.vertices[2].output, PointFrame::kOutput);
    // A field outside the recorded input is refused, not read past the record.
    std::string json = grade::traceToJson(f.trace);
    const std::string field = "[\"COLOR\",5,4]";
    ASSERT_NE(json.find(field), std::string::npos) << json;
    json.replace(json.find(field), field.size(), "[\"COLOR\",7,4]");
    EXPECT_THROW(grade::traceFromJson(json, "test"), Error);
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
