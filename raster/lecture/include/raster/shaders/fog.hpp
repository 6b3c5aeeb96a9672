// The lecture's fog in the pixel shader (lecture 11, part 2), in numerically stable form.
//
// Along a view ray from the eye, distance s, through a medium of extinction σ and source q (both
// RGB, per metre), the radiance reaching the eye from a surface of radiance L0 is
//   L = L0·T + (q/σ)·(1 − T),   T = e^{−σ·τ(s)}
// where τ is the optical depth per unit σ:
//   constant fog:        τ(s) = s
//   exponential height:  σ(y) = σ·e^{b·y}, q(y) = q·e^{b·y}, ray y(t) = y0 + d_y·t:
//                        τ(s) = e^{b·y0}·s·φ(b·d_y·s),  φ(z) = (e^z − 1)/z.
// The physics and its stable forms live in raster/media/: τ is media::heightFogOpticalDepth (the
// exponents combined before exponentiating, ψ's series for a horizontal ray, the background at s = ∞),
// and L is media::radiance's closed form L0·T + q·ℓ(σ, τ), written here as L0·T + (q/σ)·(1 − T)
// with one expm1 per channel shared by T and 1 − T (the benchmark's hot path):
//  - 1 − T is computed as −expm1(−σ·τ) so thin fog keeps its digits; in-scattering (q/σ)·(1 − T)
//    has the limit q·τ for σ → 0 (and 0 for q = 0, whatever τ), which a channel with σ = 0 uses;
//  - T = 1 + expm1(−σ·τ) is accurate to 6e-8 absolute, not relative: the displayed L is within 1e-6
//    of the exact value (fog_test.cpp), where media::radiance is within a few ulp of it.
// Domain of the guarantee: σ, q ≥ 0 with q/σ a finite float where σ > 0; s ≥ 0 or s = ∞.
#pragma once

#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "raster/input_layout.hpp"
#include "raster/media/height_fog.hpp"
#include "raster/shader.hpp"
#include "raster/simd.hpp"
#include "raster/specialised_states.hpp"

namespace raster::shaders {

struct FogMedium {
    glm::vec3 sigma{0.06f, 0.07f, 0.09f};                              // extinction, 1/m
    glm::vec3 q = glm::vec3(0.06f, 0.07f, 0.09f) * glm::vec3(0.6f, 0.65f, 0.75f);  // source term
    float b = -0.5f;      // height falloff, 1/m (height fog only)
    bool height = true;   // false: constant fog

    // Optical depth per unit σ from height y0 along unit direction with y component dy, over a
    // finite distance s (media/height_fog.hpp).
    template <class T>
    [[gnu::always_inline]] T opticalDepth(float y0, T dy, T s) const {
        if (!height) return s;
        return media::heightFogOpticalDepth(T(b), T(y0), dy, s);
    }
    // The same to s = ∞: e^{b·y0}/(−k) for a ray rising into thinning fog (k < 0), else ∞.
    template <class T>
    [[gnu::always_inline]] T opticalDepthToInfinity(float y0, T dy) const {
        if (!height) return T(std::numeric_limits<float>::infinity());
        return media::heightFogOpticalDepthToInfinity(T(b), T(y0), dy);
    }

    // In-scattered radiance of channel c over optical depth tau, given e = expm1(−σ_c·tau):
    // (q/σ)·(1 − T), or its limit q·tau when σ_c = 0 (0 when q_c = 0 too, even for tau = ∞).
    template <class T>
    T inScattered(int c, T tau, T e) const {
        if (sigma[c] == 0.0f) return q[c] == 0.0f ? T(0.0f) : T(q[c]) * tau;
        return T(q[c] / sigma[c]) * -e;
    }

    // Radiance at the eye from a surface of radiance L0 seen through optical depth tau (may be ∞).
    template <class T>
    glm::vec<3, T> applyOpticalDepth(const glm::vec<3, T>& L0, T tau) const {
        glm::vec<3, T> result;
        for (int c = 0; c < 3; ++c) {
            // One expm1 per channel: e = T − 1 (∞ gives e = −1, T = 0). T = 1 + e is off by at most
            // half an ulp of 1 (6e-8 absolute), far below 1/255 as L0 ≤ 1; 1 − T = −e keeps its full
            // precision for thin fog. Saves three of the pixel's seven exponentials. σ = 0: e = 0.
            const T e = sigma[c] == 0.0f ? T(0.0f) : expm1(-(T(sigma[c]) * tau));
            result[c] = L0[c] * (T(1.0f) + e) + inScattered(c, tau, e);
        }
        return result;
    }

