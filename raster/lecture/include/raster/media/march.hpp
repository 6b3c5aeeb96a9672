// Ray marching: the volume rendering equation (homogeneous.hpp) stepped through a medium whose
// extinction μ(s) and source q(s) vary along the ray (NOTES.md, part 1, "Sugármenetelés").
//
// Along the light's direction of travel, dL/ds = −μ(s)·L + q(s). A march splits the ray into N
// steps of Δs and applies one step rule per step, from the far end (radiance L_bg behind the medium)
// towards the eye:
//   euler                 L_{i+1} = L_i + Δs·(q_i − μ_i·L_i)          (the lecture's step)
//       first order; for μΔs > 2 the factor (1 − μΔs) is below −1 and the error grows step by step
//       (it oscillates and diverges: the scene media-euler shows it).
//   exponential           L_{i+1} = L_i·e^{−μ_iΔs} + q_i·Δs·ψ(μ_iΔs)  (homogeneous.hpp's radiance)
//       exact where μ and q are constant over the step (Hillaire 2015's energy-conserving step);
//       with μ_i, q_i taken at the step's start it is first order, never unstable: e^{−μΔs} ∈ [0, 1].
//   midpointExponential   the same with μ and q taken at the step's midpoint: second order.
// Each rule is written once, for float, Float8 and double (scalar_math.hpp), and a march front to
// back (from the eye, what a pixel shader does, with early termination) gives the exponential
// rules' values with the transmittance T carried along: L = Σ T_i·q_i·Δs·ψ(μ_iΔs) + T·L_bg.
//
// Units: s and Δs in metres, μ in 1/m, q and L in radiance (q per metre).
#pragma once

#include <concepts>
#include <cstdint>

#include "raster/media/exprel.hpp"
#include "raster/media/homogeneous.hpp"
#include "raster/media/scalar_math.hpp"

namespace raster::media {

enum class StepRule : uint8_t { euler, exponential, midpointExponential };

inline const char* stepRuleName(StepRule rule) {
    switch (rule) {
        case StepRule::euler: return "euler";
        case StepRule::exponential: return "exponential";
        case StepRule::midpointExponential: return "midpoint";
    }
    return "?";
}

// The lecture's forward Euler step: L + Δs·(q − μ·L).
template <class T>
T eulerStep(T L, T mu, T q, T ds) {
    return L + ds * (q - mu * L);
}

// The exponential step: the closed form over one step of constant μ and q (homogeneous.hpp).
template <class T>
T exponentialStep(T L, T mu, T q, T ds) {
    return radiance(L, mu, q, ds);
}

// One step of `rule`: Euler's or the exponential one (midpointExponential is the exponential step,
// sampled elsewhere: stepSampleFraction).
template <class T>
T applyStep(StepRule rule, T L, T mu, T q, T ds) {
    return rule == StepRule::euler ? eulerStep(L, mu, q, ds) : exponentialStep(L, mu, q, ds);
}

// Where a step of `rule` samples μ and q, as a fraction of Δs from the step's far end (where the light
// enters it, marching back to front): 0 for euler and exponential, ½ for midpointExponential.
inline double stepSampleFraction(StepRule rule) {
    return rule == StepRule::midpointExponential ? 0.5 : 0.0;
}

// A medium along one ray: extinction and source at the ray parameter s (metres from the ray's start,
// the eye). Any type with `double mu(double s) const` and `double q(double s) const` (a functor
// family the tests and `raster bench error` define) marches.
template <class Medium>
concept RayMedium = requires(const Medium& m, double s) {
    { m.mu(s) } -> std::convertible_to<double>;
    { m.q(s) } -> std::convertible_to<double>;
};

// The radiance reaching the eye at s = t0 from a march over [t0, t1] in `steps` steps of one rule,
// with L_bg entering at t1. Back to front, as the lecture writes the recurrence: step i covers
// [t1 − (i+1)Δs, t1 − iΔs]; its left end, for the rules that sample one, is the end nearer the
// background (where the light enters the step).
template <RayMedium Medium>
double marchBackToFront(const Medium& medium, double t0, double t1, uint32_t steps, StepRule rule, double L_bg) {
    const double ds = (t1 - t0) / steps;
    double L = L_bg;
    const double fraction = stepSampleFraction(rule);
    for (uint32_t i = 0; i < steps; ++i) {
        const double s = t1 - (i + fraction) * ds;  // the far end (where the light enters) or the midpoint
        L = applyStep(rule, L, medium.mu(s), medium.q(s), ds);
    }
    return L;
}

// A front-to-back march's running state: the radiance gathered so far and the transmittance from the
// eye to the current sample. Adding a step of constant μ, q over Δs gathers T·q·Δs·ψ(μΔs) and
// multiplies T by e^{−μΔs}: the exponential rule, summed from the eye.
template <class T>
struct MarchState {
    T radiance = T(0.0f);
    T transmittance = T(1.0f);

    void addStep(T mu, T q, T ds) {
        radiance = radiance + transmittance * gathered(mu, q, ds);
        transmittance = transmittance * media::transmittance(mu, ds);
    }
    // The background seen through what was marched.
    T finish(T background) const { return radiance + transmittance * background; }
};

}  // namespace raster::media
