// The teaching pipeline (raster/teaching_pipeline.hpp): a lab's shaders drawn through the library's
// one compiled pipeline, as raster/teaching_draw.hpp does in a lab's file, give what the template
// pipeline gives for the same functors: the image and depth bit for bit, the statistics, the trace
// and the error messages. The template draws in this file take the generic policies only, as the
// teaching pipeline does, so that even the helper-lane counts must agree.
#define RASTER_DRAWS_GENERIC_ONLY 1
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "lecture/fire_shaders.hpp"
#include "raster/pipeline.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/scenes.hpp"
#include "raster/shaders/basic.hpp"
#include "raster/teaching_pipeline.hpp"
#include "raster/trace_format.hpp"

namespace raster {
namespace {

// How a test draws: through the template pipeline or the teaching one.
enum class Path { Template, Teaching };

template <class VS, class GS, class PS>
void drawThrough(Path path, Context& ctx, const VS& vs, const GS& gs, const PS& ps, uint32_t count) {
    const DrawCall call{false, count, 0};
    if (path == Path::Template) {
        ctx.execute(vs, gs, ps, call);
    } else if constexpr (std::is_same_v<GS, NoGeometryShader>) {
        ctx.executeTeaching(teachingVertexShader(vs), teachingPixelShader(ps), call);
    } else {
        ctx.executeTeaching(teachingVertexShader(vs), teachingGeometryShader(gs), teachingPixelShader(ps), call);
    }
}

struct Frame {
    RenderTarget color;
    DepthTarget depth;
    std::vector<PipelineStatistics> draws;
};

// The lab's scene: the occluder, then the lecture's fire (GS billboards, texture, additive blend).
Frame fire(Path path, ContextOptions options, Trace* trace = nullptr) {
    const SceneOptions o{.width = 256, .height = 160, .count = 400};
    const ParticleSceneData data(o);
    Frame f{RenderTarget(o.width, o.height), DepthTarget(o.width, o.height), {}};
    Context ctx(options);
    ctx.setTrace(trace);
    ctx.setRenderTargets(&f.color, &f.depth);
    ctx.setViewport({0, 0, float(o.width), float(o.height), 0, 1});
    f.color.clear({0.05f, 0.05f, 0.1f, 1.0f});
    f.depth.clear(1.0f);
    data.drawOccluder(ctx);
    ctx.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
    ctx.setBlendState(BlendState::additive());
    ctx.setVertexBuffer(0, &data.particles);
    ctx.setPrimitiveTopology(Topology::PointList);
    shaders::GsBillboard gs;
    gs.viewProj = data.viewProj;
    gs.billboardSize = data.billboardSize;
    shaders::PsFire ps;
    ps.billboardTexture = &data.texture;
    drawThrough(path, ctx, shaders::VsBillboard{}, gs, ps, data.count);
    f.draws = ctx.drawStatisticsLog();
    return f;
}

TEST(TeachingPipeline, FireIsTheTemplatePipelinesImageBitForBit) {
    for (unsigned threads : {1u, 3u}) {
        for (bool plain : {false, true}) {
            const Frame a = fire(Path::Template, {.threads = threads, .plain = plain});
            const Frame b = fire(Path::Teaching, {.threads = threads, .plain = plain});
            EXPECT_TRUE(a.color == b.color) << threads << " threads, plain " << plain;
            EXPECT_TRUE(a.depth == b.depth);
            ASSERT_EQ(a.draws.size(), 2u);
            ASSERT_EQ(b.draws.size(), 2u);
            EXPECT_TRUE(a.draws[1] == b.draws[1]) << "the fire draw's statistics";
            EXPECT_GT(b.draws[1].psInvocations, 1000u) << "the fire was drawn";
            EXPECT_EQ(b.draws[1].gsPrimitives, plain ? 800u : b.draws[1].gsPrimitives);
        }
    }
}

TEST(TeachingPipeline, SameImageForAnyThreadCount) {
    const Frame one = fire(Path::Teaching, {.threads = 1});
    const Frame eight = fire(Path::Teaching, {.threads = 8});
    EXPECT_TRUE(one.color == eight.color);
    EXPECT_TRUE(one.draws[1] == eight.draws[1]);
}

// ---- Without a geometry shader: discard, two render targets, Src1 blending ----

struct ColorIn {
    glm::vec3 position;
    glm::vec4 color;
    RASTER_INPUT_SIGNATURE(ColorIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(color, "COLOR", 0))
};
struct ColorVertex {
    glm::vec4 position;
    glm::vec4 color;
    float fade;
};
struct VsColor {
    ColorVertex operator()(const ColorIn& in) const {
        return {glm::vec4(in.position, 1.0f), in.color, in.position.x * 0.5f + 0.5f};
    }
};
// Discards where fade < 0.2; writes the colour to target 0 and its fade as grey to target 1.
struct PsTwoTargets {
    std::optional<std::array<glm::vec4, 2>> operator()(const ColorVertex& in) const {
        if (in.fade < 0.2f) return std::nullopt;
        return std::array<glm::vec4, 2>{in.color, glm::vec4(in.fade, in.fade, in.fade, 0.5f)};
    }
};
// One colour, blended with Src1 factors (which read the single output as SV_Target1 too).
struct PsOne {
    glm::vec4 operator()(const ColorVertex& in) const { return in.color * glm::vec4(1, 1, 1, in.fade); }
};

struct Targets {
    RenderTarget a{96, 64}, b{96, 64, Format::R32G32B32A32_FLOAT};
    DepthTarget depth{96, 64};
};

template <class PS>
Targets triangles(Path path, const PS& ps, int target_count, const BlendState& blend) {
    const std::vector<ColorIn> vertices = {
        {{-0.9f, -0.8f, 0.3f}, {1, 0, 0, 1}}, {{0.9f, -0.6f, 0.5f}, {0, 1, 0, 0.5f}}, {{-0.2f, 0.9f, 0.7f}, {0, 0, 1, 1}},
        {{-0.7f, 0.7f, 0.2f}, {1, 1, 0, 1}},  {{0.8f, 0.8f, 0.9f}, {0, 1, 1, 0.25f}}, {{0.1f, -0.9f, 0.1f}, {1, 0, 1, 1}}};
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                     {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, 12}};
    const InputLayout layout(desc);
    const VertexBuffer vb = VertexBuffer::create(vertices);
    Targets t;
    t.a.clear({0.2f, 0.3f, 0.4f, 1.0f});
    t.b.clear({0, 0, 0, 0});
    t.depth.clear(1.0f);
    Context ctx({.threads = 2});
    RenderTarget* const both[2] = {&t.a, &t.b};
    ctx.setRenderTargets(std::span<RenderTarget* const>(both, size_t(target_count)), &t.depth);
    ctx.setViewport({0, 0, 96, 64, 0, 1});
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb);
    ctx.setPrimitiveTopology(Topology::TriangleList);
    ctx.setBlendState(blend);
    ctx.setDepthStencilState({true, true, ComparisonFunc::LessEqual});
    drawThrough(path, ctx, VsColor{}, NoGeometryShader{}, ps, 6);
    return t;
}

