// The geometry shader stage: output streams, strips cut into primitives, the lecture's billboard
// shader through the whole pipeline, and the errors a geometry shader can cause.
#include "raster/stages/3_geometry_shader.hpp"

#include <gtest/gtest.h>

#include <array>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "raster/check.hpp"
#include "raster/pipeline.hpp"
#include "raster/shaders/basic.hpp"
#include "lecture/fire_shaders.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shaders/billboard.hpp"

namespace raster {
namespace {

using shaders::BillboardCorner;
using shaders::GsBillboard;
using shaders::PositionOnly;
using shaders::PsConstant;
using shaders::VsBillboard;
using shaders::VsTransform;

const glm::vec4 kClear(0.1f, 0.2f, 0.3f, 1.0f);
const glm::vec4 kWhite(1.0f);

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

// A pixel position (x right, y down, in pixels) of a W×H viewport as a clip-space point with w = 1.
glm::vec3 ndcOf(float px, float py, float w, float h, float z = 0.5f) {
    return {px / w * 2.0f - 1.0f, 1.0f - py / h * 2.0f, z};
}

// Context, targets and a one-slot vec3 "POSITION" layout.
struct Fixture {
    Context ctx;
    RenderTarget color;
    DepthTarget depth;
    InputLayout layout;
    VertexBuffer vb;
    Fixture(uint32_t w, uint32_t h, Format format = Format::R8G8B8A8_UNORM) : color(w, h, format), depth(w, h) {
        color.clear(kClear);
        depth.clear(1.0f);
        ctx.setRenderTargets(&color, &depth);
        ctx.setViewport({0, 0, float(w), float(h), 0, 1});
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
        layout = InputLayout(desc);
        ctx.setInputLayout(&layout);
    }
    void setVertices(const std::vector<glm::vec3>& v) {
        vb = VertexBuffer::create(v);
        ctx.setVertexBuffer(0, &vb);
    }
    std::vector<std::pair<int, int>> paintedPixels(const glm::vec4& c) const {
        std::vector<std::pair<int, int>> p;
        for (uint32_t y = 0; y < color.height(); ++y)
            for (uint32_t x = 0; x < color.width(); ++x)
                if (color.load(x, y) == c) p.push_back({int(x), int(y)});
        return p;
    }
};

// ---- OutputStream and strip cutting --------------------------------------------------------------

PositionOnly tagged(float id) { return {glm::vec4(id, 0.0f, 0.0f, 1.0f)}; }

TEST(OutputStream, NeverWritesPastItsCapacity) {
    TriangleStream<PositionOnly, 4> stream;
    EXPECT_EQ(stream.size(), 0);
    for (int i = 0; i < 10; ++i) stream.Append(tagged(float(i)));
    EXPECT_EQ(stream.size(), 4);
    EXPECT_EQ(stream.overflow(), 6);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(stream.vertex(i).position.x, float(i)) << "the first four are kept";
    // A cut requested on a full stream does not make room either.
    stream.RestartStrip();
    stream.Append(tagged(99));
    EXPECT_EQ(stream.size(), 4);
    EXPECT_EQ(stream.overflow(), 7);
    stream.reset();
    EXPECT_EQ(stream.size(), 0);
    EXPECT_EQ(stream.overflow(), 0);
    stream.Append(tagged(5));
    EXPECT_TRUE(stream.startsStrip(0));
    EXPECT_EQ(stream.vertex(0).position.x, 5.0f);
    static_assert(TriangleStream<PositionOnly, 4>::kMaxVertices == 4);
    static_assert(LineStream<PositionOnly, 7>::kKind == PrimitiveKind::Line);
}

TEST(OutputStream, RestartStripMarksTheNextVertex) {
    PointStream<PositionOnly, 8> stream;
    stream.RestartStrip();  // before anything: vertex 0 starts a strip anyway
    stream.Append(tagged(0));
    stream.Append(tagged(1));
    stream.RestartStrip();
    stream.RestartStrip();  // twice is once
    stream.Append(tagged(2));
    stream.Append(tagged(3));
    EXPECT_TRUE(stream.startsStrip(0));
    EXPECT_FALSE(stream.startsStrip(1));
    EXPECT_TRUE(stream.startsStrip(2));
    EXPECT_FALSE(stream.startsStrip(3));
    // reset() forgets a pending cut.
    stream.RestartStrip();
    stream.reset();
    stream.Append(tagged(0));
    stream.Append(tagged(1));
    EXPECT_FALSE(stream.startsStrip(1));
}

// Appends `lengths[k]` vertices per strip, tagged 0, 1, 2, ... in order, with a RestartStrip between strips.
template <class Stream>
struct GsStrips {
    std::vector<int> lengths;
    void operator()(const Point<PositionOnly>&, Stream& out) const {
        int id = 0;
        for (size_t s = 0; s < lengths.size(); ++s) {
            if (s > 0) out.RestartStrip();
            for (int i = 0; i < lengths[s]; ++i) out.Append(tagged(float(id++)));
        }
    }
};

template <class Stream>
std::vector<std::vector<int>> emitted(const std::vector<int>& lengths) {
    GsStrips<Stream> gs{lengths};
    Stream stream;
    std::vector<std::vector<int>> prims;
    const std::array<PositionOnly, 1> in = {tagged(-1)};
    const int overflow = runGeometryShader(gs, in, stream, [&](PrimitiveKind kind, const PositionOnly* const* v) {
        EXPECT_EQ(kind, Stream::kKind);
        std::vector<int> ids;
        for (int k = 0; k < int(kind); ++k) ids.push_back(int(v[k]->position.x));
        prims.push_back(ids);
    });
    EXPECT_EQ(overflow, 0);
    return prims;
}

TEST(GeometryShaderStage, TriangleStripsAlternateWinding) {
    using S = TriangleStream<PositionOnly, 16>;
    const std::vector<std::vector<int>> one = {{0, 1, 2}, {1, 3, 2}, {2, 3, 4}, {3, 5, 4}};
    EXPECT_EQ(emitted<S>({6}), one);
    // Two strips: each starts even again.
    const std::vector<std::vector<int>> two = {{0, 1, 2}, {3, 4, 5}, {4, 6, 5}};
    EXPECT_EQ(emitted<S>({3, 4}), two);
    // Strips too short for a triangle give nothing.
    EXPECT_TRUE(emitted<S>({2, 1, 2}).empty());
    const std::vector<std::vector<int>> middle = {{2, 3, 4}};
    EXPECT_EQ(emitted<S>({2, 3, 1}), middle);
}

TEST(GeometryShaderStage, LineAndPointStrips) {
    const std::vector<std::vector<int>> lines = {{0, 1}, {1, 2}, {4, 5}};
    EXPECT_EQ((emitted<LineStream<PositionOnly, 8>>({3, 1, 2})), lines);
    const std::vector<std::vector<int>> points = {{0}, {1}, {2}, {3}};
    EXPECT_EQ((emitted<PointStream<PositionOnly, 8>>({2, 1, 1})), points);
}

// ---- The lecture's billboard ----------------------------------------------------------------------

struct PsTexCoord {
    glm::vec4 operator()(const BillboardCorner& in) const { return glm::vec4(in.tex, 0.0f, 1.0f); }
};
struct PsWhiteCorner {
    glm::vec4 operator()(const BillboardCorner&) const { return kWhite; }
};

TEST(GeometryShader, BillboardCountsTwoTrianglesPerPoint) {
    Fixture f(64, 64);
    std::vector<glm::vec3> points;
    for (int i = 0; i < 7; ++i) points.push_back({-0.8f + 0.25f * float(i), 0.1f * float(i % 3), 0.5f});
    f.setVertices(points);
    f.ctx.setPrimitiveTopology(Topology::PointList);
    GsBillboard gs;
    gs.billboardSize = {0.05f, 0.05f};
    f.ctx.draw(VsBillboard{}, gs, PsTexCoord{}, 7);
    const PipelineStatistics& s = f.ctx.drawStatistics();
    EXPECT_EQ(s.iaPrimitives, 7u);
    EXPECT_EQ(s.vsInvocations, 7u);
    EXPECT_EQ(s.gsInvocations, 7u);
    EXPECT_EQ(s.gsPrimitives, 14u);
    EXPECT_EQ(s.cInvocations, 14u);
    EXPECT_EQ(s.primitivesCulled, 0u) << "both triangles of the strip face the camera";
}

TEST(GeometryShader, BillboardCoversTheExpectedRectangle) {
    // Identity viewProj: the centre (0, 0, 0.5) stays at NDC (0, 0); the corners are at
    // x = ±0.25, y = ±0.125, i.e. on a 64×64 viewport x in [24, 40] and y in [28, 36] pixels. Pixel
    // centres inside: columns 24..39 and rows 28..35. u grows to the right (+bx has u = 1), v grows
    // downwards (+by, the top, has v = 0).
    Fixture f(64, 64, Format::R32G32B32A32_FLOAT);
    f.setVertices({{0.0f, 0.0f, 0.5f}});
    f.ctx.setPrimitiveTopology(Topology::PointList);
    GsBillboard gs;
    gs.billboardSize = {0.25f, 0.125f};
    f.ctx.draw(VsBillboard{}, gs, PsTexCoord{}, 1);  // cull back (default)
    EXPECT_EQ(f.ctx.drawStatistics().gsPrimitives, 2u);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 16u * 8u);
    for (uint32_t y = 0; y < 64; ++y) {
        for (uint32_t x = 0; x < 64; ++x) {
            const bool inside = x >= 24 && x <= 39 && y >= 28 && y <= 35;
            const glm::vec4 c = f.color.load(x, y);
            if (!inside) {
                EXPECT_EQ(c, kClear) << "pixel " << x << "," << y << " is outside the billboard";
                continue;
            }
            EXPECT_NEAR(c.x, (float(x) + 0.5f - 24.0f) / 16.0f, 1e-5f) << x << "," << y;
            EXPECT_NEAR(c.y, (float(y) + 0.5f - 28.0f) / 8.0f, 1e-5f) << x << "," << y;
            EXPECT_EQ(f.depth.load(x, y), 0.5f);
        }
    }
}

TEST(GeometryShader, BillboardKeepsItsWorldSizeUnderPerspective) {
    // Clip w = 2: the corner offsets are divided by w like the centre, so the sprite is half as wide
    // on screen: x in [28, 36], y in [30, 34] on 64×64.
    Fixture f(64, 64);
    f.setVertices({{0.0f, 0.0f, 0.5f}});
    f.ctx.setPrimitiveTopology(Topology::PointList);
    GsBillboard gs;
    gs.viewProj = glm::mat4(1.0f);
    gs.viewProj[3][3] = 2.0f;  // w = 2 for w_in = 1
    gs.billboardSize = {0.25f, 0.125f};
    f.ctx.draw(VsBillboard{}, gs, PsWhiteCorner{}, 1);
    const auto painted = f.paintedPixels(kWhite);
    ASSERT_EQ(painted.size(), 8u * 4u);
    for (const auto& [x, y] : painted) {
        EXPECT_GE(x, 28);
        EXPECT_LE(x, 35);
        EXPECT_GE(y, 30);
        EXPECT_LE(y, 33);
    }
}

// ---- Custom geometry shaders through the pipeline -------------------------------------------------

// Per point: a quad strip (4 vertices, 2 triangles) and, after RestartStrip or not, a 3-vertex strip.
struct GsTwoStrips {
    bool restart = true;
    void operator()(const Point<PositionOnly>& in, TriangleStream<PositionOnly, 8>& out) const {
        const glm::vec4 c = in[0].position;
        auto at = [&](float dx, float dy) { return PositionOnly{c + glm::vec4(dx, dy, 0, 0)}; };
        out.Append(at(-0.2f, -0.2f)), out.Append(at(-0.2f, 0.0f)), out.Append(at(0.0f, -0.2f)),
            out.Append(at(0.0f, 0.0f));
        if (restart) out.RestartStrip();
        out.Append(at(0.1f, 0.0f)), out.Append(at(0.1f, 0.2f)), out.Append(at(0.3f, 0.0f));
    }
};

TEST(GeometryShader, RestartStripSplitsPrimitives) {
    Fixture f(32, 32);
    f.setVertices({{-0.5f, 0.0f, 0.5f}, {0.5f, 0.3f, 0.5f}});
    f.ctx.setPrimitiveTopology(Topology::PointList);
    RasterizerState none;
    none.cullMode = CullMode::None;
    f.ctx.setRasterizerState(none);
    f.ctx.draw(VsTransform{}, GsTwoStrips{true}, PsConstant{kWhite}, 2);
    EXPECT_EQ(f.ctx.drawStatistics().gsInvocations, 2u);
    EXPECT_EQ(f.ctx.drawStatistics().gsPrimitives, 2u * 3u);  // 2 + 1 per point
    f.ctx.draw(VsTransform{}, GsTwoStrips{false}, PsConstant{kWhite}, 2);
    EXPECT_EQ(f.ctx.drawStatistics().gsPrimitives, 2u * 5u);  // one strip of 7
}

// A line strip of two segments, (2, 4.5) → (10, 4.5) → (10, 12.5) in pixels of a 16×16 target.
struct GsLines {
    void operator()(const Point<PositionOnly>&, LineStream<PositionOnly, 4>& out) const {
        out.Append({glm::vec4(ndcOf(2.0f, 4.5f, 16, 16), 1.0f)});
        out.Append({glm::vec4(ndcOf(10.0f, 4.5f, 16, 16), 1.0f)});
        out.Append({glm::vec4(ndcOf(10.0f, 12.5f, 16, 16), 1.0f)});
    }
};

TEST(GeometryShader, EmitsLines) {
    Fixture f(16, 16);
    f.setVertices({{0, 0, 0.5f}});
    f.ctx.setPrimitiveTopology(Topology::PointList);
    f.ctx.draw(VsTransform{}, GsLines{}, PsConstant{kWhite}, 1);
    EXPECT_EQ(f.ctx.drawStatistics().gsPrimitives, 2u);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 16u);
    // Row 4, columns 2..9 (centres 2.5 .. 9.5 in [2, 10)); column 10, rows 4..11.
    std::vector<std::pair<int, int>> expected;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x)
            if ((y == 4 && x >= 2 && x <= 9) || (x == 10 && y >= 4 && y <= 11)) expected.push_back({x, y});
    EXPECT_EQ(f.paintedPixels(kWhite), expected);
}

