// The whole pipeline: depth and blend state through real draws, determinism across thread counts,
// validation that leaves the targets alone, statistics, and the reference pipeline.
#include "raster/pipeline.hpp"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <climits>
#include <cstdlib>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "raster/check.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/scenes.hpp"
#include "raster/shaders/basic.hpp"
#include "raster/trace.hpp"

namespace raster {
namespace {

using shaders::PositionOnly;
using shaders::PsConstant;
using shaders::VsTransform;

const glm::vec4 kRed(1, 0, 0, 1);
const glm::vec4 kGreen(0, 1, 0, 1);
const glm::vec4 kClear(0.1f, 0.2f, 0.3f, 1.0f);

void expectError(const std::function<void()>& f, ErrorCode code, std::initializer_list<std::string> parts) {
    try {
        f();
        ADD_FAILURE() << "expected Error(" << errorCodeName(code) << "), nothing was thrown";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), code) << e.what();
        const std::string message = e.what();
        for (const std::string& part : parts)
            EXPECT_NE(message.find(part), std::string::npos) << "message \"" << message << "\" lacks \"" << part << "\"";
    }
}

// A context with an 8×4 colour + depth target, no culling, and a vec3 POSITION layout.
struct Fixture {
    Context ctx;
    RenderTarget color;
    DepthTarget depth;
    InputLayout layout;
    std::vector<std::unique_ptr<VertexBuffer>> buffers;  // kept alive for the context
    uint32_t width, height;
    explicit Fixture(ContextOptions options = {}, uint32_t w = 8, uint32_t h = 4)
        : ctx(options), color(w, h), depth(w, h), width(w), height(h) {
        color.clear(kClear);
        depth.clear(1.0f);
        ctx.setRenderTargets(&color, &depth);
        ctx.setViewport({0, 0, float(w), float(h), 0, 1});
        RasterizerState none;
        none.cullMode = CullMode::None;
        ctx.setRasterizerState(none);
        ctx.setPrimitiveTopology(Topology::TriangleList);
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
        layout = InputLayout(desc);
        ctx.setInputLayout(&layout);
    }
    // Two triangles over pixel columns [x0, x1), all rows, at depth z.
    void bindColumns(int x0, int x1, float z) {
        const float a = float(x0) / float(width) * 2 - 1, b = float(x1) / float(width) * 2 - 1;
        buffers.push_back(std::make_unique<VertexBuffer>(VertexBuffer::create(
            std::vector<glm::vec3>{{a, -1, z}, {a, 1, z}, {b, -1, z}, {b, -1, z}, {a, 1, z}, {b, 1, z}})));
        ctx.setVertexBuffer(0, buffers.back().get());
    }
    template <class PS>
    void drawColumns(const PS& ps, int x0, int x1, float z) {
        bindColumns(x0, x1, z);
        ctx.draw(VsTransform{}, ps, 6);
    }
    void drawColumns(const glm::vec4& c, int x0, int x1, float z) { drawColumns(PsConstant{c}, x0, x1, z); }
};

// ---- Depth --------------------------------------------------------------------------------------------

// Outcome of a pixel: which colour it shows and the depth it keeps.
struct Outcome {
    char color;  // 'c' clear, 'r' red (z = 0.3), 'g' green (z = 0.6)
    float depth;
};

struct DepthRow {
    ComparisonFunc func;
    Outcome nearOnly, farOnly;           // one fragment against the cleared 0.45
    Outcome nearThenFar, farThenNear;  // both, in the two orders
};

// By hand, the depth buffer cleared to 0.45, red at 0.3 and green at 0.6, depth write on.
const DepthRow kDepthTable[] = {
    {ComparisonFunc::Never, {'c', 0.45f}, {'c', 0.45f}, {'c', 0.45f}, {'c', 0.45f}},
    {ComparisonFunc::Less, {'r', 0.3f}, {'c', 0.45f}, {'r', 0.3f}, {'r', 0.3f}},
    {ComparisonFunc::Equal, {'c', 0.45f}, {'c', 0.45f}, {'c', 0.45f}, {'c', 0.45f}},
    {ComparisonFunc::LessEqual, {'r', 0.3f}, {'c', 0.45f}, {'r', 0.3f}, {'r', 0.3f}},
    {ComparisonFunc::Greater, {'c', 0.45f}, {'g', 0.6f}, {'g', 0.6f}, {'g', 0.6f}},
    {ComparisonFunc::NotEqual, {'r', 0.3f}, {'g', 0.6f}, {'g', 0.6f}, {'r', 0.3f}},
    {ComparisonFunc::GreaterEqual, {'c', 0.45f}, {'g', 0.6f}, {'g', 0.6f}, {'g', 0.6f}},
    {ComparisonFunc::Always, {'r', 0.3f}, {'g', 0.6f}, {'g', 0.6f}, {'r', 0.3f}},
};

glm::vec4 colorOf(char c, const RenderTarget& cleared) {
    return c == 'r' ? kRed : c == 'g' ? kGreen : cleared.load(0, 0);
}

