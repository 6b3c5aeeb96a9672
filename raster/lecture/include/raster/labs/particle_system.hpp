// The particle-system lab's scene (labs/particle-system/): everything but the student's four
// functions. The lab's file (and its solution, which fills the file's places) defines
//
//   void emit(Particle&, const Emitter&, const BirthRandom&)                          LAB 1
//   void live(Particle&, const Effectors&, float dt, const std::function<void(Particle&)>& rebirth)
//                                                                                     LAB 3 (LAB 2: move)
//   Look lookOverLife(float t)                                                        LAB 4
//
// and registers a scene made by ParticleSystemScene(options, {emit, live, lookOverLife}): the fountain
// (kFountain, kAir) that steps its sparks through those functions, the upload, the sparks drawn as
// additive billboards in front of the lecture's occluder and the side view's panel.
#pragma once

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "raster/lab.hpp"
#include "raster/particles.hpp"  // raster::Particle, the lecture's struct, and its input layout

namespace raster::particle_lab {

// The emitter: a horizontal disc (normal +y) and a cone of initial directions about +y.
struct Emitter {
    glm::vec3 centre;                // world units
    float radius;                    // world units
    float halfAngle;                 // radians: the cone of directions about +y
    float speedMin, speedMax;        // world units per second
    float lifespanMin, lifespanMax;  // seconds
    float sizeMin, sizeMax;          // world units: the billboard's half-width at birth
};

// The random numbers of one birth, each uniform in [0, 1): the lab draws them from the seed, the
// particle and how many times it has been born, so the fountain is the same for a seed on any machine
// and any number of threads.
struct BirthRandom {
    float radius, angle;  // where on the disc
    float cone, turn;     // which direction in the cone
    float speed, lifespan, size;
};

// The effectors, all constant over a step: dv/dt = gravity + buoyancy·(1 − t)·(0, 1, 0) +
// drag·(wind − v), t = age / lifespan at the step's start.
struct Effectors {
    glm::vec3 gravity;  // world units / s²
    float buoyancy;     // world units / s²: a spark's lift at birth, fading to 0 at its death
    glm::vec3 wind;     // world units / s: the air's velocity
    float drag;         // 1/s > 0: how fast a spark takes the air's velocity
};

// What a particle looks like at normalized age t = age / lifespan in [0, 1]: its billboard's
// half-width as a factor on its birth size, its colour and its opacity.
struct Look {
    float size;
    glm::vec3 colour;  // linear rgb
    float opacity;     // [0, 1]
};

// The student's functions, which the fountain calls.
struct Answers {
    void (*emit)(Particle&, const Emitter&, const BirthRandom&);
    void (*live)(Particle&, const Effectors&, float, const std::function<void(Particle&)>&);
    Look (*lookOverLife)(float);
};

inline constexpr double kStep = 1.0 / 60.0;      // seconds per simulation step (the clock's)
inline constexpr float kStepF = float(kStep);    // the same step, as the particles' float
inline constexpr double kDefaultTime = 3.0;      // seconds after the fountain is turned on
inline constexpr uint32_t kDefaultCount = 4000;  // particle slots

inline constexpr Emitter kFountain{{0.0f, -1.1f, 0.5f}, 0.1f, 0.4f, 5.5f, 6.5f, 1.2f, 2.0f, 0.03f, 0.05f};
inline constexpr Effectors kAir{{0.0f, -9.81f, 0.0f}, 3.0f, {2.0f, 0.0f, -0.4f}, 0.5f};

// A number in [0, 1) from a counter-based hash (SplitMix64's finaliser) of the seed, the particle,
// its birth and which number of that birth: independent of the order of the calls.
float random01(uint32_t seed, uint32_t particle, uint32_t birth, uint32_t which);
// The seven numbers of a particle's birth.
BirthRandom birthRandom(uint32_t seed, uint32_t particle, uint32_t birth);

// The sparks: `count` slots; slot i is first born after a wait of up to the longest lifespan (so that
// births spread over time), then lives, dies and is reborn by the answers, one fixed step at a time.
class Fountain {
  public:
    Fountain(uint32_t count, uint32_t seed, Answers answers);
    void step();
    // The upload (the lecture's Map(WRITE_DISCARD) + memcpy): the born particles, each with its look at
    // its normalized age, into `staging`; returns how many.
    size_t write(std::vector<Particle>& staging) const;

  private:
    Answers answers_;
    uint32_t seed_;
    std::vector<Particle> particles_;
    std::vector<uint32_t> births_;
    std::vector<float> wait_;  // seconds until the first birth
};

// The lab's scene: the fountain over the lecture's occluder and the side view (src/particle_lab.cpp).
// The clock's start (options' time, kDefaultTime unset) is simulated at construction.
class ParticleSystemScene : public LabScene {
  public:
    ParticleSystemScene(const SceneOptions& options, Answers answers);
    ~ParticleSystemScene() override;
    bool animated() const override { return true; }
    double time() const override;
    void render(Context& context, RenderTarget& color, DepthTarget& depth) override;

  protected:
    // The clock's rule (raster/scenes.hpp): whole steps of 1/60 s, one run once 1 − 10⁻⁴ of it is due.
    void advanceBy(double seconds) override;

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace raster::particle_lab
