// The output merger's fast twins for R8G8B8A8_UNORM: whole blends fixed at compile time, each
// accelerating the rule mergeFragment<float> (stages/9_output_merger.hpp) for one blend state and
// storing exactly its bytes. tests/output_merger_test.cpp (FastBlender) checks each against that rule.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "raster/simd/ops.hpp"
#include "raster/stages/9_output_merger.hpp"

namespace raster {

// ---- Fast paths for R8G8B8A8_UNORM ----------------------------------------------------------------
// Blenders for the pipeline's hot loop, each fixed to one RenderTargetBlendDesc with write mask 0xF.
// apply(pixel, src) writes the fragment into the 4 bytes at pixel (R, G, B, A) and stores exactly the
// bytes mergeFragment<float> would; isNoOp(src) is true when apply could not change any pixel value, so
// the fragment may be skipped. No branches on the data.

// Blending off: the pixel becomes src, clamped and rounded.
struct BlendReplaceRgba8 {
    // All four channels in one register (simd::storeUnorm8x4): every lane performs floatToUnorm8's
    // IEEE operations in the same order, hence the same bytes.
    static void apply(uint8_t* pixel, const glm::vec4& src) {
        simd::storeUnorm8x4(pixel, src);
    }
    static bool isNoOp(const glm::vec4&) { return false; }
};

// BlendState::additive(): rgb = s.rgb * s.a + d.rgb, a = s.a * s.a + d.a, with s clamped to [0, 1].
// A fragment whose clamped alpha is 0 (alpha <= 0 or NaN) adds exactly 0 to every channel: a no-op.
struct BlendAdditiveRgba8 {
    // The alpha channel's s.a * s.a is the colour channels' expression too, so all four lanes do
    // s * s.a + d: the operations blendColor performs, in its order (its d * 1 is exact).
    // In one register (simd::additiveBlendUnorm8x4): detail::addUnits255 in every lane.
    static void apply(uint8_t* pixel, const glm::vec4& src) {
        simd::additiveBlendUnorm8x4(pixel, src);
    }
    static bool isNoOp(const glm::vec4& src) { return detail::saturate(src.w) == 0.0f; }
};

}  // namespace raster