struct GsPoints {
    void operator()(const Point<PositionOnly>&, PointStream<PositionOnly, 3>& out) const {
        out.Append({glm::vec4(ndcOf(5.5f, 6.5f, 16, 16), 1.0f)});
        out.Append({glm::vec4(ndcOf(0.5f, 0.5f, 16, 16), 1.0f)});
        out.Append({glm::vec4(ndcOf(15.5f, 15.5f, 16, 16), 1.0f)});
    }
};

TEST(GeometryShader, EmitsPoints) {
    Fixture f(16, 16);
    f.setVertices({{0, 0, 0.5f}});
    f.ctx.setPrimitiveTopology(Topology::PointList);
    f.ctx.draw(VsTransform{}, GsPoints{}, PsConstant{kWhite}, 1);
    EXPECT_EQ(f.ctx.drawStatistics().gsPrimitives, 3u);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 3u);
    const std::vector<std::pair<int, int>> expected = {{0, 0}, {5, 6}, {15, 15}};
    EXPECT_EQ(f.paintedPixels(kWhite), expected);
}

// Line input: each segment of a line strip becomes its two end points.
struct GsLineEnds {
    void operator()(const Line<PositionOnly>& in, PointStream<PositionOnly, 2>& out) const {
        out.Append(in[0]);
        out.Append(in[1]);
    }
};