TEST(PipelineDepth, EveryComparisonFuncMatchesTheHandTable) {
    for (const bool reference : {false, true}) {
        for (const DepthRow& row : kDepthTable) {
            for (const bool nearFirst : {true, false}) {
                // Red (0.3) covers columns 0..5, green (0.6) columns 2..7: 0-1 red only, 2-5 both, 6-7 green only.
                Fixture f(ContextOptions{.reference = reference});
                f.depth.clear(0.45f);
                const RenderTarget cleared = f.color;
                f.ctx.setDepthStencilState({true, true, row.func});
                if (nearFirst) {
                    f.drawColumns(kRed, 0, 6, 0.3f);
                    f.drawColumns(kGreen, 2, 8, 0.6f);
                } else {
                    f.drawColumns(kGreen, 2, 8, 0.6f);
                    f.drawColumns(kRed, 0, 6, 0.3f);
                }
                const Outcome both = nearFirst ? row.nearThenFar : row.farThenNear;
                for (uint32_t y = 0; y < 4; ++y) {
                    for (uint32_t x = 0; x < 8; ++x) {
                        const Outcome o = x < 2 ? row.nearOnly : x >= 6 ? row.farOnly : both;
                        EXPECT_EQ(f.color.load(x, y), colorOf(o.color, cleared))
                            << name(row.func) << (nearFirst ? ", near first" : ", far first")
                            << (reference ? ", reference" : "") << ", pixel " << x << "," << y;
                        EXPECT_EQ(f.depth.load(x, y), o.depth)
                            << name(row.func) << (nearFirst ? ", near first" : ", far first")
                            << (reference ? ", reference" : "") << ", pixel " << x << "," << y;
                    }
                }
            }
        }
    }
}

TEST(PipelineDepth, EqualPassesTheSameDepthOnly) {
    Fixture f;
    f.depth.clear(0.45f);
    const RenderTarget cleared = f.color;
    f.ctx.setDepthStencilState({true, true, ComparisonFunc::Equal});
    f.drawColumns(kRed, 0, 4, 0.45f);
    f.drawColumns(kGreen, 4, 8, 0.4499f);
    EXPECT_EQ(f.ctx.drawStatistics().fragmentsLateDepthKilled + f.ctx.drawStatistics().fragmentsEarlyDepthKilled, 16u);
    EXPECT_EQ(f.color.load(0, 0), kRed);
    EXPECT_EQ(f.color.load(7, 0), cleared.load(7, 0));
    EXPECT_EQ(f.depth.load(0, 0), 0.45f);
    EXPECT_EQ(f.depth.load(7, 0), 0.45f);
}

TEST(PipelineDepth, WriteMaskOffKeepsDepth) {
    Fixture f;
    f.depth.clear(0.45f);
    f.ctx.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
    f.drawColumns(kRed, 0, 8, 0.3f);
    EXPECT_EQ(f.color.load(3, 2), kRed);
    EXPECT_EQ(f.depth.load(3, 2), 0.45f);
    // The depth buffer still says 0.45, so a fragment at 0.4 passes over the red.
    f.drawColumns(kGreen, 0, 8, 0.4f);
    EXPECT_EQ(f.color.load(3, 2), kGreen);
    // The same with the generic depth path (GreaterEqual is not specialised).
    f.ctx.setDepthStencilState({true, false, ComparisonFunc::GreaterEqual});
    f.drawColumns(kRed, 0, 4, 0.5f);
    EXPECT_EQ(f.color.load(0, 0), kRed);
    for (uint32_t y = 0; y < 4; ++y)
        for (uint32_t x = 0; x < 8; ++x) EXPECT_EQ(f.depth.load(x, y), 0.45f);
}

// A pixel shader compiled for one state pair only (specialised_states.hpp).
struct PsOpaqueLessOnly : PsConstant {
    using SpecialisedStates = raster::SpecialisedStates<Specialise<DepthState::Less, BlendMode::Replace>>;
};

// A draw whose state the pixel shader names takes the specialised loop; any other state the generic
// one, with the same bits as a shader compiled for every pair (which takes a specialised loop there).
TEST(PipelineSpecialisedStates, OtherStatesTakeTheGenericLoopWithTheSameBits) {
    struct Case {
        DepthStencilState depth;
        BlendState blend;
        bool named;  // the pair is PsOpaqueLessOnly's
    };
    const Case cases[] = {{{true, true, ComparisonFunc::Less}, BlendState::opaque(), true},
                          {DepthStencilState::readOnly(ComparisonFunc::Less), BlendState::additive(), false},
                          {{true, true, ComparisonFunc::LessEqual}, BlendState::opaque(), false},
                          {{false, false, ComparisonFunc::Less}, BlendState::opaque(), false}};
    for (const Case& c : cases) {
        Fixture one, all;
        for (Fixture* f : {&one, &all}) {
            f->depth.clear(0.45f);
            f->ctx.setDepthStencilState(c.depth);
            f->ctx.setBlendState(c.blend);
            f->ctx.resetFrameStatistics();
        }
        one.drawColumns(PsOpaqueLessOnly{{glm::vec4(0.25f, 0.5f, 0.75f, 1.0f)}}, 1, 7, 0.3f);
        all.drawColumns(PsConstant{glm::vec4(0.25f, 0.5f, 0.75f, 1.0f)}, 1, 7, 0.3f);
        EXPECT_EQ(one.ctx.drawStatistics().drawsSpecialised, c.named ? 1u : 0u);
        EXPECT_EQ(all.ctx.drawStatistics().drawsSpecialised, 1u) << "every pair is specialised by default";
        for (uint32_t y = 0; y < 4; ++y)
            for (uint32_t x = 0; x < 8; ++x) {
                EXPECT_EQ(one.color.load(x, y), all.color.load(x, y)) << x << "," << y;
                EXPECT_EQ(one.depth.load(x, y), all.depth.load(x, y)) << x << "," << y;
            }
        EXPECT_NE(one.color.load(3, 2), one.color.load(0, 2)) << "the draw wrote something";
    }
}

