// The relative exponentials of the volume rendering equation's closed forms, in stable form: the one
// home of ψ and φ in raster (NOTES.md, part 1, "Stable forms matter").
//
//   ψ(x) = (1 − e^{−x})/x = −expm1(−x)/x,   ψ(0) = 1     (the constant medium: L = L0·e^{−μs} + q·s·ψ(μs))
//   φ(z) = (e^z − 1)/z   =  expm1(z)/z  = ψ(−z), φ(0) = 1 (the height fog: τ = e^{b·y0}·s·φ(b·d_y·s))
//   ℓ(μ, s) = ∫₀ˢ e^{−μt} dt = s·ψ(μs) = (1 − e^{−μs})/μ,  the attenuated length, in metres:
//             s for μ = 0, 1/μ for s = ∞, ∞ for μ = 0 and s = ∞.
//
// Why not the formulas as written: (1 − e^{−x})/x loses every digit as x → 0 (1 − e^{−x} cancels,
// then 0/0 at x = 0), and (e^z − 1)/z overflows in e^z before the division brings it back. Here:
//  - |x| < 1e-4: the series 1 − x/2 + x²/6 (truncation x³/24 < 4.2e-14, far below float's 6e-8);
//  - otherwise −expm1(−x)/x, with simd.hpp's expm1 (Cody–Waite reduction y = k·ln2 + r and a
//    polynomial for e^r − 1) evaluated without a reduction for |x| < 0.366 (k = 0, where the nearest
//    k would be ±1 from 0.347 on): the k = ±1 reduction loses up to 2.1 ulp of ψ just past 0.347,
//    k = 0 up to 1.95 at 0.366, and the two meet there at 1.95;
//  - growing exponentials (x < −20, φ of z > 20): e^{−x}/(−x) as 2^k·(1 + p) with the division
//    before the last scaling by 2^k, so that ψ is finite wherever its value is a float (up to
//    −x ≈ 93.2, where e^{−x} alone overflowed at 88.7).
// Accuracy (float and Float8 alike) against a long-double reference (media/reference.hpp), as
// tests/media_test.cpp measures it over every 8191st float of either sign and the 2¹³ floats on either
// side of each branch switch (0.6 million arguments): ψ and φ within 2 ulp, no jump at a branch switch,
// never NaN for a non-NaN argument; ψ(+∞) = 0, φ(+∞) = ∞. `raster bench fog-accuracy --exhaustive`
// sweeps every finite float of both signs the same way (ψ's error, Float8 lanes against float, the
// reference pipeline's evaluation; several CPU minutes).
// Float8 is the same arithmetic as float lane by lane (the same bits). In the reference pipeline
// (shader_context.hpp) the scalar float versions take the C library's expm1 instead, as simd.hpp's
// expm1 does; double always does (std::expm1, a few double ulp).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "raster/media/scalar_math.hpp"
#include "raster/simd.hpp"

