// Lab: a particle system - emitter, effectors, life cycle, upload (lecture 11, part 3).
//
// A fountain of sparks in front of the lecture's occluder: a disc emitter shoots sparks up in a cone;
// gravity, a buoyant lift that fades as a spark cools, and drag toward a wind move them; each ages,
// dies and is born again at the emitter; its size, colour and opacity follow its life. Each frame the
// sparks are uploaded into a vertex buffer and drawn as additive camera-facing billboards, and a
// panel in the lower right corner shows the simulation's state from the side: one point per spark,
// orthographic, so that where the sparks are can be read off without the billboards' glow. Fill in
// the places marked `LAB 1` to `LAB 4`, in that order (labs/particle-system/README.md says what each
// changes in the picture); `raster view particle-system`, then K and J, compares yours with the
// solution's.
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
    // As handed out: every particle at the disc's centre, standing still, living as long as the
    // longest, at the smallest size.
    p.position = e.centre;
    p.velocity = glm::vec3(0.0f);
    p.lifespan = e.lifespanMax;
    p.age = 0.0f;
    p.size = e.sizeMin;
    (void)r;
}

// LAB 2: the effectors, one step of dt seconds, solved exactly. With the acceleration a = gravity +
// lift constant over the step, dv/dt = a + k·(w − v) relaxes v toward the terminal velocity
// u = w + a/k: v(dt) = u + (v₀ − u)·e^(−k·dt), and its integral moves the particle by
// u·dt + (v₀ − u)·(1 − e^(−k·dt))/k. (Explicit Euler, v += dv/dt·dt and x += v₀·dt, is off by about
// ½·a·dt per second of flight: 8 cm of a spark's 1.5 s.)
void move(Particle& p, const Effectors& e, float dt) {
    // As handed out: nothing moves.
    (void)p, (void)e, (void)dt;
}

// LAB 3: the life cycle, one step: the particle moves (at its age at the step's start), then ages by
// dt; once its age reaches its lifespan it dies and `rebirth` gives it its next birth at the emitter
// (emit with that birth's random numbers).
void live(Particle& p, const Effectors& e, float dt, const std::function<void(Particle&)>& rebirth) {
    // As handed out: the particle moves but never ages, so it never dies and is never reborn.
    move(p, e, dt);
    (void)rebirth;
}

// LAB 4: size, colour and opacity over life. A spark is born white-hot, (1.2, 1.3, 3) (a tint on the
// orange fire texture: above 1 makes it white), is orange, (1, 0.6, 0.5), at t = 0.3 and a dark red
// ember, (0.7, 0.12, 0.05), at its death, linearly between those keys; its opacity fades linearly
// from 1 to 0 and it shrinks linearly to half its birth size.
Look lookOverLife(float t) {
    // As handed out: white, opaque and full size all its life.
    (void)t;
    return {1.0f, glm::vec3(1.0f), 1.0f};
}

// ---- The fountain, the upload and the drawing (raster/labs/particle_system.hpp) ------------------

class ParticleSystemLab final : public ParticleSystemScene {
  public:
    explicit ParticleSystemLab(const SceneOptions& o) : ParticleSystemScene(o, {emit, live, lookOverLife}) {}
};

}  // namespace

RASTER_LAB("particle-system", "Lab: a particle system - emitter, effectors, life cycle (lecture 11, part 3)",
           ParticleSystemLab, defaultCamera("particles"))