    // Radiance at the eye from a surface of radiance L0 at distance s (s may be +∞) along unit dir.
    glm::vec3 apply(const glm::vec3& L0, const glm::vec3& eye, const glm::vec3& dir, float s) const {
        const float tau = std::isinf(s) ? opticalDepthToInfinity(eye.y, dir.y) : opticalDepth(eye.y, dir.y, s);
        return applyOpticalDepth(L0, tau);
    }
    float opticalDepth(float y0, float dy, float s) const {
        return std::isinf(s) ? opticalDepthToInfinity(y0, dy) : opticalDepth<float>(y0, dy, s);
    }
};

struct LitIn {
    glm::vec3 position;
    glm::vec3 normal;
    RASTER_INPUT_SIGNATURE(LitIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(normal, "NORMAL", 0))
};

template <class T>
struct LitVertexT {
    glm::vec<4, T> position;
    glm::vec<3, T> worldPos;
    glm::vec<3, T> normal;
};
using LitVertex = LitVertexT<float>;

struct VsLit {
    glm::mat4 viewProj{1.0f};
    LitVertex operator()(const LitIn& in) const {
        return {viewProj * glm::vec4(in.position, 1.0f), in.position, in.normal};
    }
};

// Diffuse surface, L0 = albedo·(ambient + (1 − ambient)·max(0, n·l)), seen through the fog.
// Written over its scalar type, so the pipeline runs it eight pixels wide (simd.hpp).
struct PsFog {
    // Its draws' state (specialised_states.hpp).
    using SpecialisedStates = raster::SpecialisedStates<Specialise<DepthState::Less, BlendMode::Replace>>;
    using Input = LitVertex;
    FogMedium fog;
    glm::vec3 eye{0.0f};
    glm::vec3 albedo{0.7f};
    glm::vec3 light = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
    float ambient = 0.2f;

    template <class T>
    glm::vec<4, T> operator()(const LitVertexT<T>& in) const {
        return shade(in, lambert(in));
    }

    // max(0, n·l) at the pixel.
    template <class T>
    T lambert(const LitVertexT<T>& in) const {
        const glm::vec<3, T> n = normalize(in.normal);
        return max(T(0.0f), n.x * T(light.x) + n.y * T(light.y) + n.z * T(light.z));
    }

    // The pixel's colour given its sunlit term `lit` (lambert(in), times the sun's visibility in a
    // variant whose sun can be shadowed: PsCloudGround).
    template <class T>
    glm::vec<4, T> shade(const LitVertexT<T>& in, T lit) const {
        using V3 = glm::vec<3, T>;
        const T level = T(ambient) + T(1.0f - ambient) * lit;
        const V3 L0(T(albedo.x) * level, T(albedo.y) * level, T(albedo.z) * level);
        const V3 d(in.worldPos.x - T(eye.x), in.worldPos.y - T(eye.y), in.worldPos.z - T(eye.z));
        const T s = length(d);
        const V3 L = fog.applyOpticalDepth(L0, fog.opticalDepth(eye.y, d.y / s, s));
        return {L.x, L.y, L.z, T(1.0f)};
    }
};

// The background: a full-screen triangle at depth 1 whose pixels look through the fog to s = ∞.
struct SkyIn {
    glm::vec2 ndc;
    RASTER_INPUT_SIGNATURE(SkyIn, RASTER_INPUT(ndc, "POSITION", 0))
};

template <class T>
struct SkyVertexT {
    glm::vec<4, T> position;
    glm::vec<3, T> ray;  // the pixel's view ray, world space, not normalised
};
using SkyVertex = SkyVertexT<float>;

// The far-plane corner's homogeneous world point H = invViewProj·(ndc, 1, 1) is linear in ndc,
// and so is H.xyz − eye·H.w = H.w·(P − eye): the view ray scaled by H.w (one sign over the screen:
// H.w depends on depth only). It is passed on as an attribute, linear across the screen (w = 1),
// so the pixel shader needs no unprojection.
struct VsSky {
    glm::mat4 invViewProj{1.0f};
    glm::vec3 eye{0.0f};
    SkyVertex operator()(const SkyIn& in) const {
        const glm::vec4 h = invViewProj * glm::vec4(in.ndc, 1.0f, 1.0f);
        const float sign = h.w < 0.0f ? -1.0f : 1.0f;
        return {glm::vec4(in.ndc, 1.0f, 1.0f), (glm::vec3(h) - eye * h.w) * sign};
    }
};

// The background: L0 = 0 seen through the fog to s = ∞ along the pixel's view ray, so only the
// in-scattered term (q/σ)·(1 − T) remains (the L0·T term is +0 exactly, and is not computed).
struct PsSky {
    // Its draws' state (specialised_states.hpp).
    using SpecialisedStates = raster::SpecialisedStates<Specialise<DepthState::LessEqual, BlendMode::Replace>>;
    using Input = SkyVertex;
    FogMedium fog;
    glm::vec3 eye{0.0f};
    template <class T>
    glm::vec<4, T> operator()(const SkyVertexT<T>& in) const {
        const T dy = in.ray.y / sqrt(in.ray.x * in.ray.x + in.ray.y * in.ray.y + in.ray.z * in.ray.z);
        const T tau = fog.opticalDepthToInfinity(eye.y, dy);
        glm::vec<3, T> L;
        for (int c = 0; c < 3; ++c) {
            const T e = fog.sigma[c] == 0.0f ? T(0.0f) : expm1(-(T(fog.sigma[c]) * tau));
            L[c] = fog.inScattered(c, tau, e);
        }
        return {L.x, L.y, L.z, T(1.0f)};
    }
};

}  // namespace raster::shaders
