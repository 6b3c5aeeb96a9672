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

// A template over its scalar type, so that a pixel shader reading it can run eight wide
// (shader.hpp's Wide).
template <class T>
struct PositionOnlyT {
    glm::vec<4, T> position;
};
using PositionOnly = PositionOnlyT<float>;

struct VsTransform {
    glm::mat4 viewProj{1.0f};
    PositionOnly operator()(const PositionIn& in) const { return {viewProj * glm::vec4(in.position, 1.0f)}; }
};

struct PsConstant {
    using Input = PositionOnly;
    glm::vec4 color{1.0f};
    template <class T>
    glm::vec<4, T> operator()(const PositionOnlyT<T>&) const {
        return glm::vec<4, T>(T(color.x), T(color.y), T(color.z), T(color.w));
    }
};

}  // namespace raster::shaders
