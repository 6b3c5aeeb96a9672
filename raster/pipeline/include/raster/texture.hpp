// Textures: a 2D image with an optional mip chain, read by shaders through HLSL's Texture2D methods
// (Load, Sample, SampleLevel, SampleGrad) under a SamplerState, by the Direct3D 11 rules.
//
// Storage. R8G8B8A8_UNORM keeps the bytes and reads texel n as n/255; R32G32B32A32_FLOAT keeps
// floats. Row 0 is the top row of the image, at v = 0.
//
// Mip chain (on request at creation). Level i is max(1, W >> i) × max(1, H >> i), down to 1×1, so
// a W×H texture has 1 + floor(log2(max(W, H))) levels. Each level is a box filter of the one above:
// texel (x, y) of a level w×h made from a level W×H covers the exact area [x·W/w, (x+1)·W/w) ×
// [y·H/h, (y+1)·H/h) of it and is the area-weighted mean of the texels that area touches. For even
// sides that is the plain 2×2 average; an odd side (say 5 → 2) weights its shared middle texel by the
// fraction covered (0.4, 0.4, 0.2 and 0.2, 0.4, 0.4), so every level keeps the image's mean. The means
// are computed in float from the level above as the shader reads it; UNORM levels are then rounded
// to bytes by floatToUnorm8 (half up), so each UNORM level is built from the rounded one above.
//
// Texture coordinates. (u, v) = (0, 0) is the top-left corner of texel (0, 0) and (1, 1) the
// bottom-right corner of the last texel; texel i's centre is at (i + 0.5) / W. At a level W×H:
//  - Point filtering reads texel (floor(u·W), floor(v·H)).
//  - Linear filtering takes a = u·W − 0.5, b = v·H − 0.5, i = floor(a), j = floor(b), α = a − i,
//    β = b − j and returns lerp(lerp(t(i, j), t(i+1, j), α), lerp(t(i, j+1), t(i+1, j+1), α), β)
//    with lerp(x, y, t) = x + (y − x)·t. At a texel centre α = β = 0 and the texel comes back
//    exactly (whenever u·W − 0.5 is exact in float, as it is for power-of-two sizes).
//  - Every texel index is mapped by the sampler's address mode for its axis on its own (see
//    AddressMode); a Border texel reads borderColor. Texel coordinates are clamped to ±2^24 first
//    (float has no fraction bits left there) and NaN reads as −2^24, so no coordinate can index out
//    of bounds.
//
// Level of detail (Sample and SampleGrad), in levels; W×H is level 0's size:
//     λ = log2(max(|ddx·(W, H)|, |ddy·(W, H)|)) + mipLodBias, then clamped to [minLod, maxLod].
// Zero or NaN derivatives give log2(0) = −∞, hence λ = minLod. SampleLevel uses λ = lod + mipLodBias,
// clamped the same way (a NaN lod also gives minLod). Then:
//  - λ ≤ 0 is magnification: level 0 with magFilter.
//  - λ > 0 is minification with minFilter, λ further clamped to mipLevels() − 1. mipFilter Point reads
//    level floor(λ + 0.5): the nearest level, ties going to the smaller (coarser) level, e.g. λ = 0.5
//    reads level 1. mipFilter Linear blends levels floor(λ) and floor(λ) + 1 as lerp(c0, c1, frac(λ)).
//
// Precision. Normally all filter arithmetic (coordinates, weights, blends, λ) is float. While
// inReferenceMode() (shader_context.hpp) it is double, from texels read exactly (n/255 in double for
// UNORM), and the result is rounded to float once at the end.
// One exception, the particles' case: linear filtering of a one-level R8G8B8A8_UNORM texture of at
// most kMaxFootprintSide texels a side under Clamp on both axes runs in fixed point, scalar and eight
// wide alike (outside reference mode). α is rounded to 8 fraction bits (D3D11's subtexel precision,
// D3D11_SUBTEXEL_FRACTIONAL_BIT_COUNT; at most 255/256) and β to 14; the weights then sum to exactly
// 2^22 and the sum of weighted bytes is exact in 32 bits. The result differs from the float formula
// above by at most (Δu/256 + Δv/32768)/255 + 2^−22, where Δu and Δv are the largest differences
// between the bytes being blended horizontally and vertically (one 8-bit step for a black-white
// checkerboard, about a thirtieth of one for the fire texture, whose neighbours differ by at most 8);
// at texel centres it is still the texel exactly.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <concepts>

