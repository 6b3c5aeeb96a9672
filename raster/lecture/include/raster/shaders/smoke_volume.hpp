// The `smoke-volume` scene's pixel shader: a full-screen triangle whose pixels march their view ray
// through the particles splatted into a voxel grid (raster/media/particle_volume.hpp) with the cloud's
// march (raster/media/cloud_march.hpp: single scattering, shadow rays through the medium, ambient), and
// return it premultiplied, rgb = L and alpha = 1 − T, for the blend ONE, INV_SRC_ALPHA: dst' = L + T·dst.
//
// Depth: the opaque pass (the ground, the box the smoke blows through) left its depth; the march ends
// where the view ray meets that surface. The surface point is the pixel's ndc at its stored depth
// unprojected (invViewProj), its distance from the eye the march's end; a cleared depth (1, the far
// plane, 100 m) lies beyond the volume's box and clips nothing. So smoke behind the box is hidden by
// it, smoke in front of it covers it, and smoke that passes through it is cut where it enters.
//
// Units: as the cloud's (cloud.hpp, PsCloudMarch): voxel = (world − origin)·voxelsPerMetre.
#pragma once

#include <algorithm>
#include <glm/glm.hpp>
#include <type_traits>
#include <utility>

#include "raster/shaders/cloud.hpp"
#include "raster/soft_particles.hpp"

namespace raster::shaders {

struct PsSmokeVolume {
    using Input = MediaRayVertex;
    using SpecialisedStates = PsCloudMarch::SpecialisedStates;  // drawn "over", as the cloud is
    // The march's frame, volume, light and settings (cloud.hpp; its fog is not used).
    PsCloudMarch march;
    DepthTexture sceneDepth;  // the opaque pass's depth, at the target's resolution

    // The distance from the eye to the surface behind the pixel at ndc with stored depth z, voxels.
    float surfaceDistance(const glm::vec2& ndc, float z) const {
        const glm::vec4 h = march.invViewProj * glm::vec4(ndc, z, 1.0f);
        return glm::length(glm::vec3(h) / h.w - march.eye) * march.voxelsPerMetre;
    }

    // The stretch [s0, s1] of the view ray d (voxels from the eye) that the march covers: inside the
    // volume's box and in front of the surface at stored depth z (s1 ≤ s0: none).
    std::pair<float, float> marchInterval(const glm::vec3& d, const glm::vec2& ndc, float z) const {
        const auto [s_near, s_far] = media::slabInterval(march.volume->box, march.eyeVoxels(), d);
        return {std::max(s_near, 0.0f), std::min(s_far, surfaceDistance(ndc, z))};
    }

    // Not inlined, as PsCloudMarch::shade (a call per pixel is nothing beside its march).
    [[gnu::noinline]] glm::vec4 shade(const glm::vec3& d, const glm::vec2& ndc, float z) const {
        const auto [s0, s1] = marchInterval(d, ndc, z);
        if (!(s1 > s0)) return glm::vec4(0.0f);
        const media::MarchResult r =
            media::marchCloud(*march.volume, march.light, march.settings, march.eyeVoxels(), d, s0, s1);
        return {glm::clamp(r.radiance, 0.0f, 1.0f), 1.0f - r.transmittance};
    }

    template <class T>
    glm::vec<4, T> operator()(const MediaRayVertexT<T>& in) const {
        const glm::vec<3, T> d = viewRay(march.invViewProj, in.ndc);
        const T z = sceneDepth.atPixel(in.position.x, in.position.y);
        if constexpr (std::is_same_v<T, float>) {
            return shade(d, in.ndc, z);
        } else {
            constexpr int kLanes = int(sizeof(T) / sizeof(float));
            alignas(64) float dx[kLanes], dy[kLanes], dz[kLanes], nx[kLanes], ny[kLanes], zs[kLanes], out[4][kLanes];
            d.x.store(dx), d.y.store(dy), d.z.store(dz), in.ndc.x.store(nx), in.ndc.y.store(ny), z.store(zs);
            for (int l = 0; l < kLanes; ++l) {
                const glm::vec4 c = shade({dx[l], dy[l], dz[l]}, {nx[l], ny[l]}, zs[l]);
                for (int k = 0; k < 4; ++k) out[k][l] = c[k];
            }
            return {T::load(out[0]), T::load(out[1]), T::load(out[2]), T::load(out[3])};
        }
    }
};

}  // namespace raster::shaders
