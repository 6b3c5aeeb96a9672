// Single scattering marched along one view ray, written once for every marcher that steps samples at
// their midpoints: the `media` benchmark scene's (metaball_march.hpp: its medium, its skipping and the
// exponential step summed from the eye) and the ray-marching lab's (labs/ray-marching: the student's
// density, phase function, shadow ray and step rule, stepped back to front as the lecture writes the
// recurrence). What differs between them is what they fill in, a policy of places:
//
//   Float8 extinction8(Float8 x, Float8 y, Float8 z) const   μ at eight samples (1/m); the march tests
//                                                              μ > 0 (μ ≤ 0 or NaN: nothing added)
//   float phase(float cos_theta) const                        p(cos θ) per steradian (cos θ = d·l)
//   Float8 shadowTransmittance8(const std::array<Float8, 3>& x, uint32_t lanes, const LightAtPoint* at) const
//                              e^{−τ_l} from the sample of each lane of `lanes` (bit l: lane l) towards
//                              the light, at[l] its lightAt for a point light (a directional light's
//                              lanes are not set: its l is the light's toLight everywhere); the other
//                              lanes' values unused
//   std::pair<int32_t, int32_t> span(o, d, t0, dt, n) const  (optional, front to back only) the samples
//                              [first, last] outside which μ is 0 (first > last: none)
//
// and an integrator that turns the samples into radiance:
//   Float8 prepare(Float8 mu, float ds) const        per eight samples, ahead of them (e.g. e^{−μΔs} − 1)
//   void pass(uint32_t i, float s, float mu)         a sample that adds nothing
//   void scatter(uint32_t i, float s, float mu, float prepared, float shadow_t, const glm::vec3& in)
//                              a sample with μ > 0; in = p(cos θ)·e^{−τ_l}·E + A, the in-scattered
//                              radiance per unit albedo (E: the light's irradiance at the sample)
//
// The march over [t0, t1] (the caller clips the ray o + t·d, d unit length, to the medium): N steps of
// Δs = (t1 − t0)/N sampled at their midpoints, s_i = t0 + (i + ½)·Δs from the eye (frontToBack) or
// s_i = t1 − (i + ½)·Δs from the far end (backToFront), eight at a time (per lane the scalar's
// operations, the same bits). A directional light's phase is the same at every sample (computed once,
// at the first that scatters); a point light's E, l and phase are the sample's (lightAt, chosen at
// compile time: the directional march carries no per-sample light).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <utility>

#include "raster/media/volume_light.hpp"
#include "raster/simd.hpp"

namespace raster::media {

enum class MarchOrder : uint8_t { frontToBack, backToFront };

// The eight sample positions o + d·s_i, i = i0 .. i0 + 7: s_i = t + (i + ½)·dt (frontToBack) or
// t − (i + ½)·dt (backToFront); per lane the scalar's operations.
template <MarchOrder Order = MarchOrder::frontToBack>
std::array<Float8, 3> samplePositions8(const glm::vec3& o, const glm::vec3& d, float t, float dt, uint32_t i0) {
    const Float8 half_index(simd::F32x8{0.5f, 1.5f, 2.5f, 3.5f, 4.5f, 5.5f, 6.5f, 7.5f});
    const Float8 along = (half_index + Float8(float(i0))) * Float8(dt);
    const Float8 s = Order == MarchOrder::frontToBack ? Float8(t) + along : Float8(t) - along;
    return {Float8(o.x) + Float8(d.x) * s, Float8(o.y) + Float8(d.y) * s, Float8(o.z) + Float8(d.z) * s};
}

// The light and phase at one sample of a march with view ray d (header): the phase of a directional
// light computed once, at the first sample that asks.
template <LightKind Kind, class Places>
struct SampleLight {
    const Places& places;
    const VolumeLight& light;
    glm::vec3 d;
    float phase = 0.0f;
    bool phaseKnown = false;

