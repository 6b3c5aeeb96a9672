// The back half of a draw, rasterize → PS → OM, runs screen tile by screen tile
// (Context::renderTiles, pipeline_impl.hpp); fillTile (fill/fill_tile.hpp) says which fill path each
// primitive of a tile takes, and why. This file holds what every fill path of one tile shares:
//
//  - FillTraits: which paths a (shader, depth policy, colour policy) combination may take, decided at
//    compile time, once per draw;
//  - Tile: the tile's rectangle, statistics, shader and hooks (draw_hooks.hpp), and the plain
//    per-fragment steps built from the stages — early depth test, shading a 2×2 quad, late depth
//    test and blend — that the in-order path (fill/quads.hpp) is made of and that the eight-wide
//    paths fall back to at a tile's border.
//
// The fill paths, one file each: fill/quads.hpp (in order, quad by quad: the plain path, and the
// only one of lines, points, traced draws and the reference pipeline), fill/triangles_wide.hpp
// (triangles in 4×2 blocks), fill/rectangles.hpp (billboards as screen rectangles),
// fill/deferred.hpp (opaque tiles: depth first, then one shader call per visible fragment).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "raster/bin_primitives.hpp"
#include "raster/fastpath/block_coverage.hpp"
#include "raster/fastpath/depth_bounds.hpp"
#include "raster/fastpath/interpolate_wide.hpp"
#include "raster/fastpath/merge_policy.hpp"
#include "raster/fastpath/merge_wide.hpp"
#include "raster/fastpath/rectangle.hpp"
#include "raster/fastpath/transparency.hpp"
#include "raster/shader.hpp"
#include "raster/stages/7_rasterizer.hpp"
#include "raster/stages/8_pixel_shader.hpp"
#include "raster/stages/9_output_merger.hpp"
#include "raster/statistics.hpp"
#include "raster/trace_recorder.hpp"

#if defined(RASTER_NO_FLATTEN) || defined(__SANITIZE_ADDRESS__)
#define RASTER_FLATTEN
#else
// The fill loops are flattened (their whole call tree inlined): their speed depends on the shader,
// sampler and merge being one block of code (docs/PERFORMANCE.md). Sanitizer builds leave the
// inlining to the compiler (RASTER_NO_FLATTEN, CMakeLists.txt): instrumented, the flattened tree
// takes GCC minutes and gigabytes per file; what the code does is the same either way.
#define RASTER_FLATTEN __attribute__((flatten))
#endif

