// The `cloud` scene's pixel shader: a full-screen triangle whose pixels march their view ray through a
// voxel cloud (raster/media/cloud_march.hpp) and return it premultiplied, to be blended over what is
// drawn already (ONE, INV_SRC_ALPHA: dst' = src.rgb + (1 − T)·… see below).
//
// The world and the cloud's voxels: voxel = (world − origin)·voxelsPerMetre, one uniform scale, so the
// view ray's direction is the same in both and a distance s in voxels is s/voxelsPerMetre metres.
//
// Compositing with the ground's fog (shaders/fog.hpp): the ground pass left dst = F + T_f·G along the
// ray (fog in-scattering F and transmittance T_f over the whole path, the surface's G behind). Taking
// the cloud's medium as lying at its box's entry distance s_e (the fog inside the box is left out), the
// radiance is F_e + T_e·(L + T·(dst − F_e)/T_e) = T·dst + T_e·L + (1 − T)·F_e, with F_e and T_e the
// fog's in-scattering and transmittance over [0, s_e]: the shader returns rgb = T_e·L + (1 − T)·F_e and
// alpha = 1 − T, and the blend ONE, INV_SRC_ALPHA adds T·dst. A ray that misses the box returns 0: dst
// unchanged.
//
// The ground under the cloud (PsCloudGround): the fog scene's ground shader with its sun attenuated by
// the cloud's transmittance along the shadow ray from the surface point towards the sun, or lit by a
// point light in the sun's place.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <glm/glm.hpp>

#include "raster/media/cloud_march.hpp"
#include "raster/pixel_march.hpp"
#include "raster/shaders/fog.hpp"
#include "raster/shaders/media.hpp"

namespace raster::shaders {

struct PsCloudMarch {
    using Input = MediaRayVertex;
    // Drawn blending "over" (ONE, INV_SRC_ALPHA), which no specialised loop draws: none compiled, the
    // generic loop for its one draw (specialised_states.hpp).
    using SpecialisedStates = raster::SpecialisedStates<>;
    glm::mat4 invViewProj{1.0f};
    glm::vec3 eye{0.0f};              // world, metres
    glm::vec3 origin{0.0f};           // world position of the voxels' corner (0, 0, 0)
    float voxelsPerMetre = 1.0f;
    const media::CloudVolume* volume = nullptr;
    media::VolumeLight light;
    media::CloudMarchSettings settings;
    FogMedium fog;                    // the ground's fog, in front of the cloud

    glm::vec3 eyeVoxels() const { return (eye - origin) * voxelsPerMetre; }

    // Not inlined, as PsMediaMarch::shade: the march inlined into each flattened fill loop would make
    // the scene's file a compile of minutes; a call per pixel is nothing beside its march.
    [[gnu::noinline]] glm::vec4 shade(const glm::vec3& d) const {
        const glm::vec3 o = eyeVoxels();
        const auto [s_near, s_far] = media::slabInterval(volume->box, o, d);
        const float s0 = std::max(s_near, 0.0f);
        if (!(s_far > s0)) return glm::vec4(0.0f);
        const media::MarchResult r = media::marchCloud(*volume, light, settings, o, d, s0, s_far);
        const float opacity = 1.0f - r.transmittance;
        const float tau = fog.opticalDepth(eye.y, d.y, s0 / voxelsPerMetre);
        glm::vec3 rgb;
        for (int c = 0; c < 3; ++c) {
            const float e = fog.sigma[c] == 0.0f ? 0.0f : expm1(-(fog.sigma[c] * tau));
            rgb[c] = (1.0f + e) * r.radiance[c] + opacity * fog.inScattered(c, tau, e);
        }
        return {glm::clamp(rgb, 0.0f, 1.0f), opacity};
    }

    // The march shade(d) runs over [s0, s1] (voxels along d), every evaluated sample recorded, for
    // Scene::pixelMarch: distances in metres from the eye (t1 ≤ t0: the ray missed). The colour is the
    // caller's: its shader's output for the pixel.
    PixelMarch tracedMarch(const glm::vec3& d, float s0, float s1) const {
        const float metres = 1.0f / voxelsPerMetre;
        PixelMarch march;
        const media::MarchResult r =
            media::marchCloud(*volume, light, settings, eyeVoxels(), d, s0, s1, [&](media::MarchSample s) {
                s.s *= metres;
                march.samples.push_back(s);
            });
        march.steps = s1 > s0 ? std::max(1u, uint32_t(std::ceil((s1 - s0) / settings.step))) : 0u;
        march.t0 = s0 * metres, march.t1 = s1 * metres;
        march.ds = march.steps > 0 ? (march.t1 - march.t0) / float(march.steps) : 0.0f;
        march.radiance = r.radiance, march.transmittance = r.transmittance;
        march.densityEvaluations = r.densityEvaluations;
        return march;
    }

