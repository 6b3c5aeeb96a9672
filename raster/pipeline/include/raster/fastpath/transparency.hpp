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
#include <utility>

#include "raster/sampler.hpp"
#include "raster/shader.hpp"
#include "raster/simd.hpp"
#include "raster/texture.hpp"

namespace raster::detail {

class TransparentColumns {
  public:
    static constexpr double kMargin = 1.0 / 32.0;  // texels
    static constexpr double kMaxCoord = 4.0;       // |u|, |v| anywhere in the rectangle
    static constexpr int32_t kMaxSide = 4096;      // texels
    static constexpr int kRowPairsPadding = 3;     // rowPairs' output room past n

    TransparentColumns() = default;  // skips nothing
    explicit TransparentColumns(const AlphaSource& source) {
        if (!source.texture || !source.sampler) return;
        const Texture2D& t = *source.texture;
        const SamplerState& s = *source.sampler;
        if (t.empty() || t.mipLevels() != 1 || s.addressU != AddressMode::Clamp ||
            s.addressV != AddressMode::Clamp)
            return;
        if (int64_t(t.width()) > kMaxSide || int64_t(t.height()) > kMaxSide) return;
        if (t.alphaSpans().empty()) return;
        texture_ = &t;
        width_ = int32_t(t.width());
        height_ = int32_t(t.height());
        u_float_ = source.uvFloat;
        a_below_ = -(kMaxCoord + 1.0) * double(width_), a_above_ = (kMaxCoord + 1.0) * double(width_);
    }
    bool enabled() const { return texture_ != nullptr; }
    uint32_t uvFloat() const { return u_float_; }

    // One rectangle's planes in texel coordinates: the sampler's a = u·W − 0.5 and b = v·H − 0.5 at
    // the pixel i columns right of and j rows below the box's top-left one are a0 + i·sa and
    // b0 + j·sb (in double, a few 1e−13 texel from the same products of the float planes).
    struct Planes {
        bool usable = false;
        bool constant_u = false;  // |sa| ≤ kFlat: a is a0 across the box, to well within kMargin
        double a0 = 0, sa = 0, b0 = 0, sb = 0;
        double inv_sa = 0;  // 1 / sa unless constant_u: a product instead of a quotient per row pair
        // Bounds of a beyond every a in the box (|u| ≤ kMaxCoord), for a side the clamp reaches.
        double a_below = 0, a_above = 0;
    };
    static constexpr double kFlat = 1e-12;  // texels per pixel
    // `base`, `step_x`, `step_y`: the rectangle's attribute planes (RectSetup); w, h its box's size.
    Planes planes(const float* base, const float* step_x, const float* step_y, int32_t w, int32_t h) const {
        Planes p;
        const uint32_t ku = u_float_, kv = u_float_ + 1;
        if (!enabled() || step_y[ku] != 0.0f || step_x[kv] != 0.0f) return p;
        const double bu = base[ku], su = step_x[ku], bv = base[kv], sv = step_y[kv];
        // NaN fails every comparison, so non-finite planes are rejected here too.
        auto small = [](double a) { return std::abs(a) <= kMaxCoord; };
        p.usable = small(bu) && small(bu + su * w) && small(bv) && small(bv + sv * h);
        if (!p.usable) return p;
        const double tw = width_, th = height_;
        p.a0 = bu * tw - 0.5, p.sa = su * tw, p.b0 = bv * th - 0.5, p.sb = sv * th;
        p.constant_u = std::abs(p.sa) <= kFlat;
        if (!p.constant_u) p.inv_sa = 1.0 / p.sa;
        p.a_below = a_below_, p.a_above = a_above_;
        return p;
    }

    // The pixels of the row pair j, j + 1 that may not be transparent: i in [lo, hi], within
    // [i_min, i_max] (the part of the rectangle being drawn). lo > hi: none. No division and no
    // loop: the row pair's texel rows' spans in one query (Texture2D::alphaSpanOfRows).
    void rowPair(const Planes& p, int32_t j, int32_t i_min, int32_t i_max, int32_t& lo, int32_t& hi) const {
        lo = i_min, hi = i_max;
        if (!p.usable) return;
        // Texel rows: a footprint reads rows floor(b) and floor(b) + 1, clamped.
        const double b_top = p.b0 + p.sb * j, b_bottom = b_top + p.sb;
        const double b_lo = std::min(b_top, b_bottom) - kMargin, b_hi = std::max(b_top, b_bottom) + kMargin;
        const int32_t r0 = std::clamp(int32_t(std::floor(b_lo)), 0, height_ - 1);
        const int32_t r1 = std::clamp(int32_t(std::floor(b_hi)) + 1, 0, height_ - 1);
        const Texture2D::AlphaSpan span = texture_->alphaSpanOfRows(r0, r1);
        if (span.first > span.last) {
            lo = i_min, hi = i_min - 1;
            return;
        }
        // Texel columns: floor(a) and floor(a) + 1, clamped; one of them in [first, last] needs
        // a ≥ first − 1 and a < last + 1 (no bound at a side the clamp reaches).
        const double a_lo = span.first == 0 ? p.a_below : span.first - 1 - kMargin;
        const double a_hi = span.last == width_ - 1 ? p.a_above : span.last + 1 + kMargin;
        if (p.constant_u) {
            if (!(p.a0 >= a_lo && p.a0 <= a_hi)) lo = i_min, hi = i_min - 1;
            return;
        }
        // The columns where a0 + i·sa lies in [a_lo, a_hi], for either sign of sa.
        const double t_lo = (a_lo - p.a0) * p.inv_sa, t_hi = (a_hi - p.a0) * p.inv_sa;
        const double i0 = std::ceil(std::min(t_lo, t_hi)), i1 = std::floor(std::max(t_lo, t_hi));
        // Clamped in double first: the quotients may be far outside int32_t.
        lo = int32_t(std::clamp(i0, double(i_min), double(i_max) + 1.0));
        hi = int32_t(std::clamp(i1, double(i_min) - 1.0, double(i_max)));
    }

    // rowPair for the n row pairs j0, j0 + 2, …, j0 + 2(n − 1): lo[q], hi[q] for row pair j0 + 2q,
    // the same values. With AVX2 four row pairs at a time (simd::spanIntervals, the same double
    // operations, lane by lane): the rectangle loop asks for all of a tile's row pairs at once. lo
    // and hi must have room for n rounded up to a multiple of four (kRowPairsPadding more); what
    // lies past n is unspecified.
    void rowPairs(const Planes& p, int32_t j0, int n, int32_t i_min, int32_t i_max, int32_t* lo, int32_t* hi) const {
        int q = 0;
        if (p.usable && !p.constant_u) {
            static_assert(sizeof(Texture2D::AlphaSpan) == 2 * sizeof(int32_t));
            const simd::SpanRows rows{reinterpret_cast<const int32_t*>(texture_->alphaSpanTable().data()),
                                      width_, height_, p.a0, p.inv_sa, p.b0, p.sb, p.a_below, p.a_above,
                                      kMargin, i_min, i_max};
            q = simd::spanIntervals(rows, j0, n, lo, hi);  // none where there is no vector version
        }
        for (; q < n; ++q) rowPair(p, j0 + 2 * q, i_min, i_max, lo[q], hi[q]);
    }

  private:
    const Texture2D* texture_ = nullptr;
    int32_t width_ = 0, height_ = 0;
    uint32_t u_float_ = 0;
    double a_below_ = 0, a_above_ = 0;  // Planes::a_below, a_above: the texture's alone
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
