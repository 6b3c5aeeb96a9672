// libFuzzer target: the draw front end. The fuzz bytes become an input layout, vertex and index
// buffers, a topology, a draw call, the rasterizer, blend and depth states, a viewport and scissor,
// small render targets and one of a few fixed shader sets; the draw then runs on a one-thread and
// a two-thread context (and sometimes the reference pipeline, and sometimes traced).
//
// The contract checked (pipeline.hpp, check.hpp):
//  - the draw either throws raster::Error, and then every render target is bit for bit what it
//    was before the draw, or it completes, and then every RGBA32F pixel is finite and every depth
//    is finite and in [0, 1] (the targets are cleared to such values and the shaders' outputs are
//    bounded; see each shader);
//  - both contexts (and the reference one) agree on whether it throws and with which ErrorCode,
//    and the one- and two-thread images are bit-identical (a traced draw's too: trace.hpp);
//  - anything else — another exception, a crash, a sanitizer report, a hang, an allocation over
//    libFuzzer's -malloc_limit_mb — is a finding.
// Work is capped so that one input runs in milliseconds: at most 64x64 pixels and, for a draw that
// may run, at most 1024 vertices in all. Absurd counts (up to 2^32 − 1) are passed only where the
// input assembler's checks must refuse them, or where the draw has no instance, so that they test
// that the refusal comes before the allocation.
#include <fuzzer/FuzzedDataProvider.h>
#include <strings.h>

#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "raster/pipeline.hpp"
#include "lecture/fire_shaders.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shaders/billboard.hpp"
#include "raster/texture.hpp"

namespace {

using namespace raster;

// ---- Shaders ------------------------------------------------------------------------------------

struct PosIn {
    glm::vec4 position;
    RASTER_INPUT_SIGNATURE(PosIn, RASTER_INPUT(position, "POSITION", 0))
};
template <class T>
struct PosT {
    glm::vec<4, T> position;
};
using Pos = PosT<float>;

// Pass-through: the vertex buffer's POSITION is the clip-space position.
struct VsPass {
    Pos operator()(const PosIn& in) const { return {in.position}; }
};

// A constant colour, or the fragment's depth as grey (z is in the viewport's [minDepth, maxDepth]
// for every pixel the pipeline shades: stages/8_pixel_shader.hpp). Eight wide too.
struct PsPos {
    using Input = Pos;
    glm::vec4 color{1.0f};
    bool depth = false;
    template <class T>
    glm::vec<4, T> operator()(const PosT<T>& in) const {
        if (depth) return {in.position.z, in.position.z, T(color.z), T(color.w)};
        return {T(color.x), T(color.y), T(color.z), T(color.w)};
    }
};

// Two render targets and discard: scalar only (no eight-wide twin), so the pipeline's scalar path.
struct PsMulti {
    glm::vec4 color0{1.0f}, color1{0.5f};
    uint32_t discardMask = 0;  // bit (x + 2y) mod 32 of a pixel: discarded
    std::optional<std::array<glm::vec4, 2>> operator()(const Pos& in) const {
        const uint32_t bit = (uint32_t(in.position.x) + 2u * uint32_t(in.position.y)) % 32u;
        if (discardMask >> bit & 1u) return std::nullopt;
        return std::array<glm::vec4, 2>{color0, color1};
    }
};

// Triangles in, a strip of `count` vertices out (cut where cutMask says), past maxvertexcount when
// count > 6: then the draw must throw Error(ShaderError) and write nothing.
struct GsTriangles {
    int count = 3;
    uint32_t cutMask = 0;
    float scale = 1.0f;
    void operator()(const Triangle<Pos>& in, TriangleStream<Pos, 6>& out) const {
        for (int i = 0; i < count; ++i) {
            if (cutMask >> i & 1u) out.RestartStrip();
            Pos v = in[size_t(i % 3)];
            v.position.x *= scale;
            out.Append(v);
        }
    }
};

struct GsLines {
    int count = 2;
    uint32_t cutMask = 0;
    void operator()(const Line<Pos>& in, LineStream<Pos, 4>& out) const {
        for (int i = 0; i < count; ++i) {
            if (cutMask >> i & 1u) out.RestartStrip();
            out.Append(in[size_t(i % 2)]);
        }
    }
};

struct TexIn {
    glm::vec4 position;
    glm::vec2 tex;
    RASTER_INPUT_SIGNATURE(TexIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(tex, "TEXCOORD", 0))
};
using shaders::BillboardCorner;
using shaders::BillboardCornerT;

struct VsTex {
    BillboardCorner operator()(const TexIn& in) const { return {in.position, in.tex}; }
};

// Samples the texture at the interpolated coordinate, which the vertex data makes anything: NaN,
// ±Inf, ±3e38. Eight wide too.
struct PsTex {
    using Input = BillboardCorner;
    const Texture2D* texture = nullptr;
    SamplerState sampler;
    template <class T>
    glm::vec<4, T> operator()(const BillboardCornerT<T>& in) const {
        return texture->Sample(sampler, in.tex);
    }
};

// ---- Decoding -----------------------------------------------------------------------------------

struct Input;
const Input* current_input = nullptr;  // for finding(): what the failing input decoded to
void describe(const Input& s);

[[noreturn]] void finding(const char* what, const std::string& detail = "") {
    std::fprintf(stderr, "fuzz_draw: contract broken: %s %s\n", what, detail.c_str());
    if (current_input) describe(*current_input);
    std::abort();
}

// Floats a vertex buffer or a shader constant may hold: the interesting ones often, any bits sometimes.
float specialFloat(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 15)) {
        case 0:
            return std::numeric_limits<float>::quiet_NaN();
        case 1:
            return std::numeric_limits<float>::infinity();
        case 2:
            return -std::numeric_limits<float>::infinity();
        case 3:
            return 1e-40f;  // denormal
        case 4:
            return in.ConsumeBool() ? 3e38f : -3e38f;
        case 5:
            return 0.0f;
        case 6:
            return -0.0f;
        case 7:
            return 1.0f;
        case 8:
            return in.ConsumeBool() ? 1e-30f : -1e-30f;  // w near 0
        case 9:
            return in.ConsumeFloatingPointInRange<float>(-1e6f, 1e6f);
        case 10: {
            uint32_t bits = in.ConsumeIntegral<uint32_t>();
            float f;
            std::memcpy(&f, &bits, sizeof f);
            return f;
        }
        default:
            return in.ConsumeFloatingPointInRange<float>(-2.0f, 2.0f);
    }
}