TEST(PipelineDepth, DisabledNeitherTestsNorWrites) {
    Fixture f;
    f.depth.clear(0.45f);
    f.ctx.setDepthStencilState(DepthStencilState::disabled());
    f.drawColumns(kRed, 0, 8, 0.6f);
    EXPECT_EQ(f.ctx.drawStatistics().fragmentsEarlyDepthKilled, 0u);
    f.drawColumns(kGreen, 0, 4, 0.9f);
    for (uint32_t y = 0; y < 4; ++y) {
        for (uint32_t x = 0; x < 8; ++x) {
            EXPECT_EQ(f.color.load(x, y), x < 4 ? kGreen : kRed) << x << "," << y;
            EXPECT_EQ(f.depth.load(x, y), 0.45f);
        }
    }
    // Depth enabled but no depth target: the same as disabled.
    f.ctx.setDepthStencilState({true, true, ComparisonFunc::Never});
    f.ctx.setRenderTargets(&f.color, nullptr);
    f.drawColumns(kRed, 0, 4, 0.9f);
    EXPECT_EQ(f.color.load(0, 0), kRed);
}

TEST(PipelineDepth, DepthOnlyPass) {
    Fixture f;
    f.ctx.setRenderTargets(nullptr, &f.depth);
    const RenderTarget before = f.color;
    f.drawColumns(kRed, 2, 6, 0.25f);
    EXPECT_EQ(f.depth.load(2, 0), 0.25f);
    EXPECT_EQ(f.depth.load(1, 0), 1.0f);
    EXPECT_TRUE(f.color == before);
}

// ---- Blending -----------------------------------------------------------------------------------------

TEST(PipelineBlend, AlphaBlendOverClearedTargetGivesHandBytes) {
    // Target (51, 102, 153, 255), source (1, 0.5, 0, 0.25), SrcAlpha / InvSrcAlpha:
    //   r = 1·0.25 + 0.2·0.75 = 0.4 → 102;   g = 0.5·0.25 + 0.4·0.75 = 0.425 → 108.375 → 108;
    //   b = 0 + 0.6·0.75 = 0.45 → 114.75 → 115;   a = 0.25·0.25 + 1·0.75 = 0.8125 → 207.19 → 207.
    for (const bool reference : {false, true}) {
        Fixture f(ContextOptions{.reference = reference});
        f.color.clear({0.2f, 0.4f, 0.6f, 1.0f});
        ASSERT_EQ(f.color.rgba8()[1], 102);
        f.ctx.setBlendState(BlendState::alphaBlend());
        f.drawColumns(glm::vec4(1.0f, 0.5f, 0.0f, 0.25f), 0, 4, 0.5f);
        const uint8_t* p = f.color.rgba8();
        for (uint32_t y = 0; y < 4; ++y) {
            for (uint32_t x = 0; x < 8; ++x) {
                const uint8_t* q = p + 4 * (y * 8 + x);
                const std::array<int, 4> got = {q[0], q[1], q[2], q[3]};
                const std::array<int, 4> expected =
                    x < 4 ? std::array<int, 4>{102, 108, 115, 207} : std::array<int, 4>{51, 102, 153, 255};
                EXPECT_EQ(got, expected) << x << "," << y << (reference ? " reference" : "");
            }
        }
        // Blending twice compounds: r = 1·0.25 + 0.4·0.75 = 0.55 → 140.25 → 140.
        f.depth.clear(1.0f);
        f.drawColumns(glm::vec4(1.0f, 0.5f, 0.0f, 0.25f), 0, 4, 0.5f);
        EXPECT_EQ(f.color.rgba8()[0], 140);
    }
}

TEST(PipelineBlend, WriteMaskKeepsMaskedChannels) {
    Fixture f;
    f.color.clear(glm::vec4(10, 20, 30, 40) / 255.0f);
    BlendState rb;
    rb.renderTarget[0].renderTargetWriteMask = 0x1 | 0x4;  // R and B
    f.ctx.setBlendState(rb);
    f.drawColumns(glm::vec4(1.0f), 0, 8, 0.5f);
    const uint8_t* p = f.color.rgba8() + 4 * (2 * 8 + 5);
    EXPECT_EQ((std::array<int, 4>{p[0], p[1], p[2], p[3]}), (std::array<int, 4>{255, 20, 255, 40}));
    // Mask 0 writes nothing (but the depth test and write still happen).
    BlendState none;
    none.renderTarget[0].renderTargetWriteMask = 0;
    f.ctx.setBlendState(none);
    const RenderTarget before = f.color;
    f.drawColumns(glm::vec4(0.0f), 0, 8, 0.25f);
    EXPECT_TRUE(f.color == before);
    EXPECT_EQ(f.depth.load(0, 0), 0.25f);
}

// ---- Determinism across thread counts --------------------------------------------------------------------

struct Frame {
    RenderTarget color;
    DepthTarget depth;
};

Frame renderScene(std::string_view name, const SceneOptions& options, ContextOptions contextOptions,
                  RenderProgress* progress = nullptr) {
    auto scene = makeScene(name, options);
    Context ctx(contextOptions);
    ctx.setProgress(progress);
    Frame f{RenderTarget(options.width, options.height), DepthTarget(options.width, options.height)};
    scene->render(ctx, f.color, f.depth);
    return f;
}

