// The lecture's `Particle` in its own order (position, velocity, lifespan, age) with the colour the
// input-layout lab adds after it, 48 bytes, and the vertex shader input that lab reads from it: what
// the tests match layouts against outside the lab's file (labs_test, particles_test).
#pragma once

#include <glm/glm.hpp>

#include "raster/input_layout.hpp"

namespace raster::test {

struct LectureParticle {
    glm::vec3 position, velocity;
    float lifespan, age;
    glm::vec4 colour;
};
static_assert(sizeof(LectureParticle) == 48, "the lecture's particle with its colour has no padding");

struct LectureParticleIn {
    glm::vec3 position;
    float lifespan, age;
    glm::vec4 colour;
    RASTER_INPUT_SIGNATURE(LectureParticleIn, RASTER_INPUT(position, "POSITION", 0),
                           RASTER_INPUT(lifespan, "LIFESPAN", 0), RASTER_INPUT(age, "AGE", 0),
                           RASTER_INPUT(colour, "COLOR", 0))
};

}  // namespace raster::test