// A colour component for clears, shader constants and the blend factor: finite and bounded, so
// that no blend overflows and a non-finite pixel is the pipeline's doing.
float boundedFloat(FuzzedDataProvider& in) {
    return in.ConsumeFloatingPointInRange<float>(-2.0f, 2.0f);
}
glm::vec4 boundedColor(FuzzedDataProvider& in) {
    return {boundedFloat(in), boundedFloat(in), boundedFloat(in), boundedFloat(in)};
}

const char* const kSemantics[] = {"POSITION", "TEXCOORD", "COLOR", "position", "NORMAL", "TexCoord"};

uint32_t pickOffset(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 7)) {
        case 0:
            return kAppendAlignedElement;
        case 1:
            return 0xFFFFFFFCu;  // offset + element size wraps around in 32 bits
        case 2:
            return 0xFFFFFFF0u - 4u * in.ConsumeIntegralInRange<uint32_t>(0, 3);
        case 3:
            return 0x80000000u;
        case 4:
            return in.ConsumeIntegral<uint8_t>();  // often not a multiple of 4
        case 5:
            return in.ConsumeIntegral<uint32_t>();
        default:
            return 4u * in.ConsumeIntegralInRange<uint32_t>(0, 16);
    }
}

template <size_t N>
struct Bytes {
    uint8_t b[N];
};
template <size_t N>
VertexBuffer makeBufferOf(const std::vector<uint8_t>& bytes) {
    std::vector<Bytes<N>> elements(bytes.size() / N);
    if (!elements.empty()) std::memcpy(elements.data(), bytes.data(), elements.size() * N);
    return VertexBuffer::create(elements);
}
template <size_t... I>
VertexBuffer makeBuffer(size_t stride, const std::vector<uint8_t>& bytes, std::index_sequence<I...>) {
    using Make = VertexBuffer (*)(const std::vector<uint8_t>&);
    static constexpr Make kMake[] = {&makeBufferOf<I + 1>...};
    return kMake[stride - 1](bytes);
}
constexpr size_t kMaxStride = 64;

int32_t pickScissor(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 7)) {
        case 0:
            return INT_MIN;  // right − 1 overflows a 32-bit int
        case 1:
            return INT_MIN + 1;
        case 2:
            return INT_MAX;
        case 3:
            return INT_MAX - 1;
        case 4:
            return -1;
        case 5:
            return in.ConsumeIntegral<int32_t>();
        default:
            return in.ConsumeIntegralInRange<int32_t>(0, 70);
    }
}

float pickViewportFloat(FuzzedDataProvider& in, float typical) {
    switch (in.ConsumeIntegralInRange<int>(0, 9)) {
        case 0:
            return std::numeric_limits<float>::quiet_NaN();
        case 1:
            return std::numeric_limits<float>::infinity();
        case 2:
            return -32768.0f;
        case 3:
            return 32767.0f;
        case 4:
            return in.ConsumeFloatingPointInRange<float>(-100.0f, 100.0f);
        case 5:
            return 1e-30f;
        case 6:
            return -typical;
        default:
            return typical;
    }
}

struct Element {
    int semantic;
    uint32_t semanticIndex;
    uint8_t format;
    uint32_t slot;
    uint32_t offset;
    uint8_t classification;
    uint32_t stepRate;
};