TEST(GeometryShader, TakesLinesFromALineStrip) {
    Fixture f(16, 16);
    f.setVertices({ndcOf(1.5f, 1.5f, 16, 16), ndcOf(3.5f, 1.5f, 16, 16), ndcOf(3.5f, 7.5f, 16, 16),
                   ndcOf(9.5f, 7.5f, 16, 16)});
    f.ctx.setPrimitiveTopology(Topology::LineStrip);
    f.ctx.draw(VsTransform{}, GsLineEnds{}, PsConstant{kWhite}, 4);
    EXPECT_EQ(f.ctx.drawStatistics().gsInvocations, 3u);
    EXPECT_EQ(f.ctx.drawStatistics().gsPrimitives, 6u);
    const std::vector<std::pair<int, int>> expected = {{1, 1}, {3, 1}, {3, 7}, {9, 7}};
    EXPECT_EQ(f.paintedPixels(kWhite), expected);
}

// Triangle input, passed through: the same image as no geometry shader at all.
struct GsPassThrough {
    void operator()(const Triangle<PositionOnly>& in, TriangleStream<PositionOnly, 3>& out) const {
        for (const PositionOnly& v : in) out.Append(v);
    }
};

TEST(GeometryShader, PassThroughDrawsTheSameImage) {
    const std::vector<glm::vec3> tris = {{-0.9f, -0.7f, 0.2f}, {-0.3f, 0.8f, 0.4f}, {0.6f, -0.2f, 0.9f},
                                         {0.9f, 0.9f, 0.1f},   {0.1f, 0.5f, 0.5f},  {0.7f, -0.9f, 0.3f}};
    Fixture a(40, 30), b(40, 30);
    for (Fixture* f : {&a, &b}) {
        f->setVertices(tris);
        f->ctx.setPrimitiveTopology(Topology::TriangleList);
        RasterizerState none;
        none.cullMode = CullMode::None;
        f->ctx.setRasterizerState(none);
    }
    a.ctx.draw(VsTransform{}, PsConstant{kWhite}, 6);
    b.ctx.draw(VsTransform{}, GsPassThrough{}, PsConstant{kWhite}, 6);
    EXPECT_GT(a.paintedPixels(kWhite).size(), 100u);
    EXPECT_TRUE(a.color == b.color);
    EXPECT_TRUE(a.depth == b.depth);
    EXPECT_EQ(b.ctx.drawStatistics().gsInvocations, 2u);
    EXPECT_EQ(b.ctx.drawStatistics().gsPrimitives, 2u);
    EXPECT_EQ(a.ctx.drawStatistics().gsInvocations, 0u);
    EXPECT_EQ(a.ctx.drawStatistics().psInvocations, b.ctx.drawStatistics().psInvocations);
}