namespace raster::media {

namespace detail {

// Below this |x| the series (float).
inline constexpr float kSeriesBelow = 1e-4f;
// Below this |x| e^{−x} − 1 is the reduction's polynomial at r = −x itself (k = 0).
inline constexpr float kUnreducedBelow = 0.366f;
// Above this −x, e^{−x} − 1 is e^{−x} in float, and the growing branch takes over.
inline constexpr float kGrowingAbove = 20.0f;
// Above this −x, ψ's value is past float's range whatever the divisor: +∞.
inline constexpr float kOverflowAbove = 100.0f;

// ℓ(μ, s) in float or Float8, fast path, for μ ≥ 0 (a medium's extinction; a negative μ is right
// only while −μs ≤ 20); with kPsi, ψ(μ) for any μ and s = 1, which adds the growing branch. The
// arithmetic keeps, operation for operation, what FogMedium's optical depth did before it moved here
// (the same bits), but for the unreduced band 0.347 ≤ |x| < 0.366.
template <bool kPsi, class T>
[[gnu::always_inline]] inline T attenuatedLengthFast(T mu, T s) {
    namespace rd = raster::detail;
    const T x = mu * s;
    const T y = -x;  // the exponent of e^{−μs}
    const T series = s * (T(1.0f) - x * (T(0.5f) - x * T(1.0f / 6.0f)));
    // e^y − 1 = 2^k·(1 + p) − 1 as simd.hpp's fastExpm1, k pinned to 0 in the unreduced band.
    const T yc = min(T(kOverflowAbove), max(T(-20.0f), y));
    auto k = rd::toIntRound(yc * T(1.44269504088896341f));
    using K = decltype(k);
    k = select(abs(y) < T(kUnreducedBelow), K(0), k);
    const T p = rd::expm1Reduced(yc, k);
    const T two_k = rd::bitsToFloat((min(k, K(127)) + 127) << 23);
    const T em1 = fma(two_k, p, two_k - T(1.0f));
    T result;
    if constexpr (kPsi) {
        // e^y/y = ((1 + p)·2^k1 / y)·2^(k−k1): the last factor applied after the division.
        const K k1 = rd::halfOf(k);
        const T h1 = rd::bitsToFloat((k1 + 127) << 23), h2 = rd::bitsToFloat((k - k1 + 127) << 23);
        const auto grows = y > T(kGrowingAbove);
        const T numerator = select(grows, fma(p, h1, h1), em1);
        const T inf(std::numeric_limits<float>::infinity());
        result = select(y > T(kOverflowAbove), inf, numerator / -mu * select(grows, h2, T(1.0f)));
    } else {
        result = em1 / -mu;
    }
    return select(mu == T(0.0f), s, select(abs(x) < T(kSeriesBelow), series, result));
}

// The same from the C library's expm1 and exp (the reference pipeline's scalar float path; double).
template <class T>
T attenuatedLengthLibrary(T mu, T s) {
    const T x = mu * s;
    if (mu == T(0)) return s;
    if constexpr (std::is_same_v<T, float>) {
        if (std::fabs(x) < kSeriesBelow) return s * (1.0f - x * (0.5f - x * (1.0f / 6.0f)));
        if (-x > kGrowingAbove) return float(std::exp(-double(x)) / -double(mu));
        return __builtin_expm1f(-x) / -mu;
    } else {
        // Series below 1e-8: its truncation x³/24 < 4.2e-26 relative.
        if (std::fabs(x) < 1e-8) return s * (1.0 - x * (0.5 - x * (1.0 / 6.0)));
        // e^y − 1 = e^y in double above y = 37; (e^{y/2}/(−μ))·e^{y/2} overflows only with the value.
        if (-x > 40.0) {
            const double h = std::exp(-0.5 * x);
            return h / -mu * h;
        }
        return std::expm1(-x) / -mu;
    }
}

template <bool kPsi, class T>
[[gnu::always_inline]] inline T attenuatedLengthAny(T mu, T s) {
    if constexpr (std::is_same_v<T, double>) {
        return attenuatedLengthLibrary(mu, s);
    } else if constexpr (std::is_same_v<T, float>) {
        return inReferenceMode() ? attenuatedLengthLibrary(mu, s) : attenuatedLengthFast<kPsi>(mu, s);
    } else {
        return attenuatedLengthFast<kPsi>(mu, s);
    }
}

}  // namespace detail

// ℓ(μ, s) = ∫₀ˢ e^{−μt} dt = s·ψ(μs) = (1 − e^{−μs})/μ in metres: the length of a path of s metres
// through extinction μ (1/m), each metre weighted by the transmittance from the path's start. The
// in-scattered term of the closed form is q·ℓ(μ, s). μ ≥ 0 finite; s ≥ 0 or +∞ (ℓ = 1/μ, or ∞ for
// μ = 0). T is float, Float8 or double. Always inlined, as simd.hpp's exponentials: a pixel shader's lanes
// would otherwise pass through memory (the fog scene took 9 % longer).
template <class T>
[[gnu::always_inline]] inline T attenuatedLength(T mu, T s) {
    return detail::attenuatedLengthAny<false>(mu, s);
}

// ψ(x) = (1 − e^{−x})/x, ψ(0) = 1, for any x: 1 − x/2 + … near 0, 1/x for large x, e^{−x}/(−x) for
// large negative x (∞ from about −93.2 on). T is float, Float8 or double.
template <class T>
[[gnu::always_inline]] inline T psi(T x) {
    return detail::attenuatedLengthAny<true>(x, T(1.0f));
}

// φ(z) = (e^z − 1)/z = ψ(−z), φ(0) = 1: the growth factor of the height fog's optical depth. The same
// evaluation as ψ (negation is exact).
template <class T>
T phi(T z) {
    return psi(T(-z));
}

}  // namespace raster::media