int countDiffering(const RenderTarget& a, const RenderTarget& b) {
    int n = 0;
    for (size_t i = 0; i < size_t(a.width()) * a.height() * 4; ++i) n += a.rgba8()[i] != b.rgba8()[i];
    return n;
}

TEST(PipelineDeterminism, ParticlesIdenticalForAnyThreadCount) {
    const SceneOptions options{.width = 320, .height = 180, .count = 2000};
    const Frame one = renderScene("particles", options, {.threads = 1});
    // Something was drawn: not all black.
    int lit = 0;
    for (size_t i = 0; i < 320 * 180; ++i) lit += one.color.rgba8()[4 * i] != 0;
    EXPECT_GT(lit, 1000);
    for (const unsigned threads : {2u, 8u}) {
        const Frame f = renderScene("particles", options, {.threads = threads});
        EXPECT_TRUE(f.color == one.color) << threads << " threads: " << countDiffering(f.color, one.color)
                                          << " bytes differ";
        EXPECT_TRUE(f.depth == one.depth) << threads << " threads";
    }
}

TEST(PipelineDeterminism, FogIdenticalForAnyThreadCount) {
    for (const bool height : {true, false}) {
        const SceneOptions options{.width = 320, .height = 180, .cubes = 8, .heightFog = height};
        const Frame one = renderScene("fog", options, {.threads = 1});
        for (const unsigned threads : {2u, 8u}) {
            const Frame f = renderScene("fog", options, {.threads = threads});
            EXPECT_TRUE(f.color == one.color) << threads << " threads: " << countDiffering(f.color, one.color)
                                              << " bytes differ";
            EXPECT_TRUE(f.depth == one.depth) << threads << " threads";
        }
    }
}

// The lecture's fog figures and part 1's closed form (the latter through the teaching pipeline).
TEST(PipelineDeterminism, FogFiguresIdenticalForAnyThreadCount) {
    for (const char* name : {"fog-constant", "fog-black", "fog-coloured", "fog-height", "media-closed-form"}) {
        const SceneOptions options{.width = 192, .height = 108, .cubes = 4};
        const Frame one = renderScene(name, options, {.threads = 1});
        for (const unsigned threads : {2u, 8u}) {
            const Frame f = renderScene(name, options, {.threads = threads});
            EXPECT_TRUE(f.color == one.color) << name << ", " << threads << " threads: "
                                              << countDiffering(f.color, one.color) << " bytes differ";
            EXPECT_TRUE(f.depth == one.depth) << name << ", " << threads << " threads";
        }
    }
}

TEST(PipelineDeterminism, RenderingTwiceWithOneContextGivesTheSameFrame) {
    const SceneOptions options{.width = 160, .height = 90, .count = 500};
    auto scene = makeScene("particles", options);
    Context ctx;
    Frame a{RenderTarget(160, 90), DepthTarget(160, 90)}, b{RenderTarget(160, 90), DepthTarget(160, 90)};
    scene->render(ctx, a.color, a.depth);
    scene->render(ctx, b.color, b.depth);
    EXPECT_TRUE(a.color == b.color);
    EXPECT_TRUE(a.depth == b.depth);
}

// ---- Validation ----------------------------------------------------------------------------------------

// Runs the draw, expects the error and checks that no target changed.
void expectDrawRefused(Fixture& f, const std::function<void()>& draw, ErrorCode code,
                       std::initializer_list<std::string> parts, const std::vector<const RenderTarget*>& extra = {}) {
    const RenderTarget colorBefore = f.color;
    const DepthTarget depthBefore = f.depth;
    std::vector<RenderTarget> extraBefore;
    for (const RenderTarget* t : extra) extraBefore.push_back(*t);
    expectError(draw, code, parts);
    EXPECT_TRUE(f.color == colorBefore);
    EXPECT_TRUE(f.depth == depthBefore);
    for (size_t i = 0; i < extra.size(); ++i) EXPECT_TRUE(*extra[i] == extraBefore[i]) << "extra target " << i;
}

TEST(PipelineValidation, InvalidBlendState) {
    Fixture f;
    f.bindColumns(0, 8, 0.5f);
    BlendState bad = BlendState::alphaBlend();
    bad.renderTarget[0].srcBlendAlpha = Blend::SrcColor;
    f.ctx.setBlendState(bad);
    expectDrawRefused(f, [&] { f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6); }, ErrorCode::InvalidState,
                      {"renderTarget[0].srcBlendAlpha", "SrcColor"});
    // With independent blending, slot 3 is validated too.
    BlendState slot3;
    slot3.independentBlendEnable = true;
    slot3.renderTarget[3].destBlendAlpha = Blend::InvDestColor;
    f.ctx.setBlendState(slot3);
    expectDrawRefused(f, [&] { f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6); }, ErrorCode::InvalidState,
                      {"renderTarget[3].destBlendAlpha", "InvDestColor"});
}

TEST(PipelineValidation, InvalidViewport) {
    Fixture f;
    f.bindColumns(0, 8, 0.5f);
    f.ctx.setViewport({0, 0, 0, 4, 0, 1});
    expectDrawRefused(f, [&] { f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6); }, ErrorCode::InvalidState,
                      {"viewport width"});
    f.ctx.setViewport({0, 0, 8, 4, 0.8f, 0.2f});
    expectDrawRefused(f, [&] { f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6); }, ErrorCode::InvalidState,
                      {"minDepth", "maxDepth"});
}

