// The pipeline trace (raster/trace.hpp): pixel histories against values worked out by hand, traced
// images bit-identical to untraced ones, records identical for any thread count, geometry records
// and primitive fates, overdraw and non-finite counts, statistics per draw, and stepping.
#include "raster/trace.hpp"
#include "raster/trace_format.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "raster/pipeline.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/scenes.hpp"
#include "raster/shaders/basic.hpp"

namespace raster {
namespace {

using shaders::PositionOnly;
using shaders::PsConstant;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A vertex given in clip space, so that tests can place w (and NaN) themselves.
struct ClipIn {
    glm::vec4 position;
    RASTER_INPUT_SIGNATURE(ClipIn, RASTER_INPUT(position, "POSITION", 0))
};
struct VsClip {
    PositionOnly operator()(const ClipIn& in) const { return {in.position}; }
};

// HLSL's `discard` for pixel centres left of x = 4; white elsewhere.
struct PsDiscardLeft {
    std::optional<glm::vec4> operator()(const PositionOnly& in) const {
        if (in.position.x < 4.0f) return std::nullopt;
        return glm::vec4(1.0f);
    }
};

// NaN in red for pixel centres right of x = 4 (columns 4..7); opaque blue elsewhere.
struct PsNanRight {
    glm::vec4 operator()(const PositionOnly& in) const {
        return in.position.x > 4.0f ? glm::vec4(kNaN, 0, 0, 1) : glm::vec4(0, 0, 1, 1);
    }
};

// The point (sx, sy) of an 8×8 target (pixels, y down) at depth z, in clip space with w = 1.
glm::vec4 at(float sx, float sy, float z) {
    return {sx / 4.0f - 1.0f, 1.0f - sy / 4.0f, z, 1.0f};
}

// A colour as a UNORM target stores and loads it: byte n reads back as n/255.
glm::vec4 unorm(int r, int g, int b, int a) {
    return {unorm8ToFloat(uint8_t(r)), unorm8ToFloat(uint8_t(g)), unorm8ToFloat(uint8_t(b)),
            unorm8ToFloat(uint8_t(a))};
}

// The triangles of the 8×8 scene. No edge passes through a pixel centre (i + ½, j + ½), so coverage
// does not depend on the fill rule:
//   A: i + j <= 6 (upper left)     B: i > j (right of the diagonal)     C: i + j <= 7
std::vector<glm::vec4> triangleA(float z) {
    return {at(0, 0, z), at(7.6f, 0, z), at(0, 7.6f, z)};
}
std::vector<glm::vec4> triangleB(float z) {
    return {at(0.4f, 0, z), at(8, 0, z), at(8, 7.6f, z)};
}
std::vector<glm::vec4> triangleC(float z) {
    return {at(0, 0, z), at(8.6f, 0, z), at(0, 8.6f, z)};
}
bool coversA(int i, int j) {
    return i + j <= 6;
}
bool coversB(int i, int j) {
    return i > j;
}
bool coversC(int i, int j) {
    return i + j <= 7;
}
// Two triangles sharing the diagonal, covering all 64 pixels once.
std::vector<glm::vec4> wholeTarget(float z) {
    return {at(0, 0, z), at(8, 0, z), at(0, 8, z), at(8, 0, z), at(8, 8, z), at(0, 8, z)};
}

const glm::vec4 kClear = unorm(0, 64, 0, 255);
const glm::vec4 kRed(1, 0, 0, 1);
const glm::vec4 kGreen(0, 1, 0, 1);
const glm::vec4 kBlueQuarter(0, 0, 1, 0.25f);
const glm::vec4 kWhiteTransparent(1, 1, 1, 0);

// An 8×8 colour + depth target (colour cleared to kClear, depth to 1), no culling, clip-space vertices.
struct Target8 {
    Context ctx;
    RenderTarget color{8, 8};
    DepthTarget depth{8, 8};
    InputLayout layout;
    std::vector<std::unique_ptr<VertexBuffer>> buffers;  // alive while bound

    explicit Target8(ContextOptions options = {}) : ctx(options) {
        color.clear(kClear);
        depth.clear(1.0f);
        ctx.setRenderTargets(&color, &depth);
        ctx.setViewport({0, 0, 8, 8, 0, 1});
        RasterizerState none;
        none.cullMode = CullMode::None;
        ctx.setRasterizerState(none);
        ctx.setPrimitiveTopology(Topology::TriangleList);
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32A32_FLOAT, 0, 0}};
        layout = InputLayout(desc);
        ctx.setInputLayout(&layout);
    }
    template <class PS>
    void draw(const PS& ps, const std::vector<glm::vec4>& vertices) {
        buffers.push_back(std::make_unique<VertexBuffer>(VertexBuffer::create(vertices)));
        ctx.setVertexBuffer(0, buffers.back().get());
        ctx.draw(VsClip{}, ps, uint32_t(vertices.size()));
    }
};

// The five draws of the pixel-history scene, depth Less throughout:
//   0: A at 0.5, opaque red           1: B at 0.25, alpha-blended (0, 0, 1, ¼)
//   2: C at 0.75, opaque green (behind both: fails where A or B wrote)
//   3: A at 0.1, discards left of x = 4, white right of it
//   4: A at 0.05, additive (1, 1, 1, 0): alpha 0 cannot change the pixel (but writes depth)
void drawFiveDraws(Target8& t) {
    const DepthStencilState less{true, true, ComparisonFunc::Less};
    t.ctx.setDepthStencilState(less);
    t.ctx.setBlendState(BlendState::opaque());
    t.draw(PsConstant{kRed}, triangleA(0.5f));
    t.ctx.setBlendState(BlendState::alphaBlend());
    t.draw(PsConstant{kBlueQuarter}, triangleB(0.25f));
    t.ctx.setBlendState(BlendState::opaque());
    t.draw(PsConstant{kGreen}, triangleC(0.75f));
    t.draw(PsDiscardLeft{}, triangleA(0.1f));
    t.ctx.setBlendState(BlendState::additive());
    t.draw(PsConstant{kWhiteTransparent}, triangleA(0.05f));
}
int fiveDrawsCoverage(int i, int j) {
    return 3 * coversA(i, j) + coversB(i, j) + coversC(i, j);
}

// Equal bit for bit, or both NaN.
bool same(float a, float b) {
    return (std::isnan(a) && std::isnan(b)) || (a == b && std::signbit(a) == std::signbit(b));
}
bool same(const glm::vec4& a, const glm::vec4& b) {
    return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z) && same(a.w, b.w);
}

std::string describe(const TraceFragment& f) {
    char buffer[512];
    std::snprintf(buffer, sizeof buffer,
                  "{draw %u prim %u (%d,%d) z %.9g %.9g->%.9g %s shaded %d out (%g %g %g %g) "
                  "(%g %g %g %g)->(%g %g %g %g)}",
                  f.draw, f.primitive, f.x, f.y, f.depth, f.depthBefore, f.depthAfter, toString(f.fate),
                  int(f.shaded), f.shaderOutput.x, f.shaderOutput.y, f.shaderOutput.z, f.shaderOutput.w,
                  f.colorBefore.x, f.colorBefore.y, f.colorBefore.z, f.colorBefore.w, f.colorAfter.x,
                  f.colorAfter.y, f.colorAfter.z, f.colorAfter.w);
    return buffer;
}

bool same(const TraceFragment& a, const TraceFragment& b) {
    return a.draw == b.draw && a.primitive == b.primitive && a.x == b.x && a.y == b.y &&
           same(a.depth, b.depth) && same(a.depthBefore, b.depthBefore) && same(a.depthAfter, b.depthAfter) &&
           a.fate == b.fate && a.shaded == b.shaded && same(a.shaderOutput, b.shaderOutput) &&
           same(a.colorBefore, b.colorBefore) && same(a.colorAfter, b.colorAfter);
}

// Checks two fragment lists are identical, naming the first difference.
void expectSameFragments(const std::vector<TraceFragment>& a, const std::vector<TraceFragment>& b,
                         const std::string& what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    for (size_t i = 0; i < a.size(); ++i) {
        if (!same(a[i], b[i])) {
            ADD_FAILURE() << what << ": fragment " << i << " differs: " << describe(a[i]) << " vs "
                          << describe(b[i]);
            return;
        }
    }
}

// One expected fragment of the history, every field by hand.
struct Expected {
    uint32_t draw;
    float depth, depthBefore, depthAfter;
    FragmentFate fate;
    bool shaded;
    glm::vec4 shaderOutput, colorBefore, colorAfter;
};

