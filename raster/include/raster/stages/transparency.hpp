// Transparent billboard pixels, found before shading. A pixel shader that declares an AlphaSource
// (shader.hpp; the lecture's psFire) returns alpha 0 wherever every texel its Sample may read has
// alpha 0, and under the additive blend a fragment of alpha 0 adds exactly 0 to every channel. The
// fire texture is a disc: its corners (a third of a sprite's pixels) are such pixels, and a sprite's
// texture coordinates are affine in the pixel's position (u along x, v along y), so per row pair
// the pixels that may not be transparent are one interval, found from the texture's per-row
// non-transparent columns (Texture2D::alphaSpans) in a few scalar operations. The rectangle loop
// shades only the blocks that meet it; the others are counted as fragmentsTransparentSkipped.
//
// Exactness. A pixel is skipped only if both texel columns and both texel rows of its bilinear
// footprint (the one texel of a point sample is among them) lie where alpha is 0, with Clamp on
// both axes, judged with a margin of kMargin texels on the texel coordinates. The float texture
// coordinate the shader receives differs from the exact plane value by a few ulp; with |u|, |v| ≤
// kMaxCoord and sides ≤ kMaxSide that is below 0.01 texel, and the fixed-point filter's rounding of
// α to 1/256 moves a footprint by less than that. So the image is bit-identical with and without
// the skip (tests/pixel_shader_test.cpp, TransparentSkip). Anything else (another address mode, mip
// levels, texture coordinates that vary along both axes, non-finite or large planes) skips nothing.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include "raster/sampler.hpp"
#include "raster/shader.hpp"
#include "raster/texture.hpp"

namespace raster::detail {

class TransparentColumns {
  public:
    static constexpr double kMargin = 1.0 / 32.0;  // texels
    static constexpr double kMaxCoord = 4.0;       // |u|, |v| anywhere in the rectangle
    static constexpr int32_t kMaxSide = 4096;      // texels

    TransparentColumns() = default;  // skips nothing
    explicit TransparentColumns(const AlphaSource& source) {
        if (!source.texture || !source.sampler) return;
        const Texture2D& t = *source.texture;
        const SamplerState& s = *source.sampler;
        if (t.empty() || t.mipLevels() != 1 || s.addressU != AddressMode::Clamp ||
            s.addressV != AddressMode::Clamp)
            return;
        if (int64_t(t.width()) > kMaxSide || int64_t(t.height()) > kMaxSide) return;
        spans_ = t.alphaSpans();
        width_ = int32_t(t.width());
        height_ = int32_t(t.height());
        u_float_ = source.uvFloat;
    }
    bool enabled() const { return !spans_.empty(); }
    uint32_t uvFloat() const { return u_float_; }

    // One rectangle's texture coordinate planes: u = bu + i·su, v = bv + j·sv for the pixel i
    // columns right of and j rows below the box's top-left one.
    struct Planes {
        bool usable = false;
        double bu = 0, su = 0, bv = 0, sv = 0;
        double inv_su = 0;  // 1 / su, or 0; a product instead of a quotient per row pair
    };
    // `base`, `step_x`, `step_y`: the rectangle's attribute planes (RectSetup); w, h its box's size.
    Planes planes(const float* base, const float* step_x, const float* step_y, int32_t w, int32_t h) const {
        Planes p;
        const uint32_t ku = u_float_, kv = u_float_ + 1;
        if (!enabled() || step_y[ku] != 0.0f || step_x[kv] != 0.0f) return p;
        p.bu = base[ku], p.su = step_x[ku], p.bv = base[kv], p.sv = step_y[kv];
        // NaN fails every comparison, so non-finite planes are rejected here too.
        auto small = [](double a) { return std::abs(a) <= kMaxCoord; };
        p.usable = small(p.bu) && small(p.bu + p.su * w) && small(p.bv) && small(p.bv + p.sv * h);
        if (p.su != 0) p.inv_su = 1.0 / p.su;
        return p;
    }

    // The pixels of the row pair j, j + 1 that may not be transparent: i in [lo, hi], within
    // [i_min, i_max] (the part of the rectangle being drawn). lo > hi: none.
    void rowPair(const Planes& p, int32_t j, int32_t i_min, int32_t i_max, int32_t& lo, int32_t& hi) const {
        lo = i_min, hi = i_max;
        if (!p.usable) return;
        // Texel rows: a footprint reads rows floor(b) and floor(b) + 1, b = v·H − 0.5, clamped.
        const double v0 = p.bv + p.sv * j, v1 = p.bv + p.sv * (j + 1);
        const double h = height_;
        const double b_lo = std::min(v0, v1) * h - 0.5 - kMargin, b_hi = std::max(v0, v1) * h - 0.5 + kMargin;
        const int32_t r0 = std::clamp(int32_t(std::floor(b_lo)), 0, height_ - 1);
        const int32_t r1 = std::clamp(int32_t(std::floor(b_hi)) + 1, 0, height_ - 1);
        int32_t first = width_, last = -1;
        for (int32_t r = r0; r <= r1; ++r) {
            first = std::min(first, spans_[size_t(r)].first);
            last = std::max(last, spans_[size_t(r)].last);
        }
        if (first > last) {
            lo = i_min, hi = i_min - 1;
            return;
        }
        // Texel columns: floor(a) and floor(a) + 1, a = u·W − 0.5, clamped; one of them in
        // [first, last] needs a ≥ first − 1 and a < last + 1 (no bound at a side the clamp reaches).
        const double w = width_;
        const double u_lo = first == 0 ? -kMaxCoord - 1.0 : (first - 1 - kMargin + 0.5) / w;
        const double u_hi = last == width_ - 1 ? kMaxCoord + 1.0 : (last + 1 + kMargin + 0.5) / w;
        double i0, i1;
        if (p.su > 0) {
            i0 = std::ceil((u_lo - p.bu) * p.inv_su), i1 = std::floor((u_hi - p.bu) * p.inv_su);
        } else if (p.su < 0) {
            i0 = std::ceil((u_hi - p.bu) * p.inv_su), i1 = std::floor((u_lo - p.bu) * p.inv_su);
        } else {
            if (p.bu >= u_lo && p.bu <= u_hi) return;
            lo = i_min, hi = i_min - 1;
            return;
        }
        // Clamped in double first: the quotients may be far outside int32_t.
        lo = int32_t(std::clamp(i0, double(i_min), double(i_max) + 1.0));
        hi = int32_t(std::clamp(i1, double(i_min) - 1.0, double(i_max)));
    }

  private:
    std::span<const Texture2D::AlphaSpan> spans_;
    int32_t width_ = 0, height_ = 0;
    uint32_t u_float_ = 0;
};

// The transparency skip for a draw: an AlphaSource shader, a blend for which alpha 0 is a no-op,
// and no depth write (a transparent fragment still writes depth).
template <class PS, class Depth, class Color>
inline constexpr bool kSkipsTransparent = [] {
    if constexpr (AlphaSourcePixelShader<PS> && Color::kAlphaZeroNoOp) {
        if constexpr (requires { Depth::kWrite; })
            return !Depth::kWrite;
        else
            return !Depth::kEnabled;
    } else {
        return false;
    }
}();

}  // namespace raster::detail