#include <glm/glm.hpp>

#include "raster/simd.hpp"

#include "raster/check.hpp"
#include "raster/format.hpp"
#include "raster/sampler.hpp"
#include "raster/shader_context.hpp"

namespace raster {

class Texture2D {
  public:
    static constexpr uint32_t kMaxSize = 16384;  // D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION

    // An empty texture (no levels), which reads like an unbound shader resource: (0, 0, 0, 0).
    Texture2D() = default;

    // A W×H texture from rgba (4 values a texel, row-major, row 0 on top), with a full mip chain if
    // `mipmaps`. Throws Error(InvalidArgument) for a zero side, a side above kMaxSize, or a span whose
    // size is not 4·W·H.
    static Texture2D fromRgba8(uint32_t width, uint32_t height, std::span<const uint8_t> rgba,
                               bool mipmaps = false);
    static Texture2D fromRgba32f(uint32_t width, uint32_t height, std::span<const float> rgba,
                                 bool mipmaps = false);
    // A PNG file (any colour type and bit depth, expanded to RGBA8) stored as `format`: R8G8B8A8_UNORM
    // keeps the bytes, R32G32B32A32_FLOAT stores n/255. Throws Error(BadFile) naming the path if the
    // file is missing, unreadable or corrupt or its header is over image_io.hpp's size limit (more
    // than kMaxSize a side among them), and Error(InvalidArgument) for any other format.
    static Texture2D fromPng(const std::string& path, Format format = Format::R8G8B8A8_UNORM,
                             bool mipmaps = false);

    bool empty() const { return levels_.empty(); }
    // The size of a mip level, in texels. Throws Error(InvalidArgument) if level ≥ mipLevels(),
    // except that an empty texture reports 0 × 0 at level 0.
    uint32_t width(uint32_t level = 0) const;
    uint32_t height(uint32_t level = 0) const;
    uint32_t mipLevels() const { return uint32_t(levels_.size()); }
    Format format() const { return format_; }

    // HLSL Load: texel (x, y) of `level`, unfiltered and unaddressed, as the shader sees it (UNORM as
    // n/255). Any index out of range, level included, returns (0, 0, 0, 0) as Direct3D 11 does.
    glm::vec4 load(int x, int y, int level = 0) const;

    // HLSL Sample: filtered read with the level of detail from the screen-space derivatives of uv
    // (quadGradient, so only meaningful inside a pixel shader; elsewhere the derivatives are zero and
    // λ = minLod). Only when the level of detail can change the result (mipLevels() > 1 or minFilter !=
    // magFilter) is the derivative taken; otherwise λ is 0 and no derivative call is made, which keeps
    // the one-level case free of quad replays.
    glm::vec4 Sample(const SamplerState& sampler, glm::vec2 uv) const;
    // Sample for eight pixels of a 4×2 block at once (simd.hpp), the same bits as eight scalar
    // calls: lanes are the block's pixels, and where λ matters, the derivatives are the lanes'
    // fine differences within their 2×2 quads.
    // (A template only so that Sample(s, {u, v}) still means the scalar overload.)
    template <class UV>
        requires std::same_as<UV, glm::vec<2, Float8>>
    glm::vec<4, Float8> Sample(const SamplerState& sampler, const UV& uv) const;
    // Sample for two neighbouring blocks (Float8x2, simd.hpp): the same bits as a Float8 call per
    // block; on the fixed-point path the two blocks' fetches and filters are interleaved.
    template <class UV>
        requires std::same_as<UV, glm::vec<2, Float8x2>>
    glm::vec<4, Float8x2> Sample(const SamplerState& sampler, const UV& uv) const;
    // HLSL SampleLevel: an explicit level of detail (the sampler's bias and clamps still apply).
    glm::vec4 SampleLevel(const SamplerState& sampler, glm::vec2 uv, float lod) const;
    // HLSL SampleGrad: the level of detail from the given derivatives of uv, in uv units per pixel.
    glm::vec4 SampleGrad(const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddx, glm::vec2 ddy) const;

