// AVX, AVX2 and FMA (256 bits): eight float or int32 lanes, a 4×2 pixel block, or four doubles. Each
// function is the IEEE (or exact integer) operation the scalar code does, lane by lane; the names
// are chosen, and documented, in ops.hpp. Here: how, and why with intrinsics where GCC's vector
// extensions would do.
#pragma once

#include <cstdint>
#include <cstring>
#include <utility>

#include "raster/simd/base.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // see base.hpp

namespace raster::simd::avx2 {

#if defined(__AVX__)
// Bit i set where lane i's sign bit is (a comparison's all-ones lane): one VMOVMSKPS / VMOVMSKPD.
inline uint32_t maskBits(I32x8 m) { return uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(__m256i(m)))); }
inline uint32_t maskBits(I64x4 m) { return uint32_t(_mm256_movemask_pd(_mm256_castsi256_pd(__m256i(m)))); }
// MINPS and MAXPS are exactly a < b ? a : b and a > b ? a : b (a NaN in either gives b), but GCC only
// finds them without the NaN rule.
inline F32x8 min(F32x8 a, F32x8 b) { return F32x8(_mm256_min_ps(__m256(a), __m256(b))); }
inline F32x8 max(F32x8 a, F32x8 b) { return F32x8(_mm256_max_ps(__m256(a), __m256(b))); }
// One conversion per half and one insert, where building the vector lane by lane costs a dozen
// shuffles.
inline F32x8 toFloat8(F64x4 lo, F64x4 hi) {
    return F32x8(_mm256_set_m128(_mm256_cvtpd_ps(__m256d(hi)), _mm256_cvtpd_ps(__m256d(lo))));
}
inline F32x8 floor(F32x8 a) { return F32x8(_mm256_floor_ps(__m256(a))); }
inline F32x8 sqrt(F32x8 a) { return F32x8(_mm256_sqrt_ps(__m256(a))); }
// CVTPS2DQ: the current rounding mode (to nearest, ties to even), INT32_MIN for NaN and out of range.
inline I32x8 roundToInt(F32x8 a) { return I32x8(_mm256_cvtps_epi32(__m256(a))); }
// Two 16-byte loads and one insert. Not through a copy on the stack: GCC builds that from two
// 16-byte stores (or four 8-byte ones), and a 32-byte load of them cannot be forwarded, so it waits
// until the stores retire, i.e. until everything before it in the loop has finished (perf put 8-12 %
// of the particle loop on that wait).
inline F32x8 loadRows(const void* row0, const void* row1) {
    const __m128 lo = _mm_loadu_ps(static_cast<const float*>(row0));
    const __m128 hi = _mm_loadu_ps(static_cast<const float*>(row1));
    return F32x8(_mm256_insertf128_ps(_mm256_castps128_ps256(lo), hi, 1));
}
#endif

#if defined(__FMA__)
inline F32x8 fma(F32x8 a, F32x8 b, F32x8 c) { return F32x8(_mm256_fmadd_ps(__m256(a), __m256(b), __m256(c))); }
#endif

#if defined(__AVX2__)
inline I32x8 gather(const int32_t* base, I32x8 index) { return I32x8(_mm256_i32gather_epi32(base, __m256i(index), 4)); }
inline F32x8 gather(const float* base, I32x8 index) { return F32x8(_mm256_i32gather_ps(base, __m256i(index), 4)); }

