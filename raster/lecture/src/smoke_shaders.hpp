// The smoke scene's shaders (scene_smoke.cpp): the particles reuse the fire's vertex and geometry
// shaders (a point opened into a camera-facing quad carrying the particle's colour and opacity);
// here the pixel shaders:
//   PsSmokeParticle  a round puff, alpha = opacity · (1 − r²)², r the distance from the quad's centre
//                    in half-widths, times the soft fade against the scene's depth (soft_particles.hpp);
//   PsComposite      the off-screen particles' low-resolution target sampled bilinearly at the pixel,
//                    for the blend frame·T + colour;
//   PsSolid          the opaque ground and box: a diffuse surface under one directional light.
// Written over their scalar type, so the fast path shades 4×2 pixels a call.
#pragma once

#include <glm/glm.hpp>

#include "lecture/fire_particle_shaders.hpp"
#include "raster/sampler.hpp"
#include "raster/shaders/basic.hpp"
#include "raster/shaders/fog.hpp"
#include "raster/soft_particles.hpp"
#include "raster/texture.hpp"

namespace raster::shaders {

struct PsSmokeParticle {
    using Input = FireCorner;
    DepthTexture sceneDepth;  // the opaque pass's depth at the resolution drawn to
    DepthLinearizer linearizer;
    float inverseFadeDistance = 4.0f;
    bool soft = true;

    template <class T>
    glm::vec<4, T> operator()(const FireCornerT<T>& in) const {
        const T du = in.tex.x * T(2.0f) - T(1.0f), dv = in.tex.y * T(2.0f) - T(1.0f);
        const T inside = max(T(0.0f), T(1.0f) - (du * du + dv * dv));
        T alpha = in.colour.w * inside * inside;
        if (soft) {
            const T scene = linearizer.viewDepth(sceneDepth.atPixel(in.position.x, in.position.y));
            alpha = alpha * softFade(scene, in.position.w, inverseFadeDistance);
        }
        return {in.colour.x, in.colour.y, in.colour.z, alpha};
    }
};

struct PsComposite {
    using Input = PositionOnly;
    const Texture2D* particles = nullptr;  // premultiplied rgb, a = transmittance
    glm::vec2 inverseSize{1.0f};           // 1 / (k · the low-resolution target's width and height)
    SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);

    template <class T>
    glm::vec<4, T> operator()(const PositionOnlyT<T>& in) const {
        const glm::vec<2, T> uv(in.position.x * T(inverseSize.x), in.position.y * T(inverseSize.y));
        return particles->Sample(sampler, uv);
    }
};

struct PsSolid {
    using Input = LitVertex;
    glm::vec3 light = glm::normalize(glm::vec3(0.4f, 1.0f, 0.6f));
    float ambient = 0.25f;

    // The albedo, a grey level in (0, 1], is the normal's length: the vertex carries the unit
    // normal scaled by it, so that the scene keeps fog.hpp's vertex format (LitIn).
    template <class T>
    glm::vec<4, T> operator()(const LitVertexT<T>& in) const {
        const T albedo =
            sqrt(in.normal.x * in.normal.x + in.normal.y * in.normal.y + in.normal.z * in.normal.z);
        const T lambert =
            max(T(0.0f),
                (in.normal.x * T(light.x) + in.normal.y * T(light.y) + in.normal.z * T(light.z)) / albedo);
        const T shade = albedo * (T(ambient) + T(1.0f - ambient) * lambert);
        return {shade * T(0.9f), shade * T(0.75f), shade * T(0.6f), T(1.0f)};
    }
};

}  // namespace raster::shaders
