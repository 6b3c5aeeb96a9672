// The volume rendering equation's closed form in a homogeneous medium (NOTES.md, part 1).
//
// Along a ray, radiance L changes per metre of path s as
//   dL/ds = −μ·L + q,   μ = μa + μs        extinction: absorption + out-scattering, 1/m
//                       q = ε + μs·L_in    source: emission ε plus in-scattering, radiance per metre
// where L_in = ∫ L(ω′)·p(ω′, ω) dω′ is the incident radiance weighted by the phase function
// (phase_functions.hpp; for light arriving equally from every direction, L_in is that radiance). With μ
// and q constant along the path, from L(0) at s = 0:
//   T(s) = e^{−μs}                                 transmittance
//   L(s) = L(0)·T(s) + q·ℓ(μ, s),  ℓ(μ, s) = s·ψ(μs) = (1 − e^{−μs})/μ   (exprel.hpp)
// which is the lecture's L(0)·e^{−μs} + q·(1 − e^{−μs})/μ without its 0/0 at μ = 0 (there
// L = L(0) + q·s: emission without extinction) and without its loss of every digit for thin media
// (μs = 1e-30: 1 − e^{−μs} rounds to 0). Per colour channel, RGB.
//
// Limits: s = 0 gives L(0); s = ∞ (a background infinitely far) gives q/μ, and for μ = 0 the
// background itself, or +∞ where q > 0 (a source without extinction, summed over an infinite path).
// q = 0 adds exactly nothing, even where ℓ = ∞. Domain: μ, q finite and ≥ 0, L(0) finite, s ≥ 0 or
// +∞. Over it the result is within a few ulp times the problem's condition number (tests/media_test.cpp,
// docs/ACCURACY.md), and NaN never. T is float, Float8 (a pixel shader's eight-wide path, the same bits
// as float lane by lane) or double.
//
// The height fog (height_fog.hpp) is this same solution in the optical depth per unit σ in place of s.
#pragma once

#include <cmath>
#include <cstdio>
#include <glm/glm.hpp>
#include <string>

#include "raster/check.hpp"
#include "raster/media/exprel.hpp"
#include "raster/media/scalar_math.hpp"

namespace raster::media {

// e^{−μs}: 1 for μ = 0 (even at s = ∞), 0 for s = ∞ and μ > 0.
template <class T>
T transmittance(T mu, T s) {
    using namespace detail;
    return select(mu == T(0.0f), T(1.0f), exp(-(mu * s)));
}

// The in-scattered and emitted part q·ℓ(μ, s): radiance gathered along s, seen at its start.
template <class T>
T gathered(T mu, T q, T s) {
    using namespace detail;
    return select(q == T(0.0f), T(0.0f), q * attenuatedLength(mu, s));
}

// L(s) = L(0)·e^{−μs} + q·ℓ(μ, s): the radiance arriving after a path of s metres through extinction μ
// with source q, from radiance L0 where the path began (header: domain, limits).
template <class T>
T radiance(T L0, T mu, T q, T s) {
    return L0 * transmittance(mu, s) + gathered(mu, q, s);
}

// Throws Error(InvalidArgument) "<what>: <value> is negative" (or NaN, or infinite) unless every
// channel of v is finite and ≥ 0: extinction, absorption, scattering, emission and source terms.
inline void requireCoefficient(const char* what, const glm::vec3& v) {
    for (int c = 0; c < 3; ++c) {
        const char* problem = std::isnan(v[c])   ? "is NaN"
                              : std::isinf(v[c]) ? "is infinite"
                              : v[c] < 0         ? "is negative"
                                                 : nullptr;
        if (!problem) continue;
        char text[64];
        std::snprintf(text, sizeof text, "%g %s", double(v[c]), problem);
        RASTER_REQUIRE(false, InvalidArgument, std::string(what) + ": " + text);
    }
}

// A homogeneous medium with RGB coefficients.
struct HomogeneousMedium {
    glm::vec3 absorption{0.0f};  // μa, 1/m
    glm::vec3 scattering{0.0f};  // μs, 1/m
    glm::vec3 emission{0.0f};    // ε, radiance per metre of path (W/(sr·m³))

    // Throws Error(InvalidArgument) naming the first coefficient that is negative, NaN or infinite.
    void validate() const {
        requireCoefficient("absorption", absorption);
        requireCoefficient("scattering", scattering);
        requireCoefficient("emission", emission);
    }

    glm::vec3 extinction() const { return absorption + scattering; }
    // q = ε + μs·L_in for phase-weighted incident radiance L_in (header).
    glm::vec3 source(const glm::vec3& inScattered) const { return emission + scattering * inScattered; }

    // e^{−μs} per channel over a path of s metres (s may be +∞).
    template <class T>
    glm::vec<3, T> transmittance(T s) const {
        const glm::vec3 mu = extinction();
        glm::vec<3, T> result;
        for (int c = 0; c < 3; ++c) result[c] = media::transmittance(T(mu[c]), s);
        return result;
    }

    // Radiance after s metres (s may be +∞) from radiance L0 where the path began, with incident
    // radiance inScattered (phase-weighted, per channel) feeding the in-scattering.
    template <class T>
    glm::vec<3, T> radiance(const glm::vec<3, T>& L0, T s,
                            const glm::vec3& inScattered = glm::vec3(0.0f)) const {
        const glm::vec3 mu = extinction(), q = source(inScattered);
        glm::vec<3, T> result;
        for (int c = 0; c < 3; ++c) result[c] = media::radiance(L0[c], T(mu[c]), T(q[c]), s);
        return result;
    }
};

}  // namespace raster::media
