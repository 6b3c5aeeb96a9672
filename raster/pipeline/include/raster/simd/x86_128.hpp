// SSE2 and SSSE3 (128 bits): one pixel's four channels, or one texel footprint, in one register.
// Every lane performs the scalar code's IEEE operations in the same order, hence the same bits; the
// names are chosen, and documented, in ops.hpp. Written with intrinsics because the compiler turns
// the scalar clamps into branches (it threads "clamped to 0" and "clamped to 1" into constant bytes)
// and has no pattern for PMADDUBSW.
#pragma once

#include <cstdint>
#include <cstring>

#include "raster/simd/base.hpp"

namespace raster::simd::sse {

#if defined(__SSE2__)
// saturate() per lane: MAXPS returns its second operand when the first is NaN, so NaN -> 0.
inline __m128 saturate4(__m128 v) { return _mm_min_ps(_mm_max_ps(v, _mm_setzero_ps()), _mm_set1_ps(1.0f)); }

// floatToUnorm8() per lane: the truncating conversion is the (uint8_t) cast; the packs cannot
// saturate because every lane is already in [0, 255].
inline void storeUnorm8x4(uint8_t* pixel, F32x4 rgba) {
    const __m128 scaled = _mm_add_ps(_mm_mul_ps(saturate4(__m128(rgba)), _mm_set1_ps(255.0f)), _mm_set1_ps(0.5f));
    const __m128i words = _mm_packs_epi32(_mm_cvttps_epi32(scaled), _mm_setzero_si128());
    const int32_t bits = _mm_cvtsi128_si32(_mm_packus_epi16(words, words));
    std::memcpy(pixel, &bits, 4);
}

// The additive blend's s · (a · 255) + 0.5 truncated in every lane, then the destination bytes added
// with unsigned saturation (PADDUSB: the clamp at 255).
inline void additiveBlendUnorm8x4(uint8_t* pixel, F32x4 rgba) {
    const __m128 s = saturate4(__m128(rgba));
    const __m128 alpha255 = _mm_mul_ps(_mm_shuffle_ps(s, s, _MM_SHUFFLE(3, 3, 3, 3)), _mm_set1_ps(255.0f));
    const __m128i units = _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(s, alpha255), _mm_set1_ps(0.5f)));
    const __m128i words = _mm_packs_epi32(units, _mm_setzero_si128());
    int32_t bits;
    std::memcpy(&bits, pixel, 4);
    bits = _mm_cvtsi128_si32(_mm_adds_epu8(_mm_packus_epi16(words, words), _mm_cvtsi32_si128(bits)));
    std::memcpy(pixel, &bits, 4);
}

// PAUSE: tells the core that this is a spin-wait loop (it yields the pipeline to the sibling
// hyperthread and avoids the memory-order flush when the loop exits).
inline void pause() { _mm_pause(); }
#endif

#if defined(__SSSE3__)
// The four channels of one footprint at once, as avx2::footprintFilter8 does eight pixels: the same
// integers and the same three float roundings per channel. Weights: the bytes (255 − a, a) for
// PMADDUBSW's pairs (t00, t10) and (t01, t11), whose missing 1·t0 (256 − a does not fit a byte) is
// added from the pair's low byte; then the words (2^14 − b, b) for PMADDWD's two rows. PMADDUBSW
// saturates to int16, which no weighted pair reaches: |255·t0 + a·t1| ≤ 255·128 < 2^15.
inline F32x4 footprintFilter1(const int8_t* footprint, int a, int b) {
    const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(footprint));
    const int wa = (255 - a) | (a << 8);
    const __m128i low = _mm_maddubs_epi16(_mm_set1_epi16(1), bytes);
    const __m128i rows = _mm_add_epi16(_mm_maddubs_epi16(_mm_set1_epi32(wa | (wa << 16)), bytes), low);
    const __m128i sum = _mm_madd_epi16(rows, _mm_set1_epi32((kFootprintBetaOne - b) | (b << 16)));
    return F32x4(_mm_mul_ps(_mm_add_ps(_mm_cvtepi32_ps(sum), _mm_set1_ps(kFootprintBiasSum)),
                            _mm_set1_ps(kFootprintScale)));
}
#endif

}  // namespace raster::simd::sse
