// Small shaders the scenes and tests share: a world-space position transformed by a matrix, and a
// constant colour.
#pragma once

#include <glm/glm.hpp>

#include "raster/input_layout.hpp"
#include "raster/shader.hpp"

namespace raster::shaders {

struct PositionIn {
    glm::vec3 position;
    RASTER_INPUT_SIGNATURE(PositionIn, RASTER_INPUT(position, "POSITION", 0))
};

struct PositionOnly {
    glm::vec4 position;
};

struct VsTransform {
    glm::mat4 viewProj{1.0f};
    PositionOnly operator()(const PositionIn& in) const { return {viewProj * glm::vec4(in.position, 1.0f)}; }
};

struct PsConstant {
    glm::vec4 color{1.0f};
    glm::vec4 operator()(const PositionOnly&) const { return color; }
};

}  // namespace raster::shaders
