// The input assembler through the pipeline: layouts and formats, topologies, indexed draws and the
// errors a draw raises before it writes anything.
#include "raster/stages/1_input_assembler.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "raster/check.hpp"
#include "raster/input_layout.hpp"
#include "raster/pipeline.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shaders/basic.hpp"

namespace raster {
namespace {

using shaders::PositionIn;
using shaders::PositionOnly;
using shaders::PsConstant;
using shaders::VsTransform;

// Runs f, which must throw raster::Error with `code` and a message containing every one of `parts`.
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

// A small colour + depth target pair bound to a context, with a viewport over all of it.
struct Targets {
    RenderTarget color;
    DepthTarget depth;
    Targets(Context& ctx, uint32_t w, uint32_t h) : color(w, h), depth(w, h) {
        color.clear({0.25f, 0.5f, 0.75f, 1.0f});
        depth.clear(1.0f);
        ctx.setRenderTargets(&color, &depth);
        ctx.setViewport({0, 0, float(w), float(h), 0, 1});
    }
    int paintedPixels(const glm::vec4& c) const {
        int n = 0;
        for (uint32_t y = 0; y < color.height(); ++y)
            for (uint32_t x = 0; x < color.width(); ++x)
                if (color.load(x, y) == c) ++n;
        return n;
    }
};

// Vertex shaders that write what the input assembler handed them into a test-owned vector (the
// contexts that use them run on one thread, so the vertex shader runs in order).
template <class In>
struct VsRecord {
    std::vector<In>* sink = nullptr;
    PositionOnly operator()(const In& in) const {
        sink->push_back(in);
        return {glm::vec4(0.0f, 0.0f, 0.5f, 1.0f)};
    }
};

struct PsWhite {
    glm::vec4 operator()(const PositionOnly&) const { return glm::vec4(1.0f); }
};

Context singleThreaded() { return Context(ContextOptions{.threads = 1}); }

// ---- Layouts and formats -------------------------------------------------------------------------

struct AllFormatsVertex {
    float f1;
    glm::vec2 f2;
    glm::vec3 f3;
    glm::vec4 f4;
    uint8_t rgba[4];
};

// Every vertex format into the field it fills completely, and the same elements into wider and
// narrower fields (D3D defaults (0, 0, 0, 1) for the missing components, extra ones ignored).
struct AllFormatsIn {
    float a;
    glm::vec2 b;
    glm::vec3 c;
    glm::vec4 d;
    glm::vec4 e;
    glm::vec4 aWide;  // R32_FLOAT -> (x, 0, 0, 1)
    glm::vec4 bWide;  // R32G32_FLOAT -> (x, y, 0, 1)
    glm::vec4 cWide;  // R32G32B32_FLOAT -> (x, y, z, 1)
    glm::vec3 bMid;   // R32G32_FLOAT -> (x, y, 0)
    glm::vec2 dNarrow;  // R32G32B32A32_FLOAT -> (x, y)
    float eNarrow;      // R8G8B8A8_UNORM -> r
    RASTER_INPUT_SIGNATURE(AllFormatsIn, RASTER_INPUT(a, "A", 0), RASTER_INPUT(b, "B", 0), RASTER_INPUT(c, "C", 0),
                           RASTER_INPUT(d, "D", 0), RASTER_INPUT(e, "E", 0), RASTER_INPUT(aWide, "A", 1),
                           RASTER_INPUT(bWide, "B", 1), RASTER_INPUT(cWide, "C", 1), RASTER_INPUT(bMid, "B", 2),
                           RASTER_INPUT(dNarrow, "D", 1), RASTER_INPUT(eNarrow, "e", 1))
};

TEST(InputAssembler, EveryFormatFetchesWithD3DDefaults) {
    using V = AllFormatsVertex;
    const InputElementDesc desc[] = {
        {"A", 0, Format::R32_FLOAT, 0, offsetof(V, f1)},
        {"B", 0, Format::R32G32_FLOAT, 0, offsetof(V, f2)},
        {"C", 0, Format::R32G32B32_FLOAT, 0, offsetof(V, f3)},
        {"D", 0, Format::R32G32B32A32_FLOAT, 0, offsetof(V, f4)},
        {"E", 0, Format::R8G8B8A8_UNORM, 0, offsetof(V, rgba)},
        {"A", 1, Format::R32_FLOAT, 0, offsetof(V, f1)},
        {"B", 1, Format::R32G32_FLOAT, 0, offsetof(V, f2)},
        {"C", 1, Format::R32G32B32_FLOAT, 0, offsetof(V, f3)},
        {"B", 2, Format::R32G32_FLOAT, 0, offsetof(V, f2)},
        {"D", 1, Format::R32G32B32A32_FLOAT, 0, offsetof(V, f4)},
        {"E", 1, Format::R8G8B8A8_UNORM, 0, offsetof(V, rgba)},  // matched case-insensitively by "e"
    };
    const InputLayout layout(desc);
    const std::vector<V> data = {
        {1.5f, {2, 3}, {4, 5, 6}, {7, 8, 9, 10}, {0, 51, 128, 255}},
        {-1, {-2, -3}, {-4, -5, -6}, {-7, -8, -9, -10}, {255, 0, 1, 254}},
    };
    const VertexBuffer vb = VertexBuffer::create(data);
    Context ctx = singleThreaded();
    Targets t(ctx, 4, 4);
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb);
    ctx.setPrimitiveTopology(Topology::PointList);
    std::vector<AllFormatsIn> got;
    ctx.draw(VsRecord<AllFormatsIn>{&got}, PsWhite{}, 2);
    ASSERT_EQ(got.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        const V& v = data[i];
        const AllFormatsIn& in = got[i];
        const glm::vec4 unorm(v.rgba[0] / 255.0f, v.rgba[1] / 255.0f, v.rgba[2] / 255.0f, v.rgba[3] / 255.0f);
        EXPECT_EQ(in.a, v.f1) << i;
        EXPECT_EQ(in.b, v.f2) << i;
        EXPECT_EQ(in.c, v.f3) << i;
        EXPECT_EQ(in.d, v.f4) << i;
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(in.e[c], unorm[c], 1e-7f) << i << " channel " << c;
        EXPECT_EQ(in.aWide, glm::vec4(v.f1, 0, 0, 1)) << i;
        EXPECT_EQ(in.bWide, glm::vec4(v.f2, 0, 1)) << i;
        EXPECT_EQ(in.cWide, glm::vec4(v.f3, 1)) << i;
        EXPECT_EQ(in.bMid, glm::vec3(v.f2, 0)) << i;
        EXPECT_EQ(in.dNarrow, glm::vec2(v.f4)) << i;
        EXPECT_NEAR(in.eNarrow, unorm.r, 1e-7f) << i;
    }
    // The end points of UNORM are exact.
    EXPECT_EQ(got[0].e.x, 0.0f);
    EXPECT_EQ(got[0].e.w, 1.0f);
    EXPECT_EQ(got[1].e.x, 1.0f);
}

struct PackedVertex {
    glm::vec3 position;
    uint8_t color[4];
    glm::vec2 uv;
    float weight;
};

struct PackedIn {
    glm::vec3 position;
    glm::vec4 color;
    glm::vec2 uv;
    float weight;
    RASTER_INPUT_SIGNATURE(PackedIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(color, "COLOR", 0),
                           RASTER_INPUT(uv, "TEXCOORD", 0), RASTER_INPUT(weight, "TEXCOORD", 1))
};

TEST(InputAssembler, AppendAlignedElementPacksElementsLikeOffsetof) {
    const InputElementDesc desc[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, kAppendAlignedElement},
        {"COLOR", 0, Format::R8G8B8A8_UNORM, 0, kAppendAlignedElement},
        {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, kAppendAlignedElement},
        {"TEXCOORD", 1, Format::R32_FLOAT, 0, kAppendAlignedElement},
    };
    const InputLayout layout(desc);
    ASSERT_EQ(layout.elements().size(), 4u);
    EXPECT_EQ(layout.elements()[0].byteOffset, offsetof(PackedVertex, position));
    EXPECT_EQ(layout.elements()[1].byteOffset, offsetof(PackedVertex, color));
    EXPECT_EQ(layout.elements()[2].byteOffset, offsetof(PackedVertex, uv));
    EXPECT_EQ(layout.elements()[3].byteOffset, offsetof(PackedVertex, weight));