TEST(PipelineValidation, InvalidDepthAndRasterizerState) {
    Fixture f;
    f.bindColumns(0, 8, 0.5f);
    f.ctx.setDepthStencilState({true, true, ComparisonFunc(42)});
    expectDrawRefused(f, [&] { f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6); }, ErrorCode::InvalidState,
                      {"depthFunc", "42"});
    f.ctx.setDepthStencilState({});
    RasterizerState scissor;
    scissor.scissorEnable = true;
    scissor.scissorLeft = 5;
    scissor.scissorRight = 2;
    f.ctx.setRasterizerState(scissor);
    expectDrawRefused(f, [&] { f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6); }, ErrorCode::InvalidState,
                      {"scissorRight"});
}

struct PsTwo {
    std::array<glm::vec4, 2> operator()(const PositionOnly&) const { return {kRed, kGreen}; }
};

TEST(PipelineValidation, MismatchedTargetSizes) {
    Fixture f;
    f.bindColumns(0, 8, 0.5f);
    DepthTarget small(8, 2);
    f.ctx.setRenderTargets(&f.color, &small);
    const DepthTarget smallBefore = small;
    expectDrawRefused(f, [&] { f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6); }, ErrorCode::InvalidState,
                      {"depth target", "8x2", "8x4"});
    EXPECT_TRUE(small == smallBefore);
    RenderTarget wide(9, 4);
    wide.clear(kClear);
    RenderTarget* const two[] = {&f.color, &wide};
    f.ctx.setRenderTargets(two, &f.depth);
    expectDrawRefused(
        f,
        [&] {
            f.ctx.draw(VsTransform{}, PsTwo{}, 6);
        },
        ErrorCode::InvalidState, {"render target 1", "9x4", "8x4"}, {&wide});
}

TEST(PipelineValidation, NoTargetsBound) {
    Fixture f;
    f.bindColumns(0, 8, 0.5f);
    f.ctx.setRenderTargets(nullptr, nullptr);
    expectDrawRefused(f, [&] { f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6); }, ErrorCode::InvalidState,
                      {"neither a render target nor a depth target", "setRenderTargets"});
}

TEST(PipelineValidation, ShaderWritesFewerTargetsThanBound) {
    Fixture f;
    f.bindColumns(0, 8, 0.5f);
    RenderTarget second(8, 4);
    second.clear(kGreen);
    RenderTarget* const two[] = {&f.color, &second};
    f.ctx.setRenderTargets(two, &f.depth);
    expectDrawRefused(f, [&] { f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6); }, ErrorCode::InvalidState,
                      {"2 render targets are bound", "writes 1"}, {&second});
}

TEST(PipelineValidation, EmptyScissorAtIntMinDrawsNothing) {
    // left = right = INT_MIN is an empty rectangle; right − 1 overflowed to INT_MAX in int32 and the
    // draw covered everything. Any empty rectangle, wherever it lies, draws nothing.
    for (const auto& [left, right, top, bottom] :
         std::vector<std::array<int, 4>>{{INT_MIN, INT_MIN, 0, 4},
                                         {0, 8, INT_MIN, INT_MIN},
                                         {INT_MIN, INT_MIN, INT_MIN, INT_MIN},
                                         {3, 3, 0, 4},
                                         {INT_MAX, INT_MAX, 0, 4}}) {
        Fixture f;
        f.bindColumns(0, 8, 0.5f);
        RasterizerState rs = f.ctx.rasterizerState();
        rs.scissorEnable = true;
        rs.scissorLeft = left, rs.scissorRight = right, rs.scissorTop = top, rs.scissorBottom = bottom;
        f.ctx.setRasterizerState(rs);
        const RenderTarget before = f.color;
        f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6);
        EXPECT_TRUE(f.color == before) << "scissor " << left << ".." << right << " x " << top << ".." << bottom;
        EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 0u);
    }
    // The widest rectangle draws everything.
    Fixture f;
    f.bindColumns(0, 8, 0.5f);
    RasterizerState rs = f.ctx.rasterizerState();
    rs.scissorEnable = true;
    rs.scissorLeft = rs.scissorTop = INT_MIN;
    rs.scissorRight = rs.scissorBottom = INT_MAX;
    f.ctx.setRasterizerState(rs);
    f.ctx.draw(VsTransform{}, PsConstant{kRed}, 6);
    EXPECT_EQ(f.color.load(7, 3), kRed);
}

TEST(PipelineValidation, PixelAccessOutsideTheTargetIsRefused) {
    RenderTarget color(8, 4);
    DepthTarget depth(8, 4);
    expectError([&] { color.load(8, 0); }, ErrorCode::OutOfRange, {"RenderTarget::load(8, 0)", "8x4"});
    expectError([&] { color.store(0, 4, kRed); }, ErrorCode::OutOfRange, {"RenderTarget::store(0, 4)"});
    expectError([&] { depth.load(0, UINT32_MAX); }, ErrorCode::OutOfRange, {"DepthTarget::load", "8x4"});
    expectError([&] { depth.store(9, 9, 0.5f); }, ErrorCode::OutOfRange, {"DepthTarget::store(9, 9)"});
    EXPECT_EQ(depth.load(7, 3), 1.0f);
}

