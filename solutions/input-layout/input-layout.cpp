// BEGIN NOTE
// Lab: the input layout and the vertex shader (lecture 11, part 3) - THE SOLUTION.
//
// The lecture's particles reach the vertex shader through an input layout: one
// D3D11_INPUT_ELEMENT_DESC per field the shader reads, its offset taken with offsetof from the
// lecture's `Particle` struct, its format the field's type. This is
// labs/input-layout/input-layout.cpp with every `LAB n` place filled in; its image is the one the
// student's is compared with (raster view input-layout, K and J).
// STAND-IN
//> // Lab: the input layout and the vertex shader (lecture 11, part 3).
//> //
//> // The lecture's particles reach the vertex shader through an input layout: one
//> // D3D11_INPUT_ELEMENT_DESC per field the shader reads, its offset taken with offsetof from the
//> // lecture's `Particle` struct, its format the field's type. The vertex shader then takes each
//> // particle from world space to clip space.
//> //
//> // As handed out, this file compiles and runs but draws the fire flat, dim and in the wrong colours.
//> // Fill in the three places marked `LAB n`, in order; each one changes the picture:
//> //   LAB 1  the LIFESPAN and AGE elements: their byte offsets in Particle.
//> //   LAB 2  the COLOR element: its format and its byte offset.
//> //   LAB 3  the vertex shader's transform from world space to clip space.
//> //
//> //   cmake --build build --target raster_tool && build/bin/raster view input-layout
//> //
//> // In the viewer, K shows the solution's image and J the difference from it; click a pixel for its
//> // history. `raster trace input-layout --draw 1 --limit 5` prints what the input assembler fetched
//> // for the first particles. Look at labs/input-layout/README.md for what each step should show.
// END NOTE
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "raster/lab.hpp"

namespace {

using namespace raster;

// The lecture's `Particle`: its four fields in the lecture's order, then the colour and opacity its
// attribute list adds ("méret, szín, átlátszóság"). 12 floats, 48 bytes, no padding. (Not the
// library's raster::Particle, which orders age before lifespan and carries a size.)
struct Particle {
    glm::vec3 position;  // world units
    glm::vec3 velocity;  // world units per second
    float lifespan;      // seconds
    float age;           // seconds since birth, < lifespan while alive
    glm::vec4 colour;    // linear rgb, a = opacity
};
static_assert(sizeof(Particle) == 12 * sizeof(float), "Particle must have no padding");

// IaosParticle: what the vertex shader reads of a particle (the lecture's IaosBillboard, with the
// colour). The signature names each field's semantic: the layout's elements are matched to it by name.
struct ParticleIn {
    glm::vec3 position;
    float lifespan;
    float age;
    glm::vec4 colour;
    RASTER_INPUT_SIGNATURE(ParticleIn, RASTER_INPUT(position, "POSITION", 0),
                           RASTER_INPUT(lifespan, "LIFESPAN", 0), RASTER_INPUT(age, "AGE", 0),
                           RASTER_INPUT(colour, "COLOR", 0))
};

// VsosParticle: the particle in clip space with the colour it is drawn in.
struct ParticleVertex {
    glm::vec4 position;
    glm::vec4 colour;
};

constexpr auto kPerVertex = InputClassification::PerVertexData;

// The input layout, the lecture's particleElements[] with the colour added: per element its semantic,
// the format of the field it reads, slot 0, the field's offset in Particle, per-vertex data.
// slide: input-elements
const InputElementDesc kParticleElements[] = {
    // The lecture's particleElements[0], written out: the position, three floats at the start.
    {"POSITION", 0, Format::R32G32B32_FLOAT, 0, offsetof(Particle, position), kPerVertex, 0},
    // BEGIN LAB 1
    // LAB 1: LIFESPAN and AGE, one float each, at their own offsets.
    {"LIFESPAN", 0, Format::R32_FLOAT, 0, offsetof(Particle, lifespan), kPerVertex, 0},
    {"AGE", 0, Format::R32_FLOAT, 0, offsetof(Particle, age), kPerVertex, 0},
    // STAND-IN
    //> // LAB 1: each of LIFESPAN and AGE reads one float (R32_FLOAT); give each its byte offset in
    //> // Particle with offsetof, as POSITION does. Where do they lie, with velocity in between?
    //> // As handed out both read the first float of the struct (position.x): every particle's
    //> // age / lifespan is 1, so every particle is drawn as old and dim.
    //> {"LIFESPAN", 0, Format::R32_FLOAT, 0, 0, kPerVertex, 0},
    //> {"AGE", 0, Format::R32_FLOAT, 0, 0, kPerVertex, 0},
    // END LAB 1
    // BEGIN LAB 2
    // LAB 2: COLOR, four floats (the opacity is the fourth).
    {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, offsetof(Particle, colour), kPerVertex, 0},
    // STAND-IN
    //> // LAB 2: COLOR feeds ParticleIn::colour, a glm::vec4 (rgb and opacity): which format holds four
    //> // floats, and at which offset does Particle keep them?
    //> // As handed out it reads three floats at offset 0, the position, and the shader's colour.a is
    //> // the default 1 that the input assembler fills in for a missing fourth component.
    //> {"COLOR", 0, Format::R32G32B32_FLOAT, 0, 0, kPerVertex, 0},
    // END LAB 2
};
// end slide: input-elements

// vsParticle: each particle is one point, drawn one pixel large.
struct VsParticle {
    glm::mat4 viewProj{1.0f};

