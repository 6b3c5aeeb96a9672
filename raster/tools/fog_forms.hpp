// The fog formulas raster's stable forms (raster/media/homogeneous.hpp, height_fog.hpp) are measured
// against in `raster bench fog-accuracy` (docs/ACCURACY.md, "Participating media"): what a game
// engine or the lecture's slides compute, written out in float as they are, with the C library's
// exp and exp2. They are the benchmark's, not the library's: no shader should use them.
//
// Parameters are raster's everywhere (σ(y) = σ0·e^{b·y}, a ray from height y0 with direction y
// component dy over s metres, source q, surface radiance L0; homogeneous.hpp and height_fog.hpp):
//  - lecture*: ../shared/lecture/NOTES.md's closed forms written directly, with the errata corrected
//    (L0·e^{−μs} + (q/μ)·(1 − e^{−μs}); τ = (e^{b(y0 + dy·s)} − e^{b·y0})/(b·dy),
//    L = q/σ + (L0 − q/σ)·e^{−σ·τ});
//  - slideHeightRadiance: the slide's layout, the bracket outside the exponent,
//    L = q/σ + (L0 − q/σ)·e^{−σ/(b·dy)}·(e^{b(y0 + dy·s)} − e^{b·y0});
//  - floored*: the same direct forms with the extinction raised to max(σ, 1e-5), the floor Unreal's
//    and Godot's fog shaders put under σ against the 0/0 at σ = 0;
//  - unrealOpticalDepth: Unreal Engine's exponential height fog line integral (HeightFogCommon.ush,
//    CalculateLineIntegralShared, and the C++ side's collapsed fog parameter), in base 2 as Unreal
//    writes it: density 2^{−f·y} with f = −b/ln2, the origin term 2^{clamp(−f·y0, −125, 126)}, the
//    falloff along the ray F = max(−127, f·dy·s), and (1 − 2^{−F})/F, replaced by its first-order
//    Taylor polynomial ln2 − ½·ln²2·F where |F| ≤ 0.01. Unreal's product is ln2·τ; divided by ln2
//    here (one more rounding) to compare with τ.
#pragma once

#include <algorithm>
#include <cmath>

namespace raster::tools::fog_forms {

inline constexpr float kSigmaFloor = 1e-5f;  // 1/m: the engines' floor under the extinction
inline constexpr float kLn2 = 0.693147181f;
inline constexpr float kLog2e = 1.44269504f;

// L0·e^{−μs} + (q/μ)·(1 − e^{−μs}): NaN at μ = 0, q·s·ψ's digits lost for μs → 0.
inline float lectureRadiance(float L0, float mu, float q, float s) {
    const float t = std::exp(-mu * s);
    return L0 * t + q / mu * (1.0f - t);
}

// The same with μ raised to 1e-5: finite at μ = 0, and a thinner medium taken as that thick.
inline float flooredRadiance(float L0, float mu, float q, float s) {
    return lectureRadiance(L0, std::max(mu, kSigmaFloor), q, s);
}

// (e^{b(y0 + dy·s)} − e^{b·y0})/(b·dy): 0/0 on a horizontal ray, the exponentials over- and
// underflowing where τ does not.
inline float lectureOpticalDepth(float b, float y0, float dy, float s) {
    return (std::exp(b * (y0 + dy * s)) - std::exp(b * y0)) / (b * dy);
}

// NOTES.md's corrected height fog written directly: q/σ + (L0 − q/σ)·e^{−σ·τ}.
inline float lectureHeightRadiance(float L0, float sigma, float q, float b, float y0, float dy, float s) {
    const float tau = lectureOpticalDepth(b, y0, dy, s);
    const float c = q / sigma;
    return c + (L0 - c) * std::exp(-sigma * tau);
}

// The slide's layout: only σ/(b·dy) in the exponent, the bracket multiplying it.
inline float slideHeightRadiance(float L0, float sigma, float q, float b, float y0, float dy, float s) {
    const float c = q / sigma;
    return c + (L0 - c) * std::exp(-sigma / (b * dy)) * (std::exp(b * (y0 + dy * s)) - std::exp(b * y0));
}

// Unreal's line integral of 2^{−f·y} along the ray, in raster's parameters (header).
inline float unrealOpticalDepth(float b, float y0, float dy, float s) {
    const float f = -b * kLog2e;  // Unreal's FogHeightFalloff, in base 2
    const float origin = std::exp2(std::clamp(-f * y0, -125.0f, 126.0f));
    const float falloff = std::max(-127.0f, f * (dy * s));
    const float line = std::fabs(falloff) > 0.01f ? (1.0f - std::exp2(-falloff)) / falloff
                                                  : kLn2 - 0.5f * kLn2 * kLn2 * falloff;
    return origin * line * s / kLn2;
}

}  // namespace raster::tools::fog_forms
