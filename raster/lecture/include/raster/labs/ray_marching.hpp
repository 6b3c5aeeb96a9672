// The ray-marching lab's scene (labs/ray-marching/): everything but the student's five functions. The
// lab's file (and its solution, which fills the file's places) defines
//
//   float eulerStep(float L, float mu, float q, float ds)                 LAB 1
//   float exponentialStep(float L, float mu, float q, float ds)           LAB 2
//   float henyeyGreenstein(float g, float cos_theta)                      LAB 3
//   float density(const Balls& balls, const glm::vec3& x)                 LAB 4
//   float shadowTransmittance(const Medium& m, const glm::vec3& x)        LAB 5
//
// and registers a scene made by RayMarchingScene(options, {those five}): each pixel's view ray marched
// back to front through the metaball medium (march below), the left half of the image by eulerStep,
// the right half by exponentialStep, over the background.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <utility>

#include "raster/lab.hpp"

namespace raster::ray_lab {

struct Ball {
    glm::vec3 centre{0.0f};
    float radius = 1.0f;
};
using Balls = std::array<Ball, 6>;

// The medium and its light.
struct Medium {
    Balls balls{};
    glm::vec3 lo{-1.2f, -0.8f, -1.2f}, hi{1.2f, 1.2f, 1.2f};  // the box of medium, metres
    float extinctionScale = 4.0f;                             // μ = 4·ρ, 1/m
    glm::vec3 toLight{0.0f, 1.0f, 0.0f};                      // unit, towards the light
    glm::vec3 sun{14.0f, 13.0f, 11.0f}, ambient{0.10f, 0.12f, 0.18f};
    float g = 0.4f, albedo = 0.9f;
    uint32_t steps = 64, shadowSteps = 6;
};

// The ray o + t·d meets the box for t in [first, second] (first > second where it misses).
std::pair<float, float> boxInterval(const Medium& m, const glm::vec3& o, const glm::vec3& d);

// The student's functions, which march calls.
struct Answers {
    float (*eulerStep)(float L, float mu, float q, float ds);
    float (*exponentialStep)(float L, float mu, float q, float ds);
    float (*henyeyGreenstein)(float g, float cos_theta);
    float (*density)(const Balls& balls, const glm::vec3& x);
    float (*shadowTransmittance)(const Medium& m, const glm::vec3& x);
};

// The radiance reaching the eye along the unit d: m.steps steps back to front from the box's far side
// (background L) to its near side, each sampled at its midpoint, with source
// q = μ·albedo·(p·T_l·sun + ambient), p the phase function at the angle to the light and T_l the
// shadow ray's transmittance; eulerStep where `euler`, else exponentialStep.
glm::vec3 march(const Answers& answers, const Medium& m, const glm::vec3& eye, const glm::vec3& d,
                glm::vec3 L, bool euler);

// The `media` scene's six balls (SCENES.md): c_j = frac(0.5 + (k+1)·a_j), centre
// ((2c1−1)·0.7, (2c2−1)·0.45 + 0.2, (2c3−1)·0.7), radius 0.35 + 0.3·c3.
Balls sceneBalls();
// Seed 0: the `media` scene's light; else a direction of the upper hemisphere (y ≥ 0.2) from the seed.
glm::vec3 lightDirection(uint32_t seed);

inline constexpr SceneCamera kCamera{{0.0f, 0.6f, 3.6f}, {0.0f, 0.1f, 0.0f}};

// The lab's scene: one triangle over the image, each pixel's ray marched through its panel (left:
// Euler, right: exponential). --count N: the view ray's steps (default 64); --seed S: the light.
class RayMarchingScene : public LabScene {
  public:
    RayMarchingScene(const SceneOptions& options, Answers answers);
    void render(Context& context, RenderTarget& color, DepthTarget& depth) override;

  private:
    Answers answers_;
    Medium medium_;
    glm::vec3 eye_{0.0f}, ahead_{0.0f, 0.0f, -1.0f}, right_{1.0f, 0.0f, 0.0f}, up_{0.0f, 1.0f, 0.0f};
    glm::vec2 panel_{1.0f};  // one panel's size, pixels
    VertexBuffer triangle_;
    InputLayout layout_;
};

}  // namespace raster::ray_lab
