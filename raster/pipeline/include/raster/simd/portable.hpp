// The SIMD layer's operations without intrinsics: GCC/Clang vector extensions, and loops where an
// operation has no vector-extension form. For a target that lacks the instruction set (an x86-64
// build without -march, ARM, the fuzz builds' clang): the same bits as the x86 versions, lane by
// lane, usually slower. The names are chosen, and documented, in ops.hpp.
#pragma once

#include <cstdint>
#include <cstring>

#include "raster/simd/base.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // see base.hpp

namespace raster::simd::portable {

inline uint32_t maskBits(I32x8 m) {
    uint32_t b = 0;
    for (int i = 0; i < 8; ++i) b |= uint32_t(m[i] != 0) << i;
    return b;
}
inline uint32_t maskBits(I64x4 m) {
    uint32_t b = 0;
    for (int i = 0; i < 4; ++i) b |= uint32_t(m[i] != 0) << i;
    return b;
}
inline F32x8 min(F32x8 a, F32x8 b) { return a < b ? a : b; }
inline F32x8 max(F32x8 a, F32x8 b) { return a > b ? a : b; }
inline F32x8 toFloat8(F64x4 lo, F64x4 hi) {
    F32x8 r;
    for (int i = 0; i < 4; ++i) r[i] = float(lo[i]), r[4 + i] = float(hi[i]);
    return r;
}
inline F32x8 floor(F32x8 a) {
    for (int i = 0; i < 8; ++i) a[i] = __builtin_floorf(a[i]);
    return a;
}
inline F32x8 sqrt(F32x8 a) {
    for (int i = 0; i < 8; ++i) a[i] = __builtin_sqrtf(a[i]);
    return a;
}
// Converting NaN or a value outside int32 with a C++ cast is undefined behaviour; CVTPS2DQ's answer
// INT32_MIN is spelled out.
inline int32_t roundToInt(float a) {
    const float r = __builtin_rintf(a);
    return r >= -2147483648.0f && r < 2147483648.0f ? int32_t(r) : INT32_MIN;
}
inline I32x8 roundToInt(F32x8 a) {
    I32x8 r;
    for (int i = 0; i < 8; ++i) r[i] = roundToInt(a[i]);
    return r;
}
inline F32x8 fma(F32x8 a, F32x8 b, F32x8 c) {
    for (int i = 0; i < 8; ++i) a[i] = __builtin_fmaf(a[i], b[i], c[i]);
    return a;
}
inline I32x8 gather(const int32_t* base, I32x8 index) {
    I32x8 r;
    for (int i = 0; i < 8; ++i) r[i] = base[index[i]];
    return r;
}
inline F32x8 gather(const float* base, I32x8 index) {
    F32x8 r;
    for (int i = 0; i < 8; ++i) r[i] = base[index[i]];
    return r;
}
inline F32x8 loadRows(const void* row0, const void* row1) {
    F32x8 r;
    std::memcpy(&r, row0, 16);
    std::memcpy(reinterpret_cast<char*>(&r) + 16, row1, 16);
    return r;
}

// The footprint filter's formula (base.hpp) channel by channel, in int and float.
inline F32x4 footprintFilter1(const int8_t* footprint, int a, int b) {
    F32x4 out;
    for (int c = 0; c < 4; ++c) {
        const int8_t* t = footprint + 4 * c;  // channel c of texels 00, 10, 01, 11
        const int top = (256 - a) * t[0] + a * t[1], bottom = (256 - a) * t[2] + a * t[3];
        const int sum = (kFootprintBetaOne - b) * top + b * bottom;
        out[c] = (float(sum) + kFootprintBiasSum) * kFootprintScale;
    }
    return out;
}
// avx2::footprintFilter8's coordinates, then footprintFilter1 lane by lane.
template <int N>
inline void footprintFilter8(const FootprintGrid& grid, const uint8_t* footprints, const F32x8 (&u)[N],
                             const F32x8 (&v)[N], F32x8 (&out)[N][4]) {
    for (int n = 0; n < N; ++n) {
        const F32x8 a = min(max(u[n] * grid.width - 0.5f, splat(-1.0f)), splat(grid.lastI));
        const F32x8 b = min(max(v[n] * grid.height - 0.5f, splat(-1.0f)), splat(grid.lastJ));
        const F32x8 i = floor(a), j = floor(b);
        const I32x8 wa = roundToInt((a - i) * kFootprintAlphaScale), wb = roundToInt((b - j) * kFootprintBetaScale);
        const I32x8 index = __builtin_convertvector(j * grid.rowStride + i + grid.originIndex, I32x8);
        for (int l = 0; l < 8; ++l) {
            const int8_t* f = reinterpret_cast<const int8_t*>(footprints) + 16 * size_t(uint32_t(index[l]));
            const F32x4 rgba = footprintFilter1(f, wa[l] < kFootprintAlphaMax ? wa[l] : kFootprintAlphaMax, wb[l]);
            for (int c = 0; c < 4; ++c) out[n][c][l] = rgba[c];
        }
    }
}

// BlendAdditiveRgba8 (fastpath/blend_rgba8.hpp) for eight pixels: per channel the source term
// s·(255·a) + 0.5 truncated, the destination byte added exactly, clamped at 255.
inline I32x8 additiveBlendRgba8(I32x8 dest, F32x8 r, F32x8 g, F32x8 b, F32x8 alpha) {
    auto saturate = [](F32x8 x) { return min(max(x, splat(0.0f)), splat(1.0f)); };
    const F32x8 sa = saturate(alpha), sa255 = sa * 255.0f;
    I32x8 out = {};
    const F32x8 channel[4] = {r, g, b, sa};
    for (int c = 0; c < 4; ++c) {
        const I32x8 units = __builtin_convertvector(saturate(channel[c]) * sa255 + 0.5f, I32x8);
        const I32x8 sum = units + ((dest >> (8 * c)) & 0xFF);
        out |= (sum < 255 ? sum : 255) << (8 * c);
    }
    return out;
}

// avx512::additiveBlendRgba8Pair without AVX-512: additiveBlendRgba8 on each block of the pair (block
// k's rows at bytes 16k..16k + 15 of row0 and row1), lanes outside `mask` left as they were. Returns
// the lanes whose saturated alpha is 0 (bit l of block k at 8k + l). The reference the AVX-512
// kernel is tested and recorded against (tests/simd_ops_test.cpp).
inline uint32_t additiveBlendRgba8Pair(uint8_t* row0, uint8_t* row1, const F32x8 (&rgba)[4][2], uint32_t mask) {
    uint32_t no_ops = 0;
    for (int k = 0; k < 2; ++k) {
        I32x8 dest;
        std::memcpy(&dest, row0 + 16 * k, 16);
        std::memcpy(reinterpret_cast<uint8_t*>(&dest) + 16, row1 + 16 * k, 16);
        const I32x8 sum = additiveBlendRgba8(dest, rgba[0][k], rgba[1][k], rgba[2][k], rgba[3][k]);
        for (int l = 0; l < 8; ++l) {
            const float sa = min(max(rgba[3][k], splat(0.0f)), splat(1.0f))[l];
            no_ops |= uint32_t(sa == 0.0f) << (8 * k + l);
            const int32_t pixel = sum[l];
            if (mask >> (8 * k + l) & 1) std::memcpy((l < 4 ? row0 : row1) + 16 * k + 4 * (l % 4), &pixel, 4);
        }
    }
    return no_ops;
}

// One pixel's four channels, with the same rules as sse::storeUnorm8x4 and sse::additiveBlendUnorm8x4.
inline F32x4 saturate4(F32x4 v) {
    const F32x4 zero = {}, one = zero + 1.0f;
    v = v > zero ? v : zero;  // NaN -> 0
    return v < one ? v : one;
}
inline void storeUnorm8x4(uint8_t* pixel, F32x4 rgba) {
    const I32x4 n = __builtin_convertvector(saturate4(rgba) * 255.0f + 0.5f, I32x4);
    for (int c = 0; c < 4; ++c) pixel[c] = uint8_t(n[c]);
}
inline void additiveBlendUnorm8x4(uint8_t* pixel, F32x4 rgba) {
    const F32x4 s = saturate4(rgba);
    const I32x4 units = __builtin_convertvector(s * (s[3] * 255.0f) + 0.5f, I32x4);
    uint8_t out[4];
    for (int c = 0; c < 4; ++c) out[c] = uint8_t(units[c] + pixel[c] < 255 ? units[c] + pixel[c] : 255);
    std::memcpy(pixel, out, 4);
}

// No vector version: the caller's scalar loop does every row pair (see ops.hpp).
inline int spanIntervals(const SpanRows&, int32_t, int, int32_t*, int32_t*) { return 0; }

inline void pause() {}

}  // namespace raster::simd::portable

#pragma GCC diagnostic pop
