// Eight floats at once, for shaders that are written once for `float` and run eight pixels wide.
//
// A pixel shader may, besides its scalar operator()(const In&), offer the same code for
// raster::Float8: operator()(const Wide<In>&) returning glm::vec<4, Float8>, where Wide<In> is the
// input struct template instantiated with Float8 (see shader.hpp). The pipeline then shades 4×2
// pixel blocks in one call; lanes 0–3 are the block's top row left to right, 4–7 the bottom row,
// so lanes (0,1,4,5) and (2,3,6,7) are the two 2×2 quads derivatives are taken in. Results are the
// same bits as the scalar path: every operation here is the IEEE operation the scalar code does,
// lane by lane (no fused multiply-add, no approximate reciprocal).
//
// Portable GCC/Clang vector extensions; AVX2 intrinsics where they exist for floor and gathers.
#pragma once

#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace raster {

namespace simd {
using F32x8 = float __attribute__((vector_size(32)));
using I32x8 = int32_t __attribute__((vector_size(32)));
using U32x8 = uint32_t __attribute__((vector_size(32)));
}  // namespace simd

struct Int8;

// A lane mask: all bits set where true.
struct Mask8 {
    simd::I32x8 v;
    friend Mask8 operator&(Mask8 a, Mask8 b) { return {a.v & b.v}; }
    friend Mask8 operator|(Mask8 a, Mask8 b) { return {a.v | b.v}; }
    Mask8 operator!() const { return {~v}; }
    // Bit i set when lane i is true.
    uint32_t bits() const {
#if defined(__AVX__)
        return uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(__m256i(v))));
#else
        uint32_t b = 0;
        for (int i = 0; i < 8; ++i) b |= uint32_t(v[i] != 0) << i;
        return b;
#endif
    }
    static Mask8 fromBits(uint32_t bits) {
        const simd::I32x8 lanes = {1, 2, 4, 8, 16, 32, 64, 128};
        return {(lanes & simd::I32x8(simd::I32x8{} + int32_t(bits))) != 0};
    }
};

struct alignas(32) Float8 {
    simd::F32x8 v;

    Float8() = default;
    Float8(float x) : v(simd::F32x8{} + x) {}  // NOLINT: broadcast, like a scalar in a vector expression
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
};

inline Float8 select(Mask8 m, Float8 a, Float8 b) { return m.v ? a.v : b.v; }
inline Int8 select(Mask8 m, Int8 a, Int8 b) { return m.v ? a.v : b.v; }
inline Float8 min(Float8 a, Float8 b) { return a.v < b.v ? a.v : b.v; }
inline Float8 max(Float8 a, Float8 b) { return a.v > b.v ? a.v : b.v; }
inline Int8 min(Int8 a, Int8 b) { return a.v < b.v ? a.v : b.v; }
inline Int8 max(Int8 a, Int8 b) { return a.v > b.v ? a.v : b.v; }
// Truncation toward zero, as int(float).
inline Int8 toInt(Float8 a) { return __builtin_convertvector(a.v, simd::I32x8); }
inline Float8 toFloat(Int8 a) { return __builtin_convertvector(a.v, simd::F32x8); }
inline Float8 sqrt(Float8 a) {
#if defined(__AVX__)
    return simd::F32x8(_mm256_sqrt_ps(__m256(a.v)));
#else
    Float8 r;
    for (int i = 0; i < 8; ++i) r.v[i] = __builtin_sqrtf(a.v[i]);
    return r;
#endif
}

// 32-bit loads base[index[i]] for each lane.
inline Int8 gather(const int32_t* base, Int8 index) {
#if defined(__AVX2__)
    return simd::I32x8(_mm256_i32gather_epi32(base, __m256i(index.v), 4));
#else
    Int8 r;
    for (int i = 0; i < 8; ++i) r.v[i] = base[index.v[i]];
    return r;
#endif
}
inline Float8 gather(const float* base, Int8 index) {
#if defined(__AVX2__)
    return simd::F32x8(_mm256_i32gather_ps(base, __m256i(index.v), 4));
#else
    Float8 r;
    for (int i = 0; i < 8; ++i) r.v[i] = base[index.v[i]];
    return r;
#endif
}

// Scalar twins, so one shader template reads the same for float and Float8.
inline float select(bool m, float a, float b) { return m ? a : b; }
inline float min(float a, float b) { return a < b ? a : b; }
inline float max(float a, float b) { return a > b ? a : b; }

// glm's vectors of Float8 work for + − × ÷ between vectors and with Float8 scalars.
using Vec2x8 = glm::vec<2, Float8>;
using Vec3x8 = glm::vec<3, Float8>;
using Vec4x8 = glm::vec<4, Float8>;

}  // namespace raster