    const std::vector<PackedVertex> data = {{{1, 2, 3}, {255, 0, 255, 0}, {0.5f, 0.25f}, 42.0f},
                                            {{-1, -2, -3}, {0, 255, 0, 255}, {8, 16}, -7.0f}};
    const VertexBuffer vb = VertexBuffer::create(data);
    Context ctx = singleThreaded();
    Targets t(ctx, 4, 4);
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb);
    ctx.setPrimitiveTopology(Topology::PointList);
    std::vector<PackedIn> got;
    ctx.draw(VsRecord<PackedIn>{&got}, PsWhite{}, 2);
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0].position, glm::vec3(1, 2, 3));
    EXPECT_EQ(got[0].color, glm::vec4(1, 0, 1, 0));
    EXPECT_EQ(got[0].uv, glm::vec2(0.5f, 0.25f));
    EXPECT_EQ(got[0].weight, 42.0f);
    EXPECT_EQ(got[1].position, glm::vec3(-1, -2, -3));
    EXPECT_EQ(got[1].color, glm::vec4(0, 1, 0, 1));
    EXPECT_EQ(got[1].uv, glm::vec2(8, 16));
    EXPECT_EQ(got[1].weight, -7.0f);
}

TEST(InputAssembler, AppendAlignedElementCountsPerSlot) {
    const InputElementDesc desc[] = {
        {"P", 0, Format::R32G32B32_FLOAT, 0, kAppendAlignedElement},
        {"Q", 0, Format::R32G32B32A32_FLOAT, 1, kAppendAlignedElement},
        {"R", 0, Format::R32_FLOAT, 0, kAppendAlignedElement},
        {"S", 0, Format::R32G32_FLOAT, 1, kAppendAlignedElement},
        {"T", 0, Format::R32_FLOAT, 0, 40},
        {"U", 0, Format::R32_FLOAT, 0, kAppendAlignedElement},
    };
    const InputLayout layout(desc);
    const uint32_t expected[] = {0, 0, 12, 16, 40, 44};
    for (size_t i = 0; i < 6; ++i) EXPECT_EQ(layout.elements()[i].byteOffset, expected[i]) << "element " << i;
}

