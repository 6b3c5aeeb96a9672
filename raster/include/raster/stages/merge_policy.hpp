// How the per-pixel loop talks to the depth buffer and the render targets, chosen once per draw.
//
// The pipeline looks at the draw's depth-stencil and blend state and the bound targets, picks one
// depth policy and one colour policy, and instantiates the tile loop for that pair: the common
// states (depth LESS / LESS_EQUAL with or without write, blending off or the lecture's additive
// blend on one RGBA8 target) get code with the state folded in at compile time; anything else
// takes the generic policies, which read the state per fragment. The reference pipeline always
// takes the generic policies, in double.
#pragma once

#include <cstdint>
#include <type_traits>
#include <variant>

#include "raster/render_target.hpp"
#include "raster/states.hpp"
#include "raster/stages/output_merger.hpp"

namespace raster {

struct DepthOff {
    static constexpr bool kEnabled = false;
    bool test(int32_t, int32_t, float) const { return true; }
    void write(int32_t, int32_t, float) const {}
};

template <ComparisonFunc F, bool Write>
struct DepthFixed {
    static constexpr bool kEnabled = true;
    float* depth;
    uint32_t width;
    bool test(int32_t x, int32_t y, float z) const { return depthPassesT<F>(z, depth[size_t(y) * width + x]); }
    void write(int32_t x, int32_t y, float z) const {
        if constexpr (Write) depth[size_t(y) * width + x] = z;
    }
};

struct DepthDynamic {
    static constexpr bool kEnabled = true;
    float* depth;
    uint32_t width;
    ComparisonFunc func;
    bool writeEnabled;
    bool test(int32_t x, int32_t y, float z) const { return depthPasses(func, z, depth[size_t(y) * width + x]); }
    void write(int32_t x, int32_t y, float z) const {
        if (writeEnabled) depth[size_t(y) * width + x] = z;
    }
};

using DepthPolicy = std::variant<DepthOff, DepthFixed<ComparisonFunc::Less, true>, DepthFixed<ComparisonFunc::Less, false>,
                                 DepthFixed<ComparisonFunc::LessEqual, true>,
                                 DepthFixed<ComparisonFunc::LessEqual, false>, DepthDynamic>;

// One RGBA8 target with a compile-time blender from output_merger.hpp.
template <class Blender>
struct ColorFast {
    uint8_t* pixels;
    uint32_t width;
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
    RenderTarget* const* targets;
    int count;
    const BlendState* blend;
    template <class Colors>
    bool isNoOp(const Colors&) const {
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
    template <class Colors>
    bool isNoOp(const Colors&) const {
        return true;
    }
    template <class Colors>
    void write(int32_t, int32_t, const Colors&) const {}
};

using ColorPolicy = std::variant<ColorNone, ColorFast<BlendReplaceRgba8>, ColorFast<BlendAdditiveRgba8>,
                                 ColorGeneric<float>, ColorGeneric<double>>;

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