    template <class T>
    glm::vec<4, T> operator()(const MediaRayVertexT<T>& in) const {
        const glm::vec<3, T> d = viewRay(invViewProj, in.ndc);
        if constexpr (std::is_same_v<T, float>) {
            return shade(d);
        } else {
            constexpr int kLanes = int(sizeof(T) / sizeof(float));
            alignas(64) float dx[kLanes], dy[kLanes], dz[kLanes], out[4][kLanes];
            d.x.store(dx), d.y.store(dy), d.z.store(dz);
            for (int l = 0; l < kLanes; ++l) {
                const glm::vec4 c = shade({dx[l], dy[l], dz[l]});
                for (int k = 0; k < 4; ++k) out[k][l] = c[k];
            }
            return {T::load(out[0]), T::load(out[1]), T::load(out[2]), T::load(out[3])};
        }
    }
};

// The fog scene's ground (PsFog) with the cloud's shadow: the sunlit term max(0, n·l) times the
// cloud's transmittance e^{−τ} from the surface point towards the sun (media::cloudShadowTransmittance:
// the cloud march's shadow ray, majorant-skipped, the same shadow termination). Where the shadow ray
// misses the cloud's box, or the surface faces away from the sun, nothing is marched and the term is
// multiplied by exactly 1: the fog ground's bits. The fog over the ground is the fog scene's: the
// sunlight reaching the ground is not attenuated by the fog (as PsFog has it).
//
// With a point light in the sun's place (pointLight): the sunlit term is max(0, n·l)·e^{−τ}·(I/r²)/E,
// l = (P − x)/r towards the light at P, r metres away, the shadow ray ending at the light, and I/E
// (relativeIntensity, m²) the light's intensity over the sun's irradiance (each the mean of its RGB),
// the sun's E being the 1 of the ground's sunlit term.
struct PsCloudGround {
    using SpecialisedStates = PsFog::SpecialisedStates;  // drawn as the fog scene's ground is
    using Input = LitVertex;
    PsFog ground;                     // the fog scene's shading; its light is the direction to the sun
    glm::vec3 origin{0.0f};           // world position of the voxels' corner (0, 0, 0)
    float voxelsPerMetre = 1.0f;
    const media::CloudVolume* volume = nullptr;
    media::CloudMarchSettings settings;
    bool pointLight = false;
    glm::vec3 lightPosition{0.0f};   // world, metres
    float relativeIntensity = 0.0f;  // I/E, m²

    // The sun's visibility at a world point: 1 where the shadow ray misses the cloud's box.
    float sunVisibility(const glm::vec3& world) const {
        return media::cloudShadowTransmittance(*volume, settings, (world - origin) * voxelsPerMetre, ground.light);
    }

    // The point light's sunlit term at a world point with unit normal n (header).
    float pointLit(const glm::vec3& world, const glm::vec3& n) const {
        const glm::vec3 v = lightPosition - world;
        const float r2 = glm::dot(v, v), r = std::sqrt(r2);
        const glm::vec3 l = v / r;
        const float lambert = glm::dot(n, l);
        if (!(lambert > 0.0f)) return 0.0f;
        const float t = media::cloudShadowTransmittance(*volume, settings, (world - origin) * voxelsPerMetre, l,
                                                        r * voxelsPerMetre);
        return lambert * t * relativeIntensity / r2;
    }

    template <class T>
    glm::vec<4, T> operator()(const LitVertexT<T>& in) const {
        if (pointLight) return pointLitShade(in);
        const T lambert = ground.lambert(in);
        if constexpr (std::is_same_v<T, float>) {
            return ground.shade(in, lambert > 0.0f ? lambert * sunVisibility(in.worldPos) : lambert);
        } else {
            constexpr int kLanes = int(sizeof(T) / sizeof(float));
            alignas(64) float x[kLanes], y[kLanes], z[kLanes], lit[kLanes];
            in.worldPos.x.store(x), in.worldPos.y.store(y), in.worldPos.z.store(z), lambert.store(lit);
            for (int l = 0; l < kLanes; ++l)
                if (lit[l] > 0.0f) lit[l] *= sunVisibility({x[l], y[l], z[l]});
            return ground.shade(in, T::load(lit));
        }
    }

    template <class T>
    glm::vec<4, T> pointLitShade(const LitVertexT<T>& in) const {
        const glm::vec<3, T> n = normalize(in.normal);
        if constexpr (std::is_same_v<T, float>) {
            return ground.shade(in, pointLit(in.worldPos, n));
        } else {
            constexpr int kLanes = int(sizeof(T) / sizeof(float));
            alignas(64) float x[kLanes], y[kLanes], z[kLanes], nx[kLanes], ny[kLanes], nz[kLanes], lit[kLanes];
            in.worldPos.x.store(x), in.worldPos.y.store(y), in.worldPos.z.store(z);
            n.x.store(nx), n.y.store(ny), n.z.store(nz);
            for (int l = 0; l < kLanes; ++l) lit[l] = pointLit({x[l], y[l], z[l]}, {nx[l], ny[l], nz[l]});
            return ground.shade(in, T::load(lit));
        }
    }
};

}  // namespace raster::shaders