TEST(PipelineValidation, TargetConstructionAndBinding) {
    expectError([] { RenderTarget t(0, 4); }, ErrorCode::InvalidArgument, {"0x4"});
    expectError([] { RenderTarget t(4, 0); }, ErrorCode::InvalidArgument, {"4x0"});
    expectError([] { RenderTarget t(RenderTarget::kMaxSize + 1, 1); }, ErrorCode::InvalidArgument, {"16385"});
    expectError([] { RenderTarget t(4, 4, Format::D32_FLOAT); }, ErrorCode::InvalidArgument, {"D32_FLOAT"});
    expectError([] { DepthTarget t(0, 0); }, ErrorCode::InvalidArgument, {"0x0"});
    EXPECT_NO_THROW(RenderTarget(1, 1));
    Context ctx(ContextOptions{.threads = 1});
    RenderTarget t(2, 2);
    std::array<RenderTarget*, kMaxRenderTargets + 1> nine;
    nine.fill(&t);
    expectError([&] { ctx.setRenderTargets(nine, nullptr); }, ErrorCode::InvalidArgument, {"9 render targets"});
    RenderTarget* const withNull[] = {&t, nullptr};
    expectError([&] { ctx.setRenderTargets(withNull, nullptr); }, ErrorCode::InvalidArgument, {"render target 1"});
}

// ---- Statistics ---------------------------------------------------------------------------------------

TEST(PipelineStatisticsTest, ParticlesCountGeometryShaderWork) {
    constexpr uint32_t kCount = 700;
    auto scene = makeScene("particles", {.width = 320, .height = 180, .count = kCount});
    Context ctx;
    RenderTarget color(320, 180);
    DepthTarget depth(320, 180);
    ctx.resetFrameStatistics();
    scene->render(ctx, color, depth);
    const PipelineStatistics draw = ctx.drawStatistics();  // the particle draw
    EXPECT_EQ(draw.iaVertices, kCount);
    EXPECT_EQ(draw.iaPrimitives, kCount);
    EXPECT_EQ(draw.vsInvocations, kCount);
    EXPECT_EQ(draw.gsInvocations, kCount);
    EXPECT_EQ(draw.gsPrimitives, 2 * kCount);
    EXPECT_EQ(draw.cInvocations, 2 * kCount);
    EXPECT_EQ(draw.sortsAvoided, 1u) << "additive blending needs no sort";
    EXPECT_GT(draw.psInvocations, 0u);
    EXPECT_GT(draw.fragmentsEarlyDepthKilled, 0u) << "some particles are behind the occluder";

    const PipelineStatistics frame = ctx.frameStatistics();  // occluder + particles
    EXPECT_EQ(frame.iaVertices, 6 + kCount);
    EXPECT_EQ(frame.iaPrimitives, 2 + kCount);
    EXPECT_EQ(frame.vsInvocations, 6 + kCount);
    EXPECT_EQ(frame.gsInvocations, kCount);
    EXPECT_EQ(frame.gsPrimitives, 2 * kCount);
    EXPECT_EQ(frame.cInvocations, 2 + 2 * kCount);
    EXPECT_GT(frame.psInvocations, draw.psInvocations);

    // A second frame without a reset doubles everything.
    scene->render(ctx, color, depth);
    PipelineStatistics twice = frame;
    twice += frame;
    EXPECT_TRUE(ctx.frameStatistics() == twice) << ctx.frameStatistics().toString() << "vs\n" << twice.toString();
    EXPECT_TRUE(ctx.drawStatistics() == draw);

    ctx.resetFrameStatistics();
    EXPECT_TRUE(ctx.frameStatistics() == PipelineStatistics{});
    EXPECT_TRUE(ctx.drawStatistics() == draw) << "the reset leaves the last draw's statistics";
}

// The eight-wide rectangle loop counts invocations and early depth kills per rectangle, not per
// fragment (helpers = 8·blocks − invocations, kills = covered − invocations). The traced draw goes
// fragment by fragment through 2×2 quads: both must count the same fragments. Widths that are not a
// multiple of 4 send the last column of tiles through the lane-by-lane fallback.
TEST(PipelineStatisticsTest, ParticlesCountTheSameFragmentsEightWideAndTraced) {
    for (const auto& size : {std::pair{320u, 180u}, std::pair{318u, 181u}}) {
        const uint32_t w = size.first, h = size.second;  // not a structured binding: clang 14 cannot capture one
        auto scene = makeScene("particles", {.width = w, .height = h, .count = 900});
        auto drawStatistics = [&](bool traced) {
            Context ctx(ContextOptions{.threads = 2});
            RenderTarget color(w, h);
            DepthTarget depth(w, h);
            Trace trace({.pixels = TraceOptions::everything(), .geometry = false});
            if (traced) ctx.setTrace(&trace);
            scene->render(ctx, color, depth);
            return ctx.drawStatistics();
        };
        const PipelineStatistics wide = drawStatistics(false), traced = drawStatistics(true);
        EXPECT_GT(wide.psInvocations, 20000u) << w;
        EXPECT_GT(wide.fragmentsEarlyDepthKilled, 1000u) << w;
        EXPECT_GT(wide.fragmentsBlendNoOp, 1000u) << w;
        // The fire sprites' transparent corners are skipped before the shader (transparency.hpp),
        // and every fragment skipped is one the traced draw shades to a blend no-op.
        EXPECT_GT(wide.fragmentsTransparentSkipped, 2000u) << w;
        EXPECT_EQ(traced.fragmentsTransparentSkipped, 0u) << w;
        EXPECT_EQ(wide.psInvocations + wide.fragmentsTransparentSkipped, traced.psInvocations) << w;
        EXPECT_EQ(wide.fragmentsEarlyDepthKilled, traced.fragmentsEarlyDepthKilled) << w;
        EXPECT_EQ(wide.fragmentsBlendNoOp + wide.fragmentsTransparentSkipped, traced.fragmentsBlendNoOp) << w;
        EXPECT_GT(wide.helperInvocations, 0u) << w;
    }
}

