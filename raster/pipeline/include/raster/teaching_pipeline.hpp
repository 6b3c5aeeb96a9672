// The teaching pipeline: the whole draw compiled once, in the library, for shaders seen through
// function pointers, so that a file that draws (a lab) compiles its own shaders and nothing else.
//
// A draw in a lab file (raster/lab.hpp includes raster/teaching_draw.hpp) wraps the lab's functors
// here and calls Context::executeTeaching, which runs the same stages as any other draw — IA, VS,
// GS, clip, setup, bin, rasterize, PS, OM, in the same files — through the generic depth and colour
// policies. The image is the same, bit for bit, as the lab's functors drawn through the template
// pipeline with the generic policies: every attribute is interpolated on its own, so the floats a
// vertex carries beyond the lab's struct change none of the lab's floats (tests/teaching_test.cpp).
//
// What it costs: a lab's translation unit compiles in seconds and in a fraction of the memory
// (labs/README.md has the figures); a pixel shader is an indirect call, and every vertex carries
// kTeachingVertexFloats floats through clipping and interpolation however few the lab's struct has.
// The benchmark scenes never take this path.
//
// Rules a lab's shaders follow here (each is checked when the file compiles, with a message):
//   - vertex structs start with `glm::vec4 position` (shader.hpp's rule) and hold at most
//     kTeachingVertexFloats floats; the vertex shader's input struct at most kTeachingInputFloats;
//   - a geometry shader takes points or triangles and writes a TriangleStream of at most
//     kTeachingMaxVertices vertices (the lecture's billboards and what a lab needs; another kind is
//     one more explicit instantiation in src/teaching_pipeline.cpp);
//   - a pixel shader returns what shader.hpp allows, for at most kMaxRenderTargets targets.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "raster/input_layout.hpp"
#include "raster/render_target.hpp"
#include "raster/shader.hpp"
#include "raster/stages/5_setup.hpp"

namespace raster {

// Floats one vertex carries between the stages of a teaching draw, position included (32: 128 bytes).
inline constexpr uint32_t kTeachingVertexFloats = 32;
// Floats of a vertex shader's input struct in a teaching draw.
inline constexpr uint32_t kTeachingInputFloats = 32;
// A teaching draw's geometry shader writes at most this many vertices per invocation.
inline constexpr int kTeachingMaxVertices = 64;

// A vertex between the stages: the lab's struct, float for float, then zeros.
struct TeachingVertex {
    glm::vec4 position;
    float attributes[kTeachingVertexFloats - 4];
};
// The vertex shader's input: the lab's input struct, byte for byte, as the input assembler fetched it.
struct TeachingInput {
    float floats[kTeachingInputFloats];
    // The signature is the lab's, per draw (TeachingVertexShader::signature): none of its own.
    static std::span<const ShaderInputField> inputSignature() { return {}; }
};
using TeachingColors = std::optional<std::array<glm::vec4, kMaxRenderTargets>>;
using TeachingTriangleStream = TriangleStream<TeachingVertex, kTeachingMaxVertices>;

// The names and sizes the pipeline reports in messages and in the trace: the lab's, not these.
struct TeachingShaderInfo {
    std::string name;         // the lab's functor type
    uint32_t floats = 0;      // floats of the lab's output struct (vertex, geometry shader)
};

struct TeachingVertexShader {
    const void* shader = nullptr;
    void (*run)(const void* shader, const TeachingInput& in, TeachingVertex& out) = nullptr;
    std::vector<ShaderInputField> signature;      // the lab's input struct's (a copy: it is returned by value)
    uint32_t inputBytes = 0;                      // sizeof the lab's input struct
    std::string inputName;                        // its type
    TeachingShaderInfo info;

    TeachingVertex operator()(const TeachingInput& in) const {
        TeachingVertex out{};
        run(shader, in, out);
        return out;
    }
};

template <PrimitiveKind In>
struct TeachingGeometryShader {
    const void* shader = nullptr;
    void (*run)(const void* shader, const std::array<TeachingVertex, size_t(In)>& in,
                TeachingTriangleStream& out) = nullptr;
    int maxVertices = 0;  // the lab's [maxvertexcount]
    TeachingShaderInfo info;