struct TwoSlotIn {
    glm::vec3 position;
    glm::vec4 color;
    glm::vec2 extra;
    RASTER_INPUT_SIGNATURE(TwoSlotIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(color, "COLOR", 0),
                           RASTER_INPUT(extra, "EXTRA", 0))
};

struct ColorExtra {
    glm::vec2 extra;  // a different stride than slot 0's and the colour not at offset 0
    glm::vec4 color;
};

TEST(InputAssembler, TwoSlotsWithDifferentStrides) {
    const InputElementDesc desc[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
        {"COLOR", 0, Format::R32G32B32A32_FLOAT, 1, offsetof(ColorExtra, color)},
        {"EXTRA", 0, Format::R32G32_FLOAT, 1, offsetof(ColorExtra, extra)},
    };
    const InputLayout layout(desc);
    std::vector<glm::vec3> positions;
    std::vector<ColorExtra> colors;
    for (int i = 0; i < 5; ++i) {
        positions.push_back({float(i), float(10 * i), float(100 * i)});
        colors.push_back({{float(-i), 0.5f * float(i)}, {0.1f * float(i), 1, 2, 3}});
    }
    const VertexBuffer vb0 = VertexBuffer::create(positions), vb1 = VertexBuffer::create(colors);
    EXPECT_EQ(vb0.stride(), 12u);
    EXPECT_EQ(vb1.stride(), 24u);
    Context ctx = singleThreaded();
    Targets t(ctx, 4, 4);
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb0);
    ctx.setVertexBuffer(1, &vb1);
    ctx.setPrimitiveTopology(Topology::PointList);
    std::vector<TwoSlotIn> got;
    ctx.draw(VsRecord<TwoSlotIn>{&got}, PsWhite{}, 3, 2);  // vertices 2, 3, 4
    ASSERT_EQ(got.size(), 3u);
    for (int k = 0; k < 3; ++k) {
        const int i = k + 2;
        EXPECT_EQ(got[k].position, positions[i]) << i;
        EXPECT_EQ(got[k].color, colors[i].color) << i;
        EXPECT_EQ(got[k].extra, colors[i].extra) << i;
    }
}

struct InstancedIn {
    float vertex;
    float every;     // step rate 1
    float second;    // step rate 2
    float constant;  // step rate 0
    RASTER_INPUT_SIGNATURE(InstancedIn, RASTER_INPUT(vertex, "V", 0), RASTER_INPUT(every, "I", 1),
                           RASTER_INPUT(second, "I", 2), RASTER_INPUT(constant, "I", 0))
};

std::vector<float> ramp(int n, float scale) {
    std::vector<float> v;
    for (int i = 0; i < n; ++i) v.push_back(scale * float(i));
    return v;
}

TEST(InputAssembler, PerInstanceDataFollowsStepRatesAndStartInstance) {
    const InputElementDesc desc[] = {
        {"V", 0, Format::R32_FLOAT, 0, 0, InputClassification::PerVertexData, 0},
        {"I", 1, Format::R32_FLOAT, 1, 0, InputClassification::PerInstanceData, 1},
        {"I", 2, Format::R32_FLOAT, 2, 0, InputClassification::PerInstanceData, 2},
        {"I", 0, Format::R32_FLOAT, 3, 0, InputClassification::PerInstanceData, 0},
    };
    const InputLayout layout(desc);
    constexpr uint32_t kStartInstance = 3, kInstances = 5, kVertices = 3, kStartVertex = 1;
    // Largest elements read: rate 1: 3 + 4 = 7; rate 2: 3 + 4 / 2 = 5; rate 0: 3.
    const VertexBuffer vertices = VertexBuffer::create(ramp(4, 1.0f));
    const VertexBuffer every = VertexBuffer::create(ramp(8, 10.0f));
    const VertexBuffer second = VertexBuffer::create(ramp(6, 100.0f));
    const VertexBuffer constant = VertexBuffer::create(ramp(4, 1000.0f));
    Context ctx = singleThreaded();
    Targets t(ctx, 4, 4);
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vertices);
    ctx.setVertexBuffer(1, &every);
    ctx.setVertexBuffer(2, &second);
    ctx.setVertexBuffer(3, &constant);
    ctx.setPrimitiveTopology(Topology::PointList);
    std::vector<InstancedIn> got;
    ctx.drawInstanced(VsRecord<InstancedIn>{&got}, PsWhite{}, kVertices, kInstances, kStartVertex, kStartInstance);
    ASSERT_EQ(got.size(), size_t(kVertices * kInstances));
    for (uint32_t inst = 0; inst < kInstances; ++inst) {
        for (uint32_t v = 0; v < kVertices; ++v) {
            const InstancedIn& in = got[inst * kVertices + v];
            EXPECT_EQ(in.vertex, float(kStartVertex + v)) << "instance " << inst << " vertex " << v;
            EXPECT_EQ(in.every, 10.0f * float(kStartInstance + inst)) << "instance " << inst;
            EXPECT_EQ(in.second, 100.0f * float(kStartInstance + inst / 2)) << "instance " << inst;
            EXPECT_EQ(in.constant, 1000.0f * float(kStartInstance)) << "instance " << inst;
        }
    }
    const PipelineStatistics& s = ctx.drawStatistics();
    EXPECT_EQ(s.vsInvocations, uint64_t(kVertices * kInstances));
    EXPECT_EQ(s.iaPrimitives, uint64_t(kVertices * kInstances));
    EXPECT_EQ(s.iaVertices, uint64_t(kVertices * kInstances));

    // One element fewer in the step-rate-1 buffer: the last instance reads past it.
    const VertexBuffer shortEvery = VertexBuffer::create(ramp(7, 10.0f));
    ctx.setVertexBuffer(1, &shortEvery);
    got.clear();
    expectError([&] { ctx.drawInstanced(VsRecord<InstancedIn>{&got}, PsWhite{}, kVertices, kInstances, kStartVertex,
                                        kStartInstance); },
                ErrorCode::OutOfRange, {"input slot 1", "instance element 7", "holds 7"});
    EXPECT_TRUE(got.empty()) << "the vertex shader ran before the draw was validated";
}

