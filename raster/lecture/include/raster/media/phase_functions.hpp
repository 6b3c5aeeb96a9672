// Phase functions of a participating medium (NOTES.md, part 1, with the lecture's errata corrected):
// the probability density, per steradian, that light scattered at a point leaves in a direction.
//
// Convention: θ is the angle between the light's direction of TRAVEL before the event and the
// scattered direction, cos θ = dot(travel, scattered) for unit vectors. θ = 0 is straight on
// (forward scattering), θ = π straight back. Henyey–Greenstein's g is the mean of cos θ: g > 0
// scatters forward, g < 0 backward, g = 0 is isotropic. (pbrt-v4 writes the same functions in terms
// of wo pointing back toward where the light came from, so its cos θ is the negative of this one.)
// In a march (VolumeLight, metaball_march.hpp) with view ray d from the eye and l from the sample
// towards the light, directional or point, the light travels along −l and leaves along −d: cos θ = d·l.
//
// Each function is a density over the sphere: ∫ p dω = 2π·∫₋₁¹ p(cos θ) d(cos θ) = 1, with unit 1/sr.
//   isotropic         p = 1/(4π)
//   rayleigh          p = 3/(16π)·(1 + cos²θ)      (the slide's 2/(16π) integrates to 2/3)
//   henyeyGreenstein  p = (1 − g²)/(4π·(1 + g² − 2g·cos θ)^{3/2})   (the slide's exponent 2/3 is
//                                                                    not normalised for g ≠ 0)
// Each is a template over float, Float8 (eight lanes, the same bits as float lane by lane: a pixel
// shader's eight-wide path) and double.
//
// Henyey–Greenstein, stably for every g in [−1, 1] (no clamp to |g| ≤ 0.99 as pbrt-v4 has):
//  - with a = |g| and m = sign(g)·cos θ (the cosine to the peak's direction), the denominator's base
//    1 + g² − 2g·cos θ is evaluated as (1 − a)² + 2a·(1 − m): a sum of two terms ≥ 0, where the
//    written form cancels to (1 − g)² near the peak (for a = 1 − 1e-6, 1e-12 from the difference of
//    numbers near 2: nothing left in float); 1 − g² as (1 − a)(1 + a);
//  - g = ±1 exactly (a delta, not a density) is taken as the nearest g inside (−1, 1): a = 1 − 2⁻²⁴
//    in float, 1 − 2⁻⁵³ in double, where the peak p(1) = (1 + a)/(4π(1 − a)²) is still finite.
// Sampling (sampleHenyeyGreenstein) inverts the CDF in closed form. The textbook inversion
//   cos θ = (1 + g² − ((1 − g²)/(1 − g + 2g·u))²)/(2g)
// cancels catastrophically as g → 0 (an O(g) difference of numbers near 1, divided by g; pbrt switches
// to the isotropic formula below |g| = 1e-3, a jump) and near cos θ = ±1 for |g| → 1. Here, with
// a = |g|, v the CDF variable of a (u for g ≥ 0, 1 − u mirrored for g < 0) and D = (1 − a) + 2a·v,
//   1 − cos θ = 2·((1 − a)/D)²·(1 − v)·(1 + a·v)
//   1 + cos θ = 2·((1 + a)/D)²·v·((1 − a) + a·v)
// (exact algebra, products of non-negative terms) and cos θ = 1 − (1 − cos θ) where that is the
// smaller, else (1 + cos θ) − 1: accurate to an ulp of 1 for every g and u, continuous in g through
// 0, in [−1, 1], and sin²θ = (1 − cos θ)(1 + cos θ) without cancellation for the direction sampler.
// The density of the sampled cos θ is exactly henyeyGreenstein(g, cos θ)·2π (the pdf per steradian
// is the value: pdfHenyeyGreenstein).
#pragma once

#include <cmath>
#include <glm/glm.hpp>

#include "raster/media/scalar_math.hpp"
#include "raster/simd.hpp"

