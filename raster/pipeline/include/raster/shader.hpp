// Shaders are plain C++ function objects ("functors"), as HLSL functions are plain functions:
//
//   vertex shader    Out operator()(const In& in) const
//   geometry shader  void operator()(const raster::Point<In>& in, raster::TriangleStream<Out, 4>& out) const
//                    (Point / Line / Triangle input; PointStream / LineStream / TriangleStream output;
//                    the stream's second parameter is HLSL's [maxvertexcount])
//   pixel shader     Color operator()(const In& in) const, where Color is glm::vec4,
//                    std::array<glm::vec4, N> for N render targets, or std::optional of either:
//                    returning std::nullopt is HLSL's `discard`.
//
// Shader resources (textures, samplers, constant buffers) are the functor's members. The pipeline
// is a template over the functor types, so each shader is inlined into the loop that runs it and
// a draw without a geometry shader (raster::NoGeometryShader) pays nothing for that stage.
//
// The structs passed between stages ("vertices") are flat float records whose first member is
// `glm::vec4 position` (SV_Position: clip space out of the vertex or geometry shader; in the pixel
// shader x, y are the pixel centre, z the depth and w the perspective w). Every other member is a
// float, glm::vec2, vec3 or vec4 attribute, interpolated perspective-correctly.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <utility>

#include <glm/glm.hpp>

#include "raster/check.hpp"
#include "raster/simd.hpp"

namespace raster {

template <class V>
concept ShaderVertex = std::is_trivially_copyable_v<V> && std::is_standard_layout_v<V> &&
                       sizeof(V) % sizeof(float) == 0 && alignof(V) == alignof(float) &&
                       requires(V v) {
                           { v.position } -> std::same_as<glm::vec4&>;
                       };

// Floats in a vertex record, position included.
template <class V>
inline constexpr uint32_t kVertexFloats = uint32_t(sizeof(V) / sizeof(float));

template <class V>
const float* asFloats(const V& v) { return reinterpret_cast<const float*>(&v); }
template <class V>
float* asFloats(V& v) { return reinterpret_cast<float*>(&v); }

enum class Topology : uint8_t { Undefined, PointList, LineList, LineStrip, TriangleList, TriangleStrip };
enum class PrimitiveKind : uint8_t { Point = 1, Line = 2, Triangle = 3 };

// Geometry shader input primitives.
template <class V>
using Point = std::array<V, 1>;
template <class V>
using Line = std::array<V, 2>;
template <class V>
using Triangle = std::array<V, 3>;

// A geometry shader's output stream: at most MaxVertices vertices per invocation (HLSL
// [maxvertexcount]). Appending more does not write past the stream: the extra vertices are dropped
// and the draw reports Error(ShaderError) before anything is rasterised.
template <class V, int MaxVertices, PrimitiveKind Kind>
class OutputStream {
public:
    static_assert(MaxVertices > 0 && MaxVertices <= 1024, "HLSL limits maxvertexcount to 1024");
    static constexpr int kMaxVertices = MaxVertices;
    static constexpr PrimitiveKind kKind = Kind;
    using Vertex = V;

    void Append(const V& v) {
        if (count_ == MaxVertices) {
            ++overflow_;
            return;
        }
        cut_[count_] = pending_cut_;
        pending_cut_ = false;
        vertices_[count_++] = v;
    }
    // Ends the current strip; the next Append starts a new one.
    void RestartStrip() { pending_cut_ = true; }