// ---- Topologies ----------------------------------------------------------------------------------

struct Scene2D {
    Context ctx;
    Targets targets;
    InputLayout layout;
    VertexBuffer vb;
    IndexBuffer ib;
    Scene2D(uint32_t w, uint32_t h, ContextOptions options = {}) : ctx(options), targets(ctx, w, h) {
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
        layout = InputLayout(desc);
        ctx.setInputLayout(&layout);
    }
    void setVertices(const std::vector<glm::vec3>& v) {
        vb = VertexBuffer::create(v);
        ctx.setVertexBuffer(0, &vb);
    }
    template <class I>
    void setIndices(const std::vector<I>& i) {
        ib = IndexBuffer::create(i);
        ctx.setIndexBuffer(&ib);
    }
};

const glm::vec4 kWhite(1.0f);

TEST(InputAssembler, PrimitiveCountsPerTopology) {
    Scene2D s(8, 8);
    std::vector<glm::vec3> v;
    for (int i = 0; i < 7; ++i) v.push_back({-0.9f + 0.25f * float(i), 0.1f * float(i % 3), 0.5f});
    s.setVertices(v);
    s.ctx.setRasterizerState([] {
        RasterizerState r;
        r.cullMode = CullMode::None;
        return r;
    }());
    const struct {
        Topology topology;
        uint64_t primitives;
    } cases[] = {{Topology::PointList, 7}, {Topology::LineList, 3}, {Topology::LineStrip, 6},
                 {Topology::TriangleList, 2}, {Topology::TriangleStrip, 5}};
    for (const auto& c : cases) {
        s.ctx.setPrimitiveTopology(c.topology);
        s.ctx.draw(VsTransform{}, PsConstant{kWhite}, 7);
        EXPECT_EQ(s.ctx.drawStatistics().iaPrimitives, c.primitives) << "topology " << int(c.topology);
        EXPECT_EQ(s.ctx.drawStatistics().iaVertices, 7u);
        EXPECT_EQ(s.ctx.drawStatistics().vsInvocations, 7u);
        EXPECT_EQ(s.ctx.drawStatistics().cInvocations, c.primitives);
    }
    // Too few vertices for one primitive: nothing, and no error.
    s.ctx.setPrimitiveTopology(Topology::TriangleList);
    s.ctx.draw(VsTransform{}, PsConstant{kWhite}, 2);
    EXPECT_EQ(s.ctx.drawStatistics().iaPrimitives, 0u);
}

// A strip of quads across the whole target, each quad two triangles, the first one clockwise on
// screen: with back-face culling every triangle must survive, which only holds if odd triangles are
// taken as (i, i+2, i+1).
std::vector<glm::vec3> quadStrip(int quads, float x0 = -1.0f, float x1 = 1.0f) {
    std::vector<glm::vec3> v;
    for (int i = 0; i <= quads; ++i) {
        const float x = x0 + (x1 - x0) * float(i) / float(quads);
        v.push_back({x, -1.0f, 0.5f});  // bottom
        v.push_back({x, 1.0f, 0.5f});   // top
    }
    return v;
}

TEST(InputAssembler, TriangleStripKeepsTheWindingOfItsFirstTriangle) {
    Scene2D s(16, 8);
    s.setVertices(quadStrip(4));
    s.ctx.setPrimitiveTopology(Topology::TriangleStrip);
    s.ctx.draw(VsTransform{}, PsConstant{kWhite}, 10);  // default rasterizer state: cull back
    const PipelineStatistics st = s.ctx.drawStatistics();
    EXPECT_EQ(st.iaPrimitives, 8u);
    EXPECT_EQ(st.primitivesCulled, 0u);
    EXPECT_EQ(st.psInvocations, 16u * 8u);
    EXPECT_EQ(s.targets.paintedPixels(kWhite), 16 * 8);

    // Culling the front faces instead removes every one of them.
    Scene2D f(16, 8);
    f.setVertices(quadStrip(4));
    f.ctx.setPrimitiveTopology(Topology::TriangleStrip);
    RasterizerState front;
    front.cullMode = CullMode::Front;
    f.ctx.setRasterizerState(front);
    f.ctx.draw(VsTransform{}, PsConstant{kWhite}, 10);
    EXPECT_EQ(f.ctx.drawStatistics().primitivesCulled, 8u);
    EXPECT_EQ(f.targets.paintedPixels(kWhite), 0);
}

