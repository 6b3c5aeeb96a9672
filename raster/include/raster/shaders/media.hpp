// The lecture's ray marching as a pixel shader (NOTES.md part 1, "Sugármenetelés"; SCENES.md, "Scene
// media"): a full-screen triangle whose pixel shader marches the pixel's view ray through a medium
// (raster/media/metaball_march.hpp) and returns L + T·L_bg.
//
// The view ray: ndc interpolated at the pixel centre; P_near = invViewProj·(ndc, 0, 1) and
// P_far = invViewProj·(ndc, 1, 1) after the division by w; d = normalize(P_far − P_near), from the eye.
// A scalar shader: the march's work differs from pixel to pixel (empty space skipped, rays that miss
// the box), so eight lanes in lock step would wait for the slowest.
#pragma once

#include <algorithm>
#include <glm/glm.hpp>

#include "raster/input_layout.hpp"
#include "raster/media/metaball_march.hpp"
#include "raster/shader.hpp"

namespace raster::shaders {

struct MediaRayIn {
    glm::vec2 ndc;
    RASTER_INPUT_SIGNATURE(MediaRayIn, RASTER_INPUT(ndc, "POSITION", 0))
};

struct MediaRayVertex {
    glm::vec4 position;
    glm::vec2 ndc;
};

// The full-screen triangle: passes ndc on, linear across the screen.
struct VsMediaRay {
    MediaRayVertex operator()(const MediaRayIn& in) const { return {glm::vec4(in.ndc, 0.5f, 1.0f), in.ndc}; }
};

// The pixel's view ray, unit length (header).
inline glm::vec3 viewRay(const glm::mat4& inv_view_proj, const glm::vec2& ndc) {
    const glm::vec4 a = inv_view_proj * glm::vec4(ndc, 0.0f, 1.0f);
    const glm::vec4 c = inv_view_proj * glm::vec4(ndc, 1.0f, 1.0f);
    return glm::normalize(glm::vec3(c) / c.w - glm::vec3(a) / a.w);
}

struct PsMediaMarch {
    using Input = MediaRayVertex;
    glm::mat4 invViewProj{1.0f};
    glm::vec3 eye{0.0f};
    const media::MetaballVolume* volume = nullptr;
    media::VolumeLight light;
    media::MarchSettings settings;
    glm::vec3 background{0.0f};  // L_bg, radiance behind the medium

    glm::vec4 operator()(const MediaRayVertex& in) const {
        const media::MarchResult r = media::marchMetaballs(*volume, light, settings, eye, viewRay(invViewProj, in.ndc));
        const glm::vec3 L = glm::clamp(r.radiance + r.transmittance * background, 0.0f, 1.0f);
        return {L, 1.0f};
    }
};

}  // namespace raster::shaders