namespace raster {

namespace detail {

// A copy of a trivially copyable shader (by reference otherwise: a shader that owns resources is
// still called, only without the copy's benefit).
template <class PS>
struct WideShaderCopy {
    std::conditional_t<std::is_trivially_copyable_v<PS>, PS, const PS&> value;
    explicit WideShaderCopy(const PS& ps) : value(ps) {}
    template <class In>
    [[gnu::always_inline]] auto operator()(const In& in) const {
        return value(in);
    }
};

// Two neighbouring blocks' inputs as one Float8x2 input, the left block in half 0.
template <class V>
[[gnu::always_inline]] inline WidePair<V> zipBlocks(const Wide<V>& left, const Wide<V>& right) {
    constexpr uint32_t kN = kVertexFloats<V>;
    Float8 l[kN], r[kN];
    std::memcpy(l, static_cast<const void*>(&left), sizeof l);
    std::memcpy(r, static_cast<const void*>(&right), sizeof r);
    Float8x2 f[kN];
    for (uint32_t k = 0; k < kN; ++k) f[k] = Float8x2(l[k], r[k]);
    WidePair<V> out;
    static_assert(sizeof out == sizeof f);
    std::memcpy(static_cast<void*>(&out), f, sizeof f);
    return out;
}
}  // namespace detail

// Which fill paths a draw may take, from its types alone. Real is float in the fast pipeline and
// double in the reference one.
template <class PS, class Real, class Hooks, class Depth, class Color>
struct FillTraits {
    // The reference pipeline tests depth after the shader, in D3D's literal order; the fast one
    // before it (the result is the same: shaders here cannot write depth).
    static constexpr bool kEarlyDepth = std::is_same_v<Real, float>;
    // The shader runs eight pixels (a 4×2 block) per call.
    static constexpr bool kWide = [] {
        if constexpr (WidePixelShader<PS>)
            return std::is_same_v<Real, float> && std::is_same_v<PixelShaderOutput<PS>, glm::vec4> &&
                   !Hooks::kEnabled;
        else
            return false;
    }();
    // Eight-wide with an eight-wide depth test and blend: triangles take fill/triangles_wide.hpp.
    static constexpr bool kWideMerge = kWide && Depth::kWide && Color::kWide;
    // Two neighbouring blocks per shader call where the shader also takes Float8x2 (shadePair).
    static constexpr bool kPairs = [] {
        if constexpr (PairPixelShader<PS>)
            return kWide;
        else
            return false;
    }();
    // Opaque draws with depth writes may be shaded deferred (fill/deferred.hpp).
    static constexpr bool kDeferrable = [] {
        if constexpr (requires { Depth::kWrite; })
            return kWideMerge && Depth::kEnabled && Depth::kWrite &&
                   std::is_same_v<Color, ColorFast<BlendReplaceRgba8>>;
        else
            return false;
    }();
    // Billboard pixels known to be transparent before shading are skipped (fastpath/transparency.hpp).
    static constexpr bool kSkipTransparent = kWide && detail::kSkipsTransparent<PS, Depth, Color>;
};

// What all tiles of one draw read: the shader, the output merger's policies, the binned primitives.
template <class PS, class V, class Depth, class Color>
struct DrawFill {
    const PS& ps;
    const Depth& depth;
    const Color& color;
    const std::vector<detail::Chunk<V>>& chunks;
    uint32_t chunkCount;
    float minDepth, maxDepth;  // the viewport's depth range, which interpolated depths are clamped to
    detail::TransparentColumns transparentColumns;  // skips nothing unless kSkipTransparent
    // Every primitive through the plain path (fill/quads.hpp): ContextOptions::plain.
    bool plain = false;
};

// One tile of one draw while a thread fills it: its rectangle, statistics and trace, and the plain
// per-fragment steps of the output merger. Made per tile on the thread that fills it.
template <class PS, class V, class Real, class Hooks, class Depth, class Color>
class Tile : public FillTraits<PS, Real, Hooks, Depth, Color> {
  public:
    using Traits = FillTraits<PS, Real, Hooks, Depth, Color>;
    using Draw = DrawFill<PS, V, Depth, Color>;
    using Vertex = V;
    using HooksType = Hooks;
    using RealType = Real;
    using DepthPolicyType = Depth;
    using ColorPolicyType = Color;
    using Out = PixelShaderOutput<PS>;

    Tile(const Draw& draw, uint32_t index, const PixelRect& rect, PipelineStatistics& st,
         const Hooks& hooks)
        : draw(draw),
          index(index),
          rect(rect),
          st(st),
          shader(draw.ps),
          wideShader(draw.ps),
          hooks(hooks),
          bounds(draw.depth, rect) {}

    const Draw& draw;
    const uint32_t index;  // in the tile grid: the bins' index
    const PixelRect rect;
    PipelineStatistics& st;
    QuadShader<PS> shader;
    // The eight-wide paths call a copy of the shader that lives on this thread's stack and whose
    // address stays inside the inlined loop: the compiler may then keep the shader's constants
    // (and what it computes from them alone) in registers across the blocks, which it cannot do
    // through `ps`, since a store to the targets might, for all it knows, change `ps`.
    const detail::WideShaderCopy<PS> wideShader;
    Hooks hooks;  // the trace's recording and a lab's coverage rule, or none (draw_hooks.hpp)
    TileDepthBounds<Depth, !Hooks::kEnabled> bounds;