struct Input {
    int shaderSet = 0;
    std::vector<Element> elements;
    struct Buffer {
        bool bound = false;
        size_t stride = 0;  // 0: an empty VertexBuffer{}
        std::vector<uint8_t> bytes;
    };
    std::array<Buffer, 4> buffers;
    int indexKind = 0;  // 0 none, 1 16-bit, 2 32-bit
    std::vector<uint32_t> indices;
    uint8_t topology = 0;
    DrawCall call;
    RasterizerState rasterizer;
    BlendState blend;
    DepthStencilState depth;
    Viewport viewport;
    struct Target {
        bool empty = false;
        uint32_t width = 1, height = 1;
        Format format = Format::R8G8B8A8_UNORM;
        glm::vec4 clear{0.0f};
    };
    std::vector<Target> targets;
    int depthKind = 0;  // 0 none, 1 same size as target 0 (or own size), 2 other size, 3 empty
    uint32_t depthWidth = 1, depthHeight = 1;
    float depthClear = 1.0f;
    PsPos psPos;
    PsMulti psMulti;
    GsTriangles gsTriangles;
    GsLines gsLines;
    glm::vec2 billboardSize{0.1f};
    float billboardScale = 1.0f;
    uint32_t texWidth = 1, texHeight = 1;
    bool texMipmaps = false;
    std::vector<uint8_t> texels;
    SamplerState sampler;
    bool samplerValid = true;
    bool reference = false;
    bool traced = false;
};

Element decodeElement(FuzzedDataProvider& in) {
    Element e;
    e.semantic = in.ConsumeIntegralInRange<int>(0, int(std::size(kSemantics)) - 1);
    e.semanticIndex = in.ConsumeIntegralInRange<int>(0, 7) == 0 ? 1u : 0u;
    e.format = in.ConsumeIntegralInRange<uint8_t>(0, 8);
    if (in.ConsumeIntegralInRange<int>(0, 3) != 0)
        e.format = uint8_t(Format::R32G32B32A32_FLOAT) - in.ConsumeIntegralInRange<uint8_t>(0, 1);
    const int slot = in.ConsumeIntegralInRange<int>(0, 9);
    e.slot = slot < 6    ? 0u
             : slot < 8  ? uint32_t(slot - 5)
             : slot == 8 ? 3u
                         : (in.ConsumeBool() ? 16u : 0xFFFFFFFFu);
    e.offset = in.ConsumeIntegralInRange<int>(0, 2) == 0 ? pickOffset(in) : kAppendAlignedElement;
    if (in.ConsumeIntegralInRange<int>(0, 3) == 0) e.offset = 4u * in.ConsumeIntegralInRange<uint32_t>(0, 8);
    e.classification =
        in.ConsumeIntegralInRange<int>(0, 9) == 0 ? 2 : (in.ConsumeIntegralInRange<int>(0, 3) == 0);
    const int rate = in.ConsumeIntegralInRange<int>(0, 9);
    e.stepRate = rate < 7 ? uint32_t(rate / 2) : rate == 7 ? 0x80000000u : in.ConsumeIntegral<uint32_t>();
    return e;
}

// Counts whose arrays no machine can hold (2^31 vertices need 45 GB for the input assembler alone),
// so validation must refuse them before allocating. Not 2^28: its 5.6 GB fit a 24 GiB machine,
// requireMemory rightly accepts it, and the draw then trips libFuzzer's -rss_limit_mb.
uint32_t absurdCount(FuzzedDataProvider& in) {
    static const uint32_t kAbsurd[] = {0xFFFFFFFFu, 4000000000u, 0x80000000u, 0xFFFFFFFEu};
    return kAbsurd[in.ConsumeIntegralInRange<size_t>(0, std::size(kAbsurd) - 1)];
}

