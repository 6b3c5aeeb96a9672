// The light of every single-scattering march (metaball_march.hpp, cloud_march.hpp, figure_march.hpp,
// scatter_march.hpp and the ray-marching lab through it): one directional or point light, plus
// isotropic ambient in-scattering, and what a point of the medium receives from it.
//
// Directional: the irradiance E = sun arrives along −toLight everywhere; a shadow ray from x runs
// along toLight to the medium's exit. Point: from `position`, radiant intensity I = intensity (per
// steradian, RGB), so the irradiance at x (facing the light, in a vacuum) is I/r², r = |position − x|
// (inverse-square falloff); a shadow ray from x runs along (position − x)/r and ends at the light
// (at r, or at the medium's exit if that comes first). Either way the phase function's angle is
// cos θ = d·l for a view ray d (from the eye) and l the unit vector from the sample towards the light:
// the light travels along −l and leaves towards the eye along −d, and phase_functions.hpp's cos θ is
// dot(travel, scattered) = (−l)·(−d), so g > 0 makes a light behind the medium (l ≈ d) shine through.
//
// Units: the march's (metres, or a cloud's voxels: a point light's intensity then per voxel², so that
// I/r² with r in voxels is the irradiance).
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>

namespace raster::media {

enum class LightKind : uint8_t { directional, point };

struct VolumeLight {
    glm::vec3 toLight{0.0f, 1.0f, 0.0f};  // directional: unit vector towards the light
    glm::vec3 sun{1.0f};                  // directional: irradiance E
    glm::vec3 ambient{0.0f};              // A: in-scattered radiance from all directions
    float g = 0.0f;                       // Henyey–Greenstein asymmetry (phase_functions.hpp)
    float albedo = 1.0f;                  // single-scattering albedo μs/μ
    LightKind kind = LightKind::directional;
    glm::vec3 position{0.0f};             // point: where the light is (the march's units)
    glm::vec3 intensity{0.0f};            // point: radiant intensity I, irradiance I/r² at distance r
};

// What a point x receives from the light: the unit direction towards it, how far the shadow ray may
// run (∞ for a directional light; r for a point light) and the irradiance before any medium on the
// way (E, or I/r²: +∞ at the light's own position, r = 0, where the direction is NaN).
struct LightAtPoint {
    glm::vec3 toLight;
    float distance;
    glm::vec3 irradiance;
};

inline LightAtPoint lightAt(const VolumeLight& light, const glm::vec3& x) {
    if (light.kind == LightKind::directional) return {light.toLight, INFINITY, light.sun};
    const glm::vec3 v = light.position - x;
    const float r2 = glm::dot(v, v), r = std::sqrt(r2);
    return {v / r, r, light.intensity / r2};
}

}  // namespace raster::media
