// What every header of the SIMD layer shares: the instruction sets this build targets, the x86
// intrinsics header, the raw vector types, and the fixed-point footprint filter's constants.
//
// The SIMD layer (raster/simd.hpp and this folder) is the only place in raster where a processor's
// intrinsics appear, one header per instruction set:
//     simd/x86_128.hpp  SSE2 and SSSE3, 128 bits: one RGBA pixel or one texel footprint at a time
//     simd/avx2.hpp     AVX, AVX2 and FMA, 256 bits: eight lanes (a 4×2 pixel block)
//     simd/avx512.hpp   AVX-512 F/BW/DQ/VL, 512 bits: sixteen lanes (a pair of blocks)
//     simd/portable.hpp the same operations without intrinsics (GCC/Clang vector extensions and
//                       loops), for a target that lacks the set
//     simd/ops.hpp      the names the rest of raster calls, each choosing one of the above here,
//                       at compile time (#if on the compiler's __AVX2__ etc.), so that no caller
//                       needs an #if of its own
// tests/simd_intrinsics_test.py keeps it so. Each operation is documented where its name is chosen
// (ops.hpp): what it computes, in which units, by which rule, for which stage; the instruction-set
// headers say how and why that way.
#pragma once

#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
// GCC 12's AVX-512 intrinsics start from a self-initialised "undefined" register (`__Y = __Y`), which
// -Wmaybe-uninitialized reports wherever they are inlined (fixed in GCC 13). The warning is judged
// at the header's lines, so it is silenced for them here, where the header is first included, and
// stays on for the project's own code.
// Clang (the fuzz and sanitizer builds) has no -Wmaybe-uninitialized and needs none of this.
#if defined(__clang__)
#include <immintrin.h>
#else
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#endif
#endif

// Whether the core has AVX-512 (F, BW, DQ, VL): then the particles' pair of 4×2 blocks is sampled
// and blended in one 16-lane register (simd::footprintFilterPair, simd::additiveBlendRgba8Pair), the
// same operations lane by lane, so the same bits as the eight-lane code.
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512DQ__) && defined(__AVX512VL__)
#define RASTER_AVX512 1
#else
#define RASTER_AVX512 0
#endif

// The layer's functions take and return 32- and 64-byte vectors. They are inline and inlined, so no
// vector crosses an ABI boundary: GCC's note that such vectors are passed differently with and
// without AVX (-Wpsabi, in a build without -march=native) does not apply, and is silenced here and
// in the layer's other headers, each between its own push and pop.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace raster::simd {

// GCC/Clang vector extensions: + − × ÷ and comparisons lane by lane (a comparison gives all bits set
// where true), v[i] for a lane. The layer's functions take and return these, so that they need
// nothing of raster's own types.
using F32x8 = float __attribute__((vector_size(32)));
using I32x8 = int32_t __attribute__((vector_size(32)));
using U32x8 = uint32_t __attribute__((vector_size(32)));
using F32x4 = float __attribute__((vector_size(16)));
using I32x4 = int32_t __attribute__((vector_size(16)));
using F64x4 = double __attribute__((vector_size(32)));
using I64x4 = int64_t __attribute__((vector_size(32)));

inline constexpr bool kAvx512 = RASTER_AVX512;

// x in every lane. Not `F32x8{} + x`: 0 + x is not x for x = −0, so the compiler must add, per call,
// and −0 would come out +0.
inline F32x8 splat(float x) { return F32x8{x, x, x, x, x, x, x, x}; }

// ---- The fixed-point bilinear filter of footprints (texture.hpp's "Precision") -------------------
// A footprint is the four texels of a bilinear tap, (i, j) (i+1, j) (i, j+1) (i+1, j+1), as 16 bytes,
// channel-major (bytes 4c..4c+3 hold channel c of the four), each byte − 128, read as signed bytes.
// Horizontal weights (256 − a, a), a = min(round(α·256), 255); vertical (2^14 − b, b),
// b = round(β·2^14) (round half to even, as CVTPS2DQ). Per channel
//     sum = (2^14 − b)·((256 − a)·t00 + a·t10) + b·((256 − a)·t01 + a·t11),  t = byte − 128,
// exact in 32 bits (|sum| ≤ 2^29), 2^22 units per byte; the result is (sum + 128·2^22) · 2^−22/255,
// so that at α = β = 0 it is unorm8ToFloat(t00) bit for bit (the scalings by 2^k are exact).
inline constexpr float kFootprintAlphaScale = 256.0f;
inline constexpr int kFootprintAlphaMax = 255;
inline constexpr float kFootprintBetaScale = 16384.0f;
inline constexpr int kFootprintBetaOne = 16384;
inline constexpr float kFootprintBiasSum = 536870912.0f;                // 128 · 2^22
inline constexpr float kFootprintScale = (1.0f / 255.0f) / 4194304.0f;  // unorm8ToFloat's 1/255 · 2^−22
// The AVX-512 pair filter's window: dwords of one channel plane read at once (see FootprintGrid).
inline constexpr int kFootprintPlaneWindow = 16;

// What the footprint filters read of a texture (Texture2D::buildFootprints fills it), each field
// broadcast from memory in one instruction: the pixel loop's stores to targets may alias the texture
// for all the compiler knows, so every call reloads it (hence no level list to walk and no
// int-to-float conversions). The footprints of a w × h texture are indexed (j + 1)·(w + 1) + (i + 1)
// for texel coordinates (i, j) in [−1, w−1] × [−1, h−1].
struct FootprintGrid {
    float width = 0, height = 0;   // of level 0, as floats
    float lastI = 0, lastJ = 0;    // width − 1, height − 1
    float rowStride = 0;           // width + 1 footprints per row
    float originIndex = 0;         // width + 2: the index of footprint (0, 0), as (−1, −1) is index 0
    int32_t maxI = 0, maxJ = 0;    // width − 1, height − 1
    int32_t stride = 0;            // width + 1; 0 when there are no footprints
    // Dwords from one channel plane to the next; 0 without planes. The planes (RASTER_AVX512 only)
    // are the footprints once more, one per channel: dword k of plane c is bytes 4c..4c+3 of
    // footprint k, and each plane ends in kFootprintPlaneWindow − 1 dwords of padding, so that a
    // window of kFootprintPlaneWindow dwords that begins at any footprint stays inside it.
    int32_t planeStride = 0;
    bool operator==(const FootprintGrid& other) const = default;
};

}  // namespace raster::simd

namespace raster::simd {

// What spanIntervals reads: one billboard rectangle's texture coordinate planes in texel units
// (fastpath/transparency.hpp, TransparentColumns::Planes) and the texture's alpha spans.
struct SpanRows {
    // The texture's sparse table of (first, last) column pairs, level k (the unions of 2^k rows)
    // at pairs k·height .. k·height + height − 1 (Texture2D::alphaSpanTable).
    const int32_t* spans = nullptr;
    int32_t width = 0, height = 0;  // of the texture, in texels
    // a = a0 + i·sa across the row, b = b0 + j·sb down the column; inv_sa = 1 / sa.
    double a0 = 0, inv_sa = 0, b0 = 0, sb = 0;
    double a_below = 0, a_above = 0;  // bounds of a beyond the rectangle, for a side the clamp reaches
    double margin = 0;                // texels
    int32_t i_min = 0, i_max = 0;     // the columns being drawn
};

}  // namespace raster::simd

#pragma GCC diagnostic pop