void expectHistory(const Trace& trace, int x, int y, const std::vector<Expected>& expected) {
    const std::vector<TraceFragment> history = trace.pixelHistory(x, y);
    ASSERT_EQ(history.size(), expected.size()) << "pixel " << x << "," << y;
    for (size_t i = 0; i < expected.size(); ++i) {
        const TraceFragment& f = history[i];
        const Expected& e = expected[i];
        const std::string where = "pixel " + std::to_string(x) + "," + std::to_string(y) + " fragment " +
                                  std::to_string(i) + ": " + describe(f);
        EXPECT_EQ(f.draw, e.draw) << where;
        EXPECT_EQ(f.primitive, 0u) << where;
        EXPECT_EQ(f.x, x) << where;
        EXPECT_EQ(f.y, y) << where;
        EXPECT_EQ(f.depth, e.depth) << where;
        EXPECT_EQ(f.depthBefore, e.depthBefore) << where;
        EXPECT_EQ(f.depthAfter, e.depthAfter) << where;
        EXPECT_EQ(f.fate, e.fate) << where << " expected " << toString(e.fate);
        EXPECT_EQ(f.shaded, e.shaded) << where;
        EXPECT_TRUE(same(f.shaderOutput, e.shaderOutput)) << where;
        EXPECT_TRUE(same(f.colorBefore, e.colorBefore)) << where;
        EXPECT_TRUE(same(f.colorAfter, e.colorAfter)) << where;
    }
}

// ---- Pixel history -------------------------------------------------------------------------------

// By hand, UNORM: blended values are rounded as floor(255·v + ½) and read back as n/255.
//   B (0, 0, 1, ¼) alpha-blended over red (255, 0, 0, 255):
//     r = 0·¼ + 1·¾ = 0.75 → 191;  g = 0;  b = 1·¼ + 0 = 0.25 → 64;  a = ¼·¼ + 1·¾ = 0.8125 → 207.
//   B over the clear colour (0, 64, 0, 255): g = (64/255)·¾ → 48, b → 64, a → 207.
const glm::vec4 kRedThenBlue = unorm(191, 0, 64, 207);
const glm::vec4 kClearThenBlue = unorm(0, 48, 64, 207);
const glm::vec4 kNaN4(kNaN);
const glm::vec4 kWhite(1.0f);

TEST(TracePixelHistory, OverlappingDrawsGiveHandComputedRecords) {
    Target8 t;
    // Rows 0..6 traced; row 7 is not.
    Trace trace({.pixels = {0, 0, 7, 6}});
    t.ctx.setTrace(&trace);
    drawFiveDraws(t);
    t.ctx.setTrace(nullptr);
    ASSERT_EQ(trace.draws().size(), 5u);

    // (2, 0): A, B, C, D (discarded: centre x 2.5 < 4), E.
    expectHistory(
        trace, 2, 0,
        {{0, 0.5f, 1.0f, 0.5f, FragmentFate::Written, true, kRed, kClear, unorm(255, 0, 0, 255)},
         {1, 0.25f, 0.5f, 0.25f, FragmentFate::Written, true, kBlueQuarter, unorm(255, 0, 0, 255),
          kRedThenBlue},
         {2, 0.75f, 0.25f, 0.25f, FragmentFate::EarlyDepthFailed, false, kNaN4, kRedThenBlue, kRedThenBlue},
         {3, 0.1f, 0.25f, 0.25f, FragmentFate::Discarded, true, kNaN4, kRedThenBlue, kRedThenBlue},
         {4, 0.05f, 0.25f, 0.05f, FragmentFate::BlendNoOp, true, kWhiteTransparent, kRedThenBlue,
          kRedThenBlue}});
    // (5, 0): the same, but D writes white (centre x 5.5) and E's no-op keeps it.
    expectHistory(
        trace, 5, 0,
        {{0, 0.5f, 1.0f, 0.5f, FragmentFate::Written, true, kRed, kClear, unorm(255, 0, 0, 255)},
         {1, 0.25f, 0.5f, 0.25f, FragmentFate::Written, true, kBlueQuarter, unorm(255, 0, 0, 255),
          kRedThenBlue},
         {2, 0.75f, 0.25f, 0.25f, FragmentFate::EarlyDepthFailed, false, kNaN4, kRedThenBlue, kRedThenBlue},
         {3, 0.1f, 0.25f, 0.1f, FragmentFate::Written, true, kWhite, kRedThenBlue, kWhite},
         {4, 0.05f, 0.1f, 0.05f, FragmentFate::BlendNoOp, true, kWhiteTransparent, kWhite, kWhite}});
    // (7, 1): B only, over the clear colour.
    expectHistory(
        trace, 7, 1,
        {{1, 0.25f, 1.0f, 0.25f, FragmentFate::Written, true, kBlueQuarter, kClear, kClearThenBlue}});
    // (1, 6): C only: in front of the cleared depth, so it passes.
    expectHistory(trace, 1, 6,
                  {{2, 0.75f, 1.0f, 0.75f, FragmentFate::Written, true, kGreen, kClear, kGreen}});
    // (4, 5) and (3, 6): covered by no triangle.
    EXPECT_EQ(trace.overdraw()[5 * 8 + 4], 0u);
    EXPECT_EQ(trace.overdraw()[6 * 8 + 3], 0u);
    EXPECT_TRUE(trace.pixelHistory(4, 5).empty());
    EXPECT_TRUE(trace.pixelHistory(3, 6).empty());
    // (0, 7) is covered by C but outside TraceOptions::pixels: nothing recorded, anywhere in row 7.
    EXPECT_EQ(trace.overdraw()[7 * 8 + 0], 1u) << "C covers (0, 7)";
    EXPECT_TRUE(trace.pixelHistory(0, 7).empty());
    for (const TraceFragment& f : trace.fragments()) {
        EXPECT_LE(f.y, 6) << describe(f);
        EXPECT_GE(f.x, 0);
        EXPECT_LE(f.x, 7);
    }
    // Every fragment inside the rectangle was recorded: as many records as the overdraw of rows 0..6.
    size_t covered = 0;
    for (int j = 0; j <= 6; ++j)
        for (int i = 0; i < 8; ++i) covered += size_t(fiveDrawsCoverage(i, j));
    EXPECT_EQ(trace.fragments().size(), covered);
    EXPECT_FALSE(trace.fragmentsTruncated());

    // The history agrees with the targets: the last record's after values are the pixel's.
    for (int j = 0; j <= 6; ++j) {
        for (int i = 0; i < 8; ++i) {
            const auto h = trace.pixelHistory(i, j);
            if (h.empty()) continue;
            EXPECT_TRUE(same(h.back().colorAfter, t.color.load(uint32_t(i), uint32_t(j)))) << i << "," << j;
            EXPECT_EQ(h.back().depthAfter, t.depth.load(uint32_t(i), uint32_t(j))) << i << "," << j;
        }
    }
}

TEST(TracePixelHistory, ReferencePipelineTestsDepthAfterTheShader) {
    // The reference pipeline shades before the depth test (LateDepthFailed, shaded) and never skips
    // a blend (E is Written, changing nothing); the bytes are the fast pipeline's.
    Target8 t({.reference = true});
    Trace trace({.pixels = {2, 0, 2, 0}});
    t.ctx.setTrace(&trace);
    drawFiveDraws(t);
    expectHistory(
        trace, 2, 0,
        {{0, 0.5f, 1.0f, 0.5f, FragmentFate::Written, true, kRed, kClear, unorm(255, 0, 0, 255)},
         {1, 0.25f, 0.5f, 0.25f, FragmentFate::Written, true, kBlueQuarter, unorm(255, 0, 0, 255),
          kRedThenBlue},
         {2, 0.75f, 0.25f, 0.25f, FragmentFate::LateDepthFailed, true, kGreen, kRedThenBlue, kRedThenBlue},
         {3, 0.1f, 0.25f, 0.25f, FragmentFate::Discarded, true, kNaN4, kRedThenBlue, kRedThenBlue},
         {4, 0.05f, 0.25f, 0.05f, FragmentFate::Written, true, kWhiteTransparent, kRedThenBlue,
          kRedThenBlue}});
    EXPECT_EQ(trace.fragments().size(), 5u) << "only pixel (2, 0) is traced";
}

TEST(TracePixelHistory, TracedDrawsGiveTheUntracedImage) {
    Target8 plain, traced;
    drawFiveDraws(plain);
    Trace trace({.pixels = TraceOptions::everything()});
    traced.ctx.setTrace(&trace);
    drawFiveDraws(traced);
    EXPECT_TRUE(traced.color == plain.color);
    EXPECT_TRUE(traced.depth == plain.depth);
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i)
            EXPECT_EQ(trace.pixelHistory(i, j).size(), size_t(fiveDrawsCoverage(i, j)));
}

