// Eight floats at once, for shaders that are written once for `float` and run eight pixels wide.
//
// A pixel shader may, besides its scalar operator()(const In&), offer the same code for
// raster::Float8: operator()(const Wide<In>&) returning glm::vec<4, Float8>, where Wide<In> is the
// input struct template instantiated with Float8 (see shader.hpp). The pipeline then shades 4×2
// pixel blocks in one call; lanes 0–3 are the block's top row left to right, 4–7 the bottom row,
// so lanes (0,1,4,5) and (2,3,6,7) are the two 2×2 quads derivatives are taken in. Results are the
// same bits as the scalar path: every operation here is the IEEE operation the scalar code does,
// lane by lane (a multiply-add is fused only where fma() says so; no approximate reciprocal).
// Such a shader also compiles for Float8x2 (below), two blocks side by side, which the pipeline
// uses for billboards.
//
// Portable GCC/Clang vector extensions; what they cannot express well (min and max with their NaN
// rule, floor, gathers, a mask's bits) comes from the SIMD layer's operations (simd/ops.hpp), the
// one place where a processor's intrinsics appear.
#pragma once

#include <cstdint>
#include <cstring>
#include <tuple>

#include <glm/glm.hpp>

#include "raster/shader_context.hpp"
#include "raster/simd/ops.hpp"

namespace raster {

struct Int8;

// A lane mask: all bits set where true.
struct Mask8 {
    simd::I32x8 v;
    friend Mask8 operator&(Mask8 a, Mask8 b) { return {a.v & b.v}; }
    friend Mask8 operator|(Mask8 a, Mask8 b) { return {a.v | b.v}; }
    Mask8 operator!() const { return {~v}; }
    // Bit i set when lane i is true.
    uint32_t bits() const { return simd::maskBits(v); }
    static Mask8 fromBits(uint32_t bits) {
        const simd::I32x8 lanes = {1, 2, 4, 8, 16, 32, 64, 128};
        return {(lanes & simd::I32x8(simd::I32x8{} + int32_t(bits))) != 0};
    }
};

struct alignas(32) Float8 {
    simd::F32x8 v;

    Float8() = default;
    // Broadcast, like a scalar in a vector expression. Not `F32x8{} + x`: 0 + x is not x for x = −0,
    // so the compiler must add, per call, and −0 would come out +0.
    Float8(float x) : v(simd::F32x8{x, x, x, x, x, x, x, x}) {}  // NOLINT
    Float8(simd::F32x8 x) : v(x) {}            // NOLINT
    static Float8 load(const float* p) {
        Float8 r;
        std::memcpy(&r.v, p, sizeof r.v);
        return r;
    }
    void store(float* p) const { std::memcpy(p, &v, sizeof v); }
    float operator[](int i) const { return v[i]; }
    void set(int i, float x) { v[i] = x; }

