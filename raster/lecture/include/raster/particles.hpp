// A particle system on the CPU (lecture 11, part 3): emitters give birth to particles, effectors move
// them, they age and die, their slots are reused, and each frame the living ones are written into a
// vertex buffer as the lecture's `Particle` struct (Map(WRITE_DISCARD) + memcpy), for the billboard
// shaders to draw.
//
//   raster::ParticleSystemDesc desc;
//   desc.maxParticles = 20000;
//   desc.seed = 7;
//   raster::Emitter fire = raster::Emitter::disc({0, 0, 0}, {0, 1, 0}, 0.5f);
//   fire.rate = 4000;                                   // particles per second
//   fire.velocity = {{0, 1, 0}, 0.3f, 0.5f, 1.0f};      // axis, half-angle (rad), speed min/max (m/s)
//   fire.colourOverLife = raster::ColourGradient{{0, {1, 0.9f, 0.5f}}, {1, {0.6f, 0.1f, 0}}};
//   desc.emitters = {fire};
//   desc.effectors = {raster::Buoyancy{{0, 1, 0}, 2.0f, 0.2f}, raster::Turbulence{0.8f, 1.5f}};
//   raster::ParticleSystem system(desc, &pool);         // pool: optional raster::ThreadPool*
//   each frame:  system.advance(frame_seconds);          // whole fixed steps, the rest carried over
//                std::vector<raster::Particle> vertices(system.aliveCount());
//                system.writeVertices(vertices);         // then VertexBuffer::update(vertices)
//
// Units: positions in world units (metres in the lecture's scenes), time in seconds, velocities in
// world units per second, accelerations in world units per second², rates in 1/s.
//
// The rules, and why:
//  - A fixed time step (ParticleSystemDesc::timeStep). advance(frameSeconds) runs the whole steps
//    that fit and carries the rest to the next frame, so the motion does not depend on the frame
//    rate (Gaffer on Games, "Fix your timestep!"): 60 frames of 1/60 s and 30 of 1/30 s give the
//    same state, bit for bit.
//  - Deterministic: the same desc (seed included) and the same steps give bit-identical state for any
//    thread count. Random numbers come from a counter-based hash of (seed, emitter, emission index,
//    which number), never from a shared sequential generator, so no result depends on which thread
//    ran first; particles are processed in fixed blocks of kParticleBlock slots whatever the pool's
//    size; emission and slot reuse run in one fixed order on the calling thread. (Across machines
//    or compilers the bits may differ: birth uses the C library's sin, cos, cbrt and exp.)
//  - Structure of arrays inside (one std::vector<float> per component: the effectors' loops read
//    and write only what they need, and vectorise), the lecture's struct only at the upload.
//  - Integration: each effector in the list changes the velocity in turn (v₀ → v₁), then
//    position += ½(v₀ + v₁)·dt. That is exact for a constant acceleration (gravity, buoyancy without
//    cooling: position += v₀·dt + ½·g·dt², the parabola to float rounding), and velocity-only
//    effectors use their exact solution over a step (drag: v·exp(−k·dt), so v(t) = v₀·exp(−k·t)
//    for any dt). Position-dependent effectors (attractor, vortex, turbulence) are taken at the
//    step's start position: an explicit first-order step, not a symplectic one, so keep their time
//    scales (an orbit, a swirl, an eddy's crossing) well above the step.
//  - Life: a particle is born with age 0 at its birth time, which may fall inside a step (continuous
//    emission spreads births over the step); at the end of that step it has aged by what remains of
//    the step and moved that long along its initial velocity, so a fast stream has no gaps or
//    clumps. It dies at the end of the step in which age ≥ lifespan; its slot is then free and the
//    next birth reuses it (a stack: the most recently freed first). Colour, opacity and size follow
//    the emitter's curves over normalized age t = age / lifespan ∈ [0, 1], evaluated at the upload.
//  - Every parameter is checked when given (constructor, setEmitter, setEffectors, advance): a NaN,
//    an infinity, a negative rate or a lifespan ≤ 0 throws Error(InvalidArgument) naming it, e.g.
//    "emitters[1].lifespanMin is 0: must be > 0 (seconds)". Valid parameters never produce a NaN
//    (dead slots included), as long as the motion they ask for stays within float range.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <span>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "raster/input_layout.hpp"