TEST(TracePixelHistory, TextAndJsonListTheFragments) {
    Target8 t;
    Trace trace({.pixels = {2, 0, 2, 0}});
    t.ctx.setTrace(&trace);
    drawFiveDraws(t);
    const std::string text = formatPixelHistory(trace, 2, 0);
    EXPECT_EQ(text.rfind("pixel (2, 0): 5 fragments\n", 0), 0u) << text;
    for (const char* fate : {"written", "depth-failed", "discarded", "blend-no-op"})
        EXPECT_NE(text.find(fate), std::string::npos) << fate << " missing from\n" << text;
    const std::string json = pixelHistoryJson(trace, 2, 0);
    EXPECT_EQ(json.rfind("{\"pixel\":[2,0],\"truncated\":false,\"fragments\":[{\"draw\":0,", 0), 0u) << json;
    size_t draws = 0;
    for (size_t p = json.find("\"draw\":"); p != std::string::npos; p = json.find("\"draw\":", p + 1))
        ++draws;
    EXPECT_EQ(draws, 5u) << json;
    EXPECT_NE(json.find("\"fate\":\"depth-failed\",\"shaded\":false,\"shaderOutput\":null"),
              std::string::npos)
        << json;
    EXPECT_NE(json.find("\"depth\":0.25,\"depthBefore\":0.5,\"depthAfter\":0.25,\"depthTest\":\"pass\""),
              std::string::npos)
        << json;
    EXPECT_EQ(formatPixelHistory(trace, 7, 7), "pixel (7, 7): 0 fragments\n");
    EXPECT_EQ(pixelHistoryJson(trace, 7, 7), "{\"pixel\":[7,7],\"truncated\":false,\"fragments\":[]}\n");
}

// Each draw's rasterizer state is in its record, in the pixel history's text and JSON and in the
// draw's text: next to its blend and depth state.
TEST(TracePixelHistory, RecordsTheDrawsRasterizerState) {
    Target8 t;
    Trace trace({.pixels = {2, 1, 2, 1}});
    t.ctx.setTrace(&trace);
    RasterizerState rs;
    rs.cullMode = CullMode::Front, rs.frontCounterClockwise = true, rs.depthClipEnable = false;
    rs.scissorEnable = true, rs.scissorRight = 8, rs.scissorBottom = 4;
    t.ctx.setRasterizerState(rs);
    // Clockwise on screen: back-facing under frontCounterClockwise, kept by CullMode::Front.
    t.draw(PsConstant{}, {at(0, 0, 0.5f), at(8, 0, 0.5f), at(0, 8, 0.5f)});
    ASSERT_EQ(trace.draws().size(), 1u);
    const RasterizerState& recorded = trace.draws()[0].rasterizer;
    EXPECT_EQ(recorded.cullMode, CullMode::Front);
    EXPECT_TRUE(recorded.frontCounterClockwise);
    EXPECT_FALSE(recorded.depthClipEnable);
    EXPECT_EQ(recorded.scissorBottom, 4);
    EXPECT_FALSE(trace.draws()[0].coverageTest);
    const std::string line =
        "rasterizer: cull Front, fill Solid, front counter-clockwise, scissor [0, 8) x [0, 4), depth clip "
        "off";
    EXPECT_EQ(rasterizerSummary(trace.draws()[0]), line);
    const std::string text = formatPixelHistory(trace, 2, 1);
    EXPECT_NE(text.find("pixel (2, 1): 1 fragment\n"), std::string::npos) << text;
    EXPECT_NE(text.find("\n  " + line + "\n"), std::string::npos) << text;
    EXPECT_NE(pixelHistoryJson(trace, 2, 1).find("\"rasterizer\":\"" + line + "\""), std::string::npos);
    EXPECT_NE(formatDraw(trace.draws()[0], 4).find("\n" + line + "\n"), std::string::npos);
}

// pixelHistoryJson escapes what JSON requires in names (a shader's type name is the compiler's
// text): quotes, backslashes and control characters; bytes that are not UTF-8 become U+FFFD. The
// output parses back to the same names and numbers, fields in the documented order.
TEST(TracePixelHistory, JsonEscapesNamesAndParsesBack) {
    const std::string name = "Ps<\"q\" \\ \t\n\x01 \xc3\xa9>";  // quote, backslash, tab, newline, U+0001, é
    Trace trace({.pixels = {3, 1, 3, 1}});
    TraceDraw& draw = trace.beginDraw(4, 4);
    draw.draw = 0;
    draw.pixelShader = name;
    TraceDraw& bad = trace.beginDraw(4, 4);
    bad.draw = 1;
    bad.pixelShader = "Ps\xff";  // not UTF-8
    const float kInf = std::numeric_limits<float>::infinity();
    trace.addFragments({
        {.draw = 0,
         .primitive = 7,
         .x = 3,
         .y = 1,
         .depth = 0.1f,
         .depthBefore = 1.0f,
         .depthAfter = 0.1f,
         .fate = FragmentFate::Written,
         .shaded = true,
         .shaderOutput = {1, 0.5f, 0, 1},
         .colorBefore = {0, 0, 0, 1},
         .colorAfter = {1, 0.5f, 0, 1}},
        {.draw = 1,
         .primitive = 2,
         .x = 3,
         .y = 1,
         .depth = 0.75f,
         .depthBefore = 0.1f,
         .depthAfter = kInf,
         .fate = FragmentFate::EarlyDepthFailed,
         .shaded = false,
         .shaderOutput = glm::vec4(kNaN),
         .colorBefore = {1, 0.5f, 0, 1},
         .colorAfter = {1, kNaN, -kInf, 1}},
        {.draw = 9,
         .primitive = 0,
         .x = 3,
         .y = 1,
         .depth = 0.5f,
         .depthBefore = kNaN,
         .depthAfter = kNaN,
         .fate = FragmentFate::Discarded,
         .shaded = true,
         .shaderOutput = glm::vec4(kNaN),
         .colorBefore = glm::vec4(kNaN),
         .colorAfter = glm::vec4(kNaN)},
    });
    const std::string json = pixelHistoryJson(trace, 3, 1);
    ASSERT_TRUE(json.ends_with("}\n")) << json;
    for (size_t i = 0; i + 1 < json.size(); ++i)
        ASSERT_GE(static_cast<unsigned char>(json[i]), 0x20u)
            << "a raw control character at " << i << ": " << json;
    EXPECT_NE(json.find(R"("pixelShader":"Ps<\"q\" \\ \t\n\u0001 )"
                        "\xc3\xa9"
                        R"(>")"),
              std::string::npos)
        << json;
    EXPECT_NE(json.find(R"("depth":0.1,"depthBefore":1.0,"depthAfter":0.1,)"), std::string::npos)
        << "the shortest decimal of each float: " << json;

    nlohmann::ordered_json parsed;
    ASSERT_NO_THROW(parsed = nlohmann::ordered_json::parse(json)) << json;
    EXPECT_EQ(parsed["pixel"], nlohmann::ordered_json({3, 1}));
    EXPECT_EQ(parsed["truncated"], false);
    const nlohmann::ordered_json& fragments = parsed["fragments"];
    ASSERT_EQ(fragments.size(), 3u) << json;
    const nlohmann::ordered_json& written = fragments[0];
    std::vector<std::string> keys;
    for (const auto& [key, value] : written.items()) keys.push_back(key);
    EXPECT_EQ(keys, (std::vector<std::string>{"draw", "primitive", "pixelShader", "depth", "depthBefore",
                                              "depthAfter", "depthTest", "fate", "shaded", "shaderOutput",
                                              "colorBefore", "colorAfter", "blend", "rasterizer"}));
    EXPECT_EQ(written["pixelShader"].get<std::string>(), name);
    EXPECT_EQ(written["primitive"], 7);
    EXPECT_EQ(float(written["depth"].get<double>()), 0.1f) << "reads back as the same float";
    EXPECT_EQ(written["depthTest"], "pass");
    EXPECT_EQ(written["fate"], "written");
    EXPECT_EQ(written["shaded"], true);
    EXPECT_EQ(written["shaderOutput"], nlohmann::ordered_json({1.0, 0.5, 0.0, 1.0}));
    EXPECT_EQ(written["blend"], "blend off: result = src");
    const nlohmann::ordered_json& failed = fragments[1];
    EXPECT_EQ(failed["pixelShader"].get<std::string>(), "Ps\xef\xbf\xbd") << "0xFF became U+FFFD";
    EXPECT_EQ(failed["depthTest"], "fail");
    EXPECT_TRUE(failed["depthAfter"].is_null()) << "Inf is null";
    EXPECT_TRUE(failed["shaderOutput"].is_null()) << "not shaded: null, not four nulls";
    EXPECT_EQ(failed["colorAfter"], nlohmann::ordered_json({1.0, nullptr, nullptr, 1.0}));
    const nlohmann::ordered_json& orphan = fragments[2];  // of a draw the trace has no record of
    EXPECT_EQ(orphan["pixelShader"], "");
    EXPECT_TRUE(orphan["depthTest"].is_null()) << "no depth buffer: not tested";
    EXPECT_FALSE(orphan.contains("blend"));
}