    void operator()(const std::array<TeachingVertex, size_t(In)>& in, TeachingTriangleStream& out) const {
        run(shader, in, out);
    }
};

// The rasterizer lab's coverage test for one teaching draw (Context::setCoverageTest): when `test` is
// set, the draw's triangles cover the pixels it says, asked for every pixel centre of each triangle's
// box (fill/quads.hpp), instead of the library's rule; the triangle given in the draw's vertex order
// (clockwise unless frontCounterClockwise says the facing was read the other way round) with its
// window positions computed by `viewport` exactly as setup computes them before snapping.
// Lines and points keep the library's rules, and so do billboard rectangles (a draw with a
// coverage test sets none up: each strip is drawn as its two triangles).
struct TeachingCoverage {
    CoverageTest test = nullptr;
    ViewportTransform viewport;
    bool frontCounterClockwise = false;
};

struct TeachingPixelShader {
    const void* shader = nullptr;
    void (*run)(const void* shader, const TeachingVertex& in, TeachingColors& out) = nullptr;
    int targets = 1;  // render targets the lab's shader writes
    TeachingShaderInfo info;
    // Set by Context::executeTeaching from the context's coverage test; the draw reads it through
    // detail::coverageRule into its hooks (DrawHooks::coverage, draw_hooks.hpp). The template
    // pipeline's shaders have none.
    TeachingCoverage coverage;