namespace raster {

class ThreadPool;

// ---- The lecture's particle, as the vertex buffer holds it ------------------------------------------
// 13 floats, 52 bytes, no padding. The lecture's `Particle` (position, velocity, age, lifespan) plus
// what the billboards need to look like fire: size and colour with opacity.
struct Particle {
    glm::vec3 position{0.0f};  // world units
    glm::vec3 velocity{0.0f};  // world units per second
    float age = 0.0f;          // seconds since birth
    float lifespan = 1.0f;     // seconds; dead once age >= lifespan
    float size = 1.0f;         // world units: the billboard's half-width (gsBillboard's ±billboardSize)
    glm::vec4 colour{1.0f};    // linear rgb, a = opacity in [0, 1] as the emitter's curves give them
};
static_assert(sizeof(Particle) == 13 * sizeof(float), "Particle must have no padding");

// The input layout of a vertex buffer of Particles (D3D11_INPUT_ELEMENT_DESC[], offsets from offsetof,
// slot 0, per vertex): POSITION, VELOCITY (float3), AGE, LIFESPAN, SIZE (float), COLOR (float4).
inline std::array<InputElementDesc, 6> particleInputLayout() {
    constexpr auto kPerVertex = InputClassification::PerVertexData;
    return {{
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(Particle, position)), kPerVertex, 0},
        {"VELOCITY", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(Particle, velocity)), kPerVertex, 0},
        {"AGE", 0, Format::R32_FLOAT, 0, uint32_t(offsetof(Particle, age)), kPerVertex, 0},
        {"LIFESPAN", 0, Format::R32_FLOAT, 0, uint32_t(offsetof(Particle, lifespan)), kPerVertex, 0},
        {"SIZE", 0, Format::R32_FLOAT, 0, uint32_t(offsetof(Particle, size)), kPerVertex, 0},
        {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, uint32_t(offsetof(Particle, colour)), kPerVertex, 0},
    }};
}

// ---- Curves over a particle's life ------------------------------------------------------------------
// A piecewise-linear function of normalized age t ∈ [0, 1], given by keys (t, value) with t strictly
// increasing inside [0, 1]. Before the first key it holds the first value, after the last the last.
// At a key it returns that key's value exactly; between keys a and b it returns
// value_a·(1 − s) + value_b·s with s = (t − t_a) / (t_b − t_a). One key (or the constant
// constructor) is a constant. Keys are checked when the curve is made: Error(InvalidArgument).
template <class T>
class PiecewiseLinear {
public:
    struct Key {
        float t;
        T value;
    };
    PiecewiseLinear(T constant = T(1.0f)) : keys_{{0.0f, constant}} {}
    PiecewiseLinear(std::initializer_list<Key> keys) : PiecewiseLinear(std::vector<Key>(keys)) {}
    explicit PiecewiseLinear(std::vector<Key> keys);

    T operator()(float t) const;
    const std::vector<Key>& keys() const { return keys_; }

private:
    std::vector<Key> keys_;
};
using Curve = PiecewiseLinear<float>;         // size (a factor on the particle's birth size), opacity
// (Not `Gradient`: raster::Gradient<T> is a pixel's screen-space derivatives, shader_context.hpp,
// which every header of the pipeline includes.)
using ColourGradient = PiecewiseLinear<glm::vec3>;  // colour, linear rgb
extern template class PiecewiseLinear<float>;
extern template class PiecewiseLinear<glm::vec3>;

// ---- Emitters ---------------------------------------------------------------------------------------
enum class EmitterShape : uint8_t {
    Point,   // at `centre`
    Line,    // uniform on the segment centre → end
    Disc,    // uniform over the disc's area: `centre`, `normal`, `radius` (the "plane" emitter)
    Box,     // uniform in the box `centre` ± `halfExtents` (one extent 0: a uniform rectangle)
    Sphere,  // uniform in the ball's volume: `centre`, `radius`
};

// Initial velocities: directions uniform over the solid angle of the cone about `direction` with
// half-angle `halfAngle` (0: exactly along it; π: every direction), speeds uniform in
// [speedMin, speedMax].
struct VelocityCone {
    glm::vec3 direction{0.0f, 1.0f, 0.0f};  // any nonzero length
    float halfAngle = 0.0f;                 // radians, in [0, π]
    float speedMin = 0.0f, speedMax = 0.0f; // world units per second, 0 ≤ min ≤ max
};