namespace raster::media {

namespace detail {

inline constexpr double kInvFourPi = 0.07957747154594767;  // 1/(4π)
inline constexpr double kRayleigh = 0.05968310365946075;   // 3/(16π)
inline constexpr double kTwoPi = 6.283185307179586;

// The largest |g| the Henyey–Greenstein functions take in T's arithmetic: the float or double
// nearest below 1.
template <class T>
constexpr Scalar<T> kMaxAnisotropy = std::is_same_v<T, double> ? 1.0 - 0x1p-53 : 1.0f - 0x1p-24f;

template <class T>
T constant(double c) {
    return T(Scalar<T>(c));
}

}  // namespace detail

// 1/(4π) per steradian, whatever the direction.
template <class T = float>
T isotropic() {
    return detail::constant<T>(detail::kInvFourPi);
}

// Rayleigh scattering (particles much smaller than the wavelength): 3/(16π)·(1 + cos²θ) per
// steradian, symmetric forward–backward, mean cosine 0.
template <class T>
T rayleigh(T cosTheta) {
    return detail::constant<T>(detail::kRayleigh) * (T(1.0f) + cosTheta * cosTheta);
}

// Henyey–Greenstein with anisotropy g ∈ [−1, 1] (the mean cosine; header: convention, stable form),
// per steradian. cosTheta ∈ [−1, 1].
template <class T>
T henyeyGreenstein(T g, T cosTheta) {
    using namespace detail;
    const T a = min(abs(g), T(kMaxAnisotropy<T>));
    const T m = select(g < T(0.0f), -cosTheta, cosTheta);
    const T one_minus_a = T(1.0f) - a;
    const T base = one_minus_a * one_minus_a + T(2.0f) * a * (T(1.0f) - m);
    return one_minus_a * (T(1.0f) + a) * constant<T>(kInvFourPi) / (base * sqrt(base));
}

// The density, per steradian, of the directions sampleHenyeyGreenstein draws: the value itself.
template <class T>
T pdfHenyeyGreenstein(T g, T cosTheta) {
    return henyeyGreenstein(g, cosTheta);
}

// cos θ and sin²θ of one Henyey–Greenstein sample (sin²θ = (1 − cos θ)(1 + cos θ), computed without
// cancellation: the direction sampler's sin θ for θ near 0 or π).
template <class T>
struct HenyeyGreensteinSample {
    T cosTheta;
    T sinThetaSquared;
};

// Inverts the CDF of Henyey–Greenstein at u ∈ [0, 1] (header: the stable form): cos θ ∈ [−1, 1],
// increasing with u, distributed with density henyeyGreenstein(g, cos θ)·2π for uniform u. g ∈ [−1, 1].
template <class T>
HenyeyGreensteinSample<T> sampleHenyeyGreensteinFull(T g, T u) {
    using namespace detail;
    const T a = min(abs(g), T(kMaxAnisotropy<T>));
    const T u_c = T(1.0f) - u;
    const auto backward = g < T(0.0f);
    const T v = select(backward, u_c, u);    // the CDF variable of |g| (mirrored for g < 0)
    const T v_c = select(backward, u, u_c);  // 1 − v
    const T one_minus_a = T(1.0f) - a;
    const T d = one_minus_a + T(2.0f) * a * v;  // 1 + a·(2v − 1), ≥ 1 − a > 0
    const T rm = one_minus_a / d, rp = (T(1.0f) + a) / d;
    const T one_minus_cos = T(2.0f) * rm * rm * v_c * (T(1.0f) + a * v);
    const T one_plus_cos = T(2.0f) * rp * rp * v * (one_minus_a + a * v);
    const T c = select(one_minus_cos < one_plus_cos, T(1.0f) - one_minus_cos, one_plus_cos - T(1.0f));
    const T c_clamped = min(T(1.0f), max(T(-1.0f), c));
    return {select(backward, -c_clamped, c_clamped), one_minus_cos * one_plus_cos};
}

template <class T>
T sampleHenyeyGreenstein(T g, T u) {
    return sampleHenyeyGreensteinFull(g, u).cosTheta;
}

// A scattered direction for light travelling along the unit vector `travel`: θ from
// sampleHenyeyGreenstein(g, u.x), the azimuth 2π·u.y about `travel` (in the orthonormal basis of
// Duff et al. 2017; any basis serves, the azimuth being uniform). A unit vector (to rounding); its
// density per steradian is henyeyGreenstein(g, dot(travel, result)). T is float or double.
template <class T>
glm::vec<3, T> sampleHenyeyGreensteinDirection(const glm::vec<3, T>& travel, T g, const glm::vec<2, T>& u) {
    const HenyeyGreensteinSample<T> hg = sampleHenyeyGreensteinFull(g, u.x);
    const T sin_theta = std::sqrt(std::max(hg.sinThetaSquared, T(0)));
    const T azimuth = T(detail::kTwoPi) * u.y;
    const T sign = std::copysign(T(1), travel.z);
    const T k = T(-1) / (sign + travel.z);
    const T b = travel.x * travel.y * k;
    const glm::vec<3, T> t1(T(1) + sign * travel.x * travel.x * k, sign * b, -sign * travel.x);
    const glm::vec<3, T> t2(b, sign + travel.y * travel.y * k, -travel.y);
    return (std::cos(azimuth) * sin_theta) * t1 + (std::sin(azimuth) * sin_theta) * t2 + hg.cosTheta * travel;
}

}  // namespace raster::media