    ParticleVertex operator()(const ParticleIn& in) const {
        // BEGIN LAB 3
        // LAB 3: world space to clip space (a position is a point: w = 1).
        const glm::vec4 clip = viewProj * glm::vec4(in.position, 1.0f);
        // STAND-IN
        //> // LAB 3: take the position from world space to clip space with viewProj (a position is a
        //> // point: w = 1). As handed out it is passed on untransformed: world x and y are stretched
        //> // over the screen, and the particles with world z < 0 or y < -1 are clipped.
        //> const glm::vec4 clip = glm::vec4(in.position, 1.0f);
        // END LAB 3
        // Normalized age t in [0, 1] (a lifespan <= 0 counts as dead); a particle dims to half its
        // colour, times its opacity, over its life.
        const float t = in.lifespan > 0.0f ? std::clamp(in.age / in.lifespan, 0.0f, 1.0f) : 1.0f;
        const glm::vec3 rgb = glm::vec3(in.colour) * (in.colour.a * (1.0f - 0.5f * t));
        return {clip, glm::vec4(rgb, 1.0f)};
    }
};

struct PsParticle {
    glm::vec4 operator()(const ParticleVertex& in) const { return in.colour; }
};

// ---- The fire: the lecture's particle system on the CPU (no LAB place below) ----------------------

constexpr float kStep = 1.0f / 60.0f;  // seconds per simulation step
constexpr int kSteps = 180;            // 3 s: every particle has been born (its delay is at most 2.5 s)

// A random number in [0, 1) from a counter-based hash (SplitMix64's finaliser) of the seed, the
// particle, its birth and which number of that birth: the fire is a function of the seed and the
// count alone, whatever the machine's threads or the order of the calls.
float random01(uint32_t seed, uint32_t particle, uint32_t birth, uint32_t which) {
    uint64_t h = ((uint64_t(seed) << 32) | particle) * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t(birth) << 8) | which;
    h ^= h >> 30, h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27, h *= 0x94D049BB133111EBull;
    h ^= h >> 31;
    return float(h >> 40) * 0x1p-24f;
}

