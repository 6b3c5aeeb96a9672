// The SIMD layer's operations by name: what each computes, in which units, by which rule, for which
// stage; and which instruction set's version this build takes (chosen at compile time from the
// compiler's __AVX2__ etc., i.e. from -march; there is no run-time dispatch). Callers call these
// names, never an instruction-set namespace, and need no #if of their own. Every operation gives the
// same bits in every version (tests/simd_ops_test.cpp checks each against a scalar reference, and
// simd_test's TransparentColumns.RowPairsGiveRowPairsIntervals spanIntervals against rowPair).
//
// Why hand-written intrinsics and not Google Highway (libhwy-dev 1.0.3 in Debian 12), which would
// give one source for the 256- and 512-bit kernels: Highway keeps every bit only for part of them,
// and costs instructions in the hot ones. Kernel by kernel (docs/DESIGN.md, "The SIMD layer"):
//  - the footprint filter (footprintFilter, footprintFilter1): its core is PMADDUBSW (unsigned ×
//    signed bytes, pairs added with int16 saturation), which Highway 1.0.3 has no operation for
//    (SatWidenMulPairwiseAdd came later); spelled with shifts, 16-bit multiplies and PMADDWD, the
//    weights and four channels of a block took 118 instructions for the hand-written 87 (the same
//    bits; docs/experiments/highway_footprint_filter.cpp), on the particles' hottest path. Its
//    CVTPS2DQ (round to nearest even) is Highway's NearestInt, which also rewrites out-of-range and
//    NaN lanes to INT32_MAX when their sign is clear (two more instructions and different bits from
//    roundToInt below). The AVX-512 pair's window pick (VPERMT2D across two registers) has no
//    Highway 1.0.3 operation either (TwoTablesLookupLanes came later).
//  - the eight- and sixteen-lane additive blends (additiveBlendRgba8, …Pair): they rely on
//    CVTTPS2DQ's INT32_MIN for NaN and on PACKUSDW taking it to 0; Highway's ConvertTo returns
//    INT32_MAX for a NaN whose sign bit is clear, so a NaN colour would come out 255 instead of 0.
//    Its DemoteTo to bytes adds a cross-lane permute that the in-lane PSHUFB here avoids.
//  - spanIntervals: CVTTPD2DQ (double to int32, truncating) is Highway's DemoteTo, which clamps to
//    INT32_MAX first (one more instruction per conversion, the same bits for the values here);
//    the rest would translate, but one small kernel alone does not pay for a dependency.
//  - the one-pixel SSE kernels and the lane helpers (min, max, floor, movemask…): one instruction
//    each, nothing to share; and Highway's Min and Max are MINPS/MAXPS on x86 but VMINNM/VMAXNM on
//    Arm (min(NaN, 1) = 1 there), where raster's rule (the texture clamps', saturate's) is "b".
// And an AVX-512 rewrite through Highway could not be checked for bit-exactness on the machine
// raster is developed on (a Zen 3 has no AVX-512): the kernels of avx512.hpp were measured and
// tested on an AVX-512 core when written, and are kept as they were.
#pragma once

#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#include "raster/simd/avx2.hpp"
#include "raster/simd/avx512.hpp"
#include "raster/simd/base.hpp"
#include "raster/simd/portable.hpp"
#include "raster/simd/x86_128.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // see base.hpp

