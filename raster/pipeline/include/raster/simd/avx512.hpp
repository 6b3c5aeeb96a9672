// AVX-512 F, BW, DQ and VL (512 bits): the particles' pair of 4×2 blocks in one sixteen-lane register,
// block 0 in lanes 0–7 and block 1 in lanes 8–15. The same operations lane by lane as the eight-lane
// kernels of avx2.hpp, so the same bits, in half the instructions. The names are chosen, and
// documented, in ops.hpp.
//
// Tested where the build targets AVX-512 (simd_ops_test, texture_test, output_merger_test compare these
// kernels with the eight-lane and portable ones). Elsewhere this header is not compiled; there,
// simd_ops_test checks the portable reference against the kernels' outputs recorded on an AVX-512
// machine (tests/data/simd/avx512_kernels.txt), and fails when this header's text has changed since
// that recording (docs/RELIABILITY.md, "The SIMD paths").
#pragma once

#include <cstdint>
#include <type_traits>

#include "raster/simd/base.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // see base.hpp

namespace raster::simd::avx512 {

#if RASTER_AVX512
inline __m512 join(F32x8 lo, F32x8 hi) { return _mm512_insertf32x8(_mm512_castps256_ps512(__m256(lo)), __m256(hi), 1); }

// The footprints of the pair's sixteen lanes, one register per channel (bytes − 128 of texels 00,
// 10, 01, 11 in each dword), read lane by lane: one 16-byte load each (byte offset index·16),
// transposed. Register r gathers lanes r, r + 4, r + 8, r + 12, one per 128-bit quarter, so that the
// transpose within quarters leaves lanes 4q..4q + 3 in quarter q.
[[gnu::always_inline]] inline void loadFootprints16(const uint8_t* footprints, __m512i index, __m512i (&channel)[4]) {
    const __m512i bytes = _mm512_slli_epi32(index, 4);
    __m128i quarter[4];
    // Written out: the quarter is an immediate, which clang wants a constant (GCC unrolls a loop).
    quarter[0] = _mm512_extracti32x4_epi32(bytes, 0);
    quarter[1] = _mm512_extracti32x4_epi32(bytes, 1);
    quarter[2] = _mm512_extracti32x4_epi32(bytes, 2);
    quarter[3] = _mm512_extracti32x4_epi32(bytes, 3);
    auto load = [&](__m128i q, auto lane) {
        return _mm_loadu_si128(
            reinterpret_cast<const __m128i*>(footprints + uint32_t(_mm_extract_epi32(q, decltype(lane)::value))));
    };
    __m512i y[4];
    auto gatherLanes = [&](auto r) {
        __m512i z = _mm512_castsi128_si512(load(quarter[0], r));
        z = _mm512_inserti32x4(z, load(quarter[1], r), 1);
        z = _mm512_inserti32x4(z, load(quarter[2], r), 2);
        return _mm512_inserti32x4(z, load(quarter[3], r), 3);
    };
    y[0] = gatherLanes(std::integral_constant<int, 0>{}), y[1] = gatherLanes(std::integral_constant<int, 1>{});
    y[2] = gatherLanes(std::integral_constant<int, 2>{}), y[3] = gatherLanes(std::integral_constant<int, 3>{});
    const __m512i t0 = _mm512_unpacklo_epi32(y[0], y[1]), t1 = _mm512_unpackhi_epi32(y[0], y[1]);
    const __m512i t2 = _mm512_unpacklo_epi32(y[2], y[3]), t3 = _mm512_unpackhi_epi32(y[2], y[3]);
    channel[0] = _mm512_unpacklo_epi64(t0, t2), channel[1] = _mm512_unpackhi_epi64(t0, t2);
    channel[2] = _mm512_unpacklo_epi64(t1, t3), channel[3] = _mm512_unpackhi_epi64(t1, t3);
}

// avx2::footprintFilter8<2> for the pair in one register.
[[gnu::always_inline]] inline void footprintFilterPair(const FootprintGrid& grid, const uint8_t* footprints,
                                                       const int32_t* planes, const F32x8 (&u)[2],
                                                       const F32x8 (&v)[2], F32x8 (&out)[2][4]) {
    const __m512 uu = join(u[0], u[1]), vv = join(v[0], v[1]);
    const __m512 half = _mm512_set1_ps(0.5f), minus_one = _mm512_set1_ps(-1.0f);
    const __m512 a = _mm512_min_ps(
        _mm512_max_ps(_mm512_sub_ps(_mm512_mul_ps(uu, _mm512_set1_ps(grid.width)), half), minus_one),
        _mm512_set1_ps(grid.lastI));
    const __m512 b = _mm512_min_ps(
        _mm512_max_ps(_mm512_sub_ps(_mm512_mul_ps(vv, _mm512_set1_ps(grid.height)), half), minus_one),
        _mm512_set1_ps(grid.lastJ));
    const __m512 i = _mm512_roundscale_ps(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __m512 j = _mm512_roundscale_ps(b, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __m512 alpha = _mm512_sub_ps(a, i), beta = _mm512_sub_ps(b, j);
    // The footprint's index (j + 1)·stride + (i + 1), exact in float (below 2^19).
    const __m512i index = _mm512_cvttps_epi32(
        _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(j, _mm512_set1_ps(grid.rowStride)), i), _mm512_set1_ps(grid.originIndex)));
    // Each row of the pair (lanes 0–3 and 8–11 the top row, 4–7 and 12–15 the bottom one, as a
    // billboard's blocks are laid out) reads a window of kFootprintPlaneWindow footprints from each
    // plane, beginning at the row's lane 0 or 4, when all of the row's lanes fall inside it: a
    // billboard's row has one texel row and texel columns that grow with x, so eight pixels span 8
    // footprints at one texel a pixel and 16 at just over two. Then VPERMT2D picks every lane's
    // footprint from the two rows' windows, where the other way costs 16 extracts, 16 loads and a
    // transpose.
    const __m512i first =
        _mm512_permutexvar_epi32(_mm512_setr_epi32(0, 0, 0, 0, 4, 4, 4, 4, 0, 0, 0, 0, 4, 4, 4, 4), index);
    const __m512i offset = _mm512_sub_epi32(index, first);  // unsigned: a lane left of its row's first fails
    static_assert(kFootprintPlaneWindow == 16, "VPERMT2D's second register begins at index 16");
    __m512i channel[4];
    // KORTESTW's carry (every bit set) instead of the mask compared as an integer: the mask is never
    // widened to 32 bits (see noOpLanes).
    const __mmask16 in_window = _mm512_cmplt_epu32_mask(offset, _mm512_set1_epi32(kFootprintPlaneWindow));
    if (_kortestc_mask16_u8(in_window, in_window)) [[likely]] {
        const __m512i pick =
            _mm512_or_si512(offset, _mm512_setr_epi32(0, 0, 0, 0, 16, 16, 16, 16, 0, 0, 0, 0, 16, 16, 16, 16));
        const int32_t* top = planes + uint32_t(_mm512_cvtsi512_si32(index));
        const int32_t* bottom = planes + uint32_t(_mm_cvtsi128_si32(_mm512_extracti32x4_epi32(index, 1)));
        const size_t plane = size_t(grid.planeStride);
        for (int c = 0; c < 4; ++c)
            channel[c] = _mm512_permutex2var_epi32(_mm512_loadu_si512(top + c * plane), pick,
                                                   _mm512_loadu_si512(bottom + c * plane));
    } else {
        loadFootprints16(footprints, index, channel);
    }
    // footprintFilter8's weights and filter.
    const __m512i wa8 = _mm512_min_epi32(_mm512_cvtps_epi32(_mm512_mul_ps(alpha, _mm512_set1_ps(kFootprintAlphaScale))),
                                         _mm512_set1_epi32(kFootprintAlphaMax));
    const __m512i wa16 = _mm512_or_si512(_mm512_slli_epi32(wa8, 8), _mm512_xor_si512(wa8, _mm512_set1_epi32(255)));
    const __m512i wa = _mm512_or_si512(wa16, _mm512_slli_epi32(wa16, 16));
    const __m512i wb14 = _mm512_cvtps_epi32(_mm512_mul_ps(beta, _mm512_set1_ps(kFootprintBetaScale)));
    const __m512i wb =
        _mm512_or_si512(_mm512_slli_epi32(wb14, 16), _mm512_sub_epi32(_mm512_set1_epi32(kFootprintBetaOne), wb14));
    for (int c = 0; c < 4; ++c) {
        const __m512i low = _mm512_maddubs_epi16(_mm512_set1_epi16(1), channel[c]);
        const __m512i rows = _mm512_add_epi16(_mm512_maddubs_epi16(wa, channel[c]), low);
        const __m512 sum = _mm512_cvtepi32_ps(_mm512_madd_epi16(rows, wb));
        const __m512 value = _mm512_mul_ps(_mm512_add_ps(sum, _mm512_set1_ps(kFootprintBiasSum)),
                                           _mm512_set1_ps(kFootprintScale));
        // Halves: the blend joins them again, and GCC folds the pair of shuffles away.
        out[0][c] = F32x8(_mm512_castps512_ps256(value));
        out[1][c] = F32x8(_mm512_extractf32x8_ps(value, 1));
    }
}

// The lanes of sa that equal 0 (ordered compare: NaN is not 0), bit l for lane l, in a
// general-purpose register through VMOVMSKPS on each half. Not a compare into a mask register: GCC 12
// spills such a 16-bit mask with KMOVW and, at -Og, reloads the slot as 32 bits, so bits 16–31 of a
// uint32_t made from it held stack garbage (SimdOps.EightPixelAdditiveBlendIsTheOnePixelBlendInEveryLane).
[[gnu::always_inline]] inline uint32_t noOpLanes(__m512 sa) {
    const __m256 zero = _mm256_setzero_ps();
    const int lo = _mm256_movemask_ps(_mm256_cmp_ps(_mm512_castps512_ps256(sa), zero, _CMP_EQ_OQ));
    const int hi = _mm256_movemask_ps(_mm256_cmp_ps(_mm512_extractf32x8_ps(sa, 1), zero, _CMP_EQ_OQ));
    return uint32_t(lo) | uint32_t(hi) << 8;
}

// avx2::additiveBlendRgba8 for two side-by-side blocks, loaded, blended under `mask` (bit l: lane l,
// block 1 in bits 8–15) and stored here. Returns the lanes whose saturated alpha is 0.
[[gnu::always_inline]] inline uint32_t additiveBlendRgba8Pair(uint8_t* row0, uint8_t* row1,
                                                              const F32x8 (&rgba)[4][2], uint32_t mask) {
    // The lanes' order in 128-bit quarters: block 0's top row, its bottom row, block 1's top row, its
    // bottom row; each pixel row of eight is one 32-byte load and store.
    const __m512i quarters = _mm512_setr_epi64(0, 1, 4, 5, 2, 3, 6, 7);
    const __m512i rows = _mm512_inserti64x4(_mm512_castsi256_si512(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(row0))),
                                            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(row1)), 1);
    const __m512i old = _mm512_permutexvar_epi64(quarters, rows);
    const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.0f), half = _mm512_set1_ps(0.5f);
    const __m512 sa = _mm512_min_ps(_mm512_max_ps(join(rgba[3][0], rgba[3][1]), zero), one);  // saturate's order
    const uint32_t no_ops = noOpLanes(sa);
    const __m512 sa255 = _mm512_mul_ps(sa, _mm512_set1_ps(255.0f));
    const __m512i a = _mm512_cvttps_epi32(_mm512_add_ps(_mm512_mul_ps(sa, sa255), half));
    auto units = [&](const F32x8 (&s)[2]) {  // avx2::additiveBlendRgba8's units
        return _mm512_cvttps_epi32(_mm512_add_ps(_mm512_mul_ps(_mm512_min_ps(one, join(s[0], s[1])), sa255), half));
    };
    const __m512i planar =
        _mm512_packus_epi16(_mm512_packus_epi32(units(rgba[0]), units(rgba[1])), _mm512_packus_epi32(units(rgba[2]), a));
    const __m512i to_pixels =
        _mm512_broadcast_i32x4(_mm_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15));
    const __m512i sum = _mm512_adds_epu8(old, _mm512_shuffle_epi8(planar, to_pixels));
    const __m512i out = _mm512_permutexvar_epi64(quarters, _mm512_mask_blend_epi32(__mmask16(mask), old, sum));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(row0), _mm512_castsi512_si256(out));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(row1), _mm512_extracti64x4_epi64(out, 1));
    return no_ops;
}
#endif

}  // namespace raster::simd::avx512

#pragma GCC diagnostic pop