// `count` particles at `time` seconds of simulated time, then every `interval` seconds
// (interval 0: once). All of a burst's particles are born at that instant.
struct Burst {
    float time = 0.0f;      // seconds ≥ 0
    uint32_t count = 0;
    float interval = 0.0f;  // seconds ≥ 0
};

struct Emitter {
    EmitterShape shape = EmitterShape::Point;
    glm::vec3 centre{0.0f};                 // point; line: its start; disc, box, sphere: the centre
    glm::vec3 end{0.0f};                    // line: its end
    glm::vec3 normal{0.0f, 1.0f, 0.0f};     // disc: the plane's normal, any nonzero length
    float radius = 0.0f;                    // disc, sphere: world units ≥ 0
    glm::vec3 halfExtents{0.0f};            // box: world units ≥ 0

    float rate = 0.0f;            // particles per second ≥ 0, spread evenly over time
    std::vector<Burst> bursts;
    VelocityCone velocity;
    float lifespanMin = 1.0f, lifespanMax = 1.0f;  // seconds, uniform in [min, max], 0 < min ≤ max
    float sizeMin = 0.1f, sizeMax = 0.1f;          // birth size, world units, uniform, 0 ≤ min ≤ max

    // Over normalized age: size = birth size · sizeOverLife(t), colour = (colourOverLife(t),
    // opacityOverLife(t)).
    Curve sizeOverLife{1.0f};
    ColourGradient colourOverLife{glm::vec3(1.0f)};
    Curve opacityOverLife{1.0f};

    static Emitter point(glm::vec3 position);
    static Emitter line(glm::vec3 start, glm::vec3 end);
    static Emitter disc(glm::vec3 centre, glm::vec3 normal, float radius);
    static Emitter box(glm::vec3 centre, glm::vec3 halfExtents);
    static Emitter sphere(glm::vec3 centre, float radius);
};

// ---- Effectors: each changes the velocity over one step, in list order ------------------------------
// dv/dt = acceleration: v += acceleration·dt.
struct Gravity {
    glm::vec3 acceleration{0.0f, -9.81f, 0.0f};
};
// Air moving at `velocity`: dv/dt = drag·(velocity − v), solved exactly over the step,
// v = velocity + (v − velocity)·exp(−drag·dt). drag in 1/s ≥ 0.
struct Wind {
    glm::vec3 velocity{0.0f};
    float drag = 1.0f;
};
// Hot gas rises: dv/dt = up·acceleration·(1 + (endScale − 1)·t) at normalized age t, so the lift
// fades linearly from `acceleration` at birth to `acceleration·endScale` at death as the gas cools.
struct Buoyancy {
    glm::vec3 up{0.0f, 1.0f, 0.0f};  // any nonzero length
    float acceleration = 1.0f;       // world units / s²
    float endScale = 1.0f;           // finite
};
// Linear drag in still air: dv/dt = −coefficient·v, exactly v·exp(−coefficient·dt). 1/s ≥ 0.
struct Drag {
    float coefficient = 1.0f;
};
// Pulls toward `position` with a Plummer-softened inverse square:
// dv/dt = strength·d / (|d|² + softening²)^(3/2), d = position − x. Finite everywhere, the centre
// included; strength < 0 repels. strength in world units³/s², softening in world units > 0.
struct Attractor {
    glm::vec3 position{0.0f};
    float strength = 1.0f;
    float softening = 0.1f;
};
// Swirls about the line through `centre` along `axis`: the air moves at
// u = angularSpeed·(â × r) / (1 + |r⊥|²/radius²), r = x − centre, |r⊥| the distance from the axis
// (a rigid rotation near the axis, falling off as 1/distance beyond `radius`), and the particle's
// velocity relaxes toward u like Wind's: v = u + (v − u)·exp(−drag·dt).
struct Vortex {
    glm::vec3 centre{0.0f};
    glm::vec3 axis{0.0f, 1.0f, 0.0f};  // any nonzero length; angularSpeed > 0: counter-clockwise about it
    float angularSpeed = 1.0f;         // rad/s near the axis
    float radius = 1.0f;               // world units > 0
    float drag = 1.0f;                 // 1/s ≥ 0
};
// Divergence-free turbulence, curl noise (Bridson, Hourihan, Nordenstam 2007): the air moves at
// u(x) = amplitude · curlNoise(frequency·x + drift·time), a field with no sources or sinks, so
// advected particles neither bunch up nor thin out. response = 0: the field carries the particle,
// position += u·dt on top of its own motion, velocity untouched (pure advection); response > 0: the
// velocity relaxes toward u like Wind's, v = u + (v − u)·exp(−response·dt).
struct Turbulence {
    float amplitude = 1.0f;   // world units / s: the field's rms speed (curlNoise is normalized to rms 1)
    float frequency = 1.0f;   // 1 / world units > 0: features about 1/frequency across
    glm::vec3 drift{0.0f};    // noise units per second: scrolls the field so that it changes over time
    float response = 0.0f;    // 1/s ≥ 0
    uint32_t seed = 0;        // which field, together with the system's seed
};
using Effector = std::variant<Gravity, Wind, Buoyancy, Drag, Attractor, Vortex, Turbulence>;

