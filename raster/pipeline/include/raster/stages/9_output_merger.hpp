// Stage 9, the output merger's arithmetic, one fragment at a time: the depth test, the D3D11 blend equation, and
// the write of a blended colour into a render-target pixel with the target format's conversion rules.
// The states themselves (and what each enumerator means) are in raster/states.hpp.
//
// Everything is a header template so that the pipeline can specialise its per-fragment loop per draw:
// on the precision (Real = float for the normal pipeline, double for the reference pipeline) and on the
// depth function (depthPassesT). The whole-blend twins of mergeFragment<float> for the common
// R8G8B8A8_UNORM cases live beside the fill paths, in raster/fastpath/blend_rgba8.hpp.
// Nothing here validates a state: the pipeline calls validate() (states.hpp) before a draw.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <glm/glm.hpp>

#include "raster/check.hpp"
#include "raster/format.hpp"
#include "raster/render_target.hpp"
#include "raster/states.hpp"

namespace raster {

// ---- Depth ----------------------------------------------------------------------------------------
// Whether a fragment at depth `fragment` passes against the depth buffer's `stored` value under F
// (see ComparisonFunc): IEEE comparisons, so a NaN on either side fails everything but NotEqual and
// Always. -0 and +0 are equal.
template <ComparisonFunc F>
bool depthPassesT(float fragment, float stored) {
    if constexpr (F == ComparisonFunc::Never)
        return false;
    else if constexpr (F == ComparisonFunc::Less)
        return fragment < stored;
    else if constexpr (F == ComparisonFunc::Equal)
        return fragment == stored;
    else if constexpr (F == ComparisonFunc::LessEqual)
        return fragment <= stored;
    else if constexpr (F == ComparisonFunc::Greater)
        return fragment > stored;
    else if constexpr (F == ComparisonFunc::NotEqual)
        return fragment != stored;
    else if constexpr (F == ComparisonFunc::GreaterEqual)
        return fragment >= stored;
    else
        return true;
}

// The same with the function chosen at run time. A value out of range fails (validate() refuses it).
inline bool depthPasses(ComparisonFunc f, float fragment, float stored) {
    switch (f) {
        case ComparisonFunc::Never: return depthPassesT<ComparisonFunc::Never>(fragment, stored);
        case ComparisonFunc::Less: return depthPassesT<ComparisonFunc::Less>(fragment, stored);
        case ComparisonFunc::Equal: return depthPassesT<ComparisonFunc::Equal>(fragment, stored);
        case ComparisonFunc::LessEqual: return depthPassesT<ComparisonFunc::LessEqual>(fragment, stored);
        case ComparisonFunc::Greater: return depthPassesT<ComparisonFunc::Greater>(fragment, stored);
        case ComparisonFunc::NotEqual: return depthPassesT<ComparisonFunc::NotEqual>(fragment, stored);
        case ComparisonFunc::GreaterEqual:
            return depthPassesT<ComparisonFunc::GreaterEqual>(fragment, stored);
        case ComparisonFunc::Always: return depthPassesT<ComparisonFunc::Always>(fragment, stored);
    }
    return false;
}

namespace detail {

// Clamp to [0, 1] with NaN -> 0, as D3D saturates. The operand order is what makes NaN go to 0:
// std::max(0, NaN) is 0, std::max(NaN, 0) would be NaN.
template <class Real>
Real saturate(Real v) {
    return std::min(Real(1), std::max(Real(0), v));
}

template <class Real>
glm::vec<4, Real> saturate(const glm::vec<4, Real>& v) {
    return {saturate(v.x), saturate(v.y), saturate(v.z), saturate(v.w)};
}

// The four-component factor `b` names (see Blend), in units where 1 is `one`: callers that work in
// units of 1/255 pass inputs scaled by 255 and one = 255, and get 255 * factor. Always inlined: GCC
// otherwise calls it from the generic blend, each factor through memory (the smoke scene, 6 %).
template <class Real>
[[gnu::always_inline]] inline glm::vec<4, Real> blendFactor(Blend b, const glm::vec<4, Real>& src,
                                                            const glm::vec<4, Real>& src1,
                                                            const glm::vec<4, Real>& dst,
                                                            const glm::vec<4, Real>& constant, Real one) {
    using V = glm::vec<4, Real>;
    switch (b) {
        case Blend::Zero: return V(Real(0));
        case Blend::One: return V(one);
        case Blend::SrcColor: return src;
        case Blend::InvSrcColor: return V(one) - src;
        case Blend::SrcAlpha: return V(src.w);
        case Blend::InvSrcAlpha: return V(one - src.w);
        case Blend::DestAlpha: return V(dst.w);
        case Blend::InvDestAlpha: return V(one - dst.w);
        case Blend::DestColor: return dst;
        case Blend::InvDestColor: return V(one) - dst;
        case Blend::SrcAlphaSat: {
            const Real f = std::min(src.w, one - dst.w);
            return V(f, f, f, one);
        }
        case Blend::BlendFactor: return constant;
        case Blend::InvBlendFactor: return V(one) - constant;
        case Blend::Src1Color: return src1;
        case Blend::InvSrc1Color: return V(one) - src1;
        case Blend::Src1Alpha: return V(src1.w);
        case Blend::InvSrc1Alpha: return V(one - src1.w);
    }
    return V(Real(0));
}

// D3D's min/max return the other operand when one is NaN.
template <class Real>
Real minNumber(Real a, Real b) {
    return (a < b || b != b) ? a : b;
}
template <class Real>
Real maxNumber(Real a, Real b) {
    return (a > b || b != b) ? a : b;
}

// One channel of the blend equation from its already weighted terms; Min and Max take the unweighted
// operands.
template <class Real>
Real combine(BlendOp op, Real srcTerm, Real dstTerm, Real src, Real dst) {
    switch (op) {
        case BlendOp::Add: return srcTerm + dstTerm;
        case BlendOp::Subtract: return srcTerm - dstTerm;
        case BlendOp::RevSubtract: return dstTerm - srcTerm;
        case BlendOp::Min: return minNumber(src, dst);
        case BlendOp::Max: return maxNumber(src, dst);
    }
    return Real(0);
}

// A value in units of 1/255 rounded to the nearest byte, ties up, clamped to [0, 255]. x - floor(x) is
// exact in binary floating point, so this is the only rounding (doubleToUnorm8's x * 255 + 0.5 has two
// more).
inline uint8_t roundUnits255(double x) {
    if (!(x > 0.0)) return 0;
    if (x >= 255.0) return 255;
    const double whole = std::floor(x);
    return uint8_t(whole) + uint8_t(x - whole >= 0.5);
}

// Byte n plus the source term s · factor (both in [0, 1], so the term is too) in units of 1/255,
// rounded to nearest with ties up, clamped at 255: n is exact, so this rounds the exact sum of n and
// the float term once. The term is s · (factor · 255), the order the eight-wide blend uses.
inline uint8_t addUnits255(uint8_t n, float s, float factor) {
    const int units = int(s * (factor * 255.0f) + 0.5f);
    return uint8_t(std::min(255, int(n) + units));
}

// The reference path for a UNORM target. In units of 1/255 the destination byte n is exactly n, the
// clamped sources and constant scaled by 255 are exact in double, and so is every factor; n / 255 in
// [0, 1] units is not, and was enough to round 24.5 (28 behind 12.5 % black) down to 24.
inline void blendUnormExact(const RenderTargetBlendDesc& d, const glm::dvec4& src, const glm::dvec4& src1,
                            const glm::dvec4& constant, const uint8_t* pixel, uint8_t out[4]) {
    const glm::dvec4 n(pixel[0], pixel[1], pixel[2], pixel[3]);
    const glm::dvec4 src255 = src * 255.0;
    if (!d.blendEnable) {
        for (int c = 0; c < 4; ++c) out[c] = roundUnits255(src255[c]);
        return;
    }
    const glm::dvec4 src1_255 = src1 * 255.0, constant255 = constant * 255.0;
    auto factor255 = [&](Blend b) { return blendFactor<double>(b, src255, src1_255, n, constant255, 255.0); };
    const glm::dvec4 sf = factor255(d.srcBlend), df = factor255(d.destBlend);
    const double sfa = factor255(d.srcBlendAlpha).w, dfa = factor255(d.destBlendAlpha).w;
    // src * (255 factor) is 255 src factor; n * (255 factor) / 255 is 255 dst factor with one division,
    // exact whenever the quotient is representable.
    for (int c = 0; c < 3; ++c)
        out[c] = roundUnits255(combine(d.blendOp, src[c] * sf[c], n[c] * df[c] / 255.0, src255[c], n[c]));
    out[3] = roundUnits255(combine(d.blendOpAlpha, src.w * sfa, n.w * dfa / 255.0, src255.w, n.w));
}

}  // namespace detail

// ---- Blending -------------------------------------------------------------------------------------
// The D3D11 blend equation (see Blend and BlendOp in states.hpp) for one fragment: rgb from
// srcBlend / destBlend / blendOp, alpha from srcBlendAlpha / destBlendAlpha / blendOpAlpha, each factor
// taken as the 4-vector its Blend value names (rgb for the colour equation, its alpha for the alpha
// equation). src and src1 are the pixel shader's SV_Target0 / SV_Target1, dst the target's current
// value, factor the blend factor, all in [0, 1] units. Ignores blendEnable and the write mask, clamps
// nothing and returns the unclamped result (RevSubtract may give negatives, Add more than 1).
template <class Real>
glm::vec<4, Real> blendColor(const RenderTargetBlendDesc& d, glm::vec<4, Real> src, glm::vec<4, Real> src1,
                             glm::vec<4, Real> dst, glm::vec<4, Real> factor) {
    const Real one(1);
    const auto sf = detail::blendFactor(d.srcBlend, src, src1, dst, factor, one);
    const auto df = detail::blendFactor(d.destBlend, src, src1, dst, factor, one);
    const Real sfa = detail::blendFactor(d.srcBlendAlpha, src, src1, dst, factor, one).w;
    const Real dfa = detail::blendFactor(d.destBlendAlpha, src, src1, dst, factor, one).w;
    glm::vec<4, Real> out;
    for (int c = 0; c < 3; ++c)
        out[c] = detail::combine(d.blendOp, src[c] * sf[c], dst[c] * df[c], src[c], dst[c]);
    out.w = detail::combine(d.blendOpAlpha, src.w * sfa, dst.w * dfa, src.w, dst.w);
    return out;
}

namespace detail {
// mergeFragment<float>'s Add/One channels (the additive blends): the source term alone rounded in
// units of 1/255 and the destination byte n added exactly, as the reference does. Out of line: the
// other blend states, which the generic merger mostly serves, then keep their loop small (inlined
// here, it made GCC move saturate out of line; docs/PERFORMANCE.md has the measurements).
[[gnu::noinline]] inline void addWithDestinationOne(const RenderTargetBlendDesc& d, const glm::vec4& s,
                                                    const glm::vec4& src1, const glm::vec4& factor,
                                                    const glm::vec4& dst, const uint8_t* pixel, uint8_t (&out)[4]) {
    const glm::vec4 s1 = saturate(src1), f = saturate(factor);
    if (d.blendOp == BlendOp::Add && d.destBlend == Blend::One) {
        const glm::vec4 sf = blendFactor(d.srcBlend, s, s1, dst, f, 1.0f);
        for (int c = 0; c < 3; ++c) out[c] = addUnits255(pixel[c], s[c], sf[c]);
    }
    if (d.blendOpAlpha == BlendOp::Add && d.destBlendAlpha == Blend::One)
        out[3] = addUnits255(pixel[3], s.w, blendFactor(d.srcBlendAlpha, s, s1, dst, f, 1.0f).w);
}
}  // namespace detail

// Applies one fragment to pixel (x, y) of rt (x < width, y < height), by the D3D11 rules for its format:
//  - blending off (d.blendEnable false): the pixel becomes src;
//  - blending on: the pixel becomes blendColor(d, src, src1, pixel, factor);
//  - R8G8B8A8_UNORM: src, src1 and factor are first clamped to [0, 1] (NaN -> 0), the pixel is read as
//    n / 255, and the result is clamped and stored rounding to nearest, ties up (floatToUnorm8);
//  - R32G32B32A32_FLOAT: nothing is clamped;
//  - a channel whose bit in d.renderTargetWriteMask is 0 keeps its value.
// Real = float computes in float and rounds as floatToUnorm8 does (f * 255 + 0.5 in float, so a
// value a hair below a tie can round up); where the op is Add and the destination factor One (the
// additive blends), it rounds the source term alone in units of 1/255 and adds the destination byte
// exactly (detail::addUnits255), which is both cheaper and closer to the reference.
// Real = double is the reference: for UNORM it evaluates the blend in double in units of 1/255,
// where the destination byte n is exactly n, and rounds once, to nearest with ties up. The stored
// byte is the exact result so rounded: the destination term is exact up to one division by 255 and
// the source term is exact unless source and factor need more than 53 significant bits together
// (then off by at most about 2^-44 of a step). For FLOAT it computes in double and rounds once, to
// float.
template <class Real>
void mergeFragment(RenderTarget& rt, uint32_t x, uint32_t y, const RenderTargetBlendDesc& d,
                   const glm::vec4& src, const glm::vec4& src1, const glm::vec4& factor) {
    static_assert(std::is_same_v<Real, float> || std::is_same_v<Real, double>, "Real is float or double");
    RASTER_DCHECK(x < rt.width() && y < rt.height());
    const size_t offset = 4 * (size_t(y) * rt.width() + x);
    const unsigned mask = d.renderTargetWriteMask;
    if (rt.format() == Format::R8G8B8A8_UNORM) {
        uint8_t* pixel = rt.rgba8() + offset;
        uint8_t out[4];
        if constexpr (std::is_same_v<Real, double>) {
            detail::blendUnormExact(d, detail::saturate(glm::dvec4(src)), detail::saturate(glm::dvec4(src1)),
                                    detail::saturate(glm::dvec4(factor)), pixel, out);
        } else {
            const glm::vec4 s = detail::saturate(src);
            if (!d.blendEnable) {
                for (int c = 0; c < 4; ++c) out[c] = floatToUnorm8(s[c]);
            } else {
                const glm::vec4 dst(unorm8ToFloat(pixel[0]), unorm8ToFloat(pixel[1]), unorm8ToFloat(pixel[2]),
                                    unorm8ToFloat(pixel[3]));
                const bool add_one = d.blendOp == BlendOp::Add && d.destBlend == Blend::One;
                const bool add_one_alpha = d.blendOpAlpha == BlendOp::Add && d.destBlendAlpha == Blend::One;
                if (!add_one || !add_one_alpha) {
                    const glm::vec4 result = blendColor(d, s, detail::saturate(src1), dst, detail::saturate(factor));
                    for (int c = 0; c < 4; ++c) out[c] = floatToUnorm8(result[c]);
                }
                if (add_one || add_one_alpha) detail::addWithDestinationOne(d, s, src1, factor, dst, pixel, out);
            }
        }
        for (int c = 0; c < 4; ++c)
            if (mask >> c & 1u) pixel[c] = out[c];
    } else {
        RASTER_DCHECK(rt.format() == Format::R32G32B32A32_FLOAT);
        using V = glm::vec<4, Real>;
        float* pixel = rt.rgba32f() + offset;
        V result(src);
        if (d.blendEnable)
            result = blendColor(d, V(src), V(src1), V(pixel[0], pixel[1], pixel[2], pixel[3]), V(factor));
        for (int c = 0; c < 4; ++c)
            if (mask >> c & 1u) pixel[c] = float(result[c]);
    }
}

}  // namespace raster