    // Where level 0 of a one-level texture is not transparent: per texel row (row 0 on top), the first
    // and last column whose alpha is not zero (NaN counts as not zero); first > last for a row of
    // alpha 0 only. Empty for a texture with mipmaps. Computed once at creation; what the pipeline
    // reads to skip billboard pixels that sample only alpha-0 texels (AlphaSource, shader.hpp).
    struct AlphaSpan {
        int32_t first, last;
        // The span of both rows: the least first and the greatest last.
        AlphaSpan unite(const AlphaSpan& other) const {
            return {std::min(first, other.first), std::max(last, other.last)};
        }
        bool operator==(const AlphaSpan& other) const = default;
    };
    std::span<const AlphaSpan> alphaSpans() const {
        return std::span<const AlphaSpan>(alpha_spans_).first(alpha_spans_.empty() ? 0 : levels_[0].height);
    }
    // The union of rows r0..r1's spans (0 ≤ r0 ≤ r1 < height, alphaSpans not empty): the least first
    // and the greatest last. Two reads of a table of the unions of 2^k rows, k = ⌊log2(r1 − r0 + 1)⌋,
    // made with the spans (a sparse table: height · (⌊log2 height⌋ + 1) entries).
    // The table itself: level k (rows' unions of 2^k) at entries k·height .. k·height + height − 1.
    std::span<const AlphaSpan> alphaSpanTable() const { return alpha_spans_; }
    AlphaSpan alphaSpanOfRows(int32_t r0, int32_t r1) const {
        const int32_t h = levels_[0].height;
        const int k = std::bit_width(uint32_t(r1 - r0 + 1)) - 1;
        const AlphaSpan& a = alpha_spans_[size_t(k) * size_t(h) + size_t(r0)];
        return a.unite(alpha_spans_[size_t(k) * size_t(h) + size_t(r1 - (int32_t(1) << k) + 1)]);
    }

    bool operator==(const Texture2D& other) const = default;

  private:
    struct Level {
        int width = 0, height = 0;
        size_t offset = 0;  // index of texel (0, 0) in texels_ (and of its first byte in bytes_, / 4)
        bool operator==(const Level& other) const = default;
    };

    static Texture2D build(uint32_t width, uint32_t height, Format format, std::vector<glm::vec4> texels,
                           std::vector<uint8_t> bytes, bool mipmaps);

    template <class T>
    glm::vec<4, T> texel(const Level& level, int x, int y) const;
    template <class T>
    glm::vec<4, T> filterLevel(const SamplerState& sampler, Filter filter, const Level& level, T u,
                               T v) const;
    template <class T>
    T lodFromGradients(glm::vec2 ddx, glm::vec2 ddy) const;
    template <class T>
    glm::vec4 sampleAtLod(const SamplerState& sampler, glm::vec2 uv, T lambda) const;
    glm::vec4 sampleImplicitLod(const SamplerState& sampler, glm::vec2 uv) const;
    // By value: a reference would let the shader's input struct and the sampler escape, and the
    // pixel loop would then keep them in memory and reload them after every store to a target.
    glm::vec<4, Float8> sampleLanes(SamplerState sampler, glm::vec<2, Float8> uv) const;