    // The input primitive whose fragments follow, for the trace.
    void notePrimitive([[maybe_unused]] uint32_t primitive_id) {
        if constexpr (Hooks::kEnabled) hooks.primitive = primitive_id;
    }

    // A depth no fragment of triangle t lies in front of: interpolated depths stay within the
    // vertices' (to double rounding, far below the 2^-20 margin) and are clamped to the viewport.
    float nearestDepth(const TriangleSetup& t) const {
        const float lowest = std::min({t.z[0], t.z[1], t.z[2]});
        return std::clamp(lowest - std::abs(lowest) * 0x1p-20f, draw.minDepth, draw.maxDepth);
    }

    // Whether the depth test runs after the shader (the reference pipeline, DepthDynamic::late).
    bool lateDepth() const {
        if constexpr (!Traits::kEarlyDepth)
            return true;
        else if constexpr (std::is_same_v<Depth, DepthDynamic>)
            return draw.depth.late;
        else
            return false;
    }

    // The early depth test of one fragment (the fast pipeline: before the shader), counted.
    bool earlyDepthPasses(int32_t x, int32_t y, Real z) {
        if constexpr (Hooks::kEnabled) hooks.covered(x, y);
        if constexpr (Traits::kEarlyDepth && Depth::kEnabled) {
            if (!lateDepth() && !draw.depth.test(x, y, float(z))) {
                countEarlyDepthKilled(1);
                if constexpr (Hooks::kEnabled)
                    hooks.close(hooks.open(x, y, float(z), false, glm::vec4(0.0f)),
                                 FragmentFate::EarlyDepthFailed);
                return false;
            }
        }
        return true;
    }

    // The output merger for one shaded fragment: discard, late depth test (the reference pipeline),
    // depth write, blend.
    FragmentFate depthTestAndBlend(int32_t x, int32_t y, Real z, const Out& out) {
        if (isDiscarded(out)) {
            countDiscarded(1);
            return FragmentFate::Discarded;
        }
        if constexpr (Depth::kEnabled) {
            if (lateDepth() && !draw.depth.test(x, y, float(z))) {
                countLateDepthKilled(1);
                return FragmentFate::LateDepthFailed;
            }
        }
        draw.depth.write(x, y, float(z));
        const auto& colors = colorsOf(out);
        if (draw.color.isNoOp(colors)) {
            countBlendNoOps(1);
            return FragmentFate::BlendNoOp;
        }
        draw.color.write(x, y, colors);
        return FragmentFate::Written;
    }
    // depthTestAndBlend, recorded in the trace when tracing.
    void merge(int32_t x, int32_t y, Real z, const Out& out) {
        if constexpr (Hooks::kEnabled) {
            if (!hooks.active) {
                depthTestAndBlend(x, y, z, out);
                return;
            }
            glm::vec4 target0(0.0f);
            if (!isDiscarded(out)) {
                const auto& colors = colorsOf(out);
                target0 = detail::ColorTraits<std::decay_t<decltype(colors)>>::color(colors, 0);
            }
            const size_t record = hooks.open(x, y, float(z), !isDiscarded(out), target0);
            hooks.close(record, depthTestAndBlend(x, y, z, out));
        } else {
            depthTestAndBlend(x, y, z, out);
        }
    }

    // One 2×2 quad at (qx, qy), lanes in `mask`: early depth test, shader, output merger.
    // depth_at(lane) gives a lane's depth, fill(lane, z, in) its shader input (also for helper lanes,
    // which may lie outside the primitive).
    template <class DepthAt, class FillInput>
    void shadeQuad(int32_t qx, int32_t qy, uint32_t mask, DepthAt&& depth_at, FillInput&& fill) {
        V in[4];
        Out out[4];
        Real z[4];
        uint32_t live = 0;
        for (uint32_t m = mask; m; m &= m - 1) {
            const int lane = std::countr_zero(m);
            z[lane] = depth_at(lane);
            if (!earlyDepthPasses(qx + (lane & 1), qy + (lane >> 1), z[lane])) continue;
            fill(lane, z[lane], in[lane]);
            live |= 1u << lane;
        }
        if (!live) return;
        countShaded(uint64_t(std::popcount(live)), 0);  // its helpers: counted by the shader stage
        shader.shade(
            in, live, out, [&](int lane, V& helper) { fill(lane, depth_at(lane), helper); }, st);
        for (uint32_t m = live; m; m &= m - 1) {
            const int lane = std::countr_zero(m);
            merge(qx + (lane & 1), qy + (lane >> 1), z[lane], out[lane]);
        }
    }