Input decode(FuzzedDataProvider& in) {
    Input s;
    s.shaderSet = in.ConsumeIntegralInRange<int>(0, 5);
    s.reference = in.ConsumeIntegralInRange<int>(0, 7) == 0;
    s.traced = in.ConsumeIntegralInRange<int>(0, 7) == 0;

    // Layout: usually a POSITION element first, so that most inputs get past the layout.
    const int element_count = in.ConsumeIntegralInRange<int>(1, 4);
    for (int i = 0; i < element_count; ++i) s.elements.push_back(decodeElement(in));
    if (in.ConsumeIntegralInRange<int>(0, 3) != 0) s.elements[0].semantic = 0;
    if (s.shaderSet == 4 && element_count > 1 && in.ConsumeBool()) s.elements[1].semantic = 1;

    // Vertex buffers in slots 0..3.
    for (auto& b : s.buffers) {
        b.bound = in.ConsumeIntegralInRange<int>(0, 4) != 0;
        const int stride = in.ConsumeIntegralInRange<int>(0, 12);
        b.stride = stride == 0   ? 0
                   : stride <= 8 ? size_t(4 * stride)
                   : stride == 9 ? 16
                                 : in.ConsumeIntegralInRange<size_t>(1, kMaxStride);
        const size_t count = in.ConsumeIntegralInRange<size_t>(0, in.ConsumeBool() ? 8 : 96);
        const size_t floats = (b.stride * count + 3) / 4;
        for (size_t f = 0; f < floats; ++f) {
            const float v = specialFloat(in);
            uint8_t bytes[4];
            std::memcpy(bytes, &v, 4);
            b.bytes.insert(b.bytes.end(), bytes, bytes + 4);
        }
        b.bytes.resize(b.stride * count);
    }
    // Index buffer.
    s.indexKind = in.ConsumeIntegralInRange<int>(0, 2);
    const size_t index_count = in.ConsumeIntegralInRange<size_t>(0, in.ConsumeBool() ? 12 : 128);
    for (size_t i = 0; i < index_count && s.indexKind != 0; ++i) {
        uint32_t v;
        switch (in.ConsumeIntegralInRange<int>(0, 9)) {
            case 0:
                v = s.indexKind == 1 ? 0xFFFFu : 0xFFFFFFFFu;
                break;  // the cut value
            case 1:
                v = in.ConsumeIntegral<uint32_t>();
                break;
            case 2:
                v = 0xFFFFFFF0u;
                break;
            default:
                v = in.ConsumeIntegralInRange<uint32_t>(0, 40);
        }
        s.indices.push_back(s.indexKind == 1 ? (v & 0xFFFFu) : v);
    }
    // Topology: the five, Undefined, and values outside the enum.
    s.topology = in.ConsumeIntegralInRange<int>(0, 9) == 0 ? in.ConsumeIntegral<uint8_t>()
                                                           : in.ConsumeIntegralInRange<uint8_t>(0, 5);
    if (s.shaderSet == 5 && in.ConsumeBool()) s.topology = uint8_t(Topology::PointList);
    if (s.shaderSet == 1 && in.ConsumeBool()) s.topology = uint8_t(Topology::TriangleList) + in.ConsumeBool();
    if (s.shaderSet == 2 && in.ConsumeBool()) s.topology = uint8_t(Topology::LineList) + in.ConsumeBool();

    // Draw call: one of D3D11's four, as the DrawCall execute() takes.
    const int kind = in.ConsumeIntegralInRange<int>(0, 3);
    s.call.indexed = kind == 1 || kind == 3;
    const bool instanced = kind >= 2;
    s.call.count = in.ConsumeIntegralInRange<uint32_t>(0, 64);
    if (in.ConsumeIntegralInRange<int>(0, 7) == 0) s.call.count = absurdCount(in);
    s.call.start = in.ConsumeIntegralInRange<int>(0, 5) == 0 ? in.ConsumeIntegral<uint32_t>()
                                                             : in.ConsumeIntegralInRange<uint32_t>(0, 8);
    if (s.call.indexed) {
        switch (in.ConsumeIntegralInRange<int>(0, 7)) {
            case 0:
                s.call.baseVertex = INT_MIN;
                break;
            case 1:
                s.call.baseVertex = INT_MAX;
                break;
            case 2:
                s.call.baseVertex = in.ConsumeIntegral<int32_t>();
                break;
            default:
                s.call.baseVertex = in.ConsumeIntegralInRange<int32_t>(-4, 4);
        }
    }
    if (instanced) {
        s.call.instanceCount = in.ConsumeIntegralInRange<uint32_t>(0, 4);
        if (in.ConsumeIntegralInRange<int>(0, 7) == 0) s.call.instanceCount = absurdCount(in);
        s.call.startInstance = in.ConsumeIntegralInRange<int>(0, 5) == 0
                                   ? in.ConsumeIntegral<uint32_t>()
                                   : in.ConsumeIntegralInRange<uint32_t>(0, 4);
    }

    // Rasterizer state, enums sometimes out of range.
    s.rasterizer.fillMode =
        FillMode(in.ConsumeIntegralInRange<uint8_t>(0, in.ConsumeIntegralInRange<int>(0, 9) ? 1 : 255));
    s.rasterizer.cullMode =
        CullMode(in.ConsumeIntegralInRange<uint8_t>(0, in.ConsumeIntegralInRange<int>(0, 9) ? 2 : 255));
    s.rasterizer.frontCounterClockwise = in.ConsumeBool();
    s.rasterizer.depthClipEnable = in.ConsumeBool();
    s.rasterizer.scissorEnable = in.ConsumeBool();
    s.rasterizer.scissorLeft = pickScissor(in);
    s.rasterizer.scissorTop = pickScissor(in);
    s.rasterizer.scissorRight = pickScissor(in);
    s.rasterizer.scissorBottom = pickScissor(in);

    // Blend state: the first two targets' descriptions from the input, the others default unless
    // one is spoilt (validate reads all eight when independentBlendEnable).
    s.blend.alphaToCoverageEnable = in.ConsumeIntegralInRange<int>(0, 15) == 0;
    s.blend.independentBlendEnable = in.ConsumeBool();
    auto blendEnum = [&](int valid) {
        return in.ConsumeIntegralInRange<int>(0, 15) == 0
                   ? in.ConsumeIntegral<uint8_t>()
                   : in.ConsumeIntegralInRange<uint8_t>(0, uint8_t(valid - 1));
    };
    for (int t = 0; t < 2; ++t) {
        RenderTargetBlendDesc& d = s.blend.renderTarget[t];
        d.blendEnable = in.ConsumeBool();
        d.srcBlend = Blend(blendEnum(17));
        d.destBlend = Blend(blendEnum(17));
        d.blendOp = BlendOp(blendEnum(5));
        d.srcBlendAlpha = Blend(blendEnum(17));
        d.destBlendAlpha = Blend(blendEnum(17));
        d.blendOpAlpha = BlendOp(blendEnum(5));
        d.renderTargetWriteMask =
            in.ConsumeIntegralInRange<uint8_t>(0, in.ConsumeIntegralInRange<int>(0, 15) ? 0xF : 0xFF);
    }
    if (in.ConsumeIntegralInRange<int>(0, 15) == 0)
        s.blend.renderTarget[7].blendOp = BlendOp(in.ConsumeIntegral<uint8_t>());
    s.blend.blendFactor = boundedColor(in);

    s.depth.depthEnable = in.ConsumeBool();
    s.depth.depthWriteMask = in.ConsumeBool();
    s.depth.depthFunc = ComparisonFunc(
        in.ConsumeIntegralInRange<uint8_t>(0, in.ConsumeIntegralInRange<int>(0, 15) ? 7 : 255));

    // Targets: 0-2 colour targets of 1x1..64x64, sometimes empty or of another size.
    const uint32_t width = in.ConsumeIntegralInRange<uint32_t>(1, 64),
                   height = in.ConsumeIntegralInRange<uint32_t>(1, 64);
    const int target_count = in.ConsumeIntegralInRange<int>(0, 2);
    for (int t = 0; t < target_count; ++t) {
        Input::Target target;
        target.empty = in.ConsumeIntegralInRange<int>(0, 15) == 0;
        target.width = width, target.height = height;
        if (in.ConsumeIntegralInRange<int>(0, 15) == 0)
            target.width = in.ConsumeIntegralInRange<uint32_t>(1, 64);
        target.format = in.ConsumeBool() ? Format::R8G8B8A8_UNORM : Format::R32G32B32A32_FLOAT;
        target.clear = boundedColor(in);
        s.targets.push_back(target);
    }
    s.depthKind = in.ConsumeIntegralInRange<int>(0, 4);
    if (s.depthKind == 4) s.depthKind = 1;
    s.depthWidth = s.depthKind == 2 ? in.ConsumeIntegralInRange<uint32_t>(1, 64) : width;
    s.depthHeight = s.depthKind == 2 ? in.ConsumeIntegralInRange<uint32_t>(1, 64) : height;
    s.depthClear = in.ConsumeFloatingPointInRange<float>(0.0f, 1.0f);

    // Viewport: the target's, or edge values (NaN, ∞, bounds, tiny).
    s.viewport.topLeftX = in.ConsumeIntegralInRange<int>(0, 3) ? 0.0f : pickViewportFloat(in, 0.0f);
    s.viewport.topLeftY = in.ConsumeIntegralInRange<int>(0, 3) ? 0.0f : pickViewportFloat(in, 0.0f);
    s.viewport.width =
        in.ConsumeIntegralInRange<int>(0, 3) ? float(width) : pickViewportFloat(in, float(width));
    s.viewport.height =
        in.ConsumeIntegralInRange<int>(0, 3) ? float(height) : pickViewportFloat(in, float(height));
    s.viewport.minDepth = in.ConsumeIntegralInRange<int>(0, 3) ? 0.0f : pickViewportFloat(in, 0.5f);
    s.viewport.maxDepth = in.ConsumeIntegralInRange<int>(0, 3) ? 1.0f : pickViewportFloat(in, 1.0f);

    // Shader constants.
    s.psPos.color = boundedColor(in);
    s.psPos.depth = in.ConsumeBool();
    s.psMulti.color0 = boundedColor(in);
    s.psMulti.color1 = boundedColor(in);
    s.psMulti.discardMask = in.ConsumeBool() ? in.ConsumeIntegral<uint32_t>() : 0u;
    s.gsTriangles.count = in.ConsumeIntegralInRange<int>(0, in.ConsumeIntegralInRange<int>(0, 7) ? 6 : 9);
    s.gsTriangles.cutMask = in.ConsumeIntegral<uint8_t>();
    s.gsTriangles.scale = in.ConsumeIntegralInRange<int>(0, 3) ? 1.0f : specialFloat(in);
    s.gsLines.count = in.ConsumeIntegralInRange<int>(0, in.ConsumeIntegralInRange<int>(0, 7) ? 4 : 6);
    s.gsLines.cutMask = in.ConsumeIntegral<uint8_t>();
    s.billboardSize = in.ConsumeIntegralInRange<int>(0, 3)
                          ? glm::vec2(in.ConsumeFloatingPointInRange<float>(0.0f, 1.0f))
                          : glm::vec2(specialFloat(in), specialFloat(in));
    s.billboardScale = in.ConsumeIntegralInRange<int>(0, 3) ? 1.0f : specialFloat(in);

    // Texture and sampler.
    s.texWidth = in.ConsumeIntegralInRange<uint32_t>(1, 8);
    s.texHeight = in.ConsumeIntegralInRange<uint32_t>(1, 8);
    s.texMipmaps = in.ConsumeBool();
    s.texels = in.ConsumeBytes<uint8_t>(4 * s.texWidth * s.texHeight);
    s.texels.resize(4 * s.texWidth * s.texHeight, 0);
    s.sampler.minFilter =
        Filter(in.ConsumeIntegralInRange<uint8_t>(0, in.ConsumeIntegralInRange<int>(0, 15) ? 1 : 255));
    s.sampler.magFilter = Filter(in.ConsumeIntegralInRange<uint8_t>(0, 1));
    s.sampler.mipFilter = Filter(in.ConsumeIntegralInRange<uint8_t>(0, 1));
    s.sampler.addressU =
        AddressMode(in.ConsumeIntegralInRange<uint8_t>(0, in.ConsumeIntegralInRange<int>(0, 15) ? 4 : 255));
    s.sampler.addressV = AddressMode(in.ConsumeIntegralInRange<uint8_t>(0, 4));
    s.sampler.mipLodBias = in.ConsumeIntegralInRange<int>(0, 3) ? 0.0f : specialFloat(in);
    s.sampler.minLod = in.ConsumeIntegralInRange<int>(0, 3) ? 0.0f : specialFloat(in);
    s.sampler.maxLod = in.ConsumeIntegralInRange<int>(0, 3) ? 1000.0f : specialFloat(in);
    s.sampler.borderColor = glm::clamp(boundedColor(in), 0.0f, 1.0f);
    try {
        validate(s.sampler);
    } catch (const Error&) {
        s.samplerValid = false;
    }
    return s;
}

