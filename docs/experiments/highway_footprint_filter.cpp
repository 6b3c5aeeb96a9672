// Google Highway (Debian's libhwy-dev 1.0.3) tried on the footprint filter's arithmetic: the weights
// and the four channels of one 4×2 block, written with Highway's operations and by hand (as
// raster/pipeline/include/raster/simd/avx2.hpp has it), compared bit for bit on random blocks (α·256 ties
// among them) and counted in instructions. docs/DESIGN.md, "The SIMD layer", says what followed.
//
//     apt-get install libhwy-dev
//     g++ -std=c++20 -O3 -march=native -ffp-contract=off -Iraster/pipeline/include \
//         docs/experiments/highway_footprint_filter.cpp -o /tmp/hwy_filter && /tmp/hwy_filter
//     objdump -d --no-show-raw-insn /tmp/hwy_filter | awk '/<_Z9filterHwy/,/ret/' | grep -c '^ '
//     objdump -d --no-show-raw-insn /tmp/hwy_filter | awk '/<_Z10filterAvx2/,/ret/' | grep -c '^ '
//
// GCC 12 on a Zen 3 (AVX2, 2026-12-03): 200 000 blocks, none differing; 118 instructions (Highway)
// against 87 (hand-written). Highway 1.0.3 has no operation for PMADDUBSW, so the bytes are widened
// to 16 bits by shifts and multiplied by 16-bit multiplies; its NearestInt adds the fix-up of
// out-of-range lanes to each CVTPS2DQ.
#include <hwy/highway.h>
#include <cstdio>
#include <cstring>
#include <random>
#include "raster/simd/ops.hpp"
namespace hn = hwy::HWY_NAMESPACE;
using namespace raster::simd;

// channel[c]: per lane the channel's 4 signed bytes t00 t10 t01 t11; alpha, beta in [0, 1).
__attribute__((noinline)) void filterHwy(const int32_t* channel, const float* alpha, const float* beta, float* out) {
    const hn::Full256<float> df;
    const hn::Full256<int32_t> d32;
    const hn::Full256<int16_t> d16;
    const auto a = hn::Min(hn::NearestInt(hn::Mul(hn::LoadU(df, alpha), hn::Set(df, 256.0f))), hn::Set(d32, 255));
    const auto b = hn::NearestInt(hn::Mul(hn::LoadU(df, beta), hn::Set(df, 16384.0f)));
    // (256 − a, a) as words, and (2^14 − b, b) as words, per dword lane.
    const auto wa = hn::BitCast(d16, hn::Or(hn::ShiftLeft<16>(a), hn::Sub(hn::Set(d32, 256), a)));
    const auto wb = hn::BitCast(d16, hn::Or(hn::ShiftLeft<16>(b), hn::Sub(hn::Set(d32, 16384), b)));
    for (int c = 0; c < 4; ++c) {
        const auto bytes = hn::BitCast(d16, hn::LoadU(d32, channel + 8 * c));
        const auto even = hn::ShiftRight<8>(hn::ShiftLeft<8>(bytes));  // t00, t01 sign-extended
        const auto odd = hn::ShiftRight<8>(bytes);                      // t10, t11
        // rows: word 2k = (256 − a)·t_left + a·t_right for row k, as int16 (|.| ≤ 2^15, exact).
        const auto lo_w = hn::BitCast(d16, hn::And(hn::BitCast(d32, wa), hn::Set(d32, 0xFFFF)));  // 256 − a in both words
        const auto lo = hn::Or(hn::BitCast(d16, hn::ShiftLeft<16>(hn::BitCast(d32, lo_w))), lo_w);
        const auto hi = hn::BitCast(d16, hn::ShiftRight<16>(hn::BitCast(d32, wa)));
        const auto hi2 = hn::Or(hn::BitCast(d16, hn::ShiftLeft<16>(hn::BitCast(d32, hi))), hi);
        // Lanes of `even` hold t00 (word 0) and t01 (word 1); odd t10, t11.
        const auto rows = hn::Add(hn::Mul(even, lo), hn::Mul(odd, hi2));
        hn::Vec256<int32_t> sum1 = hn::Zero(d32);
        const auto sum = hn::ReorderWidenMulAccumulate(d32, rows, wb, hn::Zero(d32), sum1);
        const auto f = hn::Mul(hn::Add(hn::ConvertTo(df, hn::RearrangeToOddPlusEven(sum, sum1)), hn::Set(df, kFootprintBiasSum)),
                               hn::Set(df, kFootprintScale));
        hn::StoreU(f, df, out + 8 * c);
    }
}

__attribute__((noinline)) void filterAvx2(const int32_t* channel, const float* alpha, const float* beta, float* out) {
    F32x8 al, be;
    std::memcpy(&al, alpha, 32), std::memcpy(&be, beta, 32);
    const __m256i wa8 = _mm256_min_epi32(_mm256_cvtps_epi32(__m256(al * kFootprintAlphaScale)), _mm256_set1_epi32(255));
    const __m256i wa16 = _mm256_or_si256(_mm256_slli_epi32(wa8, 8), _mm256_xor_si256(wa8, _mm256_set1_epi32(255)));
    const __m256i wa = _mm256_or_si256(wa16, _mm256_slli_epi32(wa16, 16));
    const __m256i wb14 = _mm256_cvtps_epi32(__m256(be * kFootprintBetaScale));
    const __m256i wb = _mm256_or_si256(_mm256_slli_epi32(wb14, 16), _mm256_sub_epi32(_mm256_set1_epi32(16384), wb14));
    for (int c = 0; c < 4; ++c) {
        const __m256i bytes = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(channel + 8 * c));
        const __m256i low = _mm256_maddubs_epi16(_mm256_set1_epi16(1), bytes);
        const __m256i rows = _mm256_add_epi16(_mm256_maddubs_epi16(wa, bytes), low);
        const __m256 sum = _mm256_cvtepi32_ps(_mm256_madd_epi16(rows, wb));
        _mm256_storeu_ps(out + 8 * c, _mm256_mul_ps(_mm256_add_ps(sum, _mm256_set1_ps(kFootprintBiasSum)), _mm256_set1_ps(kFootprintScale)));
    }
}

int main() {
    std::mt19937 rng(3);
    long diffs = 0, n = 0;
    for (int round = 0; round < 200000; ++round) {
        int32_t ch[32]; float al[8], be[8], o1[32], o2[32];
        for (auto& x : ch) x = int32_t(rng());
        for (int l = 0; l < 8; ++l) al[l] = float(rng() % 4096) / 4096.0f, be[l] = float(rng() % 65536) / 65536.0f;
        if (round % 7 == 0) for (int l = 0; l < 8; ++l) al[l] = float(2 * (rng() % 256) + 1) / 512.0f;  // ties
        filterHwy(ch, al, be, o1);
        filterAvx2(ch, al, be, o2);
        diffs += std::memcmp(o1, o2, sizeof o1) != 0;
        ++n;
    }
    printf("blocks %ld, differing %ld\n", n, diffs);
}