template <class Index>
void indexedQuadCase() {
    Scene2D s(8, 8, ContextOptions{.threads = 1});
    // Four junk vertices, then the quad's corners; baseVertex 4 skips the junk.
    std::vector<glm::vec3> v(4, glm::vec3(5.0f, 5.0f, 0.5f));
    const std::vector<glm::vec3> corners = {{-1, -1, 0.5f}, {-1, 1, 0.5f}, {1, -1, 0.5f}, {1, 1, 0.5f}};
    v.insert(v.end(), corners.begin(), corners.end());
    s.setVertices(v);
    s.setIndices(std::vector<Index>{0, 1, 2, 2, 1, 3});
    s.ctx.setPrimitiveTopology(Topology::TriangleList);
    s.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 6, 0, 4);
    const PipelineStatistics st = s.ctx.drawStatistics();
    EXPECT_EQ(st.iaVertices, 6u);
    EXPECT_EQ(st.iaPrimitives, 2u);
    EXPECT_EQ(st.vsInvocations, 4u);
    EXPECT_EQ(st.primitivesCulled, 0u);
    EXPECT_EQ(s.targets.paintedPixels(kWhite), 64);

    // The vertex shader sees the vertices in order of first use, base vertex added.
    std::vector<PositionIn> got;
    s.setIndices(std::vector<Index>{3, 1, 3, 0, 1});
    s.ctx.setPrimitiveTopology(Topology::PointList);
    s.ctx.drawIndexed(VsRecord<PositionIn>{&got}, PsWhite{}, 5, 0, 4);
    ASSERT_EQ(got.size(), 3u);
    EXPECT_EQ(got[0].position, corners[3]);
    EXPECT_EQ(got[1].position, corners[1]);
    EXPECT_EQ(got[2].position, corners[0]);
    EXPECT_EQ(s.ctx.drawStatistics().vsInvocations, 3u);
    EXPECT_EQ(s.ctx.drawStatistics().iaVertices, 5u);
    EXPECT_EQ(s.ctx.drawStatistics().iaPrimitives, 5u);

    // startIndex and a negative base vertex.
    got.clear();
    s.setIndices(std::vector<Index>{9, 9, 7, 6});
    s.ctx.drawIndexed(VsRecord<PositionIn>{&got}, PsWhite{}, 2, 2, -2);
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0].position, v[5]);
    EXPECT_EQ(got[1].position, v[4]);
}

TEST(InputAssembler, IndexedDraw16BitWithBaseVertex) { indexedQuadCase<uint16_t>(); }
TEST(InputAssembler, IndexedDraw32BitWithBaseVertex) { indexedQuadCase<uint32_t>(); }

TEST(InputAssembler, VertexShaderRunsOncePerDistinctIndex) {
    Scene2D s(8, 8);
    s.setVertices({{-1, -1, 0.5f}, {-1, 1, 0.5f}, {1, -1, 0.5f}, {1, 1, 0.5f}, {0, 0, 0.5f}});
    const std::vector<uint32_t> indices = {0, 1, 4, 4, 1, 3, 3, 2, 4, 4, 2, 0, 0, 1, 4};
    s.setIndices(indices);
    s.ctx.setPrimitiveTopology(Topology::TriangleList);
    s.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, uint32_t(indices.size()));
    EXPECT_EQ(s.ctx.drawStatistics().vsInvocations, 5u);
    EXPECT_EQ(s.ctx.drawStatistics().iaVertices, 15u);
    EXPECT_EQ(s.ctx.drawStatistics().iaPrimitives, 5u);
    // Instanced: once per distinct index per instance.
    s.ctx.drawIndexedInstanced(VsTransform{}, PsConstant{kWhite}, 6, 3);
    EXPECT_EQ(s.ctx.drawStatistics().vsInvocations, 4u * 3u);
    EXPECT_EQ(s.ctx.drawStatistics().iaPrimitives, 2u * 3u);
}

template <class Index>
void stripCutCase(Index cut) {
    // Strip 1: one clockwise triangle in the left half; cut; strip 2: a clockwise quad (two
    // triangles) in the right half. If the cut did not restart the strip's parity, strip 2's first
    // triangle would count as odd, be reversed and culled.
    Scene2D s(8, 4);
    s.setVertices({{-1, -1, 0.5f}, {-1, 1, 0.5f}, {0, -1, 0.5f},                   // 0 1 2
                   {0, -1, 0.5f}, {0, 1, 0.5f}, {1, -1, 0.5f}, {1, 1, 0.5f}});    // 3 4 5 6
    s.setIndices(std::vector<Index>{0, 1, 2, cut, 3, 4, 5, 6});
    s.ctx.setPrimitiveTopology(Topology::TriangleStrip);
    s.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 8);
    const PipelineStatistics st = s.ctx.drawStatistics();
    EXPECT_EQ(st.iaVertices, 8u);  // the cut is read too
    EXPECT_EQ(st.iaPrimitives, 3u);
    EXPECT_EQ(st.vsInvocations, 7u);
    EXPECT_EQ(st.primitivesCulled, 0u);
    for (uint32_t y = 0; y < 4; ++y)
        for (uint32_t x = 4; x < 8; ++x) EXPECT_EQ(s.targets.color.load(x, y), kWhite) << x << "," << y;
    // Lower-left triangle (0,4) (0,0) (4,4): the pixel at (0,3) is in it, (3,0) is not.
    EXPECT_EQ(s.targets.color.load(0, 3), kWhite);
    EXPECT_NE(s.targets.color.load(3, 0), kWhite);
    EXPECT_EQ(st.psInvocations, uint64_t(s.targets.paintedPixels(kWhite)));

    // The same indices as a line strip: 2 lines, cut, 3 lines.
    s.ctx.setPrimitiveTopology(Topology::LineStrip);
    s.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 8);
    EXPECT_EQ(s.ctx.drawStatistics().iaPrimitives, 5u);
    // Two cuts in a row and a cut at the start make empty strips, nothing more.
    s.setIndices(std::vector<Index>{cut, 0, 1, 2, cut, cut, 3, 4, 5});
    s.ctx.setPrimitiveTopology(Topology::TriangleStrip);
    s.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 9);
    EXPECT_EQ(s.ctx.drawStatistics().iaPrimitives, 2u);
    EXPECT_EQ(s.ctx.drawStatistics().iaVertices, 9u);
}