TEST(TracePixelHistory, MaxFragmentsTruncates) {
    Target8 t;
    Trace trace({.pixels = TraceOptions::everything(), .maxFragments = 10});
    t.ctx.setTrace(&trace);
    drawFiveDraws(t);
    EXPECT_EQ(trace.fragments().size(), 10u);
    EXPECT_TRUE(trace.fragmentsTruncated());
    EXPECT_NE(formatPixelHistory(trace, 0, 0).find("truncated"), std::string::npos);
    trace.clear();
    EXPECT_TRUE(trace.fragments().empty());
    EXPECT_TRUE(trace.draws().empty());
    EXPECT_FALSE(trace.fragmentsTruncated());
    for (const uint32_t n : trace.overdraw()) EXPECT_EQ(n, 0u);
}

// ---- Overdraw and non-finite outputs -----------------------------------------------------------------

TEST(TraceOverdraw, CountsTheTrianglesCoveringEachPixel) {
    Target8 t;
    Trace trace;  // no pixels traced: the counts cover the whole target anyway
    t.ctx.setTrace(&trace);
    drawFiveDraws(t);
    ASSERT_EQ(trace.width(), 8u);
    ASSERT_EQ(trace.height(), 8u);
    ASSERT_EQ(trace.overdraw().size(), 64u);
    EXPECT_TRUE(trace.fragments().empty());
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i)
            EXPECT_EQ(trace.overdraw()[size_t(j) * 8 + i], uint32_t(fiveDrawsCoverage(i, j)))
                << i << "," << j;
    // Two triangles sharing an edge through pixel centres: the fill rule gives each pixel to one.
    t.ctx.setDepthStencilState(DepthStencilState::disabled());
    t.draw(PsConstant{kRed}, wholeTarget(0.5f));
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i)
            EXPECT_EQ(trace.overdraw()[size_t(j) * 8 + i], uint32_t(fiveDrawsCoverage(i, j)) + 1)
                << i << "," << j;
    for (const uint32_t n : trace.nonFinite()) EXPECT_EQ(n, 0u);
}

TEST(TraceOverdraw, NonFiniteCountsNanShaderOutputs) {
    Target8 t;
    Trace trace({.pixels = {0, 0, 7, 0}});
    t.ctx.setTrace(&trace);
    t.draw(PsNanRight{}, wholeTarget(0.5f));
    t.ctx.setDepthStencilState(DepthStencilState::disabled());
    t.draw(PsNanRight{}, triangleA(0.5f));
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i)
            EXPECT_EQ(trace.nonFinite()[size_t(j) * 8 + i], uint32_t(i >= 4) * (1u + coversA(i, j)))
                << i << "," << j;
    // The record keeps the NaN; the target stores it as 0 (UNORM: NaN → 0).
    const auto h = trace.pixelHistory(5, 0);
    ASSERT_EQ(h.size(), 2u);
    EXPECT_TRUE(std::isnan(h[0].shaderOutput.x));
    EXPECT_EQ(h[0].fate, FragmentFate::Written);
    EXPECT_TRUE(same(h[0].colorAfter, glm::vec4(0, 0, 0, 1)));
}

// ---- Traced images and determinism on the scenes --------------------------------------------------------

struct Frame {
    RenderTarget color;
    DepthTarget depth;
};

Frame renderFrame(Scene& scene, Context& ctx, const SceneOptions& o) {
    Frame f{RenderTarget(o.width, o.height), DepthTarget(o.width, o.height)};
    ctx.resetFrameStatistics();
    scene.render(ctx, f.color, f.depth);
    return f;
}

int countDiffering(const RenderTarget& a, const RenderTarget& b) {
    int n = 0;
    for (size_t i = 0; i < size_t(a.width()) * a.height() * 4; ++i) n += a.rgba8()[i] != b.rgba8()[i];
    return n;
}

// Renders without a trace, then with one on every pixel, for 1, 2 and 8 threads: the images are
// the untraced one and the records the same for every thread count.
void expectTracedSceneIdentical(std::string_view name, const SceneOptions& o, bool reference = false) {
    auto scene = makeScene(name, o);
    Context plainCtx({.threads = 2, .reference = reference});
    const Frame plain = renderFrame(*scene, plainCtx, o);
    const std::vector<PipelineStatistics> plainLog = plainCtx.drawStatisticsLog();
    std::vector<TraceFragment> first;
    for (const unsigned threads : {1u, 2u, 8u}) {
        Context ctx({.threads = threads, .reference = reference});
        Trace trace({.pixels = TraceOptions::everything()});
        ctx.setTrace(&trace);
        const Frame traced = renderFrame(*scene, ctx, o);
        const std::string what = std::string(name) + ", " + std::to_string(threads) + " threads";
        EXPECT_TRUE(traced.color == plain.color)
            << what << ": " << countDiffering(traced.color, plain.color) << " bytes differ";
        EXPECT_TRUE(traced.depth == plain.depth) << what;
        EXPECT_FALSE(trace.fragmentsTruncated()) << what;
        // Every fragment rasterised was recorded.
        size_t rasterised = 0;
        for (const uint32_t n : trace.overdraw()) rasterised += n;
        EXPECT_EQ(trace.fragments().size(), rasterised) << what;
        EXPECT_GT(trace.fragments().size(), size_t(o.width) * o.height / 8) << what;
        // The statistics of the traced draws are the untraced ones, but for how the fragments were
        // culled: a traced draw shades quad by quad rather than eight wide (other helper lanes) and
        // tests every fragment's depth (no whole-tile shortcuts); and an untraced opaque draw may
        // shade deferred, leaving fragments a later one replaced unshaded, which a traced draw shades,
        // and skip blocks at the additive blend's ceiling or known to be transparent, which a traced
        // draw shades too.
        ASSERT_EQ(ctx.drawStatisticsLog().size(), plainLog.size()) << what;
        for (size_t d = 0; d < plainLog.size(); ++d) {
            const PipelineStatistics &a = ctx.drawStatisticsLog()[d], &b = plainLog[d];
            const auto fields = [](const PipelineStatistics& s) {
                return std::vector<uint64_t>{
                    s.iaVertices,
                    s.iaPrimitives,
                    s.vsInvocations,
                    s.gsInvocations,
                    s.gsPrimitives,
                    s.cInvocations,
                    s.cPrimitives,
                    s.psInvocations + s.fragmentsOverdrawSkipped + s.fragmentsBlendSaturated +
                        s.fragmentsTransparentSkipped,
                    s.primitivesNonFinite,
                    s.primitivesOutside,
                    s.primitivesClipped,
                    s.primitivesCulled,
                    s.primitivesDegenerate,
                    s.primitivesNoPixels,
                    s.rectanglesRecognized,
                    s.tilesBinned,
                    s.tilesRejected,
                    s.fragmentsLateDepthKilled,
                    s.fragmentsDiscarded,
                    // A skipped transparent fragment is a no-op that the traced draw shades.
                    s.fragmentsBlendNoOp + s.fragmentsTransparentSkipped,
                    s.sortsAvoided};
            };
            EXPECT_EQ(fields(a), fields(b)) << what << ", draw " << d << "\n"
                                            << a.toString() << "vs\n"
                                            << b.toString();
        }
        if (first.empty())
            first = trace.fragments();
        else
            expectSameFragments(trace.fragments(), first, what);
    }
}

TEST(TraceIdentity, ParticlesTracedImageIsTheUntracedOneForAnyThreadCount) {
    expectTracedSceneIdentical("particles", {.width = 320, .height = 180, .count = 2000});
}