TEST(ContextClear, BandsOnAnyThreadCountGiveTheTargetsOwnClear) {
    // Odd sizes (a last band of 7 rows), both colour formats, UNORM rounding and clamping.
    const glm::vec4 color(0.2f, 1.5f, -0.25f, 0.5f);
    for (const unsigned threads : {1u, 2u, 3u}) {
        ContextOptions options;
        options.threads = threads;
        Context ctx(options);
        for (const Format format : {Format::R8G8B8A8_UNORM, Format::R32G32B32A32_FLOAT}) {
            RenderTarget expected(37, 71, format), actual(37, 71, format);
            expected.store(3, 4, glm::vec4(0.9f));
            actual.store(3, 4, glm::vec4(0.9f));
            expected.clear(color);
            ctx.clearRenderTarget(actual, color);
            EXPECT_TRUE(actual == expected) << threads << " threads";
            EXPECT_EQ(actual.load(36, 70), expected.load(36, 70));
        }
        DepthTarget expected(37, 71), actual(37, 71);
        expected.clear(0.25f);
        ctx.clearDepthTarget(actual, 0.25f);
        EXPECT_TRUE(actual == expected) << threads << " threads";
        EXPECT_EQ(actual.load(36, 70), 0.25f);
    }
    RenderTarget rgba(5, 3);
    rgba.clear(color);
    EXPECT_EQ(rgba.rgba8()[4 * 14 + 0], 51);   // 0.2 · 255 = 51
    EXPECT_EQ(rgba.rgba8()[4 * 14 + 1], 255);  // clamped
    EXPECT_EQ(rgba.rgba8()[4 * 14 + 2], 0);
    EXPECT_EQ(rgba.rgba8()[4 * 14 + 3], 128);  // 127.5 rounds up
    rgba.clearRows(glm::vec4(1.0f), 2, 100);   // clipped to the last row
    EXPECT_EQ(rgba.load(0, 1), rgba.load(4, 0));
    EXPECT_EQ(rgba.load(2, 2), glm::vec4(1.0f));
}

TEST(PipelineStatisticsTest, ToStringNamesEveryCounter) {
    PipelineStatistics s;
    s.gsPrimitives = 12345;
    s.fragmentsBlendNoOp = 678;
    const std::string text = s.toString();
    EXPECT_NE(text.find("gsPrimitives 12345\n"), std::string::npos);
    EXPECT_NE(text.find("fragmentsBlendNoOp 678\n"), std::string::npos);
    EXPECT_NE(text.find("sortsAvoided 0\n"), std::string::npos);
}

// ---- Progress ------------------------------------------------------------------------------------------

void expectProgress(const RenderProgress& progress, uint32_t started, uint32_t finished, uint32_t tilesInDraw,
                    uint32_t tilesFinished, const char* when) {
    const RenderProgress::Snapshot s = progress.snapshot();
    EXPECT_EQ(s.drawsStarted, started) << when;
    EXPECT_EQ(s.drawsFinished, finished) << when;
    EXPECT_EQ(s.tilesInDraw, tilesInDraw) << when;
    EXPECT_EQ(s.tilesFinished, tilesFinished) << when;
}

TEST(PipelineProgress, CountsDrawsAndTheLastDrawsTiles) {
    Fixture f({}, 200, 100);  // 4×2 tiles of 64 pixels
    RenderProgress progress;
    expectProgress(progress, 0, 0, 0, 0, "new");
    f.drawColumns(kRed, 0, 200, 0.5f);
    expectProgress(progress, 0, 0, 0, 0, "progress off: nothing counted");

    f.ctx.setProgress(&progress);
    EXPECT_EQ(f.ctx.progress(), &progress);
    f.drawColumns(kRed, 0, 200, 0.5f);
    expectProgress(progress, 1, 1, 8, 8, "a whole-target draw");
    f.ctx.draw(VsTransform{}, PsConstant{kGreen}, 0);
    expectProgress(progress, 2, 2, 0, 0, "an empty draw rasterises no tile");
    f.ctx.setViewport({0, 0, 64, 64, 0, 1});
    f.drawColumns(kGreen, 0, 200, 0.5f);
    expectProgress(progress, 3, 3, 1, 1, "a draw in one tile's viewport");
    expectError([&] { f.ctx.draw(VsTransform{}, PsConstant{kGreen}, 600); }, ErrorCode::OutOfRange, {});
    expectProgress(progress, 3, 3, 1, 1, "a draw refused by validation does not start");

    f.ctx.resetFrameStatistics();
    f.ctx.setStepLimit({1, 2});  // draw 0 runs one of its two triangles, draw 1 is skipped
    f.drawColumns(kRed, 0, 200, 0.5f);
    expectProgress(progress, 4, 4, 1, 1, "a stepped draw still rasterises its tiles");
    f.drawColumns(kRed, 0, 200, 0.5f);
    expectProgress(progress, 5, 5, 0, 0, "a skipped draw is finished at once");

    progress.reset();
    expectProgress(progress, 0, 0, 0, 0, "reset");
    f.ctx.setProgress(nullptr);
    f.drawColumns(kRed, 0, 200, 0.5f);
    expectProgress(progress, 0, 0, 0, 0, "progress off again");
}