    // Bilinear footprints for the fixed-point clamp path: for every texel coordinate pair (i, j) in
    // [−1, w−1] × [−1, h−1], the four clamped texels (i, j) (i+1, j) (i, j+1) (i+1, j+1) as 16 bytes,
    // channel-major (bytes 4c..4c+3 hold channel c of the four), each byte − 128, so that one load
    // fetches what a bilinear tap needs in the order the filter multiplies it (simd/base.hpp has the
    // filter's formula). Built for one-level RGBA8 textures up to kMaxFootprintSide on a side
    // ((w+1)(h+1)·16 bytes, 4 MB at most).
    static constexpr int kMaxFootprintSide = 512;
    void buildFootprints();
    std::vector<uint8_t> footprints_;
    // The same footprints once more as four planes, one per channel, for the 512-bit pair sampler
    // (RASTER_AVX512 only; simd::FootprintGrid::planeStride says how they are laid out).
    static constexpr int kPlaneWindow = simd::kFootprintPlaneWindow;
    std::vector<int32_t> planes_;
    std::vector<AlphaSpan> alpha_spans_;  // the rows' spans, then the unions of 2, 4, 8… rows
    void buildAlphaSpans();
    // What the footprint path reads per call (simd::FootprintGrid).
    using FootprintGrid = simd::FootprintGrid;
    FootprintGrid grid_;
    // Whether footprints exist and `sampler` clamps both axes: the fixed-point filter's condition
    // shared by the scalar and eight-wide paths, which add what each needs besides (a Linear filter,
    // not reference mode). `&`, not `&&`: see Sample(Float8).
    bool footprintsClamp(const SamplerState& sampler) const {
        return (grid_.stride != 0) & (sampler.addressU == AddressMode::Clamp) &
               (sampler.addressV == AddressMode::Clamp);
    }
    // The eight-wide paths' condition for the fixed-point filter: footprintsClamp, a Linear filter
    // both ways, not reference mode. `&`, not `&&`: GCC merges the four byte tests of `&&` into one
    // 32-bit load of the sampler, which the pixel loop has just rebuilt on the stack byte by byte,
    // and that load cannot be forwarded.
    [[gnu::always_inline]] bool footprintsWide(const SamplerState& sampler) const {
        const bool bilinear = (sampler.minFilter == Filter::Linear) & (sampler.magFilter == Filter::Linear);
        return footprintsClamp(sampler) & bilinear && !inReferenceMode();
    }
    // The fixed-point filter for N blocks at once (simd::footprintFilter).
    template <int N>
    void sampleFootprints(const glm::vec<2, Float8> (&uv)[N], glm::vec<4, Float8> (&out)[N]) const;
    // The same fixed-point filter for one pixel: footprint (i, j) (clamped here), weights α, β.
    glm::vec4 filterFootprint(int i, int j, float alpha, float beta) const;