TEST(TraceIdentity, FogTracedImageIsTheUntracedOneForAnyThreadCount) {
    expectTracedSceneIdentical("fog", {.width = 320, .height = 180, .cubes = 4, .heightFog = true});
    expectTracedSceneIdentical("fog", {.width = 160, .height = 90, .cubes = 2, .heightFog = false});
}

TEST(TraceIdentity, ReferencePipelineTracedImageIsTheUntracedOne) {
    expectTracedSceneIdentical("particles", {.width = 96, .height = 54, .count = 200}, true);
    expectTracedSceneIdentical("fog", {.width = 96, .height = 54, .cubes = 2}, true);
}

TEST(TraceIdentity, RegionTraceMatchesTheFullTraceRestrictedToIt) {
    const SceneOptions o{.width = 320, .height = 180, .count = 2000};
    auto scene = makeScene("particles", o);
    Context ctx;
    Trace all({.pixels = TraceOptions::everything()});
    ctx.setTrace(&all);
    const Frame full = renderFrame(*scene, ctx, o);
    const PixelRect region{140, 80, 179, 109};
    Trace part({.pixels = region});
    ctx.setTrace(&part);
    const Frame partial = renderFrame(*scene, ctx, o);
    EXPECT_TRUE(partial.color == full.color);
    std::vector<TraceFragment> restricted;
    for (const TraceFragment& f : all.fragments())
        if (f.x >= region.x0 && f.x <= region.x1 && f.y >= region.y0 && f.y <= region.y1)
            restricted.push_back(f);
    EXPECT_GT(restricted.size(), 1000u);
    expectSameFragments(part.fragments(), restricted, "region");
    EXPECT_EQ(part.overdraw(), all.overdraw());
    // A pixel in the middle of the particles has several, in draw then primitive order.
    const auto h = all.pixelHistory(160, 100);
    ASSERT_GE(h.size(), 2u);
    for (size_t i = 1; i < h.size(); ++i)
        EXPECT_TRUE(h[i - 1].draw < h[i].draw ||
                    (h[i - 1].draw == h[i].draw && h[i - 1].primitive <= h[i].primitive))
            << describe(h[i - 1]) << " then " << describe(h[i]);
}

// ---- Geometry records -----------------------------------------------------------------------------------

TEST(TraceGeometry, ParticlesBecomeRectangles) {
    constexpr uint32_t kCount = 300;
    const SceneOptions o{.width = 320, .height = 180, .count = kCount};
    auto scene = makeScene("particles", o);
    Context ctx;
    Trace trace;
    ctx.setTrace(&trace);
    renderFrame(*scene, ctx, o);
    ASSERT_EQ(trace.draws().size(), 2u);

    const TraceDraw& occluder = trace.draws()[0];
    EXPECT_EQ(occluder.draw, 0u);
    EXPECT_TRUE(occluder.geometryShader.empty());
    EXPECT_EQ(occluder.verticesTotal, 6u);
    EXPECT_EQ(occluder.primitivesTotal, 2u);
    EXPECT_EQ(occluder.gsVerticesTotal, 0u);
    EXPECT_EQ(occluder.topology, Topology::TriangleList);
    ASSERT_EQ(occluder.primitives.size(), 2u);
    for (uint32_t i = 0; i < 2; ++i) {
        EXPECT_EQ(occluder.primitives[i].primitive, i);
        EXPECT_EQ(occluder.primitives[i].fate, PrimitiveFate::Rasterized);
        EXPECT_EQ(occluder.primitives[i].vertexCount, 3u);
        EXPECT_FALSE(occluder.primitives[i].clipped);
    }

    const TraceDraw& d = trace.draws()[1];
    EXPECT_EQ(d.draw, 1u);
    EXPECT_FALSE(d.skipped);
    EXPECT_FALSE(d.geometryShader.empty());
    EXPECT_EQ(d.topology, Topology::PointList);
    EXPECT_TRUE(d.blend.target(0).blendEnable);
    EXPECT_FALSE(d.depthStencil.depthWriteMask);
    ASSERT_EQ(d.inputFields.size(), 1u);
    EXPECT_EQ(d.inputFields[0].name, "POSITION");
    EXPECT_EQ(d.inputFields[0].offset, 0u);
    EXPECT_EQ(d.inputFields[0].components, 3u);
    EXPECT_EQ(d.vsFloats, 4u);
    EXPECT_EQ(d.gsFloats, 6u);  // position and tex
    EXPECT_EQ(d.verticesTotal, kCount);
    EXPECT_EQ(d.gsVerticesTotal, 4 * kCount);
    EXPECT_EQ(d.primitivesTotal, kCount);
    ASSERT_EQ(d.vertices.size(), kCount);
    ASSERT_EQ(d.gsVertices.size(), 4 * kCount);
    ASSERT_EQ(d.primitives.size(), kCount);
    for (uint32_t i = 0; i < kCount; ++i) {
        const TraceVertex& v = d.vertices[i];
        const glm::vec3 p = particlePosition(i);
        EXPECT_EQ(v.index, i);
        EXPECT_EQ(v.instance, 0u);
        ASSERT_EQ(v.input.size(), 3u);
        EXPECT_EQ(glm::vec3(v.input[0], v.input[1], v.input[2]), p) << i;
        ASSERT_EQ(v.output.size(), 4u);
        EXPECT_EQ(glm::vec4(v.output[0], v.output[1], v.output[2], v.output[3]), glm::vec4(p, 1.0f)) << i;
        for (uint32_t k = 0; k < 4; ++k) {
            EXPECT_EQ(d.gsVertices[4 * i + k].primitive, i);
            EXPECT_EQ(d.gsVertices[4 * i + k].startsStrip, k == 0);
        }
        const TracePrimitive& r = d.primitives[i];
        EXPECT_EQ(r.primitive, i);
        EXPECT_EQ(r.fate, PrimitiveFate::Rectangle) << i;
        EXPECT_EQ(r.vertexCount, 4u);
        EXPECT_FALSE(r.clipped);
    }
    // Particle 0 sits at the origin; its first corner is SCENES.md's camera applied to it, offset by
    // the billboard's half-size, with texture coordinate (1, 0).
    const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(60.0f), 320.0f / 180.0f, 0.1f, 100.0f);
    const glm::mat4 view = glm::lookAtRH(glm::vec3(0, 0.3f, 4), glm::vec3(0), glm::vec3(0, 1, 0));
    const glm::vec4 c = proj * view * glm::vec4(0, 0, 0, 1);
    const std::vector<float> corner = {c.x + 0.08f * proj[0][0], c.y + 0.08f * proj[1][1], c.z, c.w, 1, 0};
    const std::vector<float>& got = d.gsVertices[0].values;
    ASSERT_EQ(got.size(), 6u);
    for (size_t k = 0; k < 6; ++k) EXPECT_NEAR(got[k], corner[k], 1e-5f) << k;
    // Its rectangle's corners in pixels: the centre of the target, 0.08·P11·90/w pixels each way.
    const TracePrimitive& r = d.primitives[0];
    const float half = 0.08f * proj[1][1] * 90.0f / c.w;
    const float cy = (1 - c.y / c.w) * 90.0f;
    float x0 = 1e9f, x1 = -1e9f, y0 = 1e9f, y1 = -1e9f;
    for (int k = 0; k < 4; ++k) {
        x0 = std::min(x0, r.screen[k].x), x1 = std::max(x1, r.screen[k].x);
        y0 = std::min(y0, r.screen[k].y), y1 = std::max(y1, r.screen[k].y);
        EXPECT_NEAR(r.screen[k].z, c.z / c.w, 1e-6f);
        EXPECT_NEAR(r.screen[k].w, c.w, 1e-5f);
    }
    EXPECT_NEAR(x0, 160 - half, 0.01f);
    EXPECT_NEAR(x1, 160 + half, 0.01f);
    EXPECT_NEAR(y0, cy - half, 0.01f);
    EXPECT_NEAR(y1, cy + half, 0.01f);
    EXPECT_TRUE(d.stats == ctx.drawStatisticsLog()[1]);
    EXPECT_EQ(d.stats.rectanglesRecognized, kCount);

    const std::string text = formatDraw(d, 2);
    EXPECT_NE(text.find("vertex shader: " + std::to_string(kCount) + " invocations"), std::string::npos)
        << text;
    EXPECT_NE(text.find("geometry shader output: " + std::to_string(4 * kCount) + " vertices"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("prim 1 rectangle"), std::string::npos) << text;
    EXPECT_EQ(text.find("prim 2 rectangle"), std::string::npos) << "limit 2 shows primitives 0 and 1 only\n"
                                                                << text;
}