TEST(PipelineProgress, FrameCountsItsDrawsAndTheLastDrawsTiles) {
    RenderProgress progress;
    renderScene("particles", {.width = 320, .height = 180, .count = 500}, {}, &progress);
    // The occluder and the particles; 320×180 is 5×3 tiles.
    expectProgress(progress, 2, 2, 15, 15, "particles");
}

TEST(PipelineProgress, GrowsMonotonicallyWhileAFrameRenders) {
    // Long enough for many samples mid-draw (about a quarter of a second), short enough for a test.
    const SceneOptions options{.width = 1280, .height = 720, .count = 60000};
    auto scene = makeScene("particles", options);
    Context ctx(ContextOptions{.threads = 2});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    RenderProgress progress;
    ctx.setProgress(&progress);

    std::atomic<bool> done{false};
    std::vector<std::string> failures;
    size_t samples = 0, mid_draw = 0;
    std::thread sampler([&] {
        RenderProgress::Snapshot last;
        while (!done.load(std::memory_order_acquire)) {
            const RenderProgress::Snapshot s = progress.snapshot();
            ++samples;
            const auto fail = [&](const std::string& what) {
                if (failures.size() < 10)
                    failures.push_back(what + ": started " + std::to_string(s.drawsStarted) + " finished " +
                                       std::to_string(s.drawsFinished) + " tiles " +
                                       std::to_string(s.tilesFinished) + "/" + std::to_string(s.tilesInDraw) +
                                       " after started " + std::to_string(last.drawsStarted) + " tiles " +
                                       std::to_string(last.tilesFinished) + "/" +
                                       std::to_string(last.tilesInDraw));
            };
            if (s.drawsStarted < last.drawsStarted) fail("drawsStarted went back");
            if (s.drawsFinished < last.drawsFinished) fail("drawsFinished went back");
            if (s.drawsFinished > s.drawsStarted || s.drawsStarted > s.drawsFinished + 1)
                fail("one draw at a time");
            if (s.tilesFinished > s.tilesInDraw) fail("more tiles finished than in the draw");
            if (s.drawsStarted == last.drawsStarted &&
                (s.tilesFinished < last.tilesFinished || s.tilesInDraw < last.tilesInDraw))
                fail("tiles went back within a draw");
            if (s.drawRunning() && s.tilesFinished > 0 && s.tilesFinished < s.tilesInDraw) ++mid_draw;
            last = s;
        }
    });
    scene->render(ctx, color, depth);
    done.store(true, std::memory_order_release);
    sampler.join();
    for (const std::string& failure : failures) ADD_FAILURE() << failure;
    EXPECT_GT(samples, 100u);
    EXPECT_GT(mid_draw, 0u) << "no sample saw a draw part way through its tiles";
    expectProgress(progress, 2, 2, 20 * 12, 20 * 12, "after the frame");
}

TEST(PipelineProgress, ImagesAreTheSameWithProgressOnAndOff) {
    for (const unsigned threads : {1u, 4u}) {
        RenderProgress progress;
        const SceneOptions particles{.width = 320, .height = 180, .count = 2000};
        const Frame off = renderScene("particles", particles, {.threads = threads});
        const Frame on = renderScene("particles", particles, {.threads = threads}, &progress);
        EXPECT_TRUE(on.color == off.color)
            << threads << " threads: " << countDiffering(on.color, off.color) << " bytes differ";
        EXPECT_TRUE(on.depth == off.depth) << threads << " threads";
        const SceneOptions fog{.width = 320, .height = 180, .cubes = 8};
        const Frame fog_off = renderScene("fog", fog, {.threads = threads});
        const Frame fog_on = renderScene("fog", fog, {.threads = threads}, &progress);
        EXPECT_TRUE(fog_on.color == fog_off.color) << threads << " threads, fog";
        EXPECT_TRUE(fog_on.depth == fog_off.depth) << threads << " threads, fog";
        EXPECT_GT(progress.snapshot().drawsFinished, 2u) << "progress was on";
    }
}

// ---- Reference pipeline --------------------------------------------------------------------------------

TEST(PipelineReference, FogAgreesWithTheFastPathWithinOneStep) {
    for (const bool height : {true, false}) {
        const SceneOptions options{.width = 320, .height = 180, .cubes = 8, .heightFog = height};
        const Frame fast = renderScene("fog", options, {});
        const Frame reference = renderScene("fog", options, {.reference = true});
        int worst = 0, differing = 0;
        for (size_t i = 0; i < size_t(320) * 180 * 4; ++i) {
            const int d = std::abs(int(fast.color.rgba8()[i]) - int(reference.color.rgba8()[i]));
            worst = std::max(worst, d);
            differing += d != 0;
        }
        EXPECT_LE(worst, 1) << (height ? "height" : "constant") << " fog, " << differing << " bytes differ";
        EXPECT_TRUE(fast.depth == reference.depth) << "depth is computed in double in both pipelines";
    }
    Context reference(ContextOptions{.reference = true});
    EXPECT_TRUE(reference.reference());
    EXPECT_FALSE(Context().reference());
}

TEST(PipelineReference, ThreadCountIsHonoured) {
    EXPECT_EQ(Context(ContextOptions{.threads = 1}).threads(), 1u);
    EXPECT_EQ(Context(ContextOptions{.threads = 3}).threads(), 3u);
    EXPECT_GE(Context().threads(), 1u);
}

}  // namespace
}  // namespace raster
