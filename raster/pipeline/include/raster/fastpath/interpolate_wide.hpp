// Accelerates stage 8's interpolation (stages/8_pixel_shader.hpp) for the eight lanes of a 4×2 block:
// interpolateDepth, barycentrics and interpolateAttributes computed with the same operations in the
// same order, lane by lane, so each lane gets the scalar rule's bits. tests/pixel_shader_test.cpp
// (PixelShaderWide) and tests/fastpath_test.cpp (InterpolateWide) check them lane by lane.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "raster/simd.hpp"
#include "raster/stages/8_pixel_shader.hpp"

namespace raster {

// Four edge-function values as doubles, exactly: AVX2 has no int64 → double conversion, so the
// integer is added to the bits of 2^52 + 2^51, where a double's last mantissa bit is worth 1,
// and that value subtracted again. Exact for |x| < 2^51; edge functions stay below 2^50.2 (16.8
// coordinates within ±(32768 + kGuardBandPixels) pixels: products of two 2^24.6 differences).
inline simd::F64x4 edgesToDouble(const int64_t* e) {
    constexpr int64_t kMagicBits = 0x4338000000000000;  // 2^52 + 2^51
    constexpr double kMagic = 6755399441055744.0;
    simd::I64x4 bits;
    std::memcpy(&bits, e, sizeof bits);
    bits += kMagicBits;
    simd::F64x4 d;
    std::memcpy(&d, &bits, sizeof d);
    return d - kMagic;
}

// interpolateDepth for the eight lanes of a 4×2 block: the same double operations, four lanes at
// a time, so the same bits.
inline Float8 interpolateDepthWide(const TriangleSetup& t, const int64_t (&e)[3][8], float min_depth,
                                   float max_depth) {
    if (t.flatDepth) return Float8(flatDepth(t, min_depth, max_depth));
    simd::F64x4 half[2];
    for (int h = 0; h < 2; ++h) {
        const simd::F64x4 e0 = edgesToDouble(&e[0][4 * h]), e1 = edgesToDouble(&e[1][4 * h]),
                          e2 = edgesToDouble(&e[2][4 * h]);
        simd::F64x4 z = (e1 * t.z[0] + e2 * t.z[1] + e0 * t.z[2]) * t.invArea2;
        const double dl = min_depth, dh = max_depth;
        const simd::F64x4 lo{dl, dl, dl, dl}, hi{dh, dh, dh, dh};
        z = z < lo ? lo : z;  // std::clamp's order: below lo → lo, then above hi → hi
        z = hi < z ? hi : z;
        half[h] = z;
    }
    return toFloat8(half[0], half[1]);
}

// The barycentrics of the eight lanes: float(e) · invArea as barycentrics() computes it (the
// exact double rounds to the same float as a direct int64 → float conversion).
inline void barycentricsWide(const TriangleInterpolant<float>& ti, const int64_t (&e)[3][8], Float8 (&b)[3]) {
    for (int k = 0; k < 3; ++k) {
        const int edge = (k + 1) % 3;  // b0 from e1, b1 from e2, b2 from e0
        b[k] = toFloat8(edgesToDouble(&e[edge][0]), edgesToDouble(&e[edge][4])) * Float8(ti.invArea);
    }
}

// The eight-wide twin of barycentrics + interpolateAttributes for a 4×2 block at (x, y) whose
// lanes have edge functions e[k][lane]: the same operations lane by lane, so the same bits.
template <class V>
void interpolateAttributesWide(const TriangleInterpolant<float>& ti, const int64_t (&e)[3][8],
                               const V* const (&v)[3], int32_t x, int32_t y, Float8 z, Wide<V>& out) {
    Float8 b[3];
    barycentricsWide(ti, e, b);
    Float8 f0 = b[0] * Float8(ti.invW[0]), f1 = b[1] * Float8(ti.invW[1]), f2 = b[2] * Float8(ti.invW[2]);
    const Float8 w = Float8(1.0f) / (f0 + f1 + f2);
    f0 *= w, f1 *= w, f2 *= w;
    const float* a0 = asFloats(*v[0]);
    const float* a1 = asFloats(*v[1]);
    const float* a2 = asFloats(*v[2]);
    Float8* o = reinterpret_cast<Float8*>(&out);
    o[0] = Float8(float(x)) + Float8(simd::F32x8{0, 1, 2, 3, 0, 1, 2, 3}) + Float8(0.5f);
    o[1] = Float8(float(y)) + Float8(simd::F32x8{0, 0, 0, 0, 1, 1, 1, 1}) + Float8(0.5f);
    o[2] = z;
    o[3] = w;
    for (uint32_t i = 4; i < kVertexFloats<V>; ++i) o[i] = f0 * Float8(a0[i]) + f1 * Float8(a1[i]) + f2 * Float8(a2[i]);
}

}  // namespace raster