// The fixed-point footprint filter for N blocks of eight lanes, each step done for every block before
// the next, so that their fetch chains are in flight together. The coordinates are clamped to
// [−1, w−1] × [−1, h−1] in float rather than the footprint indices in integers: a coordinate clamped
// there selects the same footprint, whose two texels along that axis are then equal, so its weight
// cannot change the sum; NaN lands on −1.
template <int N>
[[gnu::always_inline]] inline void footprintFilter8(const FootprintGrid& grid, const uint8_t* footprints,
                                                    const F32x8 (&u)[N], const F32x8 (&v)[N], F32x8 (&out)[N][4]) {
    F32x8 alpha[N], beta[N];
    U32x8 index[N];
    // The footprint's byte offset 16·((j + 1)·stride + (i + 1)), in integers (below 2^23), unsigned
    // so that each lane's address needs no sign extension. The same offsets as the float index of
    // portable.hpp (exact there, below 2^19), by a shorter chain to the loads: convert, multiply
    // and one add where that has two float adds, a convert and a shift; the loads wait at the head
    // of each pair's chain (perf: the samples pile up on the first footprint loads).
    const __m256i stride16 = _mm256_set1_epi32(16 * grid.stride),
                  origin16 = _mm256_set1_epi32(16 * (grid.stride + 1));
    for (int n = 0; n < N; ++n) {
        const F32x8 a = min(max(u[n] * grid.width - 0.5f, splat(-1.0f)), splat(grid.lastI));
        const F32x8 b = min(max(v[n] * grid.height - 0.5f, splat(-1.0f)), splat(grid.lastJ));
        const F32x8 i = floor(a), j = floor(b);
        alpha[n] = a - i, beta[n] = b - j;
        const __m256i column =
            _mm256_add_epi32(_mm256_slli_epi32(_mm256_cvtps_epi32(__m256(i)), 4), origin16);
        index[n] =
            U32x8(_mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvtps_epi32(__m256(j)), stride16), column));
    }
    // One 16-byte load per lane (channel-major already), then a transpose into one register per
    // channel holding, per lane, the channel's bytes of the four texels (00, 10, 01, 11). (AVX2's
    // gather instead of the loads: 1.5x slower on Zen 3.)
    __m256i channel[N][4];
    for (int n = 0; n < N; ++n) {
        auto load = [&](int l) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(footprints + index[n][l])); };
        const __m256i y0 = _mm256_set_m128i(load(4), load(0)), y1 = _mm256_set_m128i(load(5), load(1));
        const __m256i y2 = _mm256_set_m128i(load(6), load(2)), y3 = _mm256_set_m128i(load(7), load(3));
        const __m256i t0 = _mm256_unpacklo_epi32(y0, y1), t1 = _mm256_unpackhi_epi32(y0, y1);
        const __m256i t2 = _mm256_unpacklo_epi32(y2, y3), t3 = _mm256_unpackhi_epi32(y2, y3);
        channel[n][0] = _mm256_unpacklo_epi64(t0, t2), channel[n][1] = _mm256_unpackhi_epi64(t0, t2);
        channel[n][2] = _mm256_unpacklo_epi64(t1, t3), channel[n][3] = _mm256_unpackhi_epi64(t1, t3);
    }
    // Weights per lane: the bytes (255 − a, a) twice, for PMADDUBSW's pairs (t00, t10) and (t01, t11),
    // whose missing 1·t0 (256 − a does not fit a byte) is added from the pair's low byte; then the
    // words (2^14 − b, b) for PMADDWD's rows. (sse::footprintFilter1 says why nothing saturates.)
    __m256i wa[N], wb[N];
    for (int n = 0; n < N; ++n) {
        const __m256i wa8 = _mm256_min_epi32(_mm256_cvtps_epi32(__m256(alpha[n] * kFootprintAlphaScale)),
                                             _mm256_set1_epi32(kFootprintAlphaMax));
        const __m256i wa16 = _mm256_or_si256(_mm256_slli_epi32(wa8, 8), _mm256_xor_si256(wa8, _mm256_set1_epi32(255)));
        wa[n] = _mm256_or_si256(wa16, _mm256_slli_epi32(wa16, 16));
        const __m256i wb14 = _mm256_cvtps_epi32(__m256(beta[n] * kFootprintBetaScale));
        wb[n] = _mm256_or_si256(_mm256_slli_epi32(wb14, 16), _mm256_sub_epi32(_mm256_set1_epi32(kFootprintBetaOne), wb14));
    }
    // Alpha first: the blend scales every channel by it, so its chain is the longest to the store.
    for (const int c : {3, 0, 1, 2})
        for (int n = 0; n < N; ++n) {
            const __m256i bytes = channel[n][c];
            // t00, t01 as words: 1·t0 + 0·t1, one operation where a shift pair is two
            const __m256i low = _mm256_maddubs_epi16(_mm256_set1_epi16(1), bytes);
            const __m256i rows = _mm256_add_epi16(_mm256_maddubs_epi16(wa[n], bytes), low);
            const __m256 sum = _mm256_cvtepi32_ps(_mm256_madd_epi16(rows, wb[n]));
            out[n][c] = F32x8(_mm256_mul_ps(_mm256_add_ps(sum, _mm256_set1_ps(kFootprintBiasSum)),
                                            _mm256_set1_ps(kFootprintScale)));
        }
}

