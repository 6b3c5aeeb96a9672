// BEGIN NOTE
// Lab: ray marching through a metaball medium (lecture, part 1: "Sugármenetelés") - THE SOLUTION.
//
// The benchmark scene `media` (six metaballs lit by a directional light with shadow rays, a
// Henyey–Greenstein phase function and an ambient term) marched back to front, as the lecture writes
// the recurrence, in two panels: left with the lecture's Euler step, right with the exponential step.
// This is labs/ray-marching/ray-marching.cpp with every `LAB n` place filled in; its image is the one
// the student's is compared with (raster view ray-marching, K and J).
// STAND-IN
//> // Lab: ray marching through a metaball medium (lecture, part 1: "Sugármenetelés").
//> //
//> // The benchmark scene `media` (six metaballs lit by a directional light with shadow rays, a
//> // Henyey–Greenstein phase function and an ambient term) marched back to front, as the lecture writes
//> // the recurrence, in two panels: left with the lecture's Euler step, right with the exponential step.
//> //
//> // As handed out, this file compiles and runs, but neither step moves the light, the phase function is
//> // isotropic, the medium is one ball of constant density and nothing casts a shadow: both panels show
//> // the background. Fill in the five places marked `LAB n`, in order (labs/ray-marching/README.md has
//> // the table):
//> //   LAB 1  eulerStep (left panel)        LAB 2  exponentialStep (right panel)
//> //   LAB 3  henyeyGreenstein              LAB 4  density (the six metaballs)
//> //   LAB 5  shadowTransmittance (the shadow ray)
//> // The grader also marches with few steps (large μ·Δs) and from another light direction.
//> //
//> //   cmake --build build-lab --target raster_tool && build-lab/bin/raster view ray-marching
//> //
//> // In the viewer, K shows the solution's image and J the difference; click a pixel for its history.
// END NOTE
//
// Options: --count N sets the view ray's steps (default 64); --seed S picks the light's direction
// (0: the `media` scene's, else a fixed direction of the upper hemisphere drawn from S).
#include <cmath>

#include "raster/labs/ray_marching.hpp"

namespace {

using namespace raster;
// Ball, Balls, Medium and boxInterval, the march that calls the functions below and the scene are the
// lab's scaffolding: raster/lecture/include/raster/labs/ray_marching.hpp.
using ray_lab::Balls;
using ray_lab::Ball;
using ray_lab::boxInterval;
using ray_lab::Medium;
using ray_lab::RayMarchingScene;

constexpr float kPi = 3.14159265358979f;

// ---- The integrator steps: dL/ds = −μ·L + q over one step of Δs, μ and q constant ----------------

// LAB 1: the lecture's forward Euler step, L + Δs·(q − μ·L).
// BEGIN LAB 1
// slide: euler-step
float eulerStep(float L, float mu, float q, float ds) {
    return L + ds * (q - mu * L);
}
// end slide: euler-step
// STAND-IN
//> // As handed out the step changes nothing: the left panel shows only the background.
//> float eulerStep(float L, float mu, float q, float ds) {
    //> (void)mu, (void)q, (void)ds;
    //> return L;
//> }
// END LAB 1

// BEGIN LAB 2
// slide: exponential-step
// LAB 2: the exponential step, exact for constant μ and q: L·e^{−μΔs} + (q/μ)·(1 − e^{−μΔs}), in a
// form that stays finite for μ → 0 (the limit L + q·Δs).
float exponentialStep(float L, float mu, float q, float ds) {
    const float x = mu * ds;
    if (x == 0.0f) return L + q * ds;
    return L * std::exp(-x) + q * ds * (-std::expm1(-x) / x);
}
// end slide: exponential-step
// STAND-IN
//> // LAB 2: the exponential step, exact for constant μ and q: L·e^{−μΔs} + (q/μ)·(1 − e^{−μΔs}), in a
//> // form that stays finite for μ → 0 (the limit L + q·Δs). It must stay right where μ·Δs is large.
//> // As handed out the step changes nothing: the right panel shows only the background.
//> float exponentialStep(float L, float mu, float q, float ds) {
    //> (void)mu, (void)q, (void)ds;
    //> return L;
//> }
// END LAB 2

// LAB 3: Henyey–Greenstein, per steradian: (1 − g²) / (4π·(1 + g² − 2g·cos θ)^{3/2}).
// BEGIN LAB 3
// slide: henyey-greenstein
float henyeyGreenstein(float g, float cos_theta) {
    const float base = 1.0f + g * g - 2.0f * g * cos_theta;
    return (1.0f - g * g) / (4.0f * kPi * base * std::sqrt(base));
}
// end slide: henyey-greenstein
// STAND-IN
//> // cos θ = d·l, the view ray's direction (from the eye) against the direction towards the light.
//> // (Check the exponent against the lecture's notes: the slide has an erratum.)
//> // As handed out it is isotropic, 1/(4π): the medium is as bright seen against the light as with it.
//> float henyeyGreenstein(float g, float cos_theta) {
    //> (void)g, (void)cos_theta;
    //> return 1.0f / (4.0f * kPi);
//> }
// END LAB 3

// LAB 4: the metaball density ρ(x) = Σ_k (1 − u_k)² over the balls with u_k = |x − c_k|²/r_k² < 1.
// BEGIN LAB 4
float density(const Balls& balls, const glm::vec3& x) {
    float rho = 0.0f;
    for (const Ball& ball : balls) {
        const glm::vec3 v = x - ball.centre;
        const float u = glm::dot(v, v) / (ball.radius * ball.radius);
        if (u < 1.0f) rho += (1.0f - u) * (1.0f - u);
    }
    return rho;
}
// STAND-IN
//> // As handed out: one ball of radius 0.8 m and density 1 in the middle of the box, the balls unused.
//> float density(const Balls& balls, const glm::vec3& x) {
    //> (void)balls;
    //> return glm::dot(x, x) < 0.64f ? 1.0f : 0.0f;
//> }
// END LAB 4

// ---- The medium and its light: Medium, boxInterval (raster/labs/ray_marching.hpp) -------------------

// LAB 5: the shadow ray: the transmittance e^{−τ} from x towards the light through the medium, τ the
// optical depth Σ μ_j·Δl over m.shadowSteps midpoint samples from x to where the ray leaves the box.
// BEGIN LAB 5
float shadowTransmittance(const Medium& m, const glm::vec3& x) {
    const float dl = boxInterval(m, x, m.toLight).second / float(m.shadowSteps);
    float tau = 0.0f;
    for (uint32_t j = 0; j < m.shadowSteps; ++j)
        tau += m.extinctionScale * density(m.balls, x + (float(j) + 0.5f) * dl * m.toLight) * dl;
    return std::exp(-tau);
}
// STAND-IN
//> // boxInterval(m, x, m.toLight).second is the distance to the box's side along the light.
//> // As handed out nothing casts a shadow: the medium is lit everywhere as on its sunny side.
//> float shadowTransmittance(const Medium& m, const glm::vec3& x) {
    //> (void)m, (void)x;
    //> return 1.0f;
//> }
// END LAB 5

// ---- The march that calls the functions above, and the scene (raster/labs/ray_marching.hpp) ------

class MarchLab final : public RayMarchingScene {
  public:
    explicit MarchLab(const SceneOptions& o)
        : RayMarchingScene(o, {eulerStep, exponentialStep, henyeyGreenstein, density, shadowTransmittance}) {}
};

}  // namespace

RASTER_LAB("ray-marching", "Lab: ray marching through a metaball medium (lecture, part 1)", MarchLab,
           ray_lab::kCamera)
