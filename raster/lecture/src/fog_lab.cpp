// The stable-fog lab's scene, less its template (raster/labs/stable_fog.hpp): the panels' media and rays.
#include <cmath>

#include "raster/labs/stable_fog.hpp"

namespace raster::fog_lab {

std::vector<Medium> panelMedia(const SceneOptions& o) {
    const glm::vec3 grey{0.6f, 0.65f, 0.75f}, sand{0.85f, 0.55f, 0.25f};
    const glm::vec3 thin{0.035f, 0.04f, 0.05f}, dense(0.12f), height{0.06f, 0.07f, 0.09f};
    const float b = -o.fogFalloff.value_or(0.5f);
    return {{o.fogSigma.value_or(thin), o.fogSource.value_or(thin * grey), 0.0f, false},
            {o.fogSigma.value_or(thin), glm::vec3(0.0f), 0.0f, false},
            {o.fogSigma.value_or(dense), o.fogSource.value_or(dense * sand), 0.0f, false},
            {o.fogSigma.value_or(height), o.fogSource.value_or(height * grey), b, true}};
}

PanelRays panelRays(const SceneOptions& o, const SceneCamera& camera) {
    const float width = float(std::max(1u, o.width / 2)), height = float(std::max(1u, o.height / 2));
    const float tan_y = std::tan(glm::radians(o.fovDegrees.value_or(60.0f)) * 0.5f);
    PanelRays rays;
    rays.eye = camera.eye;
    rays.ahead = glm::normalize(camera.target - camera.eye);
    rays.right = glm::normalize(glm::cross(rays.ahead, glm::vec3(0, 1, 0)));
    rays.up = glm::cross(rays.right, rays.ahead) * tan_y;
    rays.right *= tan_y * width / height;
    rays.size = glm::vec2(width, height);
    return rays;
}

}  // namespace raster::fog_lab