    // The eight-wide early depth test of a 4×2 block inside the tile: the covered lanes that pass,
    // those that fail counted.
    uint32_t depthTestBlock(const Depth& depth, int32_t x, int32_t y, Float8 z, uint32_t covered) {
        const uint32_t live = covered & depth.testWide(x, y, z);
        countEarlyDepthKilled(uint64_t(std::popcount(covered & ~live)));
        return live;
    }
    // One 4×2 block's inputs through an eight-wide shader, its invocations (lanes in `live`) and
    // helper lanes counted.
    template <class Shader, class In>
    glm::vec<4, Float8> shadeInputWide(const Shader& s, const In& in, uint32_t live) {
        const glm::vec<4, Float8> c = s(in);
        const uint64_t n = uint64_t(std::popcount(live));
        countShaded(n, 8 - n);
        return c;
    }
    // One 4×2 block of a triangle through an eight-wide shader: its attributes interpolated, then
    // shadeInputWide.
    template <class Shader>
    glm::vec<4, Float8> shadeBlockWide(const Shader& s, const TriangleInterpolant<Real>& ti,
                                       const int64_t (&e)[3][8], const V* const (&verts)[3], int32_t x,
                                       int32_t y, Float8 z, uint32_t live) {
        Wide<V> in;
        interpolateAttributesWide(ti, e, verts, x, y, z, in);
        return shadeInputWide(s, in, live);
    }
    // Two such blocks of one triangle, interpolated already, through one Float8x2 call (the same
    // bits as a call each): two shaders' dependency chains interleaved (see fill/rectangles.hpp).
    // (A template over the input, Wide<V>, which exists only for vertex structs templated over
    // their scalar type: a signature naming Wide<V> would not compile for the others.)
    template <class Shader, class WideIn>
    glm::vec<4, Float8x2> shadePairWide(const Shader& s, const WideIn& left, const WideIn& right,
                                        uint32_t live_left, uint32_t live_right) {
        const glm::vec<4, Float8x2> c = s(detail::zipBlocks<V>(left, right));
        const uint64_t n = uint64_t(std::popcount(live_left) + std::popcount(live_right));
        countShaded(n, 16 - n);
        return c;
    }

    // ---- What happened to the tile's fragments (statistics.hpp says what each counter means). Every
    // fill path counts through these, per fragment or in sums, so that each counts alike.
    // Fragments shaded, and helper lanes the same shader calls ran (lanes outside the primitive or
    // failing the depth test, shaded for a 2×2 quad's or a 4×2 block's sake).
    void countShaded(uint64_t fragments, uint64_t helpers) {
        st.psInvocations += fragments;
        st.helperInvocations += helpers;
    }
    void countEarlyDepthKilled(uint64_t n) { st.fragmentsEarlyDepthKilled += n; }
    void countLateDepthKilled(uint64_t n) { st.fragmentsLateDepthKilled += n; }
    void countDiscarded(uint64_t n) { st.fragmentsDiscarded += n; }
    // Merged, but the blend could not change the pixel.
    void countBlendNoOps(uint64_t n) { st.fragmentsBlendNoOp += n; }
    // Passed the depth test, not shaded: each of the following says why.
    void countSaturated(uint64_t n) { st.fragmentsBlendSaturated += n; }
    void countTransparentSkipped(uint64_t n) { st.fragmentsTransparentSkipped += n; }
    void countOverdrawSkipped(uint64_t n) { st.fragmentsOverdrawSkipped += n; }
};

}  // namespace raster