// The additive blend of eight RGBA8 pixels. The colours are clamped at 1 only: PACKUSDW turns what
// saturate's 0 would have made 0 into 0 as well (a product in (−1, 0.5) truncates to 0, a lower one
// or a NaN, kept by min(1, NaN), converts to a negative integer and saturates to 0). Per 128-bit half
// (one row): bytes r0..r3 g0..g3 b0..b3 a0..a3, transposed to pixels by PSHUFB and added to the
// destination with unsigned saturation (PADDUSB: the clamp at 255).
[[gnu::always_inline]] inline I32x8 additiveBlendRgba8(I32x8 dest, F32x8 r, F32x8 g, F32x8 b, F32x8 alpha) {
    const F32x8 sa = min(max(alpha, splat(0.0f)), splat(1.0f));  // saturate, NaN -> 0
    const F32x8 sa255 = sa * 255.0f;
    const __m256i a = _mm256_cvttps_epi32(__m256(sa * sa255 + 0.5f));
    auto units = [&](F32x8 s) {  // CVTTPS2DQ: truncation, INT_MIN for NaN and out of range
        return _mm256_cvttps_epi32(__m256(min(splat(1.0f), s) * sa255 + 0.5f));
    };
    const __m256i planar =
        _mm256_packus_epi16(_mm256_packus_epi32(units(r), units(g)), _mm256_packus_epi32(units(b), a));
    const __m256i to_pixels = _mm256_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15, 0, 4, 8, 12, 1,
                                               5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15);
    return I32x8(_mm256_adds_epu8(__m256i(dest), _mm256_shuffle_epi8(planar, to_pixels)));
}