// The decoded input, on stderr: printed with a finding, and for every input when
// RASTER_FUZZ_DESCRIBE=1 (to read what a kept input does).
void describe(const Input& s) {
    std::string t = "shaders " + std::to_string(s.shaderSet) + (s.reference ? " +reference" : "") +
                    (s.traced ? " +traced" : "") + "\nlayout:";
    for (const Element& e : s.elements)
        t += std::string(" {") + kSemantics[e.semantic] + std::to_string(e.semanticIndex) + " fmt " +
             std::to_string(e.format) + " slot " + std::to_string(e.slot) + " off " +
             std::to_string(e.offset) + " class " + std::to_string(e.classification) + " rate " +
             std::to_string(e.stepRate) + "}";
    t += "\nbuffers:";
    for (const Input::Buffer& b : s.buffers)
        t += b.bound
                 ? " {stride " + std::to_string(b.stride) + ", " + std::to_string(b.bytes.size()) + " bytes}"
                 : std::string(" {unbound}");
    t += "\nindices: kind " + std::to_string(s.indexKind) + ", " + std::to_string(s.indices.size());
    t += "\ntopology " + std::to_string(s.topology) + "; call indexed " + std::to_string(s.call.indexed) +
         " count " + std::to_string(s.call.count) + " start " + std::to_string(s.call.start) + " base " +
         std::to_string(s.call.baseVertex) + " instances " + std::to_string(s.call.instanceCount) + " from " +
         std::to_string(s.call.startInstance);
    const RasterizerState& r = s.rasterizer;
    t += "\nrasterizer fill " + std::to_string(int(r.fillMode)) + " cull " + std::to_string(int(r.cullMode)) +
         " ccw " + std::to_string(r.frontCounterClockwise) + " depthClip " +
         std::to_string(r.depthClipEnable) + " scissor " + std::to_string(r.scissorEnable) + " [" +
         std::to_string(r.scissorLeft) + "," + std::to_string(r.scissorTop) + "," +
         std::to_string(r.scissorRight) + "," + std::to_string(r.scissorBottom) + ")";
    char v[200];
    std::snprintf(v, sizeof v, "\nviewport %g %g %g %g depth %g..%g", double(s.viewport.topLeftX),
                  double(s.viewport.topLeftY), double(s.viewport.width), double(s.viewport.height),
                  double(s.viewport.minDepth), double(s.viewport.maxDepth));
    t += v;
    t += "\ntargets:";
    for (const Input::Target& g : s.targets)
        t += " {" +
             (g.empty ? std::string("empty") : std::to_string(g.width) + "x" + std::to_string(g.height)) +
             (g.format == Format::R8G8B8A8_UNORM ? " rgba8}" : " rgba32f}");
    t += " depth kind " + std::to_string(s.depthKind) + " " + std::to_string(s.depthWidth) + "x" +
         std::to_string(s.depthHeight);
    t += "\nblend independent " + std::to_string(s.blend.independentBlendEnable) + " rt0 enable " +
         std::to_string(s.blend.renderTarget[0].blendEnable) + " src " +
         std::to_string(int(s.blend.renderTarget[0].srcBlend)) + " dst " +
         std::to_string(int(s.blend.renderTarget[0].destBlend)) + " op " +
         std::to_string(int(s.blend.renderTarget[0].blendOp)) + "; depth enable " +
         std::to_string(s.depth.depthEnable) + " write " + std::to_string(s.depth.depthWriteMask) + " func " +
         std::to_string(int(s.depth.depthFunc));
    std::fprintf(stderr, "%s\n", t.c_str());
}

