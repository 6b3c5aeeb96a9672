// The lecture's fog in the pixel shader (lecture 11, part 2), in numerically stable form.
//
// Along a view ray from the eye, distance s, through a medium of extinction σ and source q (both
// RGB, per metre), the radiance reaching the eye from a surface of radiance L0 is
//   L = L0·T + (q/σ)·(1 − T),   T = e^{−σ·τ(s)}
// where τ is the optical depth per unit σ:
//   constant fog:        τ(s) = s
//   exponential height:  σ(y) = σ·e^{b·y}, q(y) = q·e^{b·y}, ray y(t) = y0 + d_y·t:
//                        τ(s) = e^{b·y0} · (e^{k·s} − 1)/k,  k = b·d_y.
// Stable forms (NOTES.md errata): (e^{x} − 1)/x is evaluated as expm1(x)/x, and as its series
// 1 + x/2 + x²/6 when |x| < 1e-4, so τ → e^{b·y0}·s for a horizontal ray (k → 0) instead of 0/0;
// at s = ∞ (the background), τ = e^{b·y0}/(−k) for a ray going up into thinning fog (k < 0), and
// T = 0 otherwise; 1 − T is computed as −expm1(−σ·τ) so thin fog keeps its digits.
#pragma once

#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "raster/input_layout.hpp"
#include "raster/shader.hpp"

namespace raster::shaders {

struct FogMedium {
    glm::vec3 sigma{0.06f, 0.07f, 0.09f};                              // extinction, 1/m
    glm::vec3 q = glm::vec3(0.06f, 0.07f, 0.09f) * glm::vec3(0.6f, 0.65f, 0.75f);  // source term
    float b = -0.5f;      // height falloff, 1/m (height fog only)
    bool height = true;   // false: constant fog

    // (e^x − 1)/x, finite and accurate for every x including 0.
    static float expm1OverX(float x) {
        if (std::fabs(x) < 1e-4f) return 1.0f + x * (0.5f + x * (1.0f / 6.0f));
        return std::expm1(x) / x;
    }

    // Optical depth per unit σ from height y0 along unit direction d for distance s (s may be +∞).
    float opticalDepth(float y0, float dy, float s) const {
        if (!height) return s;
        const float base = std::exp(b * y0);
        const float k = b * dy;
        if (std::isinf(s)) return k < 0.0f ? base / -k : std::numeric_limits<float>::infinity();
        return base * s * expm1OverX(k * s);
    }

    // Radiance at the eye from a surface of radiance L0 at distance s along unit direction dir.
    glm::vec3 apply(const glm::vec3& L0, const glm::vec3& eye, const glm::vec3& dir, float s) const {
        const float tau = opticalDepth(eye.y, dir.y, s);
        glm::vec3 result;
        for (int c = 0; c < 3; ++c) {
            const float optical = sigma[c] * tau;  // may be +∞: T = 0
            const float t = std::isinf(optical) ? 0.0f : std::exp(-optical);
            const float one_minus_t = std::isinf(optical) ? 1.0f : -std::expm1(-optical);
            result[c] = L0[c] * t + (q[c] / sigma[c]) * one_minus_t;
        }
        return result;
    }
};

struct LitIn {
    glm::vec3 position;
    glm::vec3 normal;
    RASTER_INPUT_SIGNATURE(LitIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(normal, "NORMAL", 0))
};

struct LitVertex {
    glm::vec4 position;
    glm::vec3 worldPos;
    glm::vec3 normal;
};

struct VsLit {
    glm::mat4 viewProj{1.0f};
    LitVertex operator()(const LitIn& in) const {
        return {viewProj * glm::vec4(in.position, 1.0f), in.position, in.normal};
    }
};

// Diffuse surface, L0 = albedo·(ambient + (1 − ambient)·max(0, n·l)), seen through the fog.
struct PsFog {
    FogMedium fog;
    glm::vec3 eye{0.0f};
    glm::vec3 albedo{0.7f};
    glm::vec3 light = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
    float ambient = 0.2f;

    glm::vec4 operator()(const LitVertex& in) const {
        const float lambert = std::max(0.0f, glm::dot(glm::normalize(in.normal), light));
        const glm::vec3 L0 = albedo * (ambient + (1.0f - ambient) * lambert);
        const glm::vec3 d = in.worldPos - eye;
        const float s = glm::length(d);
        return glm::vec4(fog.apply(L0, eye, d / s, s), 1.0f);
    }
};

// The background: a full-screen triangle at depth 1 whose pixels look through the fog to s = ∞.
struct SkyIn {
    glm::vec2 ndc;
    RASTER_INPUT_SIGNATURE(SkyIn, RASTER_INPUT(ndc, "POSITION", 0))
};

struct SkyVertex {
    glm::vec4 position;
    glm::vec2 ndc;
};

struct VsSky {
    SkyVertex operator()(const SkyIn& in) const { return {glm::vec4(in.ndc, 1.0f, 1.0f), in.ndc}; }
};

struct PsSky {
    FogMedium fog;
    glm::vec3 eye{0.0f};
    glm::mat4 invViewProj{1.0f};

    glm::vec4 operator()(const SkyVertex& in) const {
        const glm::vec4 a = invViewProj * glm::vec4(in.ndc, 0.0f, 1.0f);
        const glm::vec4 c = invViewProj * glm::vec4(in.ndc, 1.0f, 1.0f);
        const glm::vec3 d = glm::normalize(glm::vec3(c) / c.w - glm::vec3(a) / a.w);
        return glm::vec4(fog.apply(glm::vec3(0.0f), eye, d, std::numeric_limits<float>::infinity()), 1.0f);
    }
};

}  // namespace raster::shaders