TEST(TeachingPipeline, DiscardAndTwoTargetsAsTheTemplatePipeline) {
    const Targets a = triangles(Path::Template, PsTwoTargets{}, 2, BlendState::opaque());
    const Targets b = triangles(Path::Teaching, PsTwoTargets{}, 2, BlendState::opaque());
    EXPECT_TRUE(a.a == b.a);
    EXPECT_TRUE(a.b == b.b);
    EXPECT_TRUE(a.depth == b.depth);
    EXPECT_NE(b.b.load(48, 32), glm::vec4(0.0f)) << "target 1 was written";
    EXPECT_EQ(b.b.load(2, 32), glm::vec4(0.0f)) << "discarded at the left edge (fade < 0.2)";
}

TEST(TeachingPipeline, OneColourFeedsSrc1AsTheTemplatePipeline) {
    BlendState blend;
    RenderTargetBlendDesc& d = blend.renderTarget[0];
    d.blendEnable = true;
    d.srcBlend = Blend::Src1Alpha;
    d.destBlend = Blend::InvSrc1Alpha;
    const Targets a = triangles(Path::Template, PsOne{}, 1, blend);
    const Targets b = triangles(Path::Teaching, PsOne{}, 1, blend);
    EXPECT_TRUE(a.a == b.a);
    EXPECT_NE(b.a.load(48, 32), glm::vec4(0.2f, 0.3f, 0.4f, 1.0f)) << "something was blended";
}

// ---- The lab's names in messages and in the trace ----

std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(nothing thrown)";
}