    int size() const { return count_; }
    int overflow() const { return overflow_; }
    // Counts n vertices appended past the limit elsewhere (the teaching pipeline's stream reports
    // what the lab's own stream dropped).
    void addOverflow(int n) { overflow_ += n; }
    const V& vertex(int i) const { return vertices_[i]; }
    // True if a new strip starts at vertex i.
    bool startsStrip(int i) const { return i == 0 || cut_[i]; }
    void reset() {
        count_ = 0;
        overflow_ = 0;
        pending_cut_ = false;
    }

private:
    std::array<V, MaxVertices> vertices_;
    std::array<bool, MaxVertices> cut_{};
    int count_ = 0;
    int overflow_ = 0;
    bool pending_cut_ = false;
};

template <class V, int N>
using PointStream = OutputStream<V, N, PrimitiveKind::Point>;
template <class V, int N>
using LineStream = OutputStream<V, N, PrimitiveKind::Line>;
template <class V, int N>
using TriangleStream = OutputStream<V, N, PrimitiveKind::Triangle>;

// The readable name of a type (demangled: check.hpp's demangle), for error messages.
template <class T>
std::string typeName() {
    return demangle(typeid(T).name());
}

// Stands for "no geometry shader bound".
struct NoGeometryShader {};

namespace detail {

template <class T>
struct CallTraits;
template <class C, class R, class A>
struct CallTraits<R (C::*)(A) const> {
    using Result = R;
    using Arg = std::remove_cvref_t<A>;
};
template <class C, class A, class S>
struct CallTraits<void (C::*)(A, S) const> {
    using Arg = std::remove_cvref_t<A>;
    using Stream = std::remove_cvref_t<S>;
};

template <class A>
struct PrimitiveInput;
template <class V, size_t N>
struct PrimitiveInput<std::array<V, N>> {
    using Vertex = V;
    static constexpr PrimitiveKind kKind = PrimitiveKind(N);
};

template <class R>
struct ColorTraits {
    static_assert(sizeof(R) == 0, "a pixel shader returns glm::vec4, std::array<glm::vec4, N> or std::optional of one");
};
template <>
struct ColorTraits<glm::vec4> {
    static constexpr int kTargets = 1;
    static constexpr bool kCanDiscard = false;
    static const glm::vec4& color(const glm::vec4& c, int) { return c; }
};
template <size_t N>
struct ColorTraits<std::array<glm::vec4, N>> {
    static constexpr int kTargets = int(N);
    static constexpr bool kCanDiscard = false;
    static const glm::vec4& color(const std::array<glm::vec4, N>& c, int i) { return c[i]; }
};
template <class C>
struct ColorTraits<std::optional<C>> {
    static constexpr int kTargets = ColorTraits<C>::kTargets;
    static constexpr bool kCanDiscard = true;
};

}  // namespace detail

template <class VS>
using VertexShaderInput = typename detail::CallTraits<decltype(&VS::operator())>::Arg;
template <class VS>
using VertexShaderOutput = typename detail::CallTraits<decltype(&VS::operator())>::Result;

template <class GS>
using GeometryShaderInput =
    typename detail::PrimitiveInput<typename detail::CallTraits<decltype(&GS::operator())>::Arg>::Vertex;
template <class GS>
inline constexpr PrimitiveKind kGeometryShaderInputKind =
    detail::PrimitiveInput<typename detail::CallTraits<decltype(&GS::operator())>::Arg>::kKind;
template <class GS>
using GeometryShaderStream = typename detail::CallTraits<decltype(&GS::operator())>::Stream;
template <class GS>
using GeometryShaderOutput = typename GeometryShaderStream<GS>::Vertex;

namespace detail {
template <class PS>
struct PixelShaderTraits {
    using Input = typename CallTraits<decltype(&PS::operator())>::Arg;
    using Output = typename CallTraits<decltype(&PS::operator())>::Result;
};
// A shader with both a scalar and a wide operator() names its scalar input type `Input`.
template <class PS>
    requires requires { typename PS::Input; }
struct PixelShaderTraits<PS> {
    using Input = typename PS::Input;
    using Output = decltype(std::declval<const PS&>()(std::declval<const Input&>()));
};

template <class V, class Lanes>
struct WideOf {};
template <template <class> class S, class Lanes>
struct WideOf<S<float>, Lanes> {
    using type = S<Lanes>;
};
}  // namespace detail

template <class PS>
using PixelShaderInput = typename detail::PixelShaderTraits<PS>::Input;
template <class PS>
using PixelShaderOutput = typename detail::PixelShaderTraits<PS>::Output;

// The eight-wide twin of a vertex struct that is a template over its scalar type:
// for `template <class T> struct Corner { glm::vec<4, T> position; glm::vec<2, T> tex; }`,
// Wide<Corner<float>> is Corner<Float8>, one Float8 per float, in the same order.
template <class V>
using Wide = typename detail::WideOf<V, Float8>::type;
// The same struct over Float8x2: two neighbouring 4×2 blocks (simd.hpp).
template <class V>
using WidePair = typename detail::WideOf<V, Float8x2>::type;

// A pixel shader that can also shade eight pixels at once (see simd.hpp).
template <class PS>
concept WidePixelShader = requires { typename Wide<PixelShaderInput<PS>>; } &&
                          sizeof(Wide<PixelShaderInput<PS>>) == kVertexFloats<PixelShaderInput<PS>> * sizeof(Float8) &&
                          requires(const PS& ps, const Wide<PixelShaderInput<PS>>& in) {
                              { ps(in) } -> std::same_as<glm::vec<4, Float8>>;
                          };

// An eight-wide pixel shader that also shades two blocks in one call, over Float8x2. Every shader
// written over its scalar type is one: Float8x2 offers what Float8 offers.
template <class PS>
concept PairPixelShader = WidePixelShader<PS> && requires { typename WidePair<PixelShaderInput<PS>>; } &&
                          sizeof(WidePair<PixelShaderInput<PS>>) ==
                              kVertexFloats<PixelShaderInput<PS>> * sizeof(Float8x2) &&
                          requires(const PS& ps, const WidePair<PixelShaderInput<PS>>& in) {
                              { ps(in) } -> std::same_as<glm::vec<4, Float8x2>>;
                          };

class Texture2D;
struct SamplerState;

// What a pixel shader may declare of its output's alpha, so that the pipeline can skip pixels it
// would leave unchanged: `AlphaSource alphaSource() const` says that the output's alpha is exactly
// zero wherever `texture`, read through `sampler`, has alpha zero in every texel that a Sample at
// the input's float number `uvFloat` (u; v is the next float) may read. The lecture's psFire, which
// returns the sample itself, is one (shaders/billboard.hpp). The pipeline then skips the blocks of a
// billboard whose every pixel lies outside the texture's non-transparent columns (alphaSpans) under
// a blend that adds nothing for alpha zero (the additive blend); see fastpath/transparency.hpp.
// A shader that declares it falsely draws a wrong image, as one that returns a wrong colour would.
struct AlphaSource {
    const Texture2D* texture = nullptr;
    const SamplerState* sampler = nullptr;
    uint32_t uvFloat = 0;
};
template <class PS>
concept AlphaSourcePixelShader = requires(const PS& ps) {
    { ps.alphaSource() } -> std::same_as<AlphaSource>;
};

template <class VS>
concept VertexShader = requires { typename VertexShaderInput<VS>; } && ShaderVertex<VertexShaderOutput<VS>> &&
                       requires { VertexShaderInput<VS>::inputSignature(); };
template <class GS>
concept GeometryShader = std::is_same_v<GS, NoGeometryShader> ||
                         (ShaderVertex<GeometryShaderInput<GS>> && ShaderVertex<GeometryShaderOutput<GS>>);
template <class PS>
concept PixelShader = (requires { typename PS::Input; } ||
                       requires { typename detail::CallTraits<decltype(&PS::operator())>::Result; }) &&
                      ShaderVertex<PixelShaderInput<PS>>;

}  // namespace raster
