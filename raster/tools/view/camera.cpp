#include "camera.hpp"

#include <algorithm>
#include <cmath>

namespace raster::tools {
namespace {

constexpr float kRadiansPerPixel = 0.01f;
constexpr float kMaxPitch = 1.5f;      // radians, short of π/2
constexpr float kMinDistance = 1e-3f;  // the eye never reaches the target

}  // namespace

SceneCamera orbit(const SceneCamera& camera, float dx, float dy) {
    const glm::vec3 offset = camera.eye - camera.target;
    const float distance = std::max(glm::length(offset), kMinDistance);
    float yaw = std::atan2(offset.x, offset.z);
    float pitch = std::asin(std::clamp(offset.y / distance, -1.0f, 1.0f));
    // Dragging right swings the eye left about the target, so the scene turns with the mouse.
    yaw -= dx * kRadiansPerPixel;
    pitch = std::clamp(pitch + dy * kRadiansPerPixel, -kMaxPitch, kMaxPitch);
    const glm::vec3 direction(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                              std::cos(pitch) * std::cos(yaw));
    return {camera.target + distance * direction, camera.target};
}

SceneCamera zoom(const SceneCamera& camera, int notches) {
    const glm::vec3 offset = camera.eye - camera.target;
    const float distance = glm::length(offset);
    const float scaled = std::max(distance * std::pow(0.9f, float(notches)), kMinDistance);
    return {camera.target + offset * (scaled / distance), camera.target};
}

SceneCamera fly(const SceneCamera& camera, int forward, int right, int up) {
    const glm::vec3 view = camera.target - camera.eye;
    const float step = 0.05f * std::max(glm::length(view), kMinDistance);
    const glm::vec3 ahead = glm::normalize(view);
    const glm::vec3 up_axis(0, 1, 0);
    const glm::vec3 side = glm::normalize(glm::cross(ahead, up_axis));
    const glm::vec3 move = step * (float(forward) * ahead + float(right) * side + float(up) * up_axis);
    return {camera.eye + move, camera.target + move};
}

}  // namespace raster::tools