struct NeedsNormal {
    glm::vec3 position;
    glm::vec3 normal;
    RASTER_INPUT_SIGNATURE(NeedsNormal, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(normal, "NORMAL", 0))
};
struct VsNeedsNormal {
    shaders::PositionOnly operator()(const NeedsNormal& in) const { return {glm::vec4(in.position + in.normal, 1)}; }
};
// Five vertices into a stream of four.
struct GsTooMany {
    void operator()(const Point<shaders::PositionOnly>& in, TriangleStream<shaders::PositionOnly, 4>& out) const {
        for (int i = 0; i < 5; ++i) out.Append(in[0]);
    }
};
struct VsPoint {
    shaders::PositionOnly operator()(const shaders::PositionIn& in) const { return {glm::vec4(in.position, 1)}; }
};

TEST(TeachingPipeline, MessagesNameTheLabsTypes) {
    RenderTarget color(8, 8), second(8, 8);
    DepthTarget depth(8, 8);
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
    const InputLayout layout(desc);
    const std::vector<glm::vec3> points = {{0, 0, 0.5f}};
    const VertexBuffer vb = VertexBuffer::create(points);
    Context ctx({.threads = 1});
    ctx.setRenderTargets(&color, &depth);
    ctx.setViewport({0, 0, 8, 8, 0, 1});
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb);
    const shaders::PsConstant ps{{1, 1, 1, 1}};
    for (auto [name, draw] : std::vector<std::pair<std::string, std::function<void(Path)>>>{
             {"layout", [&](Path p) {
                  ctx.setPrimitiveTopology(Topology::PointList);
                  drawThrough(p, ctx, VsNeedsNormal{}, NoGeometryShader{}, ps, 1);
              }},
             {"overflow", [&](Path p) {
                  ctx.setPrimitiveTopology(Topology::PointList);
                  drawThrough(p, ctx, VsPoint{}, GsTooMany{}, ps, 1);
              }},
             {"targets", [&](Path p) {
                  RenderTarget* const two[2] = {&color, &second};
                  ctx.setRenderTargets(two, &depth);
                  ctx.setPrimitiveTopology(Topology::PointList);
                  drawThrough(p, ctx, VsPoint{}, NoGeometryShader{}, ps, 1);
                  ctx.setRenderTargets(&color, &depth);
              }}}) {
        const std::string expected = messageOf([&] { draw(Path::Template); });
        const std::string got = messageOf([&] { draw(Path::Teaching); });
        EXPECT_EQ(got, expected) << name;
        EXPECT_EQ(got.find("Teaching"), std::string::npos) << name << ": " << got;
        // (Braces: an EXPECT is an if-else of its own.)
        if (name == "layout") {
            EXPECT_NE(got.find("NeedsNormal"), std::string::npos) << got;
        }
        if (name == "overflow") {
            EXPECT_NE(got.find("GsTooMany appended 1 vertices past its maxvertexcount of 4"), std::string::npos)
                << got;
        }
        if (name == "targets") {
            EXPECT_NE(got.find("pixel shader writes 1"), std::string::npos) << got;
        }
    }
}

TEST(TeachingPipeline, TraceRecordsTheLabsStructs) {
    TraceOptions options;
    options.pixels = TraceOptions::everything();
    Trace a(options), b(options);
    fire(Path::Template, {.threads = 2}, &a);
    fire(Path::Teaching, {.threads = 2}, &b);
    ASSERT_EQ(a.draws().size(), 2u);
    ASSERT_EQ(b.draws().size(), 2u);
    const TraceDraw& x = a.draws()[1];
    const TraceDraw& y = b.draws()[1];
    EXPECT_EQ(y.vertexShader, x.vertexShader);
    EXPECT_EQ(y.geometryShader, x.geometryShader);
    EXPECT_EQ(y.pixelShader, x.pixelShader);
    EXPECT_NE(y.geometryShader.find("GsBillboard"), std::string::npos) << y.geometryShader;
    EXPECT_EQ(y.vsFloats, x.vsFloats);
    EXPECT_EQ(y.gsFloats, 6u) << "position and uv";
    ASSERT_EQ(y.vertices.size(), x.vertices.size());
    for (size_t i = 0; i < x.vertices.size(); ++i) {
        EXPECT_EQ(y.vertices[i].input, x.vertices[i].input);
        EXPECT_EQ(y.vertices[i].output, x.vertices[i].output);
    }
    ASSERT_EQ(y.gsVertices.size(), x.gsVertices.size());
    for (size_t i = 0; i < x.gsVertices.size(); ++i) EXPECT_EQ(y.gsVertices[i].values, x.gsVertices[i].values);
    ASSERT_EQ(b.fragments().size(), a.fragments().size());
    EXPECT_GT(b.fragments().size(), 1000u);
    for (size_t i = 0; i < a.fragments().size(); i += 97) {
        EXPECT_EQ(b.fragments()[i].x, a.fragments()[i].x);
        EXPECT_EQ(b.fragments()[i].y, a.fragments()[i].y);
        EXPECT_EQ(b.fragments()[i].fate, a.fragments()[i].fate);
        EXPECT_EQ(b.fragments()[i].colorAfter, a.fragments()[i].colorAfter);
    }
}