TEST(TraceGeometry, RecordsAreCappedButCounted) {
    constexpr uint32_t kCount = 2000, kCap = 100;
    const SceneOptions o{.width = 320, .height = 180, .count = kCount};
    auto scene = makeScene("particles", o);
    Context ctx({.threads = 8});  // several chunks of primitives
    Trace trace({.maxGeometryRecords = kCap});
    ctx.setTrace(&trace);
    renderFrame(*scene, ctx, o);
    ASSERT_EQ(trace.draws().size(), 2u);
    const TraceDraw& d = trace.draws()[1];
    EXPECT_EQ(d.verticesTotal, kCount);
    EXPECT_EQ(d.gsVerticesTotal, 4 * kCount);
    EXPECT_EQ(d.primitivesTotal, kCount);
    ASSERT_EQ(d.vertices.size(), kCap);
    ASSERT_EQ(d.gsVertices.size(), kCap);
    ASSERT_EQ(d.primitives.size(), kCap);
    // The first records, in API order.
    for (uint32_t i = 0; i < kCap; ++i) {
        EXPECT_EQ(d.vertices[i].index, i);
        EXPECT_EQ(d.gsVertices[i].primitive, i / 4);
        EXPECT_EQ(d.primitives[i].primitive, i);
    }
    ASSERT_EQ(d.primitiveVertices.size(), kCap);  // a point each
    EXPECT_EQ(d.primitiveVertices[kCap - 1], kCap - 1);
    EXPECT_EQ(d.primitivesPerInstance, kCount);

    // geometry = false keeps none (but the statistics).
    Trace bare({.geometry = false});
    ctx.setTrace(&bare);
    renderFrame(*scene, ctx, o);
    ASSERT_EQ(bare.draws().size(), 2u);
    EXPECT_TRUE(bare.draws()[1].vertices.empty());
    EXPECT_TRUE(bare.draws()[1].gsVertices.empty());
    EXPECT_TRUE(bare.draws()[1].primitives.empty());
    EXPECT_EQ(bare.draws()[1].stats.gsInvocations, kCount);
}

// Each input primitive's vertices are the buffer indices the input assembler fetched: the index
// buffer's from startIndex on, plus baseVertex, instance by instance; a point list's are its vertices.
TEST(TraceGeometry, PrimitiveVerticesAreTheIndexBuffersPlusTheBaseVertex) {
    Target8 t;
    const std::vector<glm::vec4> corners = {{-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}, {1, 1, 0.5f, 1},
                                            {-1, 1, 0.5f, 1},  {0, 0, 0.5f, 1},  {0, 1, 0.5f, 1}};
    const VertexBuffer vertices = VertexBuffer::create(corners);
    const IndexBuffer indices = IndexBuffer::create(std::vector<uint32_t>{9, 9, 9, 2, 0, 1, 3, 4, 2});
    t.ctx.setVertexBuffer(0, &vertices);
    t.ctx.setIndexBuffer(&indices);
    Trace trace;
    t.ctx.setTrace(&trace);
    t.ctx.drawIndexedInstanced(VsClip{}, PsConstant{kRed}, 6, 2, 3, 1);  // indices 3..8, base vertex 1
    t.ctx.draw(VsClip{}, PsConstant{kRed}, 3);
    ASSERT_EQ(trace.draws().size(), 2u);
    const TraceDraw& d = trace.draws()[0];
    EXPECT_EQ(d.verticesPerPrimitive, 3u);
    EXPECT_EQ(d.primitivesPerInstance, 2u);
    EXPECT_EQ(d.primitiveVertices, (std::vector<uint32_t>{3, 1, 2, 4, 5, 3, 3, 1, 2, 4, 5, 3}));
    EXPECT_EQ(trace.draws()[1].primitiveVertices, (std::vector<uint32_t>{0, 1, 2}));
    t.ctx.setPrimitiveTopology(Topology::PointList);
    trace.clear();
    t.ctx.draw(VsClip{}, PsConstant{kRed}, 4, 1);
    ASSERT_EQ(trace.draws().size(), 1u);
    EXPECT_EQ(trace.draws()[0].verticesPerPrimitive, 1u);
    EXPECT_EQ(trace.draws()[0].primitiveVertices, (std::vector<uint32_t>{1, 2, 3, 4}));
}

TEST(TraceGeometry, ReferencePipelineKeepsBillboardsAsTwoTriangles) {
    constexpr uint32_t kCount = 200;
    const SceneOptions o{.width = 96, .height = 54, .count = kCount};
    auto scene = makeScene("particles", o);
    Context ctx({.reference = true});
    Trace trace;
    ctx.setTrace(&trace);
    renderFrame(*scene, ctx, o);
    ASSERT_EQ(trace.draws().size(), 2u);
    const TraceDraw& d = trace.draws()[1];
    EXPECT_EQ(d.verticesTotal, kCount);
    EXPECT_EQ(d.gsVerticesTotal, 4 * kCount);
    EXPECT_EQ(d.primitivesTotal, 2 * kCount);
    ASSERT_EQ(d.primitives.size(), 2 * kCount);
    for (uint32_t i = 0; i < 2 * kCount; ++i) {
        EXPECT_EQ(d.primitives[i].primitive, i / 2);
        EXPECT_EQ(d.primitives[i].fate, PrimitiveFate::Rasterized) << i;
        EXPECT_EQ(d.primitives[i].vertexCount, 3u);
    }
    EXPECT_EQ(d.stats.rectanglesRecognized, 0u);
    EXPECT_EQ(d.stats.gsPrimitives, 2 * kCount);
}

TEST(TraceGeometry, PrimitiveFates) {
    Target8 t;
    RasterizerState back;  // cull back faces; clockwise on screen is front
    t.ctx.setRasterizerState(back);
    const std::vector<glm::vec4> v = {
        // 0: front-facing, on screen.
        at(1, 1, 0.5f),
        at(6, 1, 0.5f),
        at(1, 6, 0.5f),
        // 1: behind the camera (w < 0).
        {0, 0, 0.5f, -1},
        {0.5f, 0, 0.5f, -1},
        {0, 0.5f, 0.5f, -1},
        // 2: back-facing (counter-clockwise on screen).
        at(1, 1, 0.5f),
        at(1, 6, 0.5f),
        at(6, 1, 0.5f),
        // 3: a NaN vertex.
        at(1, 1, 0.5f),
        {kNaN, 0, 0.5f, 1},
        at(1, 6, 0.5f),
        // 4: crossing the near plane (one vertex at z < 0).
        at(1, 1, -0.5f),
        at(6, 1, 0.5f),
        at(1, 6, 0.5f),
        // 5: wholly right of the target.
        {2, 0, 0.5f, 1},
        {3, 0, 0.5f, 1},
        {2, -1, 0.5f, 1},
        // 6: between pixel centres.
        at(1.6f, 1.6f, 0.5f),
        at(1.9f, 1.6f, 0.5f),
        at(1.6f, 1.9f, 0.5f),
        // 7: zero area.
        at(1, 1, 0.5f),
        at(3, 3, 0.5f),
        at(5, 5, 0.5f),
    };
    Trace trace;
    t.ctx.setTrace(&trace);
    t.draw(PsConstant{kRed}, v);
    ASSERT_EQ(trace.draws().size(), 1u);
    const TraceDraw& d = trace.draws()[0];
    EXPECT_EQ(d.verticesTotal, v.size());
    ASSERT_EQ(d.vertices.size(), v.size());
    EXPECT_EQ(d.vertices[15].output[0], 2.0f) << "the vertex shader's output, x of vertex 15";
    std::vector<std::vector<const TracePrimitive*>> byInput(8);
    for (const TracePrimitive& p : d.primitives) {
        ASSERT_LT(p.primitive, 8u);
        byInput[p.primitive].push_back(&p);
    }
    auto fateOf = [&](uint32_t i) {
        EXPECT_EQ(byInput[i].size(), 1u) << "primitive " << i;
        return byInput[i].empty() ? PrimitiveFate(255) : byInput[i][0]->fate;
    };
    EXPECT_EQ(fateOf(0), PrimitiveFate::Rasterized);
    EXPECT_EQ(fateOf(1), PrimitiveFate::Outside);
    EXPECT_EQ(fateOf(2), PrimitiveFate::Culled);
    EXPECT_EQ(fateOf(3), PrimitiveFate::NonFinite);
    EXPECT_EQ(fateOf(5), PrimitiveFate::Outside);
    EXPECT_EQ(fateOf(6), PrimitiveFate::NoPixels);
    EXPECT_EQ(fateOf(7), PrimitiveFate::Degenerate);
    EXPECT_FALSE(byInput[0][0]->clipped);
    // The clipped triangle: a quadrilateral after the cut, drawn as two triangles, both marked clipped.
    ASSERT_EQ(byInput[4].size(), 2u);
    for (const TracePrimitive* p : byInput[4]) {
        EXPECT_TRUE(p->clipped);
        EXPECT_EQ(p->fate, PrimitiveFate::Rasterized);
        for (int k = 0; k < 3; ++k) EXPECT_GE(p->screen[k].z, 0.0f) << "cut at the near plane";
    }
    // Primitive 0's screen vertices in pixels.
    const TracePrimitive& p0 = *byInput[0][0];
    EXPECT_EQ(p0.vertexCount, 3u);
    EXPECT_EQ(p0.screen[0], glm::vec4(1, 1, 0.5f, 1));
    EXPECT_EQ(p0.screen[1], glm::vec4(6, 1, 0.5f, 1));
    EXPECT_EQ(p0.screen[2], glm::vec4(1, 6, 0.5f, 1));
    // The statistics say the same.
    EXPECT_EQ(d.stats.primitivesOutside, 2u);
    EXPECT_EQ(d.stats.primitivesCulled, 1u);
    EXPECT_EQ(d.stats.primitivesNonFinite, 1u);
    EXPECT_EQ(d.stats.primitivesClipped, 1u);
    EXPECT_EQ(d.stats.primitivesNoPixels, 1u);
    EXPECT_EQ(d.stats.primitivesDegenerate, 1u);
    EXPECT_EQ(d.stats.cInvocations, 8u);
}