// ---- Noise ------------------------------------------------------------------------------------------
// Gradient noise (Perlin 2002, quintic fade, so C2): a deterministic function of the point and the
// seed, 0 at every integer lattice point, values within about ±1, with its analytic gradient.
// Lattice coordinates beyond ±2³⁰ are clamped there, so no coordinate overflows an integer; an
// infinite or NaN coordinate gives a finite result too (as if at the clamped lattice point).
template <class T>
struct NoiseSample {
    T value;
    glm::vec<3, T> gradient;
};
template <class T>
NoiseSample<T> gradientNoise(glm::vec<3, T> p, uint32_t seed);
// The curl of ψ = (N(p), N(p + o₁), N(p + o₂)), N the gradient noise above and o₁, o₂ fixed integer
// offsets (so that the three fields share their cell and fade weights and differ in their
// gradients), scaled so that its rms length over space is about 1 (peaks near 3). Divergence-free
// up to rounding: the divergence of a curl vanishes wherever the field is C2. Turbulence uses the
// float version; the double one is the same formula, for checks.
template <class T>
glm::vec<3, T> curlNoise(glm::vec<3, T> p, uint32_t seed);
extern template NoiseSample<float> gradientNoise(glm::vec<3, float>, uint32_t);
extern template NoiseSample<double> gradientNoise(glm::vec<3, double>, uint32_t);
extern template glm::vec<3, float> curlNoise(glm::vec<3, float>, uint32_t);
extern template glm::vec<3, double> curlNoise(glm::vec<3, double>, uint32_t);

// ---- The system -------------------------------------------------------------------------------------
// Particles are processed in blocks of this many slots (a block's arrays stay in the core's L1/L2
// cache while every effector runs over it); the blocks are the thread pool's items.
constexpr uint32_t kParticleBlock = 2048;

struct ParticleSystemDesc {
    uint32_t maxParticles = 10000;    // slots > 0; a birth with no free slot is dropped (droppedCount)
    float timeStep = 1.0f / 60.0f;    // seconds > 0, the fixed step
    uint32_t maxStepsPerAdvance = 8;  // > 0: advance() runs at most this many, and drops the time beyond
    uint64_t seed = 0;
    std::vector<Emitter> emitters;    // at most 65535
    std::vector<Effector> effectors;  // applied in this order
};

// The state, one entry per slot. A slot is alive when age < lifespan; a dead slot has lifespan 0,
// velocity 0 and keeps its last position and age.
struct ParticleArrays {
    std::vector<float> positionX, positionY, positionZ;
    std::vector<float> velocityX, velocityY, velocityZ;
    std::vector<float> age, lifespan, size;  // size: the birth size
    std::vector<uint16_t> emitter;           // which emitter gave birth to it (its curves)
};

class ParticleSystem {
public:
    // Checks the desc (Error(InvalidArgument) naming the field) and allocates maxParticles slots,
    // about 70 bytes each with the step's bookkeeping (Error(OutOfMemory) if the machine cannot hold
    // them). `pool` may be null (one thread); it must outlive the system or be replaced first.
    explicit ParticleSystem(ParticleSystemDesc desc, ThreadPool* pool = nullptr);