// ---- The rasterizer lab's coverage test (Context::setCoverageTest) ----

struct ClipColorIn {
    glm::vec4 position, color;
    RASTER_INPUT_SIGNATURE(ClipColorIn, RASTER_INPUT(position, "POSITION", 0),
                           RASTER_INPUT(color, "COLOR", 0))
};
struct ClipColorVertex {
    glm::vec4 position, color;
};
struct VsClipColor {
    ClipColorVertex operator()(const ClipColorIn& in) const { return {in.position, in.color}; }
};
struct PsClipColor {
    glm::vec4 operator()(const ClipColorVertex& in) const { return in.color; }
};

// The rasterizer lab's triangles (CoverageSceneData) through `path`, with `test` set on the context.
RenderTarget coverageScene(Path path, CoverageTest test, const SceneOptions& o, unsigned threads = 0) {
    const CoverageSceneData data(o);
    RenderTarget color(o.width, o.height);
    DepthTarget depth(o.width, o.height);
    Context ctx({.threads = threads});
    beginSceneFrame(ctx, color, depth);
    data.bind(ctx);
    ctx.setCoverageTest(test);
    drawThrough(path, ctx, VsClipColor{}, NoGeometryShader{}, PsClipColor{}, data.vertexCount);
    return color;
}

TEST(CoverageTest, TheLibrarysRuleAsALabsTestGivesTheLibrarysImage) {
    const SceneCamera turned{{0.5f, 0.1f, 0.8660254f}, {0, 0, 0}};
    for (const SceneOptions& o : {SceneOptions{.width = 320, .height = 180, .count = 60},
                                  SceneOptions{.width = 200, .height = 150, .count = 33, .camera = turned}}) {
        const RenderTarget library = coverageScene(Path::Teaching, nullptr, o);
        EXPECT_TRUE(coverageScene(Path::Teaching, &coversPixelCentre, o, 1) == library) << o.width;
        EXPECT_TRUE(coverageScene(Path::Teaching, &coversPixelCentre, o, 8) == library) << o.width;
        EXPECT_TRUE(coverageScene(Path::Template, nullptr, o) == library) << o.width;
    }
}

// The library's rule with the opposite tie-break: a centre on a bottom or right edge is inside.
bool bottomRightRule(const CoverageTriangle& tri, int32_t px, int32_t py) {
    const CoverageTriangle mirrored = {{-tri.x[0], -tri.x[1], -tri.x[2]}, {-tri.y[0], -tri.y[1], -tri.y[2]}};
    // Mirrored through the origin, a bottom edge becomes a top one and a right edge a left one;
    // pixel (px, py)'s centre becomes pixel (−px − 1, −py − 1)'s.
    return coversPixelCentre(mirrored, -px - 1, -py - 1);
}
bool everyCentre(const CoverageTriangle&, int32_t, int32_t) {
    return true;
}

// One triangle (window positions in pixels) drawn opaque white on black, 24×16, through `test`.
RenderTarget oneTriangle(const std::array<glm::dvec2, 3>& window, CoverageTest test,
                         Path path = Path::Teaching) {
    std::vector<ClipColorIn> vertices;
    for (const glm::dvec2& w : window)
        vertices.push_back({glm::vec4(float(w.x / 12 - 1), float(1 - w.y / 8), 0.5f, 1), glm::vec4(1)});
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32A32_FLOAT, 0, 0},
                                     {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, 16}};
    const InputLayout layout(desc);
    const VertexBuffer vb = VertexBuffer::create(vertices);
    RenderTarget color(24, 16);
    DepthTarget depth(24, 16);
    Context ctx;
    beginSceneFrame(ctx, color, depth);
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb);
    ctx.setPrimitiveTopology(Topology::TriangleList);
    ctx.setCoverageTest(test);
    drawThrough(path, ctx, VsClipColor{}, NoGeometryShader{}, PsClipColor{}, 3);
    return color;
}

