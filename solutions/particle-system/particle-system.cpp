// BEGIN NOTE
// Lab: a particle system - emitter, effectors, life cycle, upload (lecture 11, part 3) - THE SOLUTION.
//
// A fountain of sparks in front of the lecture's occluder: a disc emitter shoots sparks up in a cone;
// gravity, a buoyant lift that fades as a spark cools, and drag toward a wind move them; each ages,
// dies and is born again at the emitter; its size, colour and opacity follow its life. Each frame the
// sparks are uploaded into a vertex buffer and drawn as additive camera-facing billboards, and a
// panel in the lower right corner shows the simulation's state from the side: one point per spark,
// orthographic, so that where the sparks are can be read off without the billboards' glow. This is
// labs/particle-system/particle-system.cpp with every `LAB n` place filled in; its image is the one
// the student's is compared with (raster view particle-system, K and J).
// STAND-IN
//> // Lab: a particle system - emitter, effectors, life cycle, upload (lecture 11, part 3).
//> //
//> // A fountain of sparks in front of the lecture's occluder: a disc emitter shoots sparks up in a cone;
//> // gravity, a buoyant lift that fades as a spark cools, and drag toward a wind move them; each ages,
//> // dies and is born again at the emitter; its size, colour and opacity follow its life. Each frame the
//> // sparks are uploaded into a vertex buffer and drawn as additive camera-facing billboards, and a
//> // panel in the lower right corner shows the simulation's state from the side: one point per spark,
//> // orthographic, so that where the sparks are can be read off without the billboards' glow. Fill in
//> // the places marked `LAB 1` to `LAB 4`, in that order (labs/particle-system/README.md says what each
//> // changes in the picture); `raster view particle-system`, then K and J, compares yours with the
//> // solution's.
// END NOTE
#include <algorithm>
#include <cmath>
#include <functional>

#include "raster/labs/particle_system.hpp"

namespace {

using namespace raster;

constexpr float kPi = 3.14159265358979f;

// Emitter, BirthRandom, Effectors and Look, the fountain that calls the functions below and the
// drawing are the lab's scaffolding: raster/lecture/include/raster/labs/particle_system.hpp.
using particle_lab::BirthRandom;
using particle_lab::Effectors;
using particle_lab::Emitter;
using particle_lab::Look;
using particle_lab::ParticleSystemScene;

// LAB 1: the emitter. Position uniform over the disc's area (a radius of radius·sqrt(u), not
// radius·u, which would crowd the centre); direction uniform over the cone's solid angle (cos θ
// uniform in [cos halfAngle, 1]); speed, lifespan and size uniform in their ranges; age 0.
void emit(Particle& p, const Emitter& e, const BirthRandom& r) {
    // BEGIN LAB 1
    const float rho = e.radius * std::sqrt(r.radius), phi = 2.0f * kPi * r.angle;
    p.position = e.centre + glm::vec3(rho * std::cos(phi), 0.0f, rho * std::sin(phi));
    const float cos_theta = 1.0f - r.cone * (1.0f - std::cos(e.halfAngle));
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float psi = 2.0f * kPi * r.turn;
    const glm::vec3 direction(sin_theta * std::cos(psi), cos_theta, sin_theta * std::sin(psi));
    p.velocity = direction * (e.speedMin + (e.speedMax - e.speedMin) * r.speed);
    p.lifespan = e.lifespanMin + (e.lifespanMax - e.lifespanMin) * r.lifespan;
    p.age = 0.0f;
    p.size = e.sizeMin + (e.sizeMax - e.sizeMin) * r.size;
    // STAND-IN
    //> // As handed out: every particle at the disc's centre, standing still, living as long as the
    //> // longest, at the smallest size.
    //> p.position = e.centre;
    //> p.velocity = glm::vec3(0.0f);
    //> p.lifespan = e.lifespanMax;
    //> p.age = 0.0f;
    //> p.size = e.sizeMin;
    //> (void)r;
    // END LAB 1
}

// LAB 2: the effectors, one step of dt seconds, solved exactly. With the acceleration a = gravity +
// lift constant over the step, dv/dt = a + k·(w − v) relaxes v toward the terminal velocity
// u = w + a/k: v(dt) = u + (v₀ − u)·e^(−k·dt), and its integral moves the particle by
// u·dt + (v₀ − u)·(1 − e^(−k·dt))/k. (Explicit Euler, v += dv/dt·dt and x += v₀·dt, is off by about
// ½·a·dt per second of flight: 8 cm of a spark's 1.5 s.)
void move(Particle& p, const Effectors& e, float dt) {
    // BEGIN LAB 2
    // slide: effectors
    const float heat = 1.0f - std::clamp(p.age / p.lifespan, 0.0f, 1.0f);
    const glm::vec3 a = e.gravity + glm::vec3(0.0f, e.buoyancy * heat, 0.0f);
    const glm::vec3 terminal = e.wind + a / e.drag;
    const float decay = std::exp(-e.drag * dt);
    const glm::vec3 v0 = p.velocity;
    p.velocity = terminal + (v0 - terminal) * decay;
    p.position += terminal * dt + (v0 - terminal) * ((1.0f - decay) / e.drag);
    // end slide: effectors
    // STAND-IN
    //> // As handed out: nothing moves.
    //> (void)p, (void)e, (void)dt;
    // END LAB 2
}

// LAB 3: the life cycle, one step: the particle moves (at its age at the step's start), then ages by
// dt; once its age reaches its lifespan it dies and `rebirth` gives it its next birth at the emitter
// (emit with that birth's random numbers).
void live(Particle& p, const Effectors& e, float dt, const std::function<void(Particle&)>& rebirth) {
    // BEGIN LAB 3
    // slide: life-cycle
    move(p, e, dt);
    p.age += dt;
    if (p.age >= p.lifespan) rebirth(p);
    // end slide: life-cycle
    // STAND-IN
    //> // As handed out: the particle moves but never ages, so it never dies and is never reborn.
    //> move(p, e, dt);
    //> (void)rebirth;
    // END LAB 3
}

// LAB 4: size, colour and opacity over life. A spark is born white-hot, (1.2, 1.3, 3) (a tint on the
// orange fire texture: above 1 makes it white), is orange, (1, 0.6, 0.5), at t = 0.3 and a dark red
// ember, (0.7, 0.12, 0.05), at its death, linearly between those keys; its opacity fades linearly
// from 1 to 0 and it shrinks linearly to half its birth size.
Look lookOverLife(float t) {
    // BEGIN LAB 4
    const glm::vec3 hot(1.2f, 1.3f, 3.0f), orange(1.0f, 0.6f, 0.5f), ember(0.7f, 0.12f, 0.05f);
    const glm::vec3 colour =
        t < 0.3f ? glm::mix(hot, orange, t / 0.3f) : glm::mix(orange, ember, (t - 0.3f) / 0.7f);
    return {1.0f - 0.5f * t, colour, 1.0f - t};
    // STAND-IN
    //> // As handed out: white, opaque and full size all its life.
    //> (void)t;
    //> return {1.0f, glm::vec3(1.0f), 1.0f};
    // END LAB 4
}

// ---- The fountain, the upload and the drawing (raster/labs/particle_system.hpp) ------------------

class ParticleSystemLab final : public ParticleSystemScene {
  public:
    explicit ParticleSystemLab(const SceneOptions& o) : ParticleSystemScene(o, {emit, live, lookOverLife}) {}
};

}  // namespace

RASTER_LAB("particle-system", "Lab: a particle system - emitter, effectors, life cycle (lecture 11, part 3)",
           ParticleSystemLab, defaultCamera("particles"))