    void setThreadPool(ThreadPool* pool) { pool_ = pool; }
    // Replace one emitter (index < desc().emitters.size()) or the effector list; checked as above. A
    // replaced emitter keeps its emission count and phase, so its stream goes on where it was.
    void setEmitter(size_t index, Emitter emitter);
    void setEffectors(std::vector<Effector> effectors);

    // One fixed step of desc.timeStep: effectors, aging, deaths, then this step's births. Its buffers
    // were all sized for maxParticles by the constructor, so a step cannot run out of memory midway.
    void step();
    // Adds frameSeconds (finite, ≥ 0) to the time not yet simulated and runs the whole steps in it,
    // at most desc.maxStepsPerAdvance (the rest beyond them is dropped, so that a slow frame cannot
    // make the next one slower still). A step runs when the time left reaches timeStep·(1 − 10⁻⁴):
    // frame times that add up to whole steps in exact arithmetic (two frames of 1/120 s, one step of
    // 1/60 s) do so here too, though 1/60 is no float and their sum is rounded. Returns
    // the number of steps run.
    uint32_t advance(double frameSeconds);

    // Writes the living particles, in slot order, as the lecture's struct: the Map(WRITE_DISCARD) +
    // memcpy of the upload, with size and colour from their emitter's curves at their normalized
    // age. `dst` need not be aligned. Throws Error(OutOfRange) if fewer than aliveCount() fit in
    // capacityBytes. Returns the number written (aliveCount()). Parallel over the pool's threads.
    size_t writeVertices(void* dst, size_t capacityBytes) const;
    size_t writeVertices(std::span<Particle> dst) const;
    std::vector<Particle> vertices() const;

    uint64_t stepCount() const { return steps_; }
    double time() const { return double(steps_) * double(desc_.timeStep); }  // simulated seconds
    uint32_t aliveCount() const { return alive_; }
    uint32_t capacity() const { return desc_.maxParticles; }
    uint32_t slotsUsed() const { return highWater_; }  // 1 + the highest slot ever given out
    // Births and deaths so far; aliveCount() = bornCount() − diedCount(). A particle whose age at the
    // end of its birth step already reaches its lifespan counts in both and never takes a slot.
    uint64_t bornCount() const { return born_; }
    uint64_t diedCount() const { return died_; }
    uint64_t droppedCount() const { return dropped_; }  // births with no free slot
    const ParticleArrays& arrays() const { return soa_; }
    const ParticleSystemDesc& desc() const { return desc_; }

private:
    struct Birth {
        uint32_t slot;
        uint16_t emitter;
        uint64_t index;  // the emitter's emission counter: the key of this particle's random numbers
        float age, lifespan;
    };
    void integrate(float dt, float time);
    void integrateBlock(uint32_t block, float dt, float time);
    void collectDeaths();
    void planBirths(double t0, double t1);
    void planBirth(uint16_t emitter, double birth_time, double t1);  // needs a free slot
    bool full() const { return free_.empty() && highWater_ == desc_.maxParticles; }
    void dropAll(uint16_t emitter, uint64_t count);
    void initBirths();
    void initBirth(const Birth& birth);
    void parallel(uint32_t count, const std::function<void(uint32_t)>& fn) const;

    ParticleSystemDesc desc_;
    ThreadPool* pool_ = nullptr;
    ParticleArrays soa_;
    std::vector<uint64_t> emitterKey_;      // per emitter: its random numbers' key, from the seed
    std::vector<uint64_t> emitted_;         // per emitter: births so far (dropped ones too)
    std::vector<double> phase_;             // per emitter: rate·time emitted so far
    std::vector<uint32_t> free_;            // freed slots, a stack
    std::vector<uint32_t> blockAlive_;      // per block: living particles
    std::vector<std::vector<uint32_t>> blockDeaths_;  // per block: this step's deaths, ascending
    std::vector<Birth> births_;             // this step's
    uint32_t highWater_ = 0, alive_ = 0;
    uint64_t steps_ = 0, born_ = 0, died_ = 0, dropped_ = 0;
    double pending_ = 0.0;                  // time given to advance() not yet simulated
};

}  // namespace raster