    friend Float8 operator+(Float8 a, Float8 b) { return a.v + b.v; }
    friend Float8 operator-(Float8 a, Float8 b) { return a.v - b.v; }
    friend Float8 operator*(Float8 a, Float8 b) { return a.v * b.v; }
    friend Float8 operator/(Float8 a, Float8 b) { return a.v / b.v; }
    Float8 operator-() const { return -v; }
    Float8& operator+=(Float8 b) { return v += b.v, *this; }
    Float8& operator-=(Float8 b) { return v -= b.v, *this; }
    Float8& operator*=(Float8 b) { return v *= b.v, *this; }
    Float8& operator/=(Float8 b) { return v /= b.v, *this; }
    friend Mask8 operator<(Float8 a, Float8 b) { return {a.v < b.v}; }
    friend Mask8 operator<=(Float8 a, Float8 b) { return {a.v <= b.v}; }
    friend Mask8 operator>(Float8 a, Float8 b) { return {a.v > b.v}; }
    friend Mask8 operator>=(Float8 a, Float8 b) { return {a.v >= b.v}; }
    friend Mask8 operator==(Float8 a, Float8 b) { return {a.v == b.v}; }
    friend Mask8 operator!=(Float8 a, Float8 b) { return {a.v != b.v}; }
};

struct alignas(32) Int8 {
    simd::I32x8 v;
    Int8() = default;
    Int8(int32_t x) : v(simd::I32x8{} + x) {}  // NOLINT
    Int8(simd::I32x8 x) : v(x) {}              // NOLINT
    int32_t operator[](int i) const { return v[i]; }
    friend Int8 operator+(Int8 a, Int8 b) { return a.v + b.v; }
    friend Int8 operator-(Int8 a, Int8 b) { return a.v - b.v; }
    friend Int8 operator*(Int8 a, Int8 b) { return a.v * b.v; }
    friend Int8 operator&(Int8 a, Int8 b) { return a.v & b.v; }
    friend Int8 operator|(Int8 a, Int8 b) { return a.v | b.v; }
    friend Int8 operator<<(Int8 a, int s) { return a.v << s; }
    // Logical shift right (as unsigned).
    friend Int8 operator>>(Int8 a, int s) { return simd::I32x8(simd::U32x8(a.v) >> s); }
    friend Mask8 operator<(Int8 a, Int8 b) { return {a.v < b.v}; }
    friend Mask8 operator>(Int8 a, Int8 b) { return {a.v > b.v}; }
    friend Mask8 operator==(Int8 a, Int8 b) { return {a.v == b.v}; }
};

inline Float8 select(Mask8 m, Float8 a, Float8 b) { return m.v ? a.v : b.v; }
inline Int8 select(Mask8 m, Int8 a, Int8 b) { return m.v ? a.v : b.v; }
inline int32_t min(int32_t a, int32_t b) { return a < b ? a : b; }
// min(a, b) = a < b ? a : b and max(a, b) = a > b ? a : b, lane by lane: a NaN in either gives b.
// That is exactly what MINPS and MAXPS do, but GCC only finds them without the NaN rule.
inline Float8 min(Float8 a, Float8 b) { return simd::min(a.v, b.v); }
inline Float8 max(Float8 a, Float8 b) { return simd::max(a.v, b.v); }
inline Int8 min(Int8 a, Int8 b) { return a.v < b.v ? a.v : b.v; }
inline Int8 max(Int8 a, Int8 b) { return a.v > b.v ? a.v : b.v; }
// Truncation toward zero, as int(float).
inline Int8 toInt(Float8 a) { return __builtin_convertvector(a.v, simd::I32x8); }
inline Float8 toFloat(Int8 a) { return __builtin_convertvector(a.v, simd::F32x8); }
// Eight doubles, lanes 0–3 then 4–7, each rounded to float as float(double) rounds it (to nearest,
// ties to even). One conversion per half and one insert, where building the vector lane by lane
// costs a dozen shuffles.
inline Float8 toFloat8(simd::F64x4 lo, simd::F64x4 hi) { return simd::toFloat8(lo, hi); }

// Largest integer ≤ a, as a float (exact for every float; NaN stays NaN).
inline Float8 floor(Float8 a) { return simd::floor(a.v); }
inline Float8 sqrt(Float8 a) { return simd::sqrt(a.v); }

// 32-bit loads base[index[i]] for each lane.
inline Int8 gather(const int32_t* base, Int8 index) { return simd::gather(base, index.v); }
inline Float8 gather(const float* base, Int8 index) { return simd::gather(base, index.v); }

// A 4×2 block's two rows of four (row0 the top row) as one register, lanes 0–3 and 4–7, and back.
inline Float8 loadBlock(const float* row0, const float* row1) { return simd::loadRows(row0, row1); }
inline Int8 loadBlock(const uint8_t* row0, const uint8_t* row1) { return simd::I32x8(simd::loadRows(row0, row1)); }
inline Int8 loadBlock(const uint32_t* row0, const uint32_t* row1) { return simd::I32x8(simd::loadRows(row0, row1)); }
inline void storeBlock(Float8 v, float* row0, float* row1) {
    std::memcpy(row0, &v.v, 16);
    std::memcpy(row1, reinterpret_cast<const char*>(&v.v) + 16, 16);
}
inline void storeBlock(Int8 v, uint8_t* row0, uint8_t* row1) {
    std::memcpy(row0, &v.v, 16);
    std::memcpy(row1, reinterpret_cast<const char*>(&v.v) + 16, 16);
}

// Scalar twins, so one shader template reads the same for float and Float8.
inline float select(bool m, float a, float b) { return m ? a : b; }
inline float min(float a, float b) { return a < b ? a : b; }
inline float max(float a, float b) { return a > b ? a : b; }
inline float sqrt(float a) { return __builtin_sqrtf(a); }
inline float abs(float a) { return __builtin_fabsf(a); }
inline Float8 abs(Float8 a) { return simd::F32x8(simd::I32x8(a.v) & 0x7FFFFFFF); }

// a·b + c rounded once (IEEE fusedMultiplyAdd), lane by lane the same bits as std::fma. Only where
// it is written: the build keeps -ffp-contract=off, so the compiler never fuses on its own and an
// image does not depend on its choices. One instruction with FMA hardware; without it the C
// library's (exact, slow) fmaf.
inline float fma(float a, float b, float c) { return __builtin_fmaf(a, b, c); }
inline Float8 fma(Float8 a, Float8 b, Float8 c) { return simd::fma(a.v, b.v, c.v); }

// Two 4×2 blocks side by side, sixteen lanes: a Float8 for each block, and every operation done on
// the first block, then the second. A shader written over its scalar type also compiles for it,
// and the pipeline shades two neighbouring blocks of a billboard in one call: the two blocks'
// dependency chains (a texture fetch is one long chain) then lie interleaved in the instruction
// stream, so the core works on both at once instead of waiting on one. The same bits as two
// Float8 calls, lane by lane (tests/simd_test.cpp).
struct Mask8x2 {
    Mask8 h[2];
    friend Mask8x2 operator&(Mask8x2 a, Mask8x2 b) { return {{a.h[0] & b.h[0], a.h[1] & b.h[1]}}; }
    friend Mask8x2 operator|(Mask8x2 a, Mask8x2 b) { return {{a.h[0] | b.h[0], a.h[1] | b.h[1]}}; }
    Mask8x2 operator!() const { return {{!h[0], !h[1]}}; }
    // Bit i set when lane i is true; lanes 8–15 are the second block.
    uint32_t bits() const { return h[0].bits() | (h[1].bits() << 8); }
    static Mask8x2 fromBits(uint32_t bits) { return {{Mask8::fromBits(bits & 0xFF), Mask8::fromBits(bits >> 8)}}; }
};

struct Int8x2 {
    Int8 h[2];
    Int8x2() = default;
    Int8x2(int32_t x) : h{Int8(x), Int8(x)} {}  // NOLINT
    Int8x2(Int8 a, Int8 b) : h{a, b} {}
    int32_t operator[](int i) const { return h[i >> 3][i & 7]; }
    friend Int8x2 operator+(Int8x2 a, Int8x2 b) { return {a.h[0] + b.h[0], a.h[1] + b.h[1]}; }
    friend Int8x2 operator-(Int8x2 a, Int8x2 b) { return {a.h[0] - b.h[0], a.h[1] - b.h[1]}; }
    friend Int8x2 operator*(Int8x2 a, Int8x2 b) { return {a.h[0] * b.h[0], a.h[1] * b.h[1]}; }
    friend Int8x2 operator&(Int8x2 a, Int8x2 b) { return {a.h[0] & b.h[0], a.h[1] & b.h[1]}; }
    friend Int8x2 operator|(Int8x2 a, Int8x2 b) { return {a.h[0] | b.h[0], a.h[1] | b.h[1]}; }
    friend Int8x2 operator<<(Int8x2 a, int s) { return {a.h[0] << s, a.h[1] << s}; }
    friend Int8x2 operator>>(Int8x2 a, int s) { return {a.h[0] >> s, a.h[1] >> s}; }  // logical, as Int8
    friend Mask8x2 operator<(Int8x2 a, Int8x2 b) { return {{a.h[0] < b.h[0], a.h[1] < b.h[1]}}; }
    friend Mask8x2 operator>(Int8x2 a, Int8x2 b) { return {{a.h[0] > b.h[0], a.h[1] > b.h[1]}}; }
};

struct Float8x2 {
    Float8 h[2];
    Float8x2() = default;
    Float8x2(float x) : h{Float8(x), Float8(x)} {}  // NOLINT: a broadcast, as Float8's
    Float8x2(Float8 a, Float8 b) : h{a, b} {}
    static Float8x2 load(const float* p) { return {Float8::load(p), Float8::load(p + 8)}; }
    void store(float* p) const { h[0].store(p), h[1].store(p + 8); }
    float operator[](int i) const { return h[i >> 3][i & 7]; }
    friend Float8x2 operator+(Float8x2 a, Float8x2 b) { return {a.h[0] + b.h[0], a.h[1] + b.h[1]}; }
    friend Float8x2 operator-(Float8x2 a, Float8x2 b) { return {a.h[0] - b.h[0], a.h[1] - b.h[1]}; }
    friend Float8x2 operator*(Float8x2 a, Float8x2 b) { return {a.h[0] * b.h[0], a.h[1] * b.h[1]}; }
    friend Float8x2 operator/(Float8x2 a, Float8x2 b) { return {a.h[0] / b.h[0], a.h[1] / b.h[1]}; }
    Float8x2 operator-() const { return {-h[0], -h[1]}; }
    Float8x2& operator+=(Float8x2 b) { return *this = *this + b; }
    Float8x2& operator-=(Float8x2 b) { return *this = *this - b; }
    Float8x2& operator*=(Float8x2 b) { return *this = *this * b; }
    Float8x2& operator/=(Float8x2 b) { return *this = *this / b; }
    friend Mask8x2 operator<(Float8x2 a, Float8x2 b) { return {{a.h[0] < b.h[0], a.h[1] < b.h[1]}}; }
    friend Mask8x2 operator<=(Float8x2 a, Float8x2 b) { return {{a.h[0] <= b.h[0], a.h[1] <= b.h[1]}}; }
    friend Mask8x2 operator>(Float8x2 a, Float8x2 b) { return {{a.h[0] > b.h[0], a.h[1] > b.h[1]}}; }
    friend Mask8x2 operator>=(Float8x2 a, Float8x2 b) { return {{a.h[0] >= b.h[0], a.h[1] >= b.h[1]}}; }
    friend Mask8x2 operator==(Float8x2 a, Float8x2 b) { return {{a.h[0] == b.h[0], a.h[1] == b.h[1]}}; }
    friend Mask8x2 operator!=(Float8x2 a, Float8x2 b) { return {{a.h[0] != b.h[0], a.h[1] != b.h[1]}}; }
};

inline Float8x2 select(Mask8x2 m, Float8x2 a, Float8x2 b) {
    return {select(m.h[0], a.h[0], b.h[0]), select(m.h[1], a.h[1], b.h[1])};
}
inline Int8x2 select(Mask8x2 m, Int8x2 a, Int8x2 b) {
    return {select(m.h[0], a.h[0], b.h[0]), select(m.h[1], a.h[1], b.h[1])};
}
inline Float8x2 min(Float8x2 a, Float8x2 b) { return {min(a.h[0], b.h[0]), min(a.h[1], b.h[1])}; }
inline Float8x2 max(Float8x2 a, Float8x2 b) { return {max(a.h[0], b.h[0]), max(a.h[1], b.h[1])}; }
inline Int8x2 min(Int8x2 a, Int8x2 b) { return {min(a.h[0], b.h[0]), min(a.h[1], b.h[1])}; }
inline Int8x2 max(Int8x2 a, Int8x2 b) { return {max(a.h[0], b.h[0]), max(a.h[1], b.h[1])}; }
inline Int8x2 toInt(Float8x2 a) { return {toInt(a.h[0]), toInt(a.h[1])}; }
inline Float8x2 toFloat(Int8x2 a) { return {toFloat(a.h[0]), toFloat(a.h[1])}; }
inline Float8x2 floor(Float8x2 a) { return {floor(a.h[0]), floor(a.h[1])}; }
inline Float8x2 sqrt(Float8x2 a) { return {sqrt(a.h[0]), sqrt(a.h[1])}; }
inline Float8x2 abs(Float8x2 a) { return {abs(a.h[0]), abs(a.h[1])}; }
inline Float8x2 fma(Float8x2 a, Float8x2 b, Float8x2 c) {
    return {fma(a.h[0], b.h[0], c.h[0]), fma(a.h[1], b.h[1], c.h[1])};
}
inline Int8x2 gather(const int32_t* base, Int8x2 index) { return {gather(base, index.h[0]), gather(base, index.h[1])}; }
inline Float8x2 gather(const float* base, Int8x2 index) { return {gather(base, index.h[0]), gather(base, index.h[1])}; }

// exp and expm1 for shaders, over float and Float8 with the same arithmetic (so the scalar and the
// eight-wide path agree bit for bit): Cody–Waite range reduction x = k·ln2 + r, |r| ≤ ln2/2, a
// degree-8 Taylor polynomial for e^r − 1 (truncation error < 1e-9 relative), and an exact scaling
// by 2^k. Measured against the C library over [−87, 88] (tests/simd_test.cpp): at most 1 ulp for
// exp and 2 ulp for expm1 (which keeps full relative accuracy near 0). exp underflows to 0 below −87.3
// (no denormals, as GPUs flush them); expm1 is −1 there. In the reference pipeline
// (shader_context.hpp) the scalar versions call the C library instead, so the fast pipeline's
// error against the reference includes this approximation.
namespace detail {
inline float bitsToFloat(int32_t i) { return __builtin_bit_cast(float, i); }
inline Float8 bitsToFloat(Int8 i) { return simd::F32x8(i.v); }
// To the nearest integer, ties to even (the default rounding mode; one CVTPS2DQ eight wide).
// NaN and values outside int32 give INT32_MIN, as CVTPS2DQ does: converting them with a C++ cast
// is undefined behaviour, and fastExpm1 lets a NaN argument through to here on purpose.
inline int32_t toIntRound(float a) { return simd::portable::roundToInt(a); }
inline Int8 toIntRound(Float8 a) { return simd::roundToInt(a.v); }
inline float toFloatI(int32_t i) { return float(i); }
inline Float8 toFloatI(Int8 i) { return toFloat(i); }
inline int32_t halfOf(int32_t k) { return k >> 1; }  // arithmetic shift: floor(k / 2)
inline Int8 halfOf(Int8 k) { return simd::I32x8(k.v >> 1); }
inline Float8x2 bitsToFloat(Int8x2 i) { return {bitsToFloat(i.h[0]), bitsToFloat(i.h[1])}; }
inline Int8x2 toIntRound(Float8x2 a) { return {toIntRound(a.h[0]), toIntRound(a.h[1])}; }
inline Float8x2 toFloatI(Int8x2 i) { return toFloat(i); }
inline Int8x2 halfOf(Int8x2 k) { return {halfOf(k.h[0]), halfOf(k.h[1])}; }

// e^r − 1 for r = x − k·ln2, given the integer k (the nearest to x/ln2 in expReduce; |k| ≤ 150):
// |r| ≤ ln2/2 when k is the nearest, and the polynomial stays accurate a little beyond (media/exprel.hpp
// takes k = 0 up to |x| = 0.366).
template <class T, class K>
[[gnu::always_inline]] inline T expm1Reduced(T x, K k) {
    const T k_real = toFloatI(k);
    // x − k·ln2 with ln2 in two parts, each product rounded once with its subtraction.
    const T r = fma(k_real, T(2.12194440e-4f), fma(k_real, T(-0.693359375f), x));
    // Degree 7 by Horner, one rounding a step: the next term, r^8/8!, is below 5.3e-9 for
    // |r| ≤ ln2/2, a tenth of float's half ulp.
    T p = fma(r, T(1.0f / 5040.0f), T(1.0f / 720.0f));
    p = fma(r, p, T(1.0f / 120.0f));
    p = fma(r, p, T(1.0f / 24.0f));
    p = fma(r, p, T(1.0f / 6.0f));
    p = fma(r, p, T(0.5f));
    p = fma(r, p, T(1.0f));
    return p * r;
}

// (k, e^r − 1) for x already clamped to [−104, 89], r = x − k·ln2 with k the integer nearest x/ln2.
template <class T>
[[gnu::always_inline]] inline auto expReduce(T x) {
    const T kf = x * T(1.44269504088896341f);
    const auto k = toIntRound(kf);
    return std::make_tuple(k, expm1Reduced(x, k));
}
}  // namespace detail

// Always inlined, as fastExpm1 and the pieces above: called out of line, a shader's eight or sixteen
// lanes go through memory both ways (the fog scene took 9 % longer).
template <class T>
[[gnu::always_inline]] inline T fastExp(T x) {
    const T xc = min(max(x, T(-104.0f)), T(89.0f));
    auto [k, p] = detail::expReduce(xc);
    // 2^k in two halves, so that k = 128 (x near 88.7) still scales without overflowing the exponent.
    const auto k1 = detail::halfOf(k);
    const T half1 = detail::bitsToFloat((k1 + 127) << 23);
    const T half2 = detail::bitsToFloat((k - k1 + 127) << 23);
    const T result = fma(p, half1, half1) * half2;  // (1 + p)·2^k1 with one rounding
    const T zero(0.0f), inf(__builtin_inff());
    return select(x < T(-87.3f), zero, select(x > T(88.72f), inf, select(x != x, x, result)));
}

template <class T>
[[gnu::always_inline]] inline T fastExpm1(T x) {
    // Below −20 the result rounds to −1 (e^−20 is 2e−9, under half an ulp of 1), so clamping there
    // gives −1 without a select. The clamp's operand order lets a NaN through (min and max return
    // their second operand when one is NaN), and NaN then propagates through the arithmetic.
    const T xc = min(T(89.0f), max(T(-20.0f), x));
    auto [k, p] = detail::expReduce(xc);
    const auto kk = min(k, decltype(k)(127));
    const T two_k = detail::bitsToFloat((kk + 127) << 23);
    const T result = fma(two_k, p, two_k - T(1.0f));
    return select(x > T(88.72f), T(__builtin_inff()), result);
}

inline float exp(float a) { return inReferenceMode() ? __builtin_expf(a) : fastExp(a); }
inline float expm1(float a) { return inReferenceMode() ? __builtin_expm1f(a) : fastExpm1(a); }
inline Float8 exp(Float8 a) { return fastExp(a); }
inline Float8 expm1(Float8 a) { return fastExpm1(a); }
// fastExp and fastExpm1 instantiated for the pair, so the two halves' polynomials interleave too.
inline Float8x2 exp(Float8x2 a) { return fastExp(a); }
inline Float8x2 expm1(Float8x2 a) { return fastExpm1(a); }

// Vector helpers over either scalar type (glm's own dot/normalize want arithmetic types).
template <int N, class T>
T dot(const glm::vec<N, T>& a, const glm::vec<N, T>& b) {
    T r = a[0] * b[0];
    for (int i = 1; i < N; ++i) r = r + a[i] * b[i];
    return r;
}
template <int N, class T>
T length(const glm::vec<N, T>& a) {
    return sqrt(dot(a, a));
}
template <int N, class T>
glm::vec<N, T> normalize(const glm::vec<N, T>& a) {
    const T inv = T(1.0f) / length(a);
    glm::vec<N, T> r;
    for (int i = 0; i < N; ++i) r[i] = a[i] * inv;
    return r;
}

// glm's vectors of Float8 work for + − × ÷ between vectors and with Float8 scalars.
using Vec2x8 = glm::vec<2, Float8>;
using Vec3x8 = glm::vec<3, Float8>;
using Vec4x8 = glm::vec<4, Float8>;

}  // namespace raster