// Regression: the first vertex after a cut used to be dropped ({0,1,2,cut,3,4,5,6} gave the
// triangles (0,1,2) and (4,5,6) instead of (0,1,2), (3,4,5), (4,6,5)).
TEST(InputAssembler, StripCutValueRestartsStrip16) { stripCutCase<uint16_t>(0xFFFF); }
TEST(InputAssembler, StripCutValueRestartsStrip32) { stripCutCase<uint32_t>(0xFFFFFFFFu); }

TEST(InputAssembler, CutValueOfTheOtherWidthIsAnOrdinaryIndex) {
    // 0xFFFF in a 32-bit buffer is vertex 65535, which this buffer lacks.
    Scene2D s(4, 4);
    s.setVertices(quadStrip(1));
    s.setIndices(std::vector<uint32_t>{0, 1, 2, 0xFFFF});
    s.ctx.setPrimitiveTopology(Topology::TriangleStrip);
    expectError([&] { s.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 4); }, ErrorCode::OutOfRange,
                {"vertex 65535", "holds 4"});
}

// ---- Errors --------------------------------------------------------------------------------------

// A context with a valid draw set up (a full-screen quad as a triangle list), so that each error
// test changes exactly one thing.
struct ErrorSetup {
    Context ctx;
    RenderTarget color{8, 8};
    DepthTarget depth{8, 8};
    InputLayout layout;
    VertexBuffer vb;
    IndexBuffer ib;
    ErrorSetup() {
        color.clear({0.1f, 0.2f, 0.3f, 0.4f});
        color.store(3, 5, {0.9f, 0.8f, 0.7f, 0.6f});
        depth.clear(0.75f);
        ctx.setRenderTargets(&color, &depth);
        ctx.setViewport({0, 0, 8, 8, 0, 1});
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
        layout = InputLayout(desc);
        ctx.setInputLayout(&layout);
        vb = VertexBuffer::create(std::vector<glm::vec3>{
            {-1, -1, 0.5f}, {-1, 1, 0.5f}, {1, -1, 0.5f}, {1, -1, 0.5f}, {-1, 1, 0.5f}, {1, 1, 0.5f}});
        ctx.setVertexBuffer(0, &vb);
        ib = IndexBuffer::create(std::vector<uint16_t>{0, 1, 2, 3, 4, 5});
        ctx.setIndexBuffer(&ib);
        ctx.setPrimitiveTopology(Topology::TriangleList);
    }
    void draw(uint32_t n = 6) { ctx.draw(VsTransform{}, PsConstant{kWhite}, n); }
    // Runs the failing draw and checks the error and that no target changed.
    void expectDrawError(const std::function<void()>& f, ErrorCode code, std::initializer_list<std::string> parts) {
        const RenderTarget colorBefore = color;
        const DepthTarget depthBefore = depth;
        expectError(f, code, parts);
        EXPECT_TRUE(color == colorBefore) << "the failing draw changed the render target";
        EXPECT_TRUE(depth == depthBefore) << "the failing draw changed the depth target";
    }
};

TEST(InputAssemblerErrors, TheValidSetupDraws) {
    ErrorSetup e;
    e.draw();
    EXPECT_EQ(e.color.load(0, 0), kWhite);
    EXPECT_EQ(e.depth.load(0, 0), 0.5f);
}

struct PositionNormalIn {
    glm::vec3 position;
    glm::vec3 normal;
    RASTER_INPUT_SIGNATURE(PositionNormalIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(normal, "NORMAL", 0))
};
struct VsPositionNormal {
    PositionOnly operator()(const PositionNormalIn& in) const { return {glm::vec4(in.position + in.normal, 1.0f)}; }
};

TEST(InputAssemblerErrors, ShaderInputMissingFromLayout) {
    ErrorSetup e;
    e.expectDrawError([&] { e.ctx.draw(VsPositionNormal{}, PsConstant{kWhite}, 6); }, ErrorCode::LayoutMismatch,
                      {"PositionNormalIn", "normal", "NORMAL0", "POSITION0"});
}

TEST(InputAssemblerErrors, SemanticIndexMustMatchToo) {
    ErrorSetup e;
    const InputElementDesc desc[] = {{"POSITION", 1, Format::R32G32B32_FLOAT, 0, 0}};
    const InputLayout wrongIndex(desc);
    e.ctx.setInputLayout(&wrongIndex);
    e.expectDrawError([&] { e.draw(); }, ErrorCode::LayoutMismatch, {"position", "POSITION0", "POSITION1"});
}