// ---- Statistics -----------------------------------------------------------------------------------------

TEST(TraceStatistics, ParticlesCountOneGeometryShaderRunPerParticle) {
    constexpr uint32_t kCount = 500;
    const SceneOptions o{.width = 320, .height = 180, .count = kCount};
    auto scene = makeScene("particles", o);
    Context ctx;
    Trace trace;
    ctx.setTrace(&trace);
    renderFrame(*scene, ctx, o);
    const auto& log = ctx.drawStatisticsLog();
    ASSERT_EQ(log.size(), 2u);
    EXPECT_EQ(log[0].gsInvocations, 0u);
    EXPECT_EQ(log[0].iaPrimitives, 2u);
    EXPECT_EQ(log[1].iaVertices, kCount);
    EXPECT_EQ(log[1].gsInvocations, kCount);
    EXPECT_EQ(log[1].gsPrimitives, 2 * kCount);
    EXPECT_EQ(log[1].rectanglesRecognized, kCount);
    PipelineStatistics sum = log[0];
    sum += log[1];
    EXPECT_TRUE(ctx.frameStatistics() == sum);
    ASSERT_EQ(trace.draws().size(), 2u);
    EXPECT_TRUE(trace.draws()[0].stats == log[0]);
    EXPECT_TRUE(trace.draws()[1].stats == log[1]);
}

TEST(TraceStatistics, FullyOccludedQuadRunsNoShader) {
    for (const bool reference : {false, true}) {
        for (const bool traced : {true, false}) {
            const std::string what =
                std::string(reference ? "reference" : "fast") + (traced ? ", traced" : "");
            Target8 t({.reference = reference});
            Trace trace({.pixels = TraceOptions::everything()});
            if (traced) t.ctx.setTrace(&trace);
            t.draw(PsConstant{kRed}, wholeTarget(0.25f));
            EXPECT_EQ(t.ctx.drawStatistics().psInvocations, 64u) << what;
            t.draw(PsConstant{kGreen}, wholeTarget(0.5f));
            const PipelineStatistics& s = t.ctx.drawStatistics();
            EXPECT_EQ(s.psInvocations, reference ? 64u : 0u) << what;
            EXPECT_EQ(s.fragmentsLateDepthKilled, reference ? 64u : 0u) << what;
            EXPECT_EQ(s.fragmentsDiscarded + s.fragmentsBlendNoOp, 0u) << what;
            for (uint32_t y = 0; y < 8; ++y)
                for (uint32_t x = 0; x < 8; ++x) EXPECT_EQ(t.color.load(x, y), kRed) << what;
            if (!traced) continue;
            // Traced, every fragment goes through the depth test and is counted and recorded.
            EXPECT_EQ(s.fragmentsEarlyDepthKilled, reference ? 0u : 64u) << what;
            size_t failed = 0;
            for (const TraceFragment& f : trace.fragments()) {
                if (f.draw != 1) continue;
                ++failed;
                EXPECT_EQ(f.fate, reference ? FragmentFate::LateDepthFailed : FragmentFate::EarlyDepthFailed);
                EXPECT_EQ(f.shaded, reference);
            }
            EXPECT_EQ(failed, 64u) << what;
        }
    }
}

TEST(TraceStatistics, LogHasAnEntryForSkippedAndEmptyDraws) {
    Target8 t;
    Trace trace({.pixels = TraceOptions::everything()});
    t.ctx.setTrace(&trace);
    t.ctx.resetFrameStatistics();
    t.ctx.setStepLimit({.draws = 2});
    t.draw(PsConstant{kRed}, wholeTarget(0.5f));     // 0: runs
    t.draw(PsConstant{kGreen}, {});                  // 1: empty
    t.draw(PsConstant{kGreen}, wholeTarget(0.25f));  // 2: skipped by the step limit
    EXPECT_EQ(t.ctx.drawCount(), 3u);
    const auto& log = t.ctx.drawStatisticsLog();
    ASSERT_EQ(log.size(), 3u);
    EXPECT_EQ(log[0].iaVertices, 6u);
    EXPECT_EQ(log[0].psInvocations, 64u);
    EXPECT_TRUE(log[1] == PipelineStatistics{}) << log[1].toString();
    EXPECT_TRUE(log[2] == PipelineStatistics{}) << log[2].toString();
    EXPECT_TRUE(t.ctx.frameStatistics() == log[0]);
    ASSERT_EQ(trace.draws().size(), 3u);
    EXPECT_FALSE(trace.draws()[0].skipped);
    EXPECT_FALSE(trace.draws()[1].skipped);
    EXPECT_EQ(trace.draws()[1].verticesTotal, 0u);
    EXPECT_TRUE(trace.draws()[2].skipped);
    EXPECT_EQ(trace.draws()[2].verticesTotal, 0u);
    EXPECT_NE(formatDraw(trace.draws()[2], 4).find("skipped"), std::string::npos);
    // The skipped draw left the pixels (and recorded no fragment).
    EXPECT_EQ(t.color.load(3, 3), kRed);
    EXPECT_EQ(t.depth.load(3, 3), 0.5f);
    for (const TraceFragment& f : trace.fragments()) EXPECT_EQ(f.draw, 0u);
    EXPECT_EQ(trace.fragments().size(), 64u);
    // A reset starts the numbering again: draw 0 runs.
    t.ctx.resetFrameStatistics();
    EXPECT_EQ(t.ctx.drawCount(), 0u);
    EXPECT_TRUE(t.ctx.drawStatisticsLog().empty());
    t.draw(PsConstant{kGreen}, wholeTarget(0.25f));
    EXPECT_EQ(t.ctx.drawStatisticsLog().size(), 1u);
    EXPECT_EQ(t.color.load(3, 3), kGreen);
}

// ---- Stepping -------------------------------------------------------------------------------------------