// ---- Errors ----------------------------------------------------------------------------------------

// Appends 6 vertices into a stream of 4 for points right of x = 0, 4 otherwise.
struct GsOverflow {
    void operator()(const Point<PositionOnly>& in, TriangleStream<PositionOnly, 4>& out) const {
        const glm::vec4 c = in[0].position;
        const int n = c.x > 0.0f ? 6 : 4;
        for (int i = 0; i < n; ++i)
            out.Append({c + glm::vec4(i % 2 ? 0.1f : -0.1f, i / 2 % 2 ? 0.1f : -0.1f, 0, 0)});
    }
};

TEST(GeometryShader, OverflowThrowsShaderErrorAndDrawsNothing) {
    Fixture f(32, 32);
    f.setVertices({{-0.8f, 0, 0.5f}, {-0.4f, 0, 0.5f}, {0.5f, 0, 0.5f}, {-0.6f, 0.5f, 0.5f}});
    f.ctx.setPrimitiveTopology(Topology::PointList);
    RasterizerState none;
    none.cullMode = CullMode::None;
    f.ctx.setRasterizerState(none);
    // Points 0 and 1 alone draw fine.
    f.ctx.draw(VsTransform{}, GsOverflow{}, PsConstant{kWhite}, 2);
    EXPECT_FALSE(f.paintedPixels(kWhite).empty());
    f.color.clear(kClear);
    f.depth.clear(1.0f);
    const RenderTarget before = f.color;
    const DepthTarget depthBefore = f.depth;
    expectError([&] { f.ctx.draw(VsTransform{}, GsOverflow{}, PsConstant{kWhite}, 4); }, ErrorCode::ShaderError,
                {"GsOverflow", "appended 2", "maxvertexcount of 4", "primitive 2"});
    EXPECT_TRUE(f.color == before) << "primitives 0, 1 and 3 must not be drawn either";
    EXPECT_TRUE(f.depth == depthBefore);
}