TEST(InputAssemblerErrors, UnknownFormat) {
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                     {"COLOR", 0, Format::Unknown, 0, 12}};
    expectError([&] { InputLayout layout(desc); }, ErrorCode::LayoutMismatch, {"input element 1", "COLOR0", "UNKNOWN"});
    // A render-target-only format is not a vertex format either.
    const InputElementDesc depth[] = {{"DEPTH", 0, Format::D32_FLOAT, 0, 0}};
    expectError([&] { InputLayout layout(depth); }, ErrorCode::LayoutMismatch, {"DEPTH0", "D32_FLOAT"});
}

TEST(InputAssemblerErrors, SlotBeyondMaxInputSlots) {
    const InputElementDesc ok[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, kMaxInputSlots - 1, 0}};
    EXPECT_NO_THROW(InputLayout layout(ok));
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, kMaxInputSlots, 0}};
    expectError([&] { InputLayout layout(desc); }, ErrorCode::LayoutMismatch,
                {"POSITION0", "input slot 16", "16"});
    Context ctx(ContextOptions{.threads = 1});
    const VertexBuffer vb = VertexBuffer::create(std::vector<float>{1.0f});
    expectError([&] { ctx.setVertexBuffer(kMaxInputSlots, &vb); }, ErrorCode::InvalidArgument, {"slot 16"});
}

TEST(InputAssemblerErrors, VertexBufferTooSmallForTheDraw) {
    ErrorSetup e;
    e.expectDrawError([&] { e.draw(7); }, ErrorCode::OutOfRange, {"input slot 0", "vertex 6", "holds 6"});
    e.expectDrawError([&] { e.ctx.draw(VsTransform{}, PsConstant{kWhite}, 3, 4); }, ErrorCode::OutOfRange,
                      {"vertex 6", "holds 6"});
    // An indexed draw whose index names a vertex past the buffer.
    const IndexBuffer big = IndexBuffer::create(std::vector<uint32_t>{0, 1, 6});
    e.ctx.setIndexBuffer(&big);
    e.expectDrawError([&] { e.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 3); }, ErrorCode::OutOfRange,
                      {"vertex 6", "holds 6"});
    e.expectDrawError([&] { e.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 3, 0, 4); },
                      ErrorCode::OutOfRange, {"vertex 10"});
}

TEST(InputAssemblerErrors, NoBufferBoundToASlotTheLayoutReads) {
    ErrorSetup e;
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32_FLOAT, 0, 0},
                                     {"NORMAL", 0, Format::R32G32B32_FLOAT, 2, 0}};
    const InputLayout layout(desc);
    e.ctx.setInputLayout(&layout);
    e.expectDrawError([&] { e.ctx.draw(VsPositionNormal{}, PsConstant{kWhite}, 6); }, ErrorCode::LayoutMismatch,
                      {"input slot 2", "no vertex buffer"});
    // Unbinding slot 0 too.
    e.ctx.setInputLayout(&e.layout);
    e.ctx.setVertexBuffer(0, nullptr);
    e.expectDrawError([&] { e.draw(); }, ErrorCode::LayoutMismatch, {"input slot 0", "no vertex buffer"});
}

TEST(InputAssemblerErrors, IndexRangePastTheIndexBuffer) {
    ErrorSetup e;
    e.expectDrawError([&] { e.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 7); }, ErrorCode::OutOfRange,
                      {"indices 0..6", "holds 6"});
    e.expectDrawError([&] { e.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 3, 4); }, ErrorCode::OutOfRange,
                      {"indices 4..6", "holds 6"});
    e.ctx.setIndexBuffer(nullptr);
    e.expectDrawError([&] { e.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 3); }, ErrorCode::InvalidState,
                      {"index buffer"});
}

TEST(InputAssemblerErrors, IndexPlusBaseVertexNegative) {
    ErrorSetup e;
    const IndexBuffer ib = IndexBuffer::create(std::vector<uint16_t>{5, 4, 2});
    e.ctx.setIndexBuffer(&ib);
    e.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 3, 0, -2);  // 3, 2, 0: fine
    e.color.clear({0.1f, 0.2f, 0.3f, 0.4f});
    e.expectDrawError([&] { e.ctx.drawIndexed(VsTransform{}, PsConstant{kWhite}, 3, 0, -3); }, ErrorCode::OutOfRange,
                      {"index 2", "position 2", "base vertex -3"});
}

TEST(InputAssemblerErrors, UndefinedTopology) {
    ErrorSetup e;
    e.ctx.setPrimitiveTopology(Topology::Undefined);
    e.expectDrawError([&] { e.draw(); }, ErrorCode::InvalidState, {"topology", "setPrimitiveTopology"});
}