// ---- The work cap ---------------------------------------------------------------------------------

// The first layout element the shader's (semantic, index) matches (case-insensitive), or nullptr.
const Element* matched(const Input& s, const char* semantic, uint32_t index) {
    for (const Element& e : s.elements) {
        const char* a = kSemantics[e.semantic];
        if (e.semanticIndex == index && strcasecmp(a, semantic) == 0) return &e;
    }
    return nullptr;
}

uint64_t elementCountOf(const Input& s, uint32_t slot) {
    if (slot >= s.buffers.size() || !s.buffers[slot].bound || s.buffers[slot].stride == 0) return 0;
    return s.buffers[slot].bytes.size() / s.buffers[slot].stride;
}

// Whether the input assembler's range checks must refuse the draw's vertex range, or its instances.
bool mustRefuseVertices(const Input& s) {
    if (s.call.indexed) return uint64_t(s.call.start) + s.call.count > s.indices.size();
    if (uint64_t(s.call.start) + s.call.count > 0xFFFFFFFFull) return true;
    const Element* e = matched(s, "POSITION", 0);
    return e && e->classification == 0 && s.call.instanceCount != 0 && s.call.count != 0 &&
           uint64_t(s.call.start) + s.call.count > elementCountOf(s, e->slot);
}
bool mustRefuseInstances(const Input& s) {
    const Element* e = matched(s, "POSITION", 0);
    return e && e->classification == 1 && e->stepRate >= 1 && e->stepRate <= 4 && s.call.instanceCount != 0 &&
           uint64_t(s.call.startInstance) + (s.call.instanceCount - 1) / e->stepRate >=
               elementCountOf(s, e->slot);
}