TEST(TraceStepping, ForwardsAndBackReachTheSameImages) {
    constexpr uint32_t kCount = 500;
    const SceneOptions o{.width = 320, .height = 180, .count = kCount};
    auto scene = makeScene("particles", o);
    Context ctx;
    const Frame whole = renderFrame(*scene, ctx, o);
    auto stepped = [&](Context::StepLimit limit) {
        ctx.setStepLimit(limit);
        return renderFrame(*scene, ctx, o);
    };
    // Draw 0 (the occluder's two triangles), primitive by primitive.
    Frame cleared{RenderTarget(o.width, o.height), DepthTarget(o.width, o.height)};
    cleared.color.clear({0, 0, 0, 1});
    cleared.depth.clear(1.0f);
    std::vector<Frame> occluder;
    for (uint64_t k = 0; k <= 3; ++k) occluder.push_back(stepped({1, k}));
    EXPECT_TRUE(occluder[0].color == cleared.color) << "no primitive drawn";
    EXPECT_TRUE(occluder[0].depth == cleared.depth);
    EXPECT_FALSE(occluder[1].color == occluder[0].color);
    EXPECT_FALSE(occluder[2].color == occluder[1].color);
    EXPECT_TRUE(occluder[3].color == occluder[2].color) << "the occluder has two primitives";
    const Frame noParticles = stepped({2, 0});
    EXPECT_TRUE(noParticles.color == occluder[2].color);
    EXPECT_TRUE(noParticles.depth == occluder[2].depth);
    // Forwards to {2, 5}, back to {2, 3}: the same as {2, 3} fresh.
    const Frame three = stepped({2, 3});
    const Frame five = stepped({2, 5});
    const Frame backToThree = stepped({2, 3});
    EXPECT_FALSE(five.color == three.color);
    EXPECT_TRUE(backToThree.color == three.color);
    EXPECT_TRUE(backToThree.depth == three.depth);
    Context fresh;
    fresh.setStepLimit({2, 3});
    const Frame freshThree = renderFrame(*scene, fresh, o);
    EXPECT_TRUE(freshThree.color == three.color);
    // Every particle, or no limit at all: the plain frame.
    EXPECT_TRUE(stepped({2, kCount}).color == whole.color);
    EXPECT_TRUE(stepped({3, 0}).color == whole.color);
    const Frame unlimited = stepped({});
    EXPECT_TRUE(unlimited.color == whole.color);
    EXPECT_TRUE(unlimited.depth == whole.depth);
    EXPECT_FALSE(stepped({2, kCount - 1}).color == whole.color) << "the last particle is on screen";
}

TEST(TraceStepping, StageByStageRunsTheStagesUpToTheLimit) {
    using Stage = Context::Stage;
    constexpr uint32_t kCount = 300;
    const SceneOptions o{.width = 320, .height = 180, .count = kCount};
    auto scene = makeScene("particles", o);
    Context ctx;
    const Frame whole = renderFrame(*scene, ctx, o);
    ctx.setStepLimit({1});
    const Frame occluder = renderFrame(*scene, ctx, o);  // draw 0 only
    ASSERT_FALSE(occluder.color == whole.color);
    struct Run {
        Frame frame{RenderTarget(1, 1), DepthTarget(1, 1)};
        PipelineStatistics particles;  // draw 1's statistics
        Trace trace{TraceOptions{.geometry = true}};
    };
    auto run = [&](Context::StepLimit limit) {
        auto r = std::make_unique<Run>();
        ctx.setStepLimit(limit);
        ctx.setTrace(&r->trace);
        r->frame = renderFrame(*scene, ctx, o);
        ctx.setTrace(nullptr);
        EXPECT_EQ(ctx.drawStatisticsLog().size(), 2u);
        if (ctx.drawStatisticsLog().size() == 2) r->particles = ctx.drawStatisticsLog()[1];
        return r;
    };
    // Up to the vertex shader: every point shaded, nothing after; no pixel of draw 1 written.
    const auto vs = run({2, UINT64_MAX, Stage::VertexShader});
    EXPECT_EQ(vs->particles.vsInvocations, kCount);
    EXPECT_EQ(vs->particles.gsInvocations, 0u);
    EXPECT_EQ(vs->particles.cInvocations, 0u);
    EXPECT_EQ(vs->particles.psInvocations, 0u);
    EXPECT_TRUE(vs->frame.color == occluder.color);
    EXPECT_TRUE(vs->frame.depth == occluder.depth);
    ASSERT_EQ(vs->trace.draws().size(), 2u);
    EXPECT_EQ(vs->trace.draws()[1].verticesTotal, kCount);
    EXPECT_EQ(vs->trace.draws()[1].gsVerticesTotal, 0u);
    // Up to the geometry shader: two triangles per point, none clipped or set up.
    const auto gs = run({2, UINT64_MAX, Stage::GeometryShader});
    EXPECT_EQ(gs->particles.gsInvocations, kCount);
    EXPECT_EQ(gs->particles.gsPrimitives, 2 * kCount);
    EXPECT_EQ(gs->particles.cInvocations, 0u);
    EXPECT_EQ(gs->particles.psInvocations, 0u);
    EXPECT_TRUE(gs->frame.color == occluder.color);
    EXPECT_EQ(gs->trace.draws()[1].gsVerticesTotal, 4 * kCount);
    EXPECT_EQ(gs->trace.draws()[1].primitivesTotal, 0u);
    // Up to setup: clipped and set up (as rectangles), still no pixel.
    const auto setup = run({2, UINT64_MAX, Stage::Setup});
    EXPECT_EQ(setup->particles.gsPrimitives, 2 * kCount);
    EXPECT_EQ(setup->particles.cInvocations, 2 * kCount);
    EXPECT_GT(setup->particles.rectanglesRecognized, 0u);
    EXPECT_EQ(setup->particles.psInvocations, 0u);
    EXPECT_TRUE(setup->frame.color == occluder.color);
    EXPECT_TRUE(setup->frame.depth == occluder.depth);
    EXPECT_GT(setup->trace.draws()[1].primitivesTotal, 0u);
    // The whole pipeline: the plain frame, with the same geometry statistics as setup's.
    const auto om = run({2, UINT64_MAX, Stage::OutputMerger});
    EXPECT_TRUE(om->frame.color == whole.color);
    EXPECT_TRUE(om->frame.depth == whole.depth);
    EXPECT_GT(om->particles.psInvocations, 0u);
    EXPECT_EQ(om->particles.cInvocations, setup->particles.cInvocations);
    EXPECT_EQ(om->particles.rectanglesRecognized, setup->particles.rectanglesRecognized);
    // The stage applies to the step's own draw only: earlier draws run whole, and without `draws`
    // there is no step's draw.
    const auto occluder_vs = run({1, UINT64_MAX, Stage::VertexShader});
    Frame cleared{RenderTarget(o.width, o.height), DepthTarget(o.width, o.height)};
    cleared.color.clear({0, 0, 0, 1});
    EXPECT_TRUE(occluder_vs->frame.color == cleared.color) << "draw 0 stopped after its vertex shader";
    EXPECT_TRUE(run({UINT32_MAX, UINT64_MAX, Stage::VertexShader})->frame.color == whole.color);
    // Primitive and stage limits together: the first 10 particles up to the geometry shader.
    const auto ten = run({2, 10, Stage::GeometryShader});
    EXPECT_EQ(ten->particles.gsInvocations, 10u);
    EXPECT_EQ(ten->particles.gsPrimitives, 20u);
    EXPECT_EQ(ten->particles.cInvocations, 0u);
}

TEST(TraceStepping, PixelHistoryHasOnlyTheAllowedPrimitives) {
    constexpr uint32_t kCount = 500, kAllowed = 40;
    const SceneOptions o{.width = 320, .height = 180, .count = kCount};
    auto scene = makeScene("particles", o);
    Context ctx;
    Trace all({.pixels = TraceOptions::everything()});
    ctx.setTrace(&all);
    renderFrame(*scene, ctx, o);
    Trace limited({.pixels = TraceOptions::everything()});
    ctx.setTrace(&limited);
    ctx.setStepLimit({2, kAllowed});
    renderFrame(*scene, ctx, o);
    ASSERT_EQ(limited.draws().size(), 2u);
    EXPECT_EQ(limited.draws()[1].primitivesTotal, kAllowed);
    EXPECT_EQ(limited.draws()[1].stats.gsInvocations, kAllowed);
    bool particles = false;
    for (const TraceFragment& f : limited.fragments()) {
        if (f.draw == 1) {
            particles = true;
            EXPECT_LT(f.primitive, kAllowed) << describe(f);
        }
    }
    EXPECT_TRUE(particles);
    // The fragments of the allowed primitives are the whole frame's, field by field: a pixel's
    // fragments arrive in primitive order, so later primitives never change earlier records.
    std::vector<TraceFragment> allowed;
    for (const TraceFragment& f : all.fragments())
        if (f.draw == 0 || f.primitive < kAllowed) allowed.push_back(f);
    expectSameFragments(limited.fragments(), allowed, "step limit {2, 40}");
    // Skipping the particle draw leaves the occluder's records only.
    Trace occluderOnly({.pixels = TraceOptions::everything()});
    ctx.setTrace(&occluderOnly);
    ctx.setStepLimit({1});
    renderFrame(*scene, ctx, o);
    ASSERT_EQ(occluderOnly.draws().size(), 2u);
    EXPECT_TRUE(occluderOnly.draws()[1].skipped);
    std::vector<TraceFragment> first;
    for (const TraceFragment& f : all.fragments())
        if (f.draw == 0) first.push_back(f);
    expectSameFragments(occluderOnly.fragments(), first, "step limit {1}");
}

}  // namespace
}  // namespace raster