// The lecture's Particle::reborn: at the emitter, a disc of radius 0.8 under the occluder, rising at
// 0.2 to 0.6 units per second within a cone, living 1.5 to 2.5 s, yellow to red, opacity 0.4 to 1.
void reborn(Particle& p, uint32_t seed, uint32_t index, uint32_t birth) {
    const auto random = [&](uint32_t which) { return random01(seed, index, birth, which); };
    float x = 0.0f, z = 0.0f;
    for (uint32_t attempt = 0; attempt < 8; ++attempt) {  // the first point of the square in the disc
        const float u = 2.0f * random(2 * attempt) - 1.0f, v = 2.0f * random(2 * attempt + 1) - 1.0f;
        if (u * u + v * v <= 1.0f) {
            x = u, z = v;
            break;
        }
    }
    p.position = {0.8f * x, -1.2f, 0.8f * z};
    const float speed = 0.2f + 0.4f * random(16);
    p.velocity = speed * glm::vec3(0.8f * (random(17) - 0.5f), 1.0f, 0.8f * (random(18) - 0.5f));
    p.lifespan = 1.5f + random(19);
    p.age = 0.0f;
    const float heat = random(20);
    p.colour = {1.0f, 0.3f + 0.55f * heat, 0.05f + 0.35f * heat, 0.4f + 0.6f * random(21)};
}

// The lecture's Particle::move: buoyancy lifts (0.6 units/s²), drag slows (0.5/s), a swirl turns the
// particle about the vertical axis and pulls it in; then position += velocity·dt, age += dt.
void move(Particle& p, float dt) {
    const glm::vec3 flat(p.position.x, 0.0f, p.position.z);
    const glm::vec3 swirl = 1.5f * glm::vec3(-flat.z, 0.0f, flat.x) - 0.5f * flat;
    p.velocity += (glm::vec3(0.0f, 0.6f, 0.0f) + swirl - 0.5f * p.velocity) * dt;
    p.position += p.velocity * dt;
    p.age += dt;
}

// `count` particles after kSteps steps: each is first born after a delay of up to 2.5 s (a negative
// age counts it down), so that births spread over time, and reborn whenever its age passes its lifespan.
std::vector<Particle> simulateFire(uint32_t count, uint32_t seed) {
    std::vector<Particle> particles(count);
    std::vector<uint32_t> births(count, 0);
    for (uint32_t i = 0; i < count; ++i) {
        reborn(particles[i], seed, i, 0);
        particles[i].age = -2.5f * random01(seed, i, 0, 22);
    }
    for (int step = 0; step < kSteps; ++step) {
        for (uint32_t i = 0; i < count; ++i) {
            Particle& p = particles[i];
            if (p.age < 0.0f) {
                p.age += kStep;
                continue;
            }
            move(p, kStep);
            if (p.age > p.lifespan) reborn(p, seed, i, ++births[i]);
        }
    }
    return particles;
}

class InputLayoutLab final : public LabScene {
  public:
    explicit InputLayoutLab(const SceneOptions& o) : data_(o), layout_(kParticleElements) {
        vs_.viewProj = data_.viewProj;
        particles_ = simulateFire(o.count.value_or(kDefaultParticleCount), o.seed);
        // The upload: the lecture's Map(WRITE_DISCARD) + memcpy of std::vector<Particle>.
        buffer_ = VertexBuffer::create(std::span<const Particle>(particles_));
    }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);  // clear, bind, viewport, no culling
        data_.drawOccluder(context);             // draw 0: the occluder, opaque, depth test and write
        // Draw 1: the particles, one point each, opaque, depth tested and written.
        context.setInputLayout(&layout_);
        context.setVertexBuffer(0, &buffer_);
        context.setPrimitiveTopology(Topology::PointList);
        context.draw(vs_, PsParticle{}, uint32_t(particles_.size()));
    }

  private:
    ParticleSceneData data_;  // the occluder and the camera of SCENES.md's particle scene
    InputLayout layout_;
    std::vector<Particle> particles_;
    VertexBuffer buffer_;
    VsParticle vs_;
};

}  // namespace

RASTER_LAB("input-layout", "Lab: the input layout and the vertex shader (lecture 11, part 3)", InputLayoutLab,
           defaultCamera("particles"))