void capWork(Input& s) {
    const bool no_instances = s.call.instanceCount == 0;
    const bool no_vertices = s.call.count == 0;
    if (!mustRefuseVertices(s) && !no_instances) s.call.count = std::min<uint32_t>(s.call.count, 256);
    if (!mustRefuseInstances(s) && !no_vertices && !mustRefuseVertices(s))
        s.call.instanceCount = std::min<uint32_t>(s.call.instanceCount, 4);
}

// ---- Running ----------------------------------------------------------------------------------------

struct Resources {
    InputLayout layout;
    std::array<VertexBuffer, 4> buffers;
    IndexBuffer indices;
    std::vector<RenderTarget> targets;
    std::optional<DepthTarget> depth;
    Texture2D texture;
};

// The bytes of every target, to compare bit for bit (== on floats would equate 0 and −0).
std::vector<uint8_t> snapshot(const Resources& r) {
    std::vector<uint8_t> out;
    auto add = [&](const void* p, size_t n) {
        const uint8_t* b = static_cast<const uint8_t*>(p);
        out.insert(out.end(), b, b + n);
    };
    for (const RenderTarget& t : r.targets) {
        const size_t pixels = size_t(t.width()) * t.height();
        if (t.empty()) continue;
        if (t.format() == Format::R8G8B8A8_UNORM)
            add(t.rgba8(), 4 * pixels);
        else
            add(t.rgba32f(), 16 * pixels);
    }
    if (r.depth && !r.depth->empty()) add(r.depth->data(), 4 * size_t(r.depth->width()) * r.depth->height());
    return out;
}

void clearTargets(const Input& s, Resources& r) {
    for (size_t i = 0; i < r.targets.size(); ++i)
        if (!r.targets[i].empty()) r.targets[i].clear(s.targets[i].clear);
    if (r.depth && !r.depth->empty()) r.depth->clear(s.depthClear);
}

// Whether blending into a float target can leave float range from bounded inputs. An equation whose
// destination factor is neither Zero nor One, or whose source factor reads the destination, multiplies
// the destination by up to 3 (1 - s for s in [-2, 2]) or by itself (1 - d.a) once per fragment that
// lands on the pixel, and float arithmetic then rightly reaches ±Inf: D3D11 blends float targets in
// float32, unclamped. (2026-12-03: alpha = (1 - d.a)·d.a - (1 - d.a)·s.a, RevSubtract, from a clear of
// 0.6 under sprites of alpha 1: -0.16, -1.34, -5.47, -41.8, …, -Inf at the ninth overlapping fragment;
// corpus issue30_blend_feedback_overflow.)
// Min and Max stay within their operands, and Zero/One destination factors grow the destination by
// at most a bounded term per fragment.
bool readsDestination(Blend b) {
    return b == Blend::DestAlpha || b == Blend::InvDestAlpha || b == Blend::DestColor ||
           b == Blend::InvDestColor || b == Blend::SrcAlphaSat;
}
bool blendCanDiverge(const RenderTargetBlendDesc& d) {
    if (!d.blendEnable) return false;
    auto equation = [](BlendOp op, Blend src, Blend dst) {
        if (op == BlendOp::Min || op == BlendOp::Max) return false;
        return (dst != Blend::Zero && dst != Blend::One) || readsDestination(src);
    };
    return equation(d.blendOp, d.srcBlend, d.destBlend) || equation(d.blendOpAlpha, d.srcBlendAlpha, d.destBlendAlpha);
}

void checkFinite(const Resources& r, const BlendState& blend, bool color_bounded) {
    for (size_t i = 0; i < r.targets.size(); ++i) {
        const RenderTarget& t = r.targets[i];
        if (t.empty() || t.format() != Format::R32G32B32A32_FLOAT || !color_bounded) continue;
        if (blendCanDiverge(blend.target(int(i)))) continue;
        for (size_t k = 0; k < 4 * size_t(t.width()) * t.height(); ++k)
            if (!std::isfinite(t.rgba32f()[k]))
                finding("non-finite RGBA32F pixel value", std::to_string(t.rgba32f()[k]));
    }
    if (r.depth && !r.depth->empty())
        for (size_t i = 0; i < size_t(r.depth->width()) * r.depth->height(); ++i) {
            const float d = r.depth->data()[i];
            if (!(d >= 0.0f && d <= 1.0f)) finding("depth outside [0, 1]", std::to_string(d));
        }
}

struct Outcome {
    bool threw = false;
    ErrorCode code = ErrorCode::InvalidArgument;
    std::string message;
    std::vector<uint8_t> image;
};