// The pixels `test` says a triangle covers, as the pipeline gives the test the triangle.
std::vector<bool> expectedCoverage(const std::array<glm::dvec2, 3>& window, CoverageTest test) {
    CoverageTriangle tri;
    for (int k = 0; k < 3; ++k) tri.x[k] = window[k].x, tri.y[k] = window[k].y;
    // Only centres inside the snapped box are asked.
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (const glm::dvec2& w : window)
        x0 = std::min(x0, w.x), x1 = std::max(x1, w.x), y0 = std::min(y0, w.y), y1 = std::max(y1, w.y);
    std::vector<bool> out(24 * 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x)
            out[y * 24 + x] =
                x + 0.5 >= x0 && x + 0.5 <= x1 && y + 0.5 >= y0 && y + 0.5 <= y1 && test(tri, x, y);
    return out;
}

TEST(CoverageTest, ALabsTestDecidesExactlyThePixelsItCovers) {
    // Windows positions on the 1/256 grid (exact after the float clip coordinates and the snap):
    // edges through pixel centres in both windings, a sliver, a triangle between centres.
    const std::vector<std::array<glm::dvec2, 3>> triangles = {
        {{{2.5, 2.5}, {20.5, 2.5}, {2.5, 12.5}}},     {{{2.5, 2.5}, {2.5, 12.5}, {20.5, 2.5}}},
        {{{20.5, 2.5}, {20.5, 12.5}, {2.5, 12.5}}},   {{{4.5, 1.5}, {18.5, 14.5}, {4.75, 1.5}}},
        {{{3.25, 3.25}, {9.75, 3.5}, {6.0, 11.625}}}, {{{0.5, 0.5}, {23.5, 15.5}, {0.5, 15.5}}}};
    for (size_t i = 0; i < triangles.size(); ++i) {
        const auto& tri = triangles[i];
        EXPECT_TRUE(oneTriangle(tri, &coversPixelCentre) == oneTriangle(tri, nullptr)) << "triangle " << i;
        for (CoverageTest test : {&coversPixelCentre, &bottomRightRule, &everyCentre}) {
            const RenderTarget image = oneTriangle(tri, test);
            const std::vector<bool> expected = expectedCoverage(tri, test);
            size_t wrong = 0;
            for (size_t p = 0; p < expected.size(); ++p)
                wrong += (image.rgba8()[4 * p] == 255) != expected[p];
            EXPECT_EQ(wrong, 0u) << "triangle " << i;
        }
        // The template pipeline's draws ignore a coverage test.
        EXPECT_TRUE(oneTriangle(tri, &everyCentre, Path::Template) == oneTriangle(tri, nullptr))
            << "triangle " << i;
    }
    // The opposite tie-break differs where a centre lies on an edge: on all three triangles whose
    // edges run through pixel centres.
    for (size_t i : {0u, 1u, 2u})
        EXPECT_FALSE(oneTriangle(triangles[i], &bottomRightRule) == oneTriangle(triangles[i], nullptr)) << i;
}

TEST(CoverageTest, TheTraceSaysALabsTestDecided) {
    Trace trace;
    const SceneOptions o{.width = 64, .height = 48, .count = 5};
    const CoverageSceneData data(o);
    RenderTarget color(o.width, o.height);
    DepthTarget depth(o.width, o.height);
    Context ctx;
    ctx.setTrace(&trace);
    beginSceneFrame(ctx, color, depth);
    data.bind(ctx);
    ctx.setCoverageTest(&coversPixelCentre);
    drawThrough(Path::Teaching, ctx, VsClipColor{}, NoGeometryShader{}, PsClipColor{}, data.vertexCount);
    ctx.setCoverageTest(nullptr);
    drawThrough(Path::Teaching, ctx, VsClipColor{}, NoGeometryShader{}, PsClipColor{}, data.vertexCount);
    ASSERT_EQ(trace.draws().size(), 2u);
    EXPECT_TRUE(trace.draws()[0].coverageTest);
    EXPECT_FALSE(trace.draws()[1].coverageTest);
    EXPECT_NE(rasterizerSummary(trace.draws()[0]).find(", coverage: the lab's test"), std::string::npos);
}

}  // namespace
}  // namespace raster