// The transparent-pixel intervals of four row pairs at a time: TransparentColumns::rowPair's double
// operations lane by lane (four doubles in a register, their int32 results in 128 bits), for row pairs
// j0, j0 + 2, … while fewer than n are done; returns how many it wrote (n rounded up to four).
[[gnu::always_inline]] inline int spanIntervals(const SpanRows& s, int32_t j0, int n, int32_t* lo, int32_t* hi) {
    const __m256d b0 = _mm256_set1_pd(s.b0), sb = _mm256_set1_pd(s.sb), margin = _mm256_set1_pd(s.margin);
    const __m256d a0 = _mm256_set1_pd(s.a0), inv_sa = _mm256_set1_pd(s.inv_sa);
    const __m256d a_below = _mm256_set1_pd(s.a_below), a_above = _mm256_set1_pd(s.a_above);
    const __m256d lo_min = _mm256_set1_pd(double(s.i_min)), lo_max = _mm256_set1_pd(double(s.i_max) + 1.0);
    const __m256d hi_min = _mm256_set1_pd(double(s.i_min) - 1.0), hi_max = _mm256_set1_pd(double(s.i_max));
    const __m128i one = _mm_set1_epi32(1), zero = _mm_setzero_si128();
    const __m128i rows = _mm_set1_epi32(s.height), last_row = _mm_set1_epi32(s.height - 1);
    const __m128i last_column = _mm_set1_epi32(s.width - 1);
    const __m128i empty_lo = _mm_set1_epi32(s.i_min), empty_hi = _mm_set1_epi32(s.i_min - 1);
    auto clampRow = [&](__m128i r) { return _mm_max_epi32(_mm_min_epi32(r, last_row), zero); };
    auto wide = [](__m128i mask) { return _mm256_castsi256_pd(_mm256_cvtepi32_epi64(mask)); };
    int q = 0;
    for (; q < n; q += 4) {
        const __m256d rows_j = _mm256_add_pd(_mm256_set1_pd(double(j0 + 2 * q)), _mm256_set_pd(6, 4, 2, 0));
        const __m256d top = _mm256_add_pd(b0, _mm256_mul_pd(sb, rows_j)), bottom = _mm256_add_pd(top, sb);
        const __m256d b_lo = _mm256_sub_pd(_mm256_min_pd(top, bottom), margin);
        const __m256d b_hi = _mm256_add_pd(_mm256_max_pd(top, bottom), margin);
        const __m128i r0 = clampRow(_mm256_cvttpd_epi32(_mm256_floor_pd(b_lo)));
        const __m128i r1 = clampRow(_mm_add_epi32(_mm256_cvttpd_epi32(_mm256_floor_pd(b_hi)), one));
        // k = floor(log2(r1 − r0 + 1)) from the exponent of the count as a float (exact: ≤ 4096).
        const __m128i count = _mm_add_epi32(_mm_sub_epi32(r1, r0), one);
        const __m128i k =
            _mm_sub_epi32(_mm_srli_epi32(_mm_castps_si128(_mm_cvtepi32_ps(count)), 23), _mm_set1_epi32(127));
        const __m128i level = _mm_mullo_epi32(k, rows);
        const __m128i ia = _mm_slli_epi32(_mm_add_epi32(level, r0), 1);
        const __m128i ib =
            _mm_slli_epi32(_mm_add_epi32(level, _mm_sub_epi32(_mm_add_epi32(r1, one), _mm_sllv_epi32(one, k))), 1);
        // Each span's (first, last) as one 8-byte load: gathers measured slower on Zen 5
        // (docs/PERFORMANCE.md).
        auto spansAt = [&](__m128i index) {  // the four spans' firsts and lasts
            alignas(16) int32_t at[4];
            _mm_store_si128(reinterpret_cast<__m128i*>(at), index);
            auto span = [&](int e) { return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(s.spans + at[e])); };
            const __m128 s01 = _mm_castsi128_ps(_mm_unpacklo_epi64(span(0), span(1)));
            const __m128 s23 = _mm_castsi128_ps(_mm_unpacklo_epi64(span(2), span(3)));
            return std::pair{_mm_castps_si128(_mm_shuffle_ps(s01, s23, _MM_SHUFFLE(2, 0, 2, 0))),
                             _mm_castps_si128(_mm_shuffle_ps(s01, s23, _MM_SHUFFLE(3, 1, 3, 1)))};
        };
        const auto [first_a, last_a] = spansAt(ia);
        const auto [first_b, last_b] = spansAt(ib);
        const __m128i first = _mm_min_epi32(first_a, first_b), last = _mm_max_epi32(last_a, last_b);
        const __m128i empty = _mm_cmpgt_epi32(first, last);
        const __m256d a_lo = _mm256_blendv_pd(_mm256_sub_pd(_mm256_cvtepi32_pd(_mm_sub_epi32(first, one)), margin),
                                              a_below, wide(_mm_cmpeq_epi32(first, zero)));
        const __m256d a_hi = _mm256_blendv_pd(_mm256_add_pd(_mm256_cvtepi32_pd(_mm_add_epi32(last, one)), margin),
                                              a_above, wide(_mm_cmpeq_epi32(last, last_column)));
        const __m256d t_lo = _mm256_mul_pd(_mm256_sub_pd(a_lo, a0), inv_sa);
        const __m256d t_hi = _mm256_mul_pd(_mm256_sub_pd(a_hi, a0), inv_sa);
        const __m256d i0 = _mm256_ceil_pd(_mm256_min_pd(t_lo, t_hi));
        const __m256d i1 = _mm256_floor_pd(_mm256_max_pd(t_lo, t_hi));
        const __m128i l =
            _mm_blendv_epi8(_mm256_cvttpd_epi32(_mm256_min_pd(_mm256_max_pd(i0, lo_min), lo_max)), empty_lo, empty);
        const __m128i h =
            _mm_blendv_epi8(_mm256_cvttpd_epi32(_mm256_min_pd(_mm256_max_pd(i1, hi_min), hi_max)), empty_hi, empty);
        // Four at a time, past n too: the remainder copied element by element compiled to two calls
        // to memcpy per rectangle.
        _mm_storeu_si128(reinterpret_cast<__m128i*>(lo + q), l);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(hi + q), h);
    }
    return q;
}
#endif

}  // namespace raster::simd::avx2

#pragma GCC diagnostic pop
