// The lecture's ray marching as a pixel shader (NOTES.md part 1, "Sugármenetelés"; SCENES.md, "Scene
// media"): a full-screen triangle whose pixel shader marches the pixel's view ray through a medium
// (raster/media/metaball_march.hpp) and returns L + T·L_bg.
//
// The view ray: ndc interpolated at the pixel centre; P_near = invViewProj·(ndc, 0, 1) and
// P_far = invViewProj·(ndc, 1, 1) after the division by w; d = normalize(P_far − P_near), from the eye.
#pragma once

#include <algorithm>
#include <type_traits>
#include <glm/glm.hpp>

#include "raster/input_layout.hpp"
#include "raster/media/metaball_march.hpp"
#include "raster/shader.hpp"
#include "raster/specialised_states.hpp"

namespace raster::shaders {

struct MediaRayIn {
    glm::vec2 ndc;
    RASTER_INPUT_SIGNATURE(MediaRayIn, RASTER_INPUT(ndc, "POSITION", 0))
};

template <class T>
struct MediaRayVertexT {
    glm::vec<4, T> position;
    glm::vec<2, T> ndc;
};
using MediaRayVertex = MediaRayVertexT<float>;

// The full-screen triangle: passes ndc on, linear across the screen.
struct VsMediaRay {
    MediaRayVertex operator()(const MediaRayIn& in) const { return {glm::vec4(in.ndc, 0.5f, 1.0f), in.ndc}; }
};

// Pixel (x, y)'s centre in a width × height target as the full-screen triangle interpolates ndc there
// (y up): the ray a media scene's pixel shader marches for that pixel (Scene::pixelMarch).
inline glm::vec2 pixelNdc(uint32_t x, uint32_t y, uint32_t width, uint32_t height) {
    return {(float(x) + 0.5f) / float(width) * 2.0f - 1.0f, 1.0f - (float(y) + 0.5f) / float(height) * 2.0f};
}

// The pixel's view ray, unit length (header), over float or eight lanes with the same operations per
// lane: H(z) = M·(ndc, z, 1) summed column by column, P = H.xyz/H.w, d = (P_far − P_near)·(1/|…|).
template <class T>
glm::vec<3, T> viewRay(const glm::mat4& inv_view_proj, const glm::vec<2, T>& ndc) {
    const glm::mat4& m = inv_view_proj;
    auto unproject = [&](float z) {
        glm::vec<4, T> h;
        for (int r = 0; r < 4; ++r) h[r] = T(m[0][r]) * ndc.x + T(m[1][r]) * ndc.y + T(m[2][r] * z + m[3][r]);
        return glm::vec<3, T>(h.x / h.w, h.y / h.w, h.z / h.w);
    };
    const glm::vec<3, T> a = unproject(0.0f), c = unproject(1.0f);
    const glm::vec<3, T> v(c.x - a.x, c.y - a.y, c.z - a.z);
    const T inv = T(1.0f) / sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    return {v.x * inv, v.y * inv, v.z * inv};
}

// Marches each pixel's view ray: eight (or sixteen) at a time the pipeline's wide path finds the rays
// and their stretches through the box together, then marches them one by one (their work differs:
// empty space skipped, rays that miss). The same bits as the scalar call, lane by lane.
struct PsMediaMarch {
    // Its draws' state (specialised_states.hpp).
    using SpecialisedStates = raster::SpecialisedStates<Specialise<DepthState::Off, BlendMode::Replace>>;
    using Input = MediaRayVertex;
    glm::mat4 invViewProj{1.0f};
    glm::vec3 eye{0.0f};
    const media::MetaballVolume* volume = nullptr;
    media::VolumeLight light;
    media::MarchSettings settings;
    glm::vec3 background{0.0f};  // L_bg, radiance behind the medium

    // Not inlined: the fill loops are flattened (pipeline_impl.hpp), and the march inlined into each
    // of their instantiations made scene_media_march.cpp a compile of minutes. A call per pixel is
    // nothing beside its march.
    [[gnu::noinline]] glm::vec4 shade(const glm::vec3& d, float t_near, float t_far) const {
        const media::MarchResult r =
            media::marchMetaballs(*volume, light, settings, eye, d, std::max(t_near, 0.0f), t_far);
        const glm::vec3 L = glm::clamp(r.radiance + r.transmittance * background, 0.0f, 1.0f);
        return {L, 1.0f};
    }

    template <class T>
    glm::vec<4, T> operator()(const MediaRayVertexT<T>& in) const {
        const glm::vec<3, T> d = viewRay(invViewProj, in.ndc);
        const auto [t_near, t_far] = media::slabInterval(volume->box, eye, d);
        if constexpr (std::is_same_v<T, float>) {
            return shade(d, t_near, t_far);
        } else {
            constexpr int kLanes = int(sizeof(T) / sizeof(float));
            alignas(64) float dx[kLanes], dy[kLanes], dz[kLanes], tn[kLanes], tf[kLanes], out[4][kLanes];
            d.x.store(dx), d.y.store(dy), d.z.store(dz), t_near.store(tn), t_far.store(tf);
            for (int l = 0; l < kLanes; ++l) {
                const glm::vec4 c = shade({dx[l], dy[l], dz[l]}, tn[l], tf[l]);
                for (int k = 0; k < 4; ++k) out[k][l] = c[k];
            }
            return {T::load(out[0]), T::load(out[1]), T::load(out[2]), T::load(out[3])};
        }
    }
};

}  // namespace raster::shaders
