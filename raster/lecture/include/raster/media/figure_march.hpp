// The march of the lecture's part-1 figures (NOTES.md, part 1; scenes media-absorption, media-emission,
// media-scattering, media-euler in src/scene_media_figures.cpp): the volume rendering equation
// dL/ds = −μ·L + q stepped back to front through a metaball medium with any of march.hpp's step rules,
// as the lecture writes the recurrence — plain and scalar, beside the `media` scene's fast front-to-back
// march (metaball_march.hpp), whose medium and shadow ray it reuses.
//
// The medium is the metaball density ρ(x) (metaballs.hpp; a MetaballVolume built with extinction
// scale 1, so that its extinction() is ρ) times coefficients per unit density, RGB:
//   μ = (σa + σs)·ρ                                        extinction, 1/m
//   q = ε·ρ + σs·ρ·(p(cos θ)·e^{−(σa+σs)·τ_l}·E + A)       source, radiance per metre
// where τ_l = ∫ρ dl along the shadow ray to the box's exit towards the light (VolumeLight,
// volume_light.hpp: a directional light, E its irradiance; or a point light, E = I/r² and the shadow
// ray ending at the light where that comes first; A an isotropic ambient radiance; the light's g and
// albedo are the medium's here, unused), cos θ = d·l (phase_functions.hpp's convention: the
// light travels along −l and leaves along −d) and p the chosen phase function. σa alone: a medium that
// only absorbs (q = 0); ε alone: one that only emits (μ = 0, L = L_bg + ∫q ds).
//
// The ray o + t·d (d unit length) crosses the box for t in [t0, t1], t0 = max(t_near, 0); N steps of
// Δs = (t1 − t0)/N, marched from the far end (L = L_bg, the background) to the eye, step i covering
// [t0 + i·Δs, t0 + (i+1)·Δs] and sampled where stepSampleFraction(rule) says (its far end, or its
// midpoint), then L ← applyStep(rule, L, μ_i, q_i, Δs) per channel (march.hpp: the Euler and the
// exponential steps, written once there). A sample where ρ = 0 has μ = q = 0, which every rule
// leaves L exactly as it is (Euler: L + Δs·0; exponential: L·1 + 0), so the samples outside every
// ball are skipped (metaball_march.hpp's ballSpan, conservative): the same value.
//
// Euler's factor per step is 1 − μΔs: in [0, 1] for μΔs ≤ 1 (L stays between L and q/μ), negative
// above 1 (overshoot), below −1 for μΔs > 2 (the error grows step by step, with alternating sign).
// The exponential rules' factor e^{−μΔs} is in [0, 1] for every μΔs.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>

#include "raster/media/march.hpp"
#include "raster/media/metaball_march.hpp"
#include "raster/media/phase_functions.hpp"

namespace raster::media {

enum class PhaseFunction : uint8_t { isotropic, rayleigh, henyeyGreenstein };

// p(cos θ) per steradian (phase_functions.hpp); g only for Henyey–Greenstein.
inline float phaseValue(PhaseFunction phase, float g, float cos_theta) {
    switch (phase) {
        case PhaseFunction::isotropic: return isotropic<float>();
        case PhaseFunction::rayleigh: return rayleigh(cos_theta);
        case PhaseFunction::henyeyGreenstein: return henyeyGreenstein(g, cos_theta);
    }
    return 0.0f;
}

// Coefficients per unit metaball density (header), RGB, each ≥ 0.
struct FigureMedium {
    glm::vec3 absorption{0.0f};  // σa, 1/m
    glm::vec3 scattering{0.0f};  // σs, 1/m
    glm::vec3 emission{0.0f};    // ε, radiance per metre
    PhaseFunction phase = PhaseFunction::isotropic;
    float g = 0.0f;  // Henyey–Greenstein's anisotropy (mean cosine)
};

struct FigureMarch {
    StepRule rule = StepRule::exponential;
    uint32_t steps = 32;       // N along the view ray (≥ 1)
    uint32_t shadowSteps = 8;  // M along each shadow ray (≥ 1), where the medium scatters
};

// The radiance reaching the eye along o + t·d with L_bg behind the medium (header). `volume` built
// with extinction scale 1.
inline glm::vec3 marchFigure(const MetaballVolume& volume, const FigureMedium& medium, const VolumeLight& light,
                             const FigureMarch& march, const glm::vec3& eye, const glm::vec3& d,
                             const glm::vec3& background) {
    const auto [t_near, t_far] = slabInterval(volume.box, eye, d);
    const float t0 = std::max(t_near, 0.0f), t1 = t_far;
    if (!(t1 > t0)) return background;
    const float ds = (t1 - t0) / float(march.steps);
    const float offset = 1.0f - float(stepSampleFraction(march.rule));  // sample i at t0 + (i + offset)·Δs
    const auto [first, last] = detail::ballSpan(volume, eye, d, t0 + (offset - 0.5f) * ds, ds, march.steps);
    const glm::vec3 extinction = medium.absorption + medium.scattering;
    const bool scatters = medium.scattering != glm::vec3(0.0f);
    const bool point = light.kind == LightKind::point;
    const float phase = phaseValue(medium.phase, medium.g, glm::dot(d, light.toLight));  // directional
    const glm::vec3 inv_light = 1.0f / light.toLight;
    MarchSettings shadow_settings;
    shadow_settings.shadowSteps = march.shadowSteps;
    MarchResult counts;
    glm::vec3 L = background;
    for (int32_t i = last; i >= first; --i) {
        const glm::vec3 x = eye + d * (t0 + (float(i) + offset) * ds);
        const float rho = volume.extinction(x, 0x3fu);
        if (rho == 0.0f) continue;  // μ = q = 0: every rule leaves L as it is
        glm::vec3 q = medium.emission * rho;
        if (scatters) {
            const LightAtPoint at = lightAt(light, x);
            const float length = point ? detail::pointShadowLength(volume.box, x, at)
                                       : detail::exitDistance(volume.box, x, at.toLight, inv_light);
            const float tau = detail::shadowDepth(volume, shadow_settings, x, at.toLight, length, counts);
            const float p = point ? phaseValue(medium.phase, medium.g, glm::dot(d, at.toLight)) : phase;
            const glm::vec3 in_scattered = p * glm::exp(-extinction * tau) * at.irradiance + light.ambient;
            q += medium.scattering * rho * in_scattered;
        }
        const glm::vec3 mu = extinction * rho;
        for (int c = 0; c < 3; ++c) L[c] = applyStep(march.rule, L[c], mu[c], q[c], ds);
    }
    return L;
}

}  // namespace raster::media