namespace raster::simd {

// ---- Lanes --------------------------------------------------------------------------------------
// maskBits(m): bit i set where lane i of the comparison mask m is true (all bits set); eight lanes
//   of int32, or four of int64.
// min(a, b), max(a, b): a < b ? a : b and a > b ? a : b, lane by lane: a NaN in either gives b.
// toFloat8(lo, hi): eight doubles, lanes 0–3 then 4–7, each rounded to float as float(double) rounds
//   it (to nearest, ties to even).
// floor(a): the largest integer ≤ a, as a float (exact for every float; NaN stays NaN).
// sqrt(a): the correctly rounded square root, as sqrtf.
// roundToInt(a): to the nearest integer, ties to even (the default rounding mode); NaN and values
//   outside int32 give INT32_MIN.
// loadRows(row0, row1): 32 bytes, the first 16 from row0 and the next 16 from row1 (a 4×2 block's
//   two rows of four 32-bit values).
#if defined(__AVX__)
using avx2::floor;
using avx2::loadRows;
using avx2::maskBits;
using avx2::max;
using avx2::min;
using avx2::roundToInt;
using avx2::sqrt;
using avx2::toFloat8;
#else
using portable::floor;
using portable::loadRows;
using portable::maskBits;
using portable::max;
using portable::min;
using portable::roundToInt;
using portable::sqrt;
using portable::toFloat8;
#endif
// fma(a, b, c): a·b + c rounded once (IEEE fusedMultiplyAdd), lane by lane the same bits as std::fma.
// One instruction with FMA hardware; without it the C library's (exact, slow) fmaf.
#if defined(__FMA__)
using avx2::fma;
#else
using portable::fma;
#endif
// gather(base, index): base[index[i]] for each lane, 32-bit loads.
#if defined(__AVX2__)
using avx2::gather;
#else
using portable::gather;
#endif

// A hint in a spin-wait loop (the thread pool's): PAUSE on x86, nothing elsewhere.
#if defined(__SSE2__)
using sse::pause;
#else
using portable::pause;
#endif

// ---- Texture2D's fixed-point bilinear filter (texture.hpp, "Precision"; the formula in base.hpp) --
// footprintFilter1(footprint, a, b): one sample's four channels (R, G, B, A as n/255 floats) from the
//   16 bytes of its footprint and its integer weights a = min(round(α·256), 255), b = round(β·2^14).
inline glm::vec4 footprintFilter1(const int8_t* footprint, int a, int b) {
#if defined(__SSSE3__)
    const F32x4 rgba = sse::footprintFilter1(footprint, a, b);
#else
    const F32x4 rgba = portable::footprintFilter1(footprint, a, b);
#endif
    glm::vec4 out;
    std::memcpy(&out, &rgba, sizeof out);
    return out;
}
// footprintFilter<N>(grid, footprints, planes, u, v, out): N 4×2 blocks of samples (N = 1 or 2) at
//   texture coordinates (u, v), each lane the same bits as Texture2D::filterFootprint's sample at its
//   (u, v): a = u·w − 0.5 and b = v·h − 0.5 clamped to [−1, w−1] × [−1, h−1] (NaN to −1), footprint
//   (floor(a), floor(b)), α = a − floor(a), β = b − floor(b). out[n][c] is channel c of block n.
//   `planes` is read only by the AVX-512 pair (FootprintGrid::planeStride).
template <int N>
[[gnu::always_inline]] inline void footprintFilter(const FootprintGrid& grid, const uint8_t* footprints,
                                                   const int32_t* planes, const F32x8 (&u)[N],
                                                   const F32x8 (&v)[N], F32x8 (&out)[N][4]) {
#if RASTER_AVX512
    if constexpr (N == 2) {
        avx512::footprintFilterPair(grid, footprints, planes, u, v, out);
        return;
    }
#endif
#if defined(__AVX2__)
    avx2::footprintFilter8<N>(grid, footprints, u, v, out);
#else
    portable::footprintFilter8<N>(grid, footprints, u, v, out);
#endif
    (void)planes;
}

// ---- The output merger's RGBA8 blenders (fastpath/blend_rgba8.hpp, BlendReplaceRgba8, BlendAdditiveRgba8)
// storeUnorm8x4(pixel, rgba): floatToUnorm8 (format.hpp) per channel: saturate (NaN to 0), ·255 + 0.5,
//   truncated; the four bytes R, G, B, A written at pixel.
// additiveBlendUnorm8x4(pixel, rgba): the additive blend (SrcAlpha, One) into the four bytes at
//   pixel: with s = saturate(rgba), every channel adds trunc(s·(s.a·255) + 0.5) units of 1/255 to
//   its byte, clamped at 255 (detail::addUnits255's order of operations).
#if defined(__SSE2__)
namespace one_pixel = sse;
#else
namespace one_pixel = portable;
#endif
inline F32x4 lanesOf(const glm::vec4& v) {
    F32x4 r;
    std::memcpy(&r, &v, sizeof r);
    return r;
}
inline void storeUnorm8x4(uint8_t* pixel, const glm::vec4& rgba) { one_pixel::storeUnorm8x4(pixel, lanesOf(rgba)); }
inline void additiveBlendUnorm8x4(uint8_t* pixel, const glm::vec4& rgba) {
    one_pixel::additiveBlendUnorm8x4(pixel, lanesOf(rgba));
}
// additiveBlendRgba8(dest, r, g, b, a): additiveBlendUnorm8x4 for eight pixels at once: dest holds
//   their bytes (R in the low byte of each lane), the result their new bytes.
#if defined(__AVX2__)
using avx2::additiveBlendRgba8;
#else
using portable::additiveBlendRgba8;
#endif
// additiveBlendRgba8Pair(row0, row1, rgba, mask): the same for two side-by-side 4×2 blocks, row0 and
//   row1 each eight pixels (32 bytes) wide, rgba[c][k] channel c of block k; only lanes whose bit is
//   set in mask (block 1 in bits 8–15) are written. Returns the lanes whose saturated alpha is 0.
//   AVX-512 only: where kAvx512 is false it is declared, for an `if constexpr (simd::kAvx512)`, and
//   never defined.
#if RASTER_AVX512
using avx512::additiveBlendRgba8Pair;
#else
uint32_t additiveBlendRgba8Pair(uint8_t* row0, uint8_t* row1, const F32x8 (&rgba)[4][2], uint32_t mask);
#endif

// ---- TransparentColumns (fastpath/transparency.hpp) ------------------------------------------------
// spanIntervals(rows, j0, n, lo, hi): TransparentColumns::rowPair's interval [lo[q], hi[q]] for row
//   pairs j0 + 2q, the same double operations lane by lane, four row pairs at a time (so up to three
//   entries past n are written). Returns how many it wrote: n rounded up to four, or 0 where there is
//   no vector version and the caller's scalar loop must do them all.
#if defined(__AVX2__)
using avx2::spanIntervals;
#else
using portable::spanIntervals;
#endif

}  // namespace raster::simd

#pragma GCC diagnostic pop
