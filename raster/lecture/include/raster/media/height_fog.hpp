// Exponential height fog's optical depth (NOTES.md, part 2, with the slide's misplaced exponent
// corrected), in stable form.
//
// Extinction and source fall off with height y alike: σ(y) = σ0·e^{b·y}, q(y) = q0·e^{b·y} (b in 1/m:
// b < 0 thins upward). Along the ray y(t) = y0 + d_y·t from the eye (d_y the y component of the unit
// direction) the equation dL/ds = σ(y)·(q0/σ0 − L) has the homogeneous solution (homogeneous.hpp) in
// the variable τ, the optical depth per unit σ0, in metres:
//   τ(s) = ∫₀ˢ e^{b·(y0 + d_y·t)} dt = e^{b·y0}·s·φ(k·s),   k = b·d_y,   φ(z) = (e^z − 1)/z (exprel.hpp)
//   L(s) = L(0)·e^{−σ0·τ} + q0·ℓ(σ0, τ)  =  media::radiance(L(0), σ0, q0, τ)
// The slide writes e^{−σ/(b·d_y)}·(e^{b(y0 + s·d_y)} − e^{b·y0}), with the bracket outside the
// exponent; the whole product σ0·τ belongs in it.
//
// Stable form, finite for every finite input where τ is a float:
//  - φ(k·s)·e^{b·y0} is never formed as written (e^{b·y0} may underflow while e^{k·s} overflows:
//    a camera high above dense fog, looking down). With x = |k|·s and the exponents combined first,
//    τ = e^E·ℓ(|k|, s), E = b·y0 + max(k·s, 0), ℓ(|k|, s) = s·ψ(x) ≤ s: for k > 0
//    e^{b·y0}·(e^{x} − 1)/k = e^{b·y0 + x}·(1 − e^{−x})/k, for k ≤ 0 it is as written;
//  - e^E is taken as (e^{E/2})² with ℓ between the factors, so that e^E alone may overflow or
//    underflow while τ does not; τ(0) = 0 whatever E is;
//  - a horizontal ray (d_y = ±0, or b = 0) is ℓ(0, s) = s, τ = e^{b·y0}·s: continuous in d_y
//    through 0 (ψ's series), no 0/0;
//  - s = ∞ (the background): e^{b·y0}/(−k) for a ray rising into thinning fog (k < 0), ∞ otherwise.
// Domain: b, y0, d_y, s finite (s may be +∞), s ≥ 0. T is float, Float8 (the same bits as float lane
// by lane) or double. Over it τ is within a few ulp times its condition number (1 + |b·y0| + |k·s|,
// roughly) of the exact value, or 0 below 2⁻¹²⁶ (the fast exp flushes), or +∞ past FLT_MAX; L from it
// likewise (tests/media_test.cpp, tests/fuzz/fuzz_fog.cpp), but for τ's float range: a τ flushed to 0
// loses q0·τ < q0·2⁻¹²⁶ of gathered radiance, and a τ past FLT_MAX gives L's limit q0/σ0 (∞ for
// σ0 = 0), where without extinction q0·τ itself may still be a float (q0 < 1 deep in dense fog,
// e^{b·y0} > 1e38).
#pragma once

#include <limits>

#include "raster/media/exprel.hpp"
#include "raster/media/scalar_math.hpp"

namespace raster::media {

// m·e^x as (m·e^{x/2})·e^{x/2}: e^x alone may overflow (x > 88.7 in float) or underflow (x < −87.3)
// where m·e^x does not. m ≥ 0; the result is 0 or ∞ only where m·e^x rounds to that (or m = ∞).
template <class T>
[[gnu::always_inline]] inline T scaledExp(T m, T x) {
    using namespace detail;
    const T half = exp(x * T(0.5f));
    return (m * half) * half;
}

// τ(s), the optical depth per unit σ0 from height y0 along a ray with direction y component dy over
// s metres (header: the stable form). s ≥ 0 or +∞. Inlined always (exprel.hpp says why).
template <class T>
[[gnu::always_inline]] inline T heightFogOpticalDepth(T b, T y0, T dy, T s) {
    using namespace detail;
    const T k = b * dy;
    const T abs_k = abs(k);
    const T length = attenuatedLength(abs_k, s);  // s·ψ(|k|·s)
    const T exponent = b * y0 + select(k > T(0.0f), abs_k * s, T(0.0f));
    const T inf(std::numeric_limits<Scalar<T>>::infinity());
    // length = ∞ only for a horizontal ray to s = ∞, where e^E = 0 in float must not give ∞·0.
    return select(s == T(0.0f), T(0.0f), select(length == inf, inf, scaledExp(length, exponent)));
}

// τ(∞): e^{b·y0}/(−k) for a ray rising into thinning fog (k = b·dy < 0), else +∞. ℓ(|k|, ∞) = 1/|k|.
template <class T>
[[gnu::always_inline]] inline T heightFogOpticalDepthToInfinity(T b, T y0, T dy) {
    using namespace detail;
    const T k = b * dy;
    const T inf(std::numeric_limits<Scalar<T>>::infinity());
    return select(k < T(0.0f), scaledExp(T(1.0f) / -k, b * y0), inf);
}

}  // namespace raster::media