    LightAtPoint at(const glm::vec3& x) const {
        if constexpr (Kind == LightKind::directional) {
            (void)x;
            return {light.toLight, INFINITY, light.sun};
        } else {
            return lightAt(light, x);
        }
    }
    // p(cos θ)·e^{−τ_l}·E + A for a sample that received `at` through shadow_t (a directional light's
    // `at` unused: its l and E are the light's).
    glm::vec3 inScattered(const LightAtPoint& at, float shadow_t) {
        if constexpr (Kind == LightKind::directional) {
            if (!phaseKnown) phase = places.phase(glm::dot(d, light.toLight)), phaseKnown = true;
            return phase * shadow_t * light.sun + light.ambient;
        } else {
            return places.phase(glm::dot(d, at.toLight)) * shadow_t * at.irradiance + light.ambient;
        }
    }
};

// The march over [t0, t1] (header) of a light of kind Kind; returns how many samples' μ it evaluated.
// Flattened: the places' and the integrator's pieces (sample positions, densities, shadow rays, the
// eight-wide exponentials) inlined into the loop, as one function written out would have them; called
// out of line they pass their eight lanes through memory, and the `media` scene took 1.4 times as long.
template <MarchOrder Order, LightKind Kind, class Places, class Integrator>
[[gnu::flatten]] uint32_t marchScattering(const Places& places, const VolumeLight& light, const glm::vec3& o,
                                          const glm::vec3& d, float t0, float t1, uint32_t steps,
                                          Integrator& integrator) {
    const float ds = (t1 - t0) / float(steps);
    std::pair<int32_t, int32_t> span{0, int32_t(steps) - 1};
    if constexpr (Order == MarchOrder::frontToBack && requires { places.span(o, d, t0, ds, steps); })
        span = places.span(o, d, t0, ds, steps);
    const auto [first, last] = span;
    const float start = Order == MarchOrder::frontToBack ? t0 : t1;
    SampleLight<Kind, Places> lit{places, light, d};
    // A point light's scattering lanes' light, set as they are found. A directional light's is the same
    // everywhere and is not copied per sample: built on the stack and copied back whole, each copy
    // stalled on its store, the copies took a quarter of the `media` scene's march.
    std::array<LightAtPoint, 8> at;
    uint32_t evaluated = 0;
    for (int32_t i0 = first; i0 <= last; i0 += 8) {
        const std::array<Float8, 3> x = samplePositions8<Order>(o, d, start, ds, uint32_t(i0));
        const Float8 mu = places.extinction8(x[0], x[1], x[2]);
        const int32_t lanes = std::min(8, last - i0 + 1);
        evaluated += uint32_t(lanes);
        uint32_t scattering = 0;
        for (int32_t l = 0; l < lanes; ++l)
            if (mu[l] > 0.0f) {
                scattering |= 1u << l;
                if constexpr (Kind == LightKind::point) at[size_t(l)] = lit.at({x[0][l], x[1][l], x[2][l]});
            }
        const Float8 shadow_t = places.shadowTransmittance8(x, scattering, at.data());
        const Float8 prepared = integrator.prepare(mu, ds);
        for (int32_t l = 0; l < lanes; ++l) {
            const uint32_t i = uint32_t(i0 + l);
            const float along = (float(i) + 0.5f) * ds;
            const float s = Order == MarchOrder::frontToBack ? t0 + along : t1 - along;
            if (scattering >> l & 1u)
                integrator.scatter(i, s, mu[l], prepared[l], shadow_t[l], lit.inScattered(at[size_t(l)], shadow_t[l]));
            else
                integrator.pass(i, s, mu[l]);
        }
    }
    return evaluated;
}

// The lecture's recurrence from the far end to the eye: L ← step(L, μ, q, Δs) per channel, with
// q = μ·albedo·in (radiance per metre) at each sample that scatters; L starts as the background.
// `step` is any rule of the form of march.hpp's (Euler's, the exponential one, a student's).
template <class Step>
struct TowardsTheEye {
    glm::vec3 radiance;
    float albedo;
    Step step;
    float ds = 0.0f;

    Float8 prepare(Float8, float step_length) {
        ds = step_length;
        return Float8(0.0f);
    }
    void pass(uint32_t, float, float) {}
    void scatter(uint32_t, float, float mu, float, float, const glm::vec3& in) {
        const glm::vec3 q = mu * albedo * in;
        for (int c = 0; c < 3; ++c) radiance[c] = step(radiance[c], mu, q[c], ds);
    }
};

// The radiance reaching the eye along o + t·d over [t0, t1], `background` entering at t1, marched back
// to front with the places' `float step(float L, float mu, float q, float ds) const` (header).
template <LightKind Kind = LightKind::directional, class Places>
glm::vec3 marchTowardsTheEye(const Places& places, const VolumeLight& light, const glm::vec3& o, const glm::vec3& d,
                             float t0, float t1, uint32_t steps, const glm::vec3& background) {
    auto step = [&places](float L, float mu, float q, float ds) { return places.step(L, mu, q, ds); };
    TowardsTheEye<decltype(step)> integrator{background, light.albedo, step};
    marchScattering<MarchOrder::backToFront, Kind>(places, light, o, d, t0, t1, steps, integrator);
    return integrator.radiance;
}

}  // namespace raster::media