Outcome runOn(Context& ctx, const Input& s, Resources& r, Trace* trace) {
    ctx.resetFrameStatistics();
    ctx.setTrace(trace);
    ctx.setInputLayout(&r.layout);
    for (uint32_t slot = 0; slot < kMaxInputSlots; ++slot)
        ctx.setVertexBuffer(slot,
                            slot < r.buffers.size() && s.buffers[slot].bound ? &r.buffers[slot] : nullptr);
    ctx.setIndexBuffer(s.indexKind ? &r.indices : nullptr);
    ctx.setPrimitiveTopology(Topology(s.topology));
    ctx.setRasterizerState(s.rasterizer);
    ctx.setBlendState(s.blend);
    ctx.setDepthStencilState(s.depth);
    ctx.setViewport(s.viewport);
    std::vector<RenderTarget*> targets;
    for (RenderTarget& t : r.targets) targets.push_back(&t);
    ctx.setRenderTargets(targets, r.depth ? &*r.depth : nullptr);

    clearTargets(s, r);
    const std::vector<uint8_t> before = snapshot(r);
    Outcome o;
    try {
        switch (s.shaderSet) {
            case 0:
                ctx.execute(VsPass{}, NoGeometryShader{}, s.psPos, s.call);
                break;
            case 1:
                ctx.execute(VsPass{}, s.gsTriangles, s.psPos, s.call);
                break;
            case 2:
                ctx.execute(VsPass{}, s.gsLines, s.psPos, s.call);
                break;
            case 3:
                ctx.execute(VsPass{}, NoGeometryShader{}, s.psMulti, s.call);
                break;
            case 4:
                ctx.execute(VsTex{}, NoGeometryShader{}, PsTex{&r.texture, s.sampler}, s.call);
                break;
            default: {
                shaders::GsBillboard gs;
                gs.viewProj = glm::mat4(s.billboardScale);
                gs.billboardSize = s.billboardSize;
                shaders::PsFire ps;
                ps.billboardTexture = &r.texture;
                ps.sampler = s.sampler;
                ctx.execute(shaders::VsBillboard{}, gs, ps, s.call);
            }
        }
    } catch (const Error& e) {
        o.threw = true;
        o.code = e.code();
        o.message = e.what();
    }
    ctx.setTrace(nullptr);
    o.image = snapshot(r);
    if (o.threw && o.image != before) finding("a draw that threw changed a render target:", o.message);
    // Colour outputs are bounded unless the sampler is invalid (an unspecified colour, sampler.hpp).
    if (!o.threw) checkFinite(r, s.blend, s.shaderSet < 4 || s.samplerValid);
    return o;
}

std::optional<Resources> build(const Input& s) {
    Resources r;
    std::vector<InputElementDesc> desc;
    for (const Element& e : s.elements)
        desc.push_back({kSemantics[e.semantic], e.semanticIndex, Format(e.format), e.slot, e.offset,
                        InputClassification(e.classification), e.stepRate});
    // Resources the draw is given are made with their own checks; refused ones end the input.
    try {
        r.layout = InputLayout(desc);
    } catch (const Error&) {
        return std::nullopt;
    }
    for (size_t i = 0; i < r.buffers.size(); ++i)
        if (s.buffers[i].stride != 0)
            r.buffers[i] =
                makeBuffer(s.buffers[i].stride, s.buffers[i].bytes, std::make_index_sequence<kMaxStride>{});
    if (s.indexKind == 1) {
        std::vector<uint16_t> i16(s.indices.begin(), s.indices.end());
        r.indices = IndexBuffer::create(i16);
    } else if (s.indexKind == 2) {
        r.indices = IndexBuffer::create(s.indices);
    }
    for (const Input::Target& t : s.targets)
        r.targets.push_back(t.empty ? RenderTarget() : RenderTarget(t.width, t.height, t.format));
    if (s.depthKind == 3)
        r.depth.emplace();
    else if (s.depthKind != 0)
        r.depth.emplace(s.depthWidth, s.depthHeight);
    r.texture = Texture2D::fromRgba8(s.texWidth, s.texHeight, s.texels, s.texMipmaps);
    return r;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static Context one(ContextOptions{.threads = 1});
    static Context two(ContextOptions{.threads = 2});
    static Context reference(ContextOptions{.threads = 2, .reference = true});
    FuzzedDataProvider in(data, size);
    Input s = decode(in);
    capWork(s);
    current_input = &s;
    static const bool kDescribe = std::getenv("RASTER_FUZZ_DESCRIBE") != nullptr;
    if (kDescribe) describe(s);
    std::optional<Resources> r = build(s);
    if (!r) return 0;

    const Outcome a = runOn(one, s, *r, nullptr);
    Trace trace(TraceOptions{.pixels = TraceOptions::everything()});
    const Outcome b = runOn(two, s, *r, s.traced ? &trace : nullptr);
    if (a.threw != b.threw || (a.threw && a.code != b.code))
        finding("one and two threads disagree on throwing:", a.message + " | " + b.message);
    if (a.image != b.image)
        finding(s.traced ? "the traced two-thread image differs from the one-thread image"
                         : "the two-thread image differs from the one-thread image");
    if (s.reference) {
        const Outcome c = runOn(reference, s, *r, nullptr);
        if (a.threw != c.threw || (a.threw && a.code != c.code))
            finding("the reference pipeline disagrees on throwing:", a.message + " | " + c.message);
    }
    return 0;
}