    std::vector<Level> levels_;
    std::vector<glm::vec4> texels_;  // every level, as the shader reads it (UNORM already n/255)
    std::vector<uint8_t> bytes_;     // UNORM only: the stored bytes of every level
    Format format_ = Format::Unknown;
};

// ---- Implementation -------------------------------------------------------------------------------
// Inline because Sample is the inner loop of texturing pixel shaders.

namespace detail {

inline constexpr float kMaxTexelCoord = 16777216.0f;  // 2^24

// NaN fails both comparisons and lands on the low end.
template <class T>
inline T clampTexelCoord(T a) {
    return a > T(-kMaxTexelCoord) ? (a < T(kMaxTexelCoord) ? a : T(kMaxTexelCoord)) : T(-kMaxTexelCoord);
}

// floor for |a| ≤ 2^24, without a libm call on targets that lack a rounding instruction.
template <class T>
inline int floorToInt(T a) {
    const int i = int(a);
    return T(i) > a ? i - 1 : i;
}

inline int wrapTexel(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
}
inline int mirrorTexel(int i, int n) {
    const int m = wrapTexel(i, 2 * n);
    return m < n ? m : 2 * n - 1 - m;
}
inline int mirrorOnceTexel(int i, int n) {
    const int m = i < 0 ? -1 - i : i;
    return m < n ? m : n - 1;
}
inline int clampTexel(int i, int n) {
    return i < 0 ? 0 : (i < n ? i : n - 1);
}
inline int borderTexel(int i, int n) {
    return unsigned(i) < unsigned(n) ? i : -1;
}

// Texel index i in a level n texels wide → an index in [0, n), or −1 for the border colour.
inline int addressTexel(AddressMode mode, int i, int n) {
    switch (mode) {
        case AddressMode::Wrap:
            return wrapTexel(i, n);
        case AddressMode::Mirror:
            return mirrorTexel(i, n);
        case AddressMode::Border:
            return borderTexel(i, n);
        case AddressMode::MirrorOnce:
            return mirrorOnceTexel(i, n);
        case AddressMode::Clamp:
            break;
    }
    return clampTexel(i, n);
}

// Texels i and i + 1 together: one switch for the pair of a linear filter's axis.
inline void addressTexelPair(AddressMode mode, int i, int n, int& j0, int& j1) {
    switch (mode) {
        case AddressMode::Wrap:
            j0 = wrapTexel(i, n);
            j1 = j0 + 1 == n ? 0 : j0 + 1;
            return;
        case AddressMode::Mirror:
            j0 = mirrorTexel(i, n);
            j1 = mirrorTexel(i + 1, n);
            return;
        case AddressMode::Border:
            j0 = borderTexel(i, n);
            j1 = borderTexel(i + 1, n);
            return;
        case AddressMode::MirrorOnce:
            j0 = mirrorOnceTexel(i, n);
            j1 = mirrorOnceTexel(i + 1, n);
            return;
        case AddressMode::Clamp:
            break;
    }
    j0 = clampTexel(i, n);
    j1 = clampTexel(i + 1, n);
}

// x + (y − x)·t, per component.
template <class T>
inline glm::vec<4, T> lerp(const glm::vec<4, T>& x, const glm::vec<4, T>& y, T t) {
    return x + (y - x) * t;
}
#if defined(__GNUC__)
// The same arithmetic (so the same bits) in one SIMD register: glm without GLM_FORCE_INTRINSICS
// leaves vec4 arithmetic to four scalar operations each, and the blend is the bulk of a bilinear sample.
inline glm::vec4 lerp(const glm::vec4& x, const glm::vec4& y, float t) {
    using Float4 = float __attribute__((vector_size(16)));
    Float4 vx, vy;
    std::memcpy(&vx, &x, sizeof vx);
    std::memcpy(&vy, &y, sizeof vy);
    const Float4 r = vx + (vy - vx) * t;
    glm::vec4 out;
    std::memcpy(&out, &r, sizeof out);
    return out;
}
#endif

}  // namespace detail

template <class T>
inline glm::vec<4, T> Texture2D::texel(const Level& level, int x, int y) const {
    RASTER_DCHECK(x >= 0 && x < level.width && y >= 0 && y < level.height);
    const size_t k = level.offset + size_t(y) * size_t(level.width) + size_t(x);
    if constexpr (std::is_same_v<T, float>) {
        return texels_[k];
    } else {
        if (bytes_.empty()) return glm::vec<4, T>(texels_[k]);
        const uint8_t* p = &bytes_[4 * k];
        return glm::vec<4, T>(T(p[0]), T(p[1]), T(p[2]), T(p[3])) / T(255);
    }
}

template <class T>
[[gnu::always_inline]] inline glm::vec<4, T> Texture2D::filterLevel(const SamplerState& sampler, Filter filter,
                                                                    const Level& level, T u, T v) const {
    using Vec = glm::vec<4, T>;
    const T w = T(level.width), h = T(level.height);
    if (filter == Filter::Point) {
        const int x = detail::addressTexel(sampler.addressU,
                                           detail::floorToInt(detail::clampTexelCoord(u * w)), level.width);
        const int y = detail::addressTexel(sampler.addressV,
                                           detail::floorToInt(detail::clampTexelCoord(v * h)), level.height);
        return (x | y) < 0 ? Vec(sampler.borderColor) : texel<T>(level, x, y);
    }
    const T a = detail::clampTexelCoord(u * w - T(0.5));
    const T b = detail::clampTexelCoord(v * h - T(0.5));
    const int i = detail::floorToInt(a), j = detail::floorToInt(b);
    const T alpha = a - T(i), beta = b - T(j);
    if constexpr (std::is_same_v<T, float>) {
        // Footprints exist only for one-level textures, so `level` is level 0.
        if (footprintsClamp(sampler)) return filterFootprint(i, j, alpha, beta);
    }
    int x0, x1, y0, y1;
    detail::addressTexelPair(sampler.addressU, i, level.width, x0, x1);
    detail::addressTexelPair(sampler.addressV, j, level.height, y0, y1);
    Vec t00, t10, t01, t11;
    if ((x0 | x1 | y0 | y1) >= 0) {
        t00 = texel<T>(level, x0, y0);
        t10 = texel<T>(level, x1, y0);
        t01 = texel<T>(level, x0, y1);
        t11 = texel<T>(level, x1, y1);
    } else {
        const Vec border(sampler.borderColor);
        t00 = (x0 | y0) < 0 ? border : texel<T>(level, x0, y0);
        t10 = (x1 | y0) < 0 ? border : texel<T>(level, x1, y0);
        t01 = (x0 | y1) < 0 ? border : texel<T>(level, x0, y1);
        t11 = (x1 | y1) < 0 ? border : texel<T>(level, x1, y1);
    }
    return detail::lerp(detail::lerp(t00, t10, alpha), detail::lerp(t01, t11, alpha), beta);
}

inline glm::vec4 Texture2D::Sample(const SamplerState& sampler, glm::vec2 uv) const {
    // One level and one filter: λ cannot matter, so no derivative and no call out of line.
    if (levels_.size() == 1 && sampler.minFilter == sampler.magFilter && !inReferenceMode())
        return filterLevel<float>(sampler, sampler.magFilter, levels_[0], uv.x, uv.y);
    return sampleImplicitLod(sampler, uv);
}

inline glm::vec4 Texture2D::filterFootprint(int i, int j, float alpha, float beta) const {
    const int ii = std::clamp(i, -1, grid_.maxI) + 1, jj = std::clamp(j, -1, grid_.maxJ) + 1;
    const int8_t* f = reinterpret_cast<const int8_t*>(footprints_.data()) +
                      16 * (size_t(jj) * size_t(grid_.stride) + size_t(ii));
    // The fixed-point weights (the header's "Precision"; simd/base.hpp has the formula).
    const int a = std::min(int(std::lrint(alpha * simd::kFootprintAlphaScale)), simd::kFootprintAlphaMax);
    const int b = int(std::lrint(beta * simd::kFootprintBetaScale));
    return simd::footprintFilter1(f, a, b);
}

namespace detail {

inline Float8 clampTexelCoord8(Float8 a) {
    // As clampTexelCoord: NaN lands on the low end (max(NaN, lo) is lo).
    return min(max(a, Float8(-kMaxTexelCoord)), Float8(kMaxTexelCoord));
}
inline Int8 floorToInt8(Float8 a) { return toInt(floor(a)); }
inline Int8 clampTexel8(Int8 i, int n) { return max(Int8(0), min(i, Int8(n - 1))); }

// The four channels of eight RGBA8 texels, as n/255 (unorm8ToFloat's arithmetic).
inline glm::vec<4, Float8> unpackRgba8(Int8 t) {
    const Float8 k(1.0f / 255.0f);
    return {toFloat(t & Int8(0xFF)) * k, toFloat((t >> 8) & Int8(0xFF)) * k, toFloat((t >> 16) & Int8(0xFF)) * k,
            toFloat(t >> 24) * k};
}

inline glm::vec<4, Float8> lerp8(const glm::vec<4, Float8>& x, const glm::vec<4, Float8>& y, Float8 t) {
    return {x.x + (y.x - x.x) * t, x.y + (y.y - x.y) * t, x.z + (y.z - x.z) * t, x.w + (y.w - x.w) * t};
}

// filterLevel's linear-filter coordinates, eight lanes: texel (i, j) is the footprint's top left,
// α and β the weights of its right and lower neighbours, for a level of w × h texels.
struct Bilinear8 {
    Int8 i, j;
    Float8 alpha, beta;
};
[[gnu::always_inline]] inline Bilinear8 bilinear8(const glm::vec<2, Float8>& uv, Float8 w, Float8 h) {
    const Float8 a = clampTexelCoord8(uv.x * w - Float8(0.5f));
    const Float8 b = clampTexelCoord8(uv.y * h - Float8(0.5f));
    const Float8 fa = floor(a), fb = floor(b);
    return {toInt(fa), toInt(fb), a - fa, b - fb};
}

}  // namespace detail

template <int N>
[[gnu::always_inline]] inline void Texture2D::sampleFootprints(const glm::vec<2, Float8> (&uv)[N],
                                                               glm::vec<4, Float8> (&out)[N]) const {
    // filterLevel's linear filter with clamped addressing, i.e. filterFootprint, lane by lane the
    // same operations; N blocks' steps interleaved, two blocks in one register where the core has
    // AVX-512.
    simd::F32x8 u[N], v[N], rgba[N][4];
    for (int n = 0; n < N; ++n) u[n] = uv[n].x.v, v[n] = uv[n].y.v;
    simd::footprintFilter<N>(grid_, footprints_.data(), planes_.data(), u, v, rgba);
    for (int n = 0; n < N; ++n) out[n] = {Float8(rgba[n][0]), Float8(rgba[n][1]), Float8(rgba[n][2]), Float8(rgba[n][3])};
}

template <class UV>
    requires std::same_as<UV, glm::vec<2, Float8>>
[[gnu::always_inline]] inline glm::vec<4, Float8> Texture2D::Sample(const SamplerState& sampler, const UV& uv) const {
    // The lecture's case first, with as few loads as the tests allow (see FootprintGrid).
    if (footprintsWide(sampler)) {
        const glm::vec<2, Float8> in[1] = {uv};
        glm::vec<4, Float8> out[1];
        sampleFootprints<1>(in, out);
        return out[0];
    }
    // The common case in registers: one level, one filter, clamped UNORM8 texels. Everything
    // else goes lane by lane through the scalar code.
    if (levels_.size() != 1 || sampler.minFilter != sampler.magFilter || bytes_.empty() ||
        sampler.addressU != AddressMode::Clamp || sampler.addressV != AddressMode::Clamp || inReferenceMode())
        return sampleLanes(sampler, uv);
    const Level& level = levels_[0];
    const int32_t* texels = reinterpret_cast<const int32_t*>(bytes_.data()) + level.offset;
    const Float8 w = float(level.width), h = float(level.height);
    if (sampler.magFilter == Filter::Point) {
        const Int8 x = detail::clampTexel8(detail::floorToInt8(detail::clampTexelCoord8(uv.x * w)), level.width);
        const Int8 y = detail::clampTexel8(detail::floorToInt8(detail::clampTexelCoord8(uv.y * h)), level.height);
        return detail::unpackRgba8(gather(texels, y * Int8(level.width) + x));
    }
    const auto [i, j, alpha, beta] = detail::bilinear8(uv, w, h);
    const Int8 x0 = detail::clampTexel8(i, level.width), x1 = detail::clampTexel8(i + Int8(1), level.width);
    const Int8 row0 = detail::clampTexel8(j, level.height) * Int8(level.width);
    const Int8 row1 = detail::clampTexel8(j + Int8(1), level.height) * Int8(level.width);
    const auto t00 = detail::unpackRgba8(gather(texels, row0 + x0));
    const auto t10 = detail::unpackRgba8(gather(texels, row0 + x1));
    const auto t01 = detail::unpackRgba8(gather(texels, row1 + x0));
    const auto t11 = detail::unpackRgba8(gather(texels, row1 + x1));
    return detail::lerp8(detail::lerp8(t00, t10, alpha), detail::lerp8(t01, t11, alpha), beta);
}

template <class UV>
    requires std::same_as<UV, glm::vec<2, Float8x2>>
[[gnu::always_inline]] inline glm::vec<4, Float8x2> Texture2D::Sample(const SamplerState& sampler,
                                                                      const UV& uv) const {
    const glm::vec<2, Float8> in[2] = {{uv.x.h[0], uv.y.h[0]}, {uv.x.h[1], uv.y.h[1]}};
    glm::vec<4, Float8> out[2];
    if (footprintsWide(sampler))
        sampleFootprints<2>(in, out);
    else
        out[0] = Sample(sampler, in[0]), out[1] = Sample(sampler, in[1]);
    return {Float8x2(out[0].x, out[1].x), Float8x2(out[0].y, out[1].y), Float8x2(out[0].z, out[1].z),
            Float8x2(out[0].w, out[1].w)};
}

}  // namespace raster