TEST(GeometryShader, TopologyMustMatchTheShadersInput) {
    Fixture f(16, 16);
    f.setVertices({{-1, -1, 0.5f}, {-1, 1, 0.5f}, {1, -1, 0.5f}, {1, 1, 0.5f}});
    const RenderTarget before = f.color;
    f.ctx.setPrimitiveTopology(Topology::TriangleList);
    expectError([&] { f.ctx.draw(VsBillboard{}, GsBillboard{}, PsTexCoord{}, 3); }, ErrorCode::InvalidState,
                {"GsBillboard", "1-vertex", "3-vertex"});
    f.ctx.setPrimitiveTopology(Topology::TriangleStrip);
    expectError([&] { f.ctx.draw(VsBillboard{}, GsBillboard{}, PsTexCoord{}, 4); }, ErrorCode::InvalidState,
                {"GsBillboard"});
    f.ctx.setPrimitiveTopology(Topology::PointList);
    expectError([&] { f.ctx.draw(VsTransform{}, GsPassThrough{}, PsConstant{kWhite}, 3); }, ErrorCode::InvalidState,
                {"GsPassThrough", "3-vertex", "1-vertex"});
    f.ctx.setPrimitiveTopology(Topology::LineList);
    expectError([&] { f.ctx.draw(VsTransform{}, GsPassThrough{}, PsConstant{kWhite}, 4); }, ErrorCode::InvalidState,
                {"GsPassThrough", "2-vertex"});
    EXPECT_TRUE(f.color == before);
}

}  // namespace
}  // namespace raster