TEST(InputAssemblerErrors, ElementDoesNotFitTheStride) {
    ErrorSetup e;
    // A float4 element at byte 0 of a 12-byte (vec3) buffer.
    const InputElementDesc wide[] = {{"POSITION", 0, Format::R32G32B32A32_FLOAT, 0, 0}};
    const InputLayout wideLayout(wide);
    e.ctx.setInputLayout(&wideLayout);
    // The message names the element and the shader's field it feeds, so that a layout copied from
    // another struct points at its culprit.
    e.expectDrawError([&] { e.draw(); }, ErrorCode::LayoutMismatch,
                      {"input slot 0", "element POSITION0 (feeding `position`)", "R32G32B32A32_FLOAT",
                       "ends at byte 16", "stride of 12"});
    // A float2 at byte 8 of the same buffer: ends at byte 16.
    const InputElementDesc late[] = {{"POSITION", 0, Format::R32G32_FLOAT, 0, 8}};
    const InputLayout lateLayout(late);
    e.ctx.setInputLayout(&lateLayout);
    e.expectDrawError([&] { e.draw(); }, ErrorCode::LayoutMismatch, {"byte 8", "stride of 12"});
}

TEST(InputAssemblerErrors, DuplicateSemantic) {
    const InputElementDesc desc[] = {{"TEXCOORD", 0, Format::R32G32_FLOAT, 0, 0},
                                     {"POSITION", 0, Format::R32G32B32_FLOAT, 0, 8},
                                     {"texcoord", 0, Format::R32G32_FLOAT, 1, 0}};
    expectError([&] { InputLayout layout(desc); }, ErrorCode::LayoutMismatch, {"input element 2", "texcoord0", "repeats"});
    // The same name with another index is fine.
    const InputElementDesc ok[] = {{"TEXCOORD", 0, Format::R32G32_FLOAT, 0, 0},
                                   {"TEXCOORD", 1, Format::R32G32_FLOAT, 0, 8}};
    EXPECT_NO_THROW(InputLayout layout(ok));
}

TEST(InputAssemblerErrors, StepRateOnPerVertexData) {
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0, InputClassification::PerVertexData, 1}};
    expectError([&] { InputLayout layout(desc); }, ErrorCode::LayoutMismatch, {"POSITION0", "instanceDataStepRate"});
}

TEST(InputAssemblerErrors, NoInputLayout) {
    ErrorSetup e;
    e.ctx.setInputLayout(nullptr);
    e.expectDrawError([&] { e.draw(); }, ErrorCode::InvalidState, {"input layout", "setInputLayout"});
}

TEST(InputAssemblerErrors, ErrorsLeaveStatisticsConsistent) {
    // A failed draw neither counts in the frame nor runs the vertex shader.
    ErrorSetup e;
    e.ctx.resetFrameStatistics();
    e.draw();
    const PipelineStatistics once = e.ctx.frameStatistics();
    EXPECT_THROW(e.draw(7), Error);
    EXPECT_TRUE(e.ctx.frameStatistics() == once);
}

TEST(InputAssemblerErrors, OffsetNearTwoToThe32IsRefusedNotWrapped) {
    // offset + size wrapped around in 32 bits (0xFFFFFFFC + 12 = 8 <= a stride of 12), and the draw
    // read ~4 GiB past the buffer. The layout itself now refuses an element that ends past 2048 bytes.
    for (const uint32_t offset : {0xFFFFFFFCu, 0xFFFFFFF8u, 0xFFFFFFF4u, 0x80000000u, 2048u}) {
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, offset}};
        expectError([&] { InputLayout layout(desc); }, ErrorCode::LayoutMismatch,
                    {"POSITION0", "byte offset " + std::to_string(offset), "2048"});
    }
    // An element that ends exactly at 2048 is a valid layout; a 12-byte buffer does not hold it.
    ErrorSetup e;
    const InputElementDesc last[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 2036}};
    const InputLayout layout(last);
    e.ctx.setInputLayout(&layout);
    e.expectDrawError([&] { e.draw(); }, ErrorCode::LayoutMismatch, {"byte 2036", "stride of 12"});
    // Appended elements are counted in 64 bits too: the one that crosses 2048 is named.
    std::vector<InputElementDesc> many;
    for (uint32_t i = 0; i < 129; ++i) many.push_back({"TEXCOORD", i, Format::R32G32B32A32_FLOAT, 0});
    expectError([&] { InputLayout l(many); }, ErrorCode::LayoutMismatch, {"input element 128", "byte offset 2048"});
}

TEST(InputAssemblerErrors, CountsTooLargeForTheMachineAreRefusedBeforeAllocating) {
    // 4e9 instances of a triangle: 1.2e10 vertex shader outputs (192 GB) are refused as
    // Error(OutOfMemory) naming the count, not thrown as std::bad_alloc, and nothing is drawn.
    ErrorSetup e;
    e.expectDrawError([&] { e.ctx.drawInstanced(VsTransform{}, PsConstant{kWhite}, 3, 4000000000u); },
                      ErrorCode::OutOfMemory, {"12000000000 vertex shader outputs", "4000000000 instances"});
    // 4e9 vertices: the input assembler's arrays (84 GB) are refused before they are made.
    e.expectDrawError([&] { e.ctx.draw(VsTransform{}, PsConstant{kWhite}, 4000000000u); }, ErrorCode::OutOfMemory,
                      {"input assembler", "4000000000 vertices"});
}

TEST(InputAssemblerErrors, TopologyOutsideTheEnumIsNamedByItsValue) {
    ErrorSetup e;
    e.ctx.setPrimitiveTopology(Topology(99));
    e.expectDrawError([&] { e.draw(); }, ErrorCode::InvalidState, {"topology", "invalid value 99"});
}

}  // namespace
}  // namespace raster
