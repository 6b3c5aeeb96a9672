// How the per-pixel loop talks to the depth buffer and the render targets, chosen once per draw.
//
// The pipeline looks at the draw's depth-stencil and blend state and the bound targets, picks one
// depth policy and one colour policy, and instantiates the tile loop for that pair. The lecture's
// common states get code with the state folded in at compile time and the eight-wide fill paths
// (kSpecialisedPair: depth off or LESS / LESS_EQUAL with or without write, against blending off or
// the lecture's additive blend into one RGBA8 target: 10 pairs, or those the pixel shader names,
// specialised_states.hpp). Anything else takes the generic policies, which read the state per
// fragment (genericDepthPolicy, genericColorPolicy): the same bits, 6 pairs, compiled once per
// shader set and shared with traced draws, the plain path and files that draw through the generic
// policies only (the teaching pipeline that labs draw through). The reference pipeline always
// takes the generic policies, in double.
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <limits>
#include <variant>

#include "raster/fastpath/blend_rgba8.hpp"
#include "raster/render_target.hpp"
#include "raster/simd.hpp"
#include "raster/specialised_states.hpp"
#include "raster/stages/5_setup.hpp"
#include "raster/stages/9_output_merger.hpp"
#include "raster/states.hpp"

namespace raster {

// Depth and colour policies with kWide also take a whole 4×2 block (rows y and y + 1, columns
// x..x + 3, all inside the target) at once, lane masks as in simd.hpp; they give the same bits as
// eight single-pixel calls.

namespace detail {
template <ComparisonFunc F>
Mask8 depthPasses8(Float8 fragment, Float8 stored) {
    if constexpr (F == ComparisonFunc::Less) return fragment < stored;
    else if constexpr (F == ComparisonFunc::LessEqual) return fragment <= stored;
    else if constexpr (F == ComparisonFunc::Greater) return fragment > stored;
    else if constexpr (F == ComparisonFunc::GreaterEqual) return fragment >= stored;
    else if constexpr (F == ComparisonFunc::Equal) return fragment == stored;
    else if constexpr (F == ComparisonFunc::NotEqual) return fragment != stored;
    else if constexpr (F == ComparisonFunc::Always) return Mask8::fromBits(0xFF);
    else return Mask8::fromBits(0);
}
// D3D's saturate with NaN -> 0, as detail::saturate in stages/9_output_merger.hpp, lane by lane.
inline Float8 saturate8(Float8 v) {
    // max first: max(NaN, 0) is 0, as saturate's NaN rule wants.
    return min(max(v, Float8(0.0f)), Float8(1.0f));
}
inline Int8 toUnorm8x8(Float8 v) { return toInt(saturate8(v) * Float8(255.0f) + Float8(0.5f)); }
}  // namespace detail

struct DepthOff {
    static constexpr bool kEnabled = false;
    static constexpr bool kWide = true;
    uint32_t testWide(int32_t, int32_t, Float8) const { return 0xFF; }
    void writeWide(int32_t, int32_t, Float8, uint32_t) const {}
    bool test(int32_t, int32_t, float) const { return true; }
    void write(int32_t, int32_t, float) const {}
};

template <ComparisonFunc F, bool Write>
struct DepthFixed {
    static constexpr bool kEnabled = true;
    static constexpr bool kWide = true;
    static constexpr ComparisonFunc kFunc = F;
    static constexpr bool kWrite = Write;
    float* depth;
    uint32_t width;
    uint32_t testWide(int32_t x, int32_t y, Float8 z) const {
        const float* row0 = depth + size_t(y) * width + x;
        return detail::depthPasses8<F>(z, loadBlock(row0, row0 + width)).bits();
    }
    void writeWide(int32_t x, int32_t y, Float8 z, uint32_t mask) const {
        if constexpr (Write) {
            float* row0 = depth + size_t(y) * width + x;
            const Float8 old = loadBlock(row0, row0 + width);
            storeBlock(select(Mask8::fromBits(mask), z, old), row0, row0 + width);
        }
    }
    bool test(int32_t x, int32_t y, float z) const { return depthPassesT<F>(z, depth[size_t(y) * width + x]); }
    void write(int32_t x, int32_t y, float z) const {
        if constexpr (Write) depth[size_t(y) * width + x] = z;
    }
    // Per-tile occlusion: under Less and LessEqual a depth write only lowers the stored value, so
    // the farthest stored depth of a tile, taken once per draw, bounds the tile for the whole draw.
    static constexpr bool kBoundsTile = F == ComparisonFunc::Less || F == ComparisonFunc::LessEqual;
    // The nearest stored depth in rect; −∞ if any entry is NaN (a NaN fails every test, so no
    // fragment passes everywhere there).
    float nearest(const PixelRect& rect) const {
        Float8 m(std::numeric_limits<float>::infinity());
        Mask8 nan{simd::I32x8{}};
        float tail = std::numeric_limits<float>::infinity();
        bool tail_nan = false;
        for (int32_t y = rect.y0; y <= rect.y1; ++y) {
            const float* row = depth + size_t(y) * width;
            int32_t x = rect.x0;
            for (; x + 7 <= rect.x1; x += 8) {
                const Float8 d = Float8::load(row + x);
                m = select(d < m, d, m);
                nan = nan | (d != d);
            }
            for (; x <= rect.x1; ++x) tail = row[x] < tail ? row[x] : tail, tail_nan |= row[x] != row[x];
        }
        if (nan.bits() != 0 || tail_nan) return -std::numeric_limits<float>::infinity();
        for (int l = 0; l < 8; ++l) tail = m[l] < tail ? m[l] : tail;
        return tail;
    }
    // True when a fragment of depth `farthest` or nearer passes against every stored depth of at
    // least `nearest`.
    static bool passesAll(float farthest, float nearest) {
        return F == ComparisonFunc::Less ? farthest < nearest : farthest <= nearest;
    }
    // The farthest stored depth in rect (NaN entries, which fail every test, are left out).
    float farthest(const PixelRect& rect) const {
        Float8 m(-std::numeric_limits<float>::infinity());
        float tail = -std::numeric_limits<float>::infinity();
        for (int32_t y = rect.y0; y <= rect.y1; ++y) {
            const float* row = depth + size_t(y) * width;
            int32_t x = rect.x0;
            for (; x + 7 <= rect.x1; x += 8) {
                const Float8 d = Float8::load(row + x);
                m = select(d > m, d, m);
            }
            for (; x <= rect.x1; ++x) tail = row[x] > tail ? row[x] : tail;
        }
        for (int l = 0; l < 8; ++l) tail = m[l] > tail ? m[l] : tail;
        return tail;
    }
    // True when every fragment of depth >= nearest fails against a tile whose farthest depth is `far`.
    static bool occluded(float nearest, float far) {
        return F == ComparisonFunc::Less ? nearest >= far : nearest > far;
    }
};

struct DepthDynamic {
    static constexpr bool kEnabled = true;
    static constexpr bool kWide = false;
    float* depth;
    uint32_t width;
    ComparisonFunc func;
    bool writeEnabled;
    // Tested after the pixel shader, in D3D's literal order (the plain path; the reference pipeline
    // always tests late). The same pixels either way: shaders here cannot write depth.
    bool late = false;
    bool test(int32_t x, int32_t y, float z) const { return depthPasses(func, z, depth[size_t(y) * width + x]); }
    void write(int32_t x, int32_t y, float z) const {
        if (writeEnabled) depth[size_t(y) * width + x] = z;
    }
};

using DepthPolicy = std::variant<DepthOff, DepthFixed<ComparisonFunc::Less, true>, DepthFixed<ComparisonFunc::Less, false>,
                                 DepthFixed<ComparisonFunc::LessEqual, true>,
                                 DepthFixed<ComparisonFunc::LessEqual, false>, DepthDynamic>;

// One RGBA8 target with a compile-time blender from stages/9_output_merger.hpp.
template <class Blender>
struct ColorFast {
    static constexpr bool kWide = std::is_same_v<Blender, BlendReplaceRgba8> || std::is_same_v<Blender, BlendAdditiveRgba8>;
    uint8_t* pixels;
    uint32_t width;
    // Whether this blend has a ceiling: a pixel value no fragment can change. The additive blend
    // adds non-negative units with unsigned saturation, so a pixel at 255 in all four bytes stays
    // there whatever the shader returns (NaN included: saturate makes it 0).
    static constexpr bool kCeiling = std::is_same_v<Blender, BlendAdditiveRgba8>;
    // Whether a fragment of alpha 0 leaves the pixel as it is (the additive blend scales every
    // channel by the source alpha): what the transparency skip needs (transparency.hpp).
    static constexpr bool kAlphaZeroNoOp = std::is_same_v<Blender, BlendAdditiveRgba8>;
    // Whether all pixels of n side-by-side 4×2 blocks at (x, y) are at the ceiling (n = 1 or 2).
    template <int n>
    bool atCeiling(int32_t x, int32_t y) const {
        static_assert(n == 1 || n == 2);
        const uint8_t* row0 = pixels + 4 * (size_t(y) * width + x);
        const uint8_t* row1 = row0 + 4 * size_t(width);
        Int8 both;
        if constexpr (n == 2) {  // two rows of eight: one register each, ANDed, then one test
            // 32-byte loads, though writeWide stores 16 at a time: the blocks' last stores are long
            // retired here, and four 16-byte loads measured slower (PERFORMANCE.md).
            Int8 top, bottom;
            std::memcpy(&top.v, row0, 32);
            std::memcpy(&bottom.v, row1, 32);
            both = top & bottom;
        } else {
            both = loadBlock(row0, row1);
        }
        return (both == Int8(-1)).bits() == 0xFFu;
    }
    // Lanes whose fragment cannot change the pixel.
    uint32_t noOpWide(const glm::vec<4, Float8>& c) const {
        if constexpr (std::is_same_v<Blender, BlendAdditiveRgba8>)
            return (detail::saturate8(c.w) == Float8(0.0f)).bits();
        else
            return 0;
    }
    [[gnu::always_inline]] void writeWide(int32_t x, int32_t y, const glm::vec<4, Float8>& c, uint32_t mask) const {
        uint8_t* row0 = pixels + 4 * (size_t(y) * width + x);
        uint8_t* row1 = row0 + 4 * size_t(width);
        const Int8 old = loadBlock(row0, row1);
        Int8 out;
        if constexpr (std::is_same_v<Blender, BlendAdditiveRgba8>) {
            // As BlendAdditiveRgba8::apply, in units of 1/255: the source term s·(255·a) rounded half
            // up, then the destination byte added exactly, clamped at 255.
            const Int8 sum = simd::additiveBlendRgba8(old.v, c.x.v, c.y.v, c.z.v, c.w.v);
            out = mask == 0xFFu ? sum : select(Mask8::fromBits(mask), sum, old);
        } else {
            const Int8 r = detail::toUnorm8x8(c.x), g = detail::toUnorm8x8(c.y), b = detail::toUnorm8x8(c.z);
            const Int8 a = detail::toUnorm8x8(c.w);
            out = select(Mask8::fromBits(mask), r | (g << 8) | (b << 16) | (a << 24), old);
        }
        storeBlock(out, row0, row1);
    }
    // Whether writeWidePair exists: the additive blend where the core has AVX-512.
    static constexpr bool kWidePair = simd::kAvx512 && std::is_same_v<Blender, BlendAdditiveRgba8>;
    // writeWide for two side-by-side blocks at (x, y) and (x + 4, y) in one 16-lane register, block 0
    // in lanes 0–7 (`mask` bits 0–7) and block 1 in lanes 8–15: the same operations lane by lane, so
    // the same bytes. Returns the lanes whose fragment cannot change the pixel (noOpWide's). Called
    // only where kWidePair.
    [[gnu::always_inline]] uint32_t writeWidePair(int32_t x, int32_t y, const glm::vec<4, Float8x2>& c,
                                                  uint32_t mask) const {
        if constexpr (kWidePair) {
            uint8_t* row0 = pixels + 4 * (size_t(y) * width + x);
            const simd::F32x8 rgba[4][2] = {
                {c.x.h[0].v, c.x.h[1].v}, {c.y.h[0].v, c.y.h[1].v}, {c.z.h[0].v, c.z.h[1].v}, {c.w.h[0].v, c.w.h[1].v}};
            return simd::additiveBlendRgba8Pair(row0, row0 + 4 * size_t(width), rgba, mask);
        } else {
            return 0;
        }
    }
    template <class Colors>
    bool isNoOp(const Colors& c) const {
        return Blender::isNoOp(colorAt(c, 0));
    }
    template <class Colors>
    void write(int32_t x, int32_t y, const Colors& c) const {
        Blender::apply(pixels + 4 * (size_t(y) * width + x), colorAt(c, 0));
    }
    static const glm::vec4& colorAt(const glm::vec4& c, int) { return c; }
    template <size_t N>
    static const glm::vec4& colorAt(const std::array<glm::vec4, N>& c, int i) { return c[i]; }
};

// Any targets, any blend state, per fragment; Real = double in the reference pipeline.
template <class Real>
struct ColorGeneric {
    static constexpr bool kWide = false;
    // No ceiling: traced draws show every fragment, the reference skips none (atCeiling is only
    // called under `if constexpr (Color::kCeiling)`).
    static constexpr bool kCeiling = false;
    static constexpr bool kAlphaZeroNoOp = false;
    static constexpr bool kWidePair = false;
    uint32_t writeWidePair(int32_t, int32_t, const glm::vec<4, Float8x2>&, uint32_t) const { return 0; }
    uint32_t noOpWide(const glm::vec<4, Float8>&) const { return 0; }
    void writeWide(int32_t, int32_t, const glm::vec<4, Float8>&, uint32_t) const {}
    RenderTarget* const* targets;
    int count;
    const BlendState* blend;
    // One RGBA8 target blended additively (SrcAlpha, One): a fragment whose saturated alpha is 0
    // cannot change it, as BlendAdditiveRgba8::isNoOp says (set for traced draws, so that the
    // trace and the statistics show the skip the fast path makes).
    bool additiveUnorm = false;
    template <class Colors>
    bool isNoOp(const Colors& c) const {
        if constexpr (std::is_same_v<Real, float>)
            return additiveUnorm && BlendAdditiveRgba8::isNoOp(at(c, 0));
        else
            return false;
    }
    template <class Colors>
    void write(int32_t x, int32_t y, const Colors& c) const {
        for (int i = 0; i < count; ++i) {
            // The second output feeds the Src1 (dual-source) factors, as SV_Target1 does in D3D11.
            mergeFragment<Real>(*targets[i], uint32_t(x), uint32_t(y), blend->target(i), at(c, i), at(c, 1),
                                blend->blendFactor);
        }
    }
    static const glm::vec4& at(const glm::vec4& c, int) { return c; }
    template <size_t N>
    static const glm::vec4& at(const std::array<glm::vec4, N>& c, int i) {
        return c[size_t(i) < N ? size_t(i) : N - 1];
    }
};

struct ColorNone {  // no render target bound: a depth-only pass
    static constexpr bool kWide = true;
    static constexpr bool kCeiling = false;
    static constexpr bool kAlphaZeroNoOp = false;
    static constexpr bool kWidePair = false;
    uint32_t writeWidePair(int32_t, int32_t, const glm::vec<4, Float8x2>&, uint32_t) const { return 0; }
    uint32_t noOpWide(const glm::vec<4, Float8>&) const { return 0xFF; }
    void writeWide(int32_t, int32_t, const glm::vec<4, Float8>&, uint32_t) const {}
    template <class Colors>
    bool isNoOp(const Colors&) const {
        return true;
    }
    template <class Colors>
    void write(int32_t, int32_t, const Colors&) const {}
};

using ColorPolicy = std::variant<ColorNone, ColorFast<BlendReplaceRgba8>, ColorFast<BlendAdditiveRgba8>,
                                 ColorGeneric<float>, ColorGeneric<double>>;

template <class Color>
constexpr bool kIsColorFast = false;
template <class Blender>
constexpr bool kIsColorFast<ColorFast<Blender>> = true;

// The pairs the tile loop is compiled for with the state folded in (see the top of this file).
// Why these: they are the lecture's opaque geometry and its additive particles, what the benchmark
// scenes draw; each pair costs about a second of -O3 compile per shader set, so a pair is added
// where a scene needs its speed, not for completeness.
template <class Depth, class Color>
constexpr bool kSpecialisedPair = !std::is_same_v<Depth, DepthDynamic> && kIsColorFast<Color>;

// A new alternative of either variant needs its case in specialised_states.hpp (if specialised),
// genericDepthPolicy and withGenericPolicies below.
static_assert(std::variant_size_v<DepthPolicy> == 6 && std::variant_size_v<ColorPolicy> == 5);

namespace detail {
template <DepthState D>
struct DepthPolicyOfT;
template <>
struct DepthPolicyOfT<DepthState::Off> {
    using type = DepthOff;
};
template <>
struct DepthPolicyOfT<DepthState::Less> {
    using type = DepthFixed<ComparisonFunc::Less, true>;
};
template <>
struct DepthPolicyOfT<DepthState::LessNoWrite> {
    using type = DepthFixed<ComparisonFunc::Less, false>;
};
template <>
struct DepthPolicyOfT<DepthState::LessEqual> {
    using type = DepthFixed<ComparisonFunc::LessEqual, true>;
};
template <>
struct DepthPolicyOfT<DepthState::LessEqualNoWrite> {
    using type = DepthFixed<ComparisonFunc::LessEqual, false>;
};
template <BlendMode B>
using ColorPolicyOf = std::conditional_t<B == BlendMode::Replace, ColorFast<BlendReplaceRgba8>, ColorFast<BlendAdditiveRgba8>>;

// run(d, c) if the draw's policies are the pair's; whether they were.
template <class Pair, class Run>
bool runIfPair(const DepthPolicy& depth, const ColorPolicy& color, Run& run) {
    using D = typename DepthPolicyOfT<Pair::kDepth>::type;
    using C = ColorPolicyOf<Pair::kBlend>;
    static_assert(kSpecialisedPair<D, C>);
    const auto* d = std::get_if<D>(&depth);
    const auto* c = std::get_if<C>(&color);
    if (!d || !c) return false;
    run(*d, *c);
    return true;
}
}  // namespace detail

// Calls run(d, c) with the draw's depth and colour policies as their own types when the pair is
// one of `States` (specialised_states.hpp: the pixel shader's SpecialisedStates, or all 10 pairs of
// kSpecialisedPair), and returns true; returns false, without calling run, for any other pair.
template <class... Pairs, class Run>
bool withSpecialisedPolicies(SpecialisedStates<Pairs...>, const DepthPolicy& depth, const ColorPolicy& color,
                             Run&& run) {
    return (detail::runIfPair<Pairs>(depth, color, run) || ...);
}

// The same state through the generic policies: the same bits as the specialised ones
// (output_merger_test and trace_test check it), the state read per fragment.
using GenericDepthPolicy = std::variant<DepthOff, DepthDynamic>;
using GenericColorPolicy = std::variant<ColorNone, ColorGeneric<float>, ColorGeneric<double>>;

namespace detail {
template <ComparisonFunc F, bool Write>
DepthDynamic dynamicDepth(const DepthFixed<F, Write>& d) {
    return DepthDynamic{d.depth, d.width, F, Write};
}
}  // namespace detail

inline GenericDepthPolicy genericDepthPolicy(const DepthPolicy& policy) {
    using enum ComparisonFunc;
    if (const auto* d = std::get_if<DepthOff>(&policy)) return *d;
    if (const auto* d = std::get_if<DepthFixed<Less, true>>(&policy)) return detail::dynamicDepth(*d);
    if (const auto* d = std::get_if<DepthFixed<Less, false>>(&policy)) return detail::dynamicDepth(*d);
    if (const auto* d = std::get_if<DepthFixed<LessEqual, true>>(&policy)) return detail::dynamicDepth(*d);
    if (const auto* d = std::get_if<DepthFixed<LessEqual, false>>(&policy)) return detail::dynamicDepth(*d);
    return std::get<DepthDynamic>(policy);
}

namespace detail {
template <class Depth, class Run>
void withGenericColor(const Depth& depth, const GenericColorPolicy& color, Run& run) {
    if (const auto* c = std::get_if<ColorNone>(&color)) return run(depth, *c);
    if (const auto* c = std::get_if<ColorGeneric<float>>(&color)) return run(depth, *c);
    return run(depth, std::get<ColorGeneric<double>>(color));
}
}  // namespace detail

// Calls run(d, c) with the generic policies as their own types: the 6 generic tile loops.
template <class Run>
void withGenericPolicies(const GenericDepthPolicy& depth, const GenericColorPolicy& color, Run&& run) {
    if (const auto* d = std::get_if<DepthOff>(&depth)) return detail::withGenericColor(*d, color, run);
    return detail::withGenericColor(std::get<DepthDynamic>(depth), color, run);
}

inline GenericColorPolicy genericColorPolicy(const ColorPolicy& policy, const BlendState& blend,
                                             RenderTarget* const* targets, int count) {
    if (std::holds_alternative<ColorNone>(policy)) return ColorNone{};
    if (std::holds_alternative<ColorGeneric<double>>(policy)) return std::get<ColorGeneric<double>>(policy);
    if (std::holds_alternative<ColorGeneric<float>>(policy)) return std::get<ColorGeneric<float>>(policy);
    return ColorGeneric<float>{targets, count, &blend,
                               std::holds_alternative<ColorFast<BlendAdditiveRgba8>>(policy)};
}

inline bool sameBlend(const RenderTargetBlendDesc& a, const RenderTargetBlendDesc& b) {
    return a.blendEnable == b.blendEnable && a.srcBlend == b.srcBlend && a.destBlend == b.destBlend &&
           a.blendOp == b.blendOp && a.srcBlendAlpha == b.srcBlendAlpha && a.destBlendAlpha == b.destBlendAlpha &&
           a.blendOpAlpha == b.blendOpAlpha && a.renderTargetWriteMask == b.renderTargetWriteMask;
}

inline DepthPolicy chooseDepthPolicy(const DepthStencilState& ds, DepthTarget* depth, bool reference) {
    if (!depth || !ds.depthEnable) return DepthOff{};
    float* d = depth->data();
    const uint32_t w = depth->width();
    if (!reference) {
        if (ds.depthFunc == ComparisonFunc::Less)
            return ds.depthWriteMask ? DepthPolicy(DepthFixed<ComparisonFunc::Less, true>{d, w})
                                     : DepthPolicy(DepthFixed<ComparisonFunc::Less, false>{d, w});
        if (ds.depthFunc == ComparisonFunc::LessEqual)
            return ds.depthWriteMask ? DepthPolicy(DepthFixed<ComparisonFunc::LessEqual, true>{d, w})
                                     : DepthPolicy(DepthFixed<ComparisonFunc::LessEqual, false>{d, w});
    }
    return DepthDynamic{d, w, ds.depthFunc, ds.depthWriteMask};
}

inline ColorPolicy chooseColorPolicy(const BlendState& bs, RenderTarget* const* targets, int count, bool reference) {
    if (count == 0) return ColorNone{};
    if (reference) return ColorGeneric<double>{targets, count, &bs};
    if (count == 1 && targets[0]->format() == Format::R8G8B8A8_UNORM) {
        const RenderTargetBlendDesc& d = bs.target(0);
        RenderTargetBlendDesc replace;  // blending off, full write mask
        if (sameBlend(d, replace) || (!d.blendEnable && d.renderTargetWriteMask == 0xF))
            return ColorFast<BlendReplaceRgba8>{targets[0]->rgba8(), targets[0]->width()};
        if (sameBlend(d, BlendState::additive().target(0)))
            return ColorFast<BlendAdditiveRgba8>{targets[0]->rgba8(), targets[0]->width()};
    }
    return ColorGeneric<float>{targets, count, &bs};
}

// True when the blend result does not depend on the order fragments arrive in (so no sort is
// needed): blending off with no overlap is not order-independent, additive ONE/SRC_ALPHA-ONE is.
inline bool isOrderIndependent(const BlendState& bs, int count) {
    for (int i = 0; i < count; ++i) {
        const RenderTargetBlendDesc& d = bs.target(i);
        if (!d.blendEnable) return false;
        const bool add = d.blendOp == BlendOp::Add && d.blendOpAlpha == BlendOp::Add;
        const bool minmax = (d.blendOp == BlendOp::Min || d.blendOp == BlendOp::Max) &&
                            (d.blendOpAlpha == BlendOp::Min || d.blendOpAlpha == BlendOp::Max);
        const bool dst_one = d.destBlend == Blend::One && d.destBlendAlpha == Blend::One;
        const bool src_indep = d.srcBlend != Blend::DestColor && d.srcBlend != Blend::InvDestColor &&
                               d.srcBlend != Blend::DestAlpha && d.srcBlend != Blend::InvDestAlpha &&
                               d.srcBlend != Blend::SrcAlphaSat && d.srcBlendAlpha != Blend::DestAlpha &&
                               d.srcBlendAlpha != Blend::InvDestAlpha && d.srcBlendAlpha != Blend::SrcAlphaSat;
        if (!(minmax || (add && dst_one && src_indep))) return false;
    }
    return count > 0;
}

}  // namespace raster
