// A long-double evaluation of the media formulas, written from the physics for clarity rather than
// speed: what tests/media_test.cpp, tests/fuzz/fuzz_fog.cpp and `raster bench fog-accuracy`
// (docs/ACCURACY.md) measure raster's float forms against. long double (x87, 64-bit significand) has
// 40 bits beyond float's 24 and exponents to ±16382, so the reference's own error is negligible at
// float's scale; where a value passes even that range (e^{b·y0} for b·y0 = 2e5) it is carried as a
// logarithm.
//
// relativeCondition() estimates a value's condition number: how many float ulps of the result one
// ulp of change in each input moves it, summed over the inputs. A float evaluation cannot be
// expected within fewer ulps of the truth than that, so the tests' tolerances are "a few ulp times
// (1 + κ)".
#pragma once

#include <array>
#include <cmath>
#include <limits>

namespace raster::media::reference {

using Real = long double;
inline constexpr Real kFloatUnitRoundoff = 0x1p-24L;
inline constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

// ψ(x) = (1 − e^{−x})/x, ψ(0) = 1.
inline Real psi(Real x) {
    return x == 0 ? 1.0L : -std::expm1(-x) / x;
}
inline Real phi(Real z) {
    return psi(-z);
}

// ln(s·φ(z)) for s ≥ 0 finite and any z: the logarithm avoids e^z overflowing long double.
inline Real logLengthPhi(Real s, Real z) {
    if (s == 0) return -kInfinity;
    if (z > 0) return z + std::log(-std::expm1(-z)) - std::log(z) + std::log(s);
    return std::log(phi(z)) + std::log(s);
}

// ℓ(μ, s) = s·ψ(μs): s for μ = 0, 1/μ for s = ∞ (μ > 0).
inline Real attenuatedLength(Real mu, Real s) {
    if (mu == 0) return s;
    if (std::isinf(s)) return mu > 0 ? 1.0L / mu : kInfinity;
    return s * psi(mu * s);
}

// L0·e^{−μs} + q·ℓ(μ, s) (homogeneous.hpp), s ≥ 0 or ∞.
inline Real radiance(Real L0, Real mu, Real q, Real s) {
    const Real t = mu == 0 ? 1.0L : std::exp(-mu * s);
    return L0 * t + (q == 0 ? 0.0L : q * attenuatedLength(mu, s));
}

// ln τ, the height fog's optical depth per unit σ0 (height_fog.hpp): b·y0 + ln(s·φ(b·d_y·s)); at
// s = ∞, b·y0 − ln(−k) for k = b·d_y < 0, else +∞. −∞ for s = 0.
inline Real logHeightFogOpticalDepth(Real b, Real y0, Real dy, Real s) {
    const Real k = b * dy;
    if (std::isinf(s)) return k < 0 ? b * y0 - std::log(-k) : kInfinity;
    return b * y0 + logLengthPhi(s, k * s);
}

inline Real heightFogOpticalDepth(Real b, Real y0, Real dy, Real s) {
    return std::exp(logHeightFogOpticalDepth(b, y0, dy, s));
}

// The height fog's radiance: radiance() in τ. τ past long double's range is +∞ (σ0·τ is then past
// every float's reach too, or σ0 = 0).
inline Real heightFogRadiance(Real L0, Real sigma, Real q, Real b, Real y0, Real dy, Real s) {
    return radiance(L0, sigma, q, heightFogOpticalDepth(b, y0, dy, s));
}

// Σ over the inputs of |f(x with x_i·(1 + u)) − f(x)| / (u·|f(x)|), u = float's unit roundoff: the
// relative condition number for a float computation. 0 where f(x) is 0 or not finite (the caller
// checks those exactly), and a perturbed value that is not finite counts as a large change.
template <size_t N, class F>
Real relativeCondition(F f, const std::array<Real, N>& x) {
    const Real v = f(x);
    if (v == 0 || !std::isfinite(v)) return 0;
    Real kappa = 0;
    for (size_t i = 0; i < N; ++i) {
        std::array<Real, N> xi = x;
        xi[i] *= 1 + kFloatUnitRoundoff;
        const Real vi = f(xi);
        kappa += std::isfinite(vi) ? std::fabs(vi - v) / (kFloatUnitRoundoff * std::fabs(v)) : Real(1e30);
    }
    return kappa;
}

// The adversarial grid of tests/media_test.cpp and of docs/ACCURACY.md's table: extinction and
// source from nothing to absurd, distances from 0 through a megametre to the background, the eye from
// a kilometre below the fog's reference height to a kilometre above, rays straight up, straight down,
// grazing (1e-7) and horizontal (±0), and falloffs from none to 200 per metre (e^{b·y0} from e^{−2e5}
// to e^{2e5}: nothing of which a float holds, while τ may well be a float).
struct AdversarialGrid {
    static constexpr float kExtinction[] = {0, 1e-30f, 1e-20f, 1e-10f, 1e-5f, 1e-3f,
                                            1, 1e3f,   1e10f,  1e20f,  1e30f};
    static constexpr float kSource[] = {0, 0.6f, 1e30f};
    static constexpr float kSurface[] = {0, 0.5f};
    static constexpr float kDistance[] = {
        0, 1e-30f, 1e-6f, 1, 1e3f, 1e6f, std::numeric_limits<float>::infinity()};
    static constexpr float kDirectionY[] = {1, -1, 1e-7f, -1e-7f, 0, -0.0f};
    static constexpr float kHeight[] = {-1000, -100, -1, 0, 1.5f, 100, 1000};
    static constexpr float kFalloff[] = {-200, -1, -1e-3f, 0, 1e-3f, 1, 200};
};

}  // namespace raster::media::reference