    TeachingColors operator()(const TeachingVertex& in) const {
        TeachingColors out;
        run(shader, in, out);
        return out;
    }
};

namespace detail {

template <class V>
void checkTeachingVertex() {
    static_assert(offsetof(V, position) == 0,
                  "a teaching draw's vertex structs start with `glm::vec4 position` (raster/shader.hpp)");
    static_assert(sizeof(V) <= sizeof(TeachingVertex),
                  "a teaching draw's vertex struct holds at most kTeachingVertexFloats floats "
                  "(raster/teaching_pipeline.hpp)");
}

// The lab's struct from a TeachingVertex (its leading floats), and back (zeros after it).
template <class V>
V narrowVertex(const TeachingVertex& t) {
    V v;
    std::memcpy(static_cast<void*>(&v), &t, sizeof(V));
    return v;
}
template <class V>
TeachingVertex widenVertex(const V& v) {
    TeachingVertex t{};
    std::memcpy(static_cast<void*>(&t), &v, sizeof(V));
    return t;
}

// A lab's pixel shader output as the teaching pipeline's: what ColorGeneric would read from the
// lab's own type at every target index (a single colour at every index, as for Src1 blending; an
// array's last colour past its end), or nullopt for a discard.
inline void widenColors(const glm::vec4& c, TeachingColors& out) {
    out.emplace();
    out->fill(c);
}
template <size_t N>
void widenColors(const std::array<glm::vec4, N>& c, TeachingColors& out) {
    static_assert(N >= 1 && N <= kMaxRenderTargets, "a pixel shader writes 1 to kMaxRenderTargets targets");
    out.emplace();
    for (size_t i = 0; i < kMaxRenderTargets; ++i) (*out)[i] = c[i < N ? i : N - 1];
}
template <class C>
void widenColors(const std::optional<C>& c, TeachingColors& out) {
    if (c)
        widenColors(*c, out);
    else
        out.reset();
}

}  // namespace detail

// The lab's functors seen through function pointers. The functors must outlive the draw.
template <class VS>
TeachingVertexShader teachingVertexShader(const VS& vs) {
    using In = VertexShaderInput<VS>;
    using Out = VertexShaderOutput<VS>;
    static_assert(sizeof(In) <= sizeof(TeachingInput),
                  "a teaching draw's vertex shader input holds at most kTeachingInputFloats floats");
    detail::checkTeachingVertex<Out>();
    TeachingVertexShader t;
    t.shader = &vs;
    t.run = [](const void* shader, const TeachingInput& in, TeachingVertex& out) {
        In lab_in;
        std::memcpy(static_cast<void*>(&lab_in), &in, sizeof(In));
        out = detail::widenVertex((*static_cast<const VS*>(shader))(lab_in));
    };
    const auto signature = In::inputSignature();
    t.signature.assign(signature.begin(), signature.end());
    t.inputBytes = uint32_t(sizeof(In));
    t.inputName = typeName<In>();
    t.info = {typeName<VS>(), kVertexFloats<Out>};
    return t;
}

template <class GS>
auto teachingGeometryShader(const GS& gs) {
    constexpr PrimitiveKind kIn = kGeometryShaderInputKind<GS>;
    using Stream = GeometryShaderStream<GS>;
    using In = GeometryShaderInput<GS>;
    using Out = GeometryShaderOutput<GS>;
    static_assert(kIn == PrimitiveKind::Point || kIn == PrimitiveKind::Triangle,
                  "a teaching draw's geometry shader takes points or triangles (raster/teaching_pipeline.hpp)");
    static_assert(Stream::kKind == PrimitiveKind::Triangle,
                  "a teaching draw's geometry shader writes a TriangleStream (raster/teaching_pipeline.hpp)");
    static_assert(Stream::kMaxVertices <= kTeachingMaxVertices,
                  "a teaching draw's geometry shader writes at most kTeachingMaxVertices vertices");
    detail::checkTeachingVertex<In>();
    detail::checkTeachingVertex<Out>();
    TeachingGeometryShader<kIn> t;
    t.shader = &gs;
    t.run = [](const void* shader, const std::array<TeachingVertex, size_t(kIn)>& in,
               TeachingTriangleStream& out) {
        std::array<In, size_t(kIn)> lab_in;
        for (size_t i = 0; i < lab_in.size(); ++i) lab_in[i] = detail::narrowVertex<In>(in[i]);
        Stream lab_out;
        (*static_cast<const GS*>(shader))(lab_in, lab_out);
        for (int i = 0; i < lab_out.size(); ++i) {
            if (i > 0 && lab_out.startsStrip(i)) out.RestartStrip();
            out.Append(detail::widenVertex(lab_out.vertex(i)));
        }
        out.addOverflow(lab_out.overflow());
    };
    t.maxVertices = Stream::kMaxVertices;
    t.info = {typeName<GS>(), kVertexFloats<Out>};
    return t;
}

template <class PS>
TeachingPixelShader teachingPixelShader(const PS& ps) {
    using In = PixelShaderInput<PS>;
    detail::checkTeachingVertex<In>();
    TeachingPixelShader t;
    t.shader = &ps;
    t.run = [](const void* shader, const TeachingVertex& in, TeachingColors& out) {
        detail::widenColors((*static_cast<const PS*>(shader))(detail::narrowVertex<In>(in)), out);
    };
    t.targets = detail::ColorTraits<PixelShaderOutput<PS>>::kTargets;
    t.info = {typeName<PS>(), 0};
    return t;
}

// Which overload of Context::executeTeaching a geometry shader takes.
using TeachingPointGeometryShader = TeachingGeometryShader<PrimitiveKind::Point>;
using TeachingTriangleGeometryShader = TeachingGeometryShader<PrimitiveKind::Triangle>;

// What the pipeline reads of a shader beyond its types, for messages, validation and the trace: a
// functor's own types say it all; a teaching shader says the lab's.
namespace detail {

struct VertexInputDescription {
    std::vector<ShaderInputField> signature;
    size_t bytes = 0;  // of the input struct
    std::string name;  // of the input struct
};
template <class VS>
VertexInputDescription vertexInputOf(const VS&) {
    using In = VertexShaderInput<VS>;
    const auto signature = In::inputSignature();  // a std::array, by value
    return {{signature.begin(), signature.end()}, sizeof(In), typeName<In>()};
}
inline VertexInputDescription vertexInputOf(const TeachingVertexShader& vs) {
    return {vs.signature, vs.inputBytes, vs.inputName};
}

template <class S>
std::string shaderName(const S&) {
    return typeName<S>();
}
inline std::string shaderName(const TeachingVertexShader& s) { return s.info.name; }
template <PrimitiveKind In>
std::string shaderName(const TeachingGeometryShader<In>& s) {
    return s.info.name;
}
inline std::string shaderName(const TeachingPixelShader& s) { return s.info.name; }

// Floats of the vertex shader's output struct.
template <class VS>
uint32_t vertexShaderFloats(const VS&) {
    return kVertexFloats<VertexShaderOutput<VS>>;
}
inline uint32_t vertexShaderFloats(const TeachingVertexShader& vs) { return vs.info.floats; }
// Floats of the geometry shader's output struct, and its [maxvertexcount].
template <class GS>
uint32_t geometryShaderFloats(const GS&) {
    return kVertexFloats<GeometryShaderOutput<GS>>;
}
template <PrimitiveKind In>
uint32_t geometryShaderFloats(const TeachingGeometryShader<In>& gs) {
    return gs.info.floats;
}
template <class GS>
int maxVertexCount(const GS&) {
    return GeometryShaderStream<GS>::kMaxVertices;
}
template <PrimitiveKind In>
int maxVertexCount(const TeachingGeometryShader<In>& gs) {
    return gs.maxVertices;
}
inline int maxVertexCount(const NoGeometryShader&) { return 0; }
// Render targets the pixel shader writes.
template <class PS>
int pixelShaderTargets(const PS&) {
    return ColorTraits<PixelShaderOutput<PS>>::kTargets;
}
inline int pixelShaderTargets(const TeachingPixelShader& ps) { return ps.targets; }
// The draw's coverage rule (DrawHooks::coverage): a teaching draw's when the lab set a test; none for
// every other shader.
template <class PS>
const TeachingCoverage* coverageRule(const PS&) {
    return nullptr;
}
inline const TeachingCoverage* coverageRule(const TeachingPixelShader& ps) {
    return ps.coverage.test ? &ps.coverage : nullptr;
}

}  // namespace detail

}  // namespace raster
