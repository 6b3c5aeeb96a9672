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
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "raster/lab.hpp"
#include "raster/particles.hpp"  // raster::Particle, the lecture's struct, and its input layout

namespace {

using namespace raster;

constexpr float kPi = 3.14159265358979f;

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

// What a particle looks like at normalized age t = age / lifespan in [0, 1]: its billboard's
// half-width as a factor on its birth size, its colour and its opacity.
struct Look {
    float size;
    glm::vec3 colour;  // linear rgb
    float opacity;     // [0, 1]
};

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

// ---- The fountain: the lab's simulation loop, upload and drawing (no LAB place below) --------------

constexpr double kStep = 1.0 / 60.0;      // seconds per simulation step (the clock's)
constexpr float kStepF = float(kStep);    // the same step, as the particles' float
constexpr double kDefaultTime = 3.0;      // seconds after the fountain is turned on
constexpr uint32_t kDefaultCount = 4000;  // particle slots

const Emitter kFountain{{0.0f, -1.1f, 0.5f}, 0.1f, 0.4f, 5.5f, 6.5f, 1.2f, 2.0f, 0.03f, 0.05f};
const Effectors kAir{{0.0f, -9.81f, 0.0f}, 3.0f, {2.0f, 0.0f, -0.4f}, 0.5f};

// A number in [0, 1) from a counter-based hash (SplitMix64's finaliser) of the seed, the particle,
// its birth and which number of that birth: independent of the order of the calls.
float random01(uint32_t seed, uint32_t particle, uint32_t birth, uint32_t which) {
    uint64_t h = (uint64_t(seed) << 32 | particle) * 0x9E3779B97F4A7C15ull + (uint64_t(birth) << 4 | which);
    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
    return float((h ^ (h >> 31)) >> 40) * 0x1p-24f;
}

BirthRandom birthRandom(uint32_t seed, uint32_t particle, uint32_t birth) {
    const auto u = [&](uint32_t which) { return random01(seed, particle, birth, which); };
    return {u(0), u(1), u(2), u(3), u(4), u(5), u(6)};
}

// The sparks: `count` slots; slot i is first born after a wait of up to the longest lifespan (so that
// births spread over time), then lives, dies and is reborn by the functions above, one fixed step at
// a time.
class Fountain {
  public:
    Fountain(uint32_t count, uint32_t seed)
        : seed_(seed), particles_(count), births_(count, 0), wait_(count) {
        for (uint32_t i = 0; i < count; ++i) wait_[i] = kFountain.lifespanMax * random01(seed, i, 0, 15);
    }

    void step() {
        for (uint32_t i = 0; i < particles_.size(); ++i) {
            Particle& p = particles_[i];
            const auto rebirth = [&](Particle& q) {
                emit(q, kFountain, birthRandom(seed_, i, ++births_[i]));
            };
            if (wait_[i] > 0.0f) {  // not yet born: count down, be born when the wait is over
                wait_[i] -= kStepF;
                if (wait_[i] <= 0.0f) emit(p, kFountain, birthRandom(seed_, i, 0));
                continue;
            }
            live(p, kAir, kStepF, rebirth);
        }
    }

    // The upload (the lecture's Map(WRITE_DISCARD) + memcpy): the born particles, each with its look at
    // its normalized age, into `staging`; returns how many.
    size_t write(std::vector<Particle>& staging) const {
        staging.clear();
        for (size_t i = 0; i < particles_.size(); ++i) {
            if (wait_[i] > 0.0f) continue;
            Particle v = particles_[i];
            const Look look = lookOverLife(std::clamp(v.age / v.lifespan, 0.0f, 1.0f));
            v.size *= look.size;
            v.colour = glm::vec4(look.colour, look.opacity);
            staging.push_back(v);
        }
        return staging.size();
    }

  private:
    uint32_t seed_;
    std::vector<Particle> particles_;
    std::vector<uint32_t> births_;
    std::vector<float> wait_;  // seconds until the first birth
};

// ---- Shaders: the billboards lab's sprite, and the side view's points ------------------------------

struct SparkIn {
    glm::vec3 position;
    float size;
    glm::vec4 colour;
    RASTER_INPUT_SIGNATURE(SparkIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(size, "SIZE", 0),
                           RASTER_INPUT(colour, "COLOR", 0))
};
struct SparkVertex {
    glm::vec4 position;  // world, w = 1
    glm::vec4 colour;
    float size;
};
struct SparkCorner {
    glm::vec4 position;  // clip space
    glm::vec4 colour;
    glm::vec2 tex;
};

struct VsSpark {
    SparkVertex operator()(const SparkIn& in) const {
        return {glm::vec4(in.position, 1.0f), in.colour, in.size};
    }
};

// gsBillboard: the sprite opened in clip space, its half-size times the projection's scale.
struct GsSpark {
    glm::mat4 viewProj{1.0f};
    glm::vec2 projScale{1.0f, 1.0f};  // P[0][0], P[1][1]

    void operator()(const Point<SparkVertex>& in, TriangleStream<SparkCorner, 4>& stream) const {
        const glm::vec4 c = viewProj * in[0].position;
        const float bx = in[0].size * projScale.x, by = in[0].size * projScale.y;
        stream.Append({c + glm::vec4(bx, by, 0, 0), in[0].colour, {1, 0}});
        stream.Append({c + glm::vec4(bx, -by, 0, 0), in[0].colour, {1, 1}});
        stream.Append({c + glm::vec4(-bx, by, 0, 0), in[0].colour, {0, 0}});
        stream.Append({c + glm::vec4(-bx, -by, 0, 0), in[0].colour, {0, 1}});
    }
};

// psFire tinted: the fire texture times the spark's colour and opacity.
struct PsSpark {
    const Texture2D* texture = nullptr;
    SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);
    glm::vec4 operator()(const SparkCorner& in) const { return texture->Sample(sampler, in.tex) * in.colour; }
};

// The side view: x to the right, y up, z ignored; one soft dot per particle, added up. A dot, not a
// one-pixel point, so that a position moved by a float's last bit (a correct answer written
// otherwise) changes the picture by a fraction of a step, never by a whole point in another pixel.
struct PointIn {
    glm::vec3 position;
    RASTER_INPUT_SIGNATURE(PointIn, RASTER_INPUT(position, "POSITION", 0))
};
struct PointVertex {
    glm::vec4 position;
};
constexpr glm::vec2 kSideCentre{0.3f, -0.2f};  // world units: the panel's centre
constexpr float kSideHalfWidth = 1.6f;         // world units from the centre to the panel's edges
struct VsSide {
    PointVertex operator()(const PointIn& in) const {
        const glm::vec2 xy = (glm::vec2(in.position) - kSideCentre) / kSideHalfWidth;
        return {glm::vec4(xy, 0.5f, 1.0f)};
    }
};
struct DotCorner {
    glm::vec4 position;  // clip space
    glm::vec2 offset;    // from the dot's centre, in dot radii
};
// The dot: a square of kDotRadius pixels about the point, its brightness (1 − r²)², 0 at its rim.
constexpr float kDotRadius = 1.5f;  // pixels
struct GsDot {
    float halfSize = 0.0f;  // kDotRadius in clip units: 2·kDotRadius / the panel's side in pixels
    void operator()(const Point<PointVertex>& in, TriangleStream<DotCorner, 4>& stream) const {
        const glm::vec4 c = in[0].position;
        stream.Append({c + glm::vec4(halfSize, halfSize, 0, 0), {1, 1}});
        stream.Append({c + glm::vec4(halfSize, -halfSize, 0, 0), {1, -1}});
        stream.Append({c + glm::vec4(-halfSize, halfSize, 0, 0), {-1, 1}});
        stream.Append({c + glm::vec4(-halfSize, -halfSize, 0, 0), {-1, -1}});
    }
};
struct PsDot {
    glm::vec4 operator()(const DotCorner& in) const {
        const float fall = std::max(0.0f, 1.0f - glm::dot(in.offset, in.offset));
        return {0.4f * fall * fall, 0.4f * fall * fall, 0.4f * fall * fall, 1.0f};
    }
};
struct VsClip {
    PointVertex operator()(const PointIn& in) const { return {glm::vec4(in.position, 1.0f)}; }
};
struct PsConstant {
    glm::vec4 colour;
    glm::vec4 operator()(const PointVertex&) const { return colour; }
};

class ParticleSystemLab final : public LabScene {
  public:
    explicit ParticleSystemLab(const SceneOptions& o)
        : data_(occluderOptions(o)), fountain_(o.count.value_or(kDefaultCount), o.seed) {
        const glm::mat4 proj = sceneProjection(o);
        gs_.viewProj = data_.viewProj;
        gs_.projScale = {proj[0][0], proj[1][1]};
        ps_.texture = &data_.texture;
        const auto elements = particleInputLayout();  // raster::Particle's, from offsetof
        layout_ = InputLayout(elements);
        const glm::vec3 panel[6] = {{-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
        panel_ = VertexBuffer::create(std::span<const glm::vec3>(panel));
        vertices_ = VertexBuffer::create(std::vector<Particle>{});
        advanceBy(o.time.value_or(kDefaultTime));  // the clock's start: the steps before the first frame
    }
    bool animated() const override { return true; }
    double time() const override { return time_; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        data_.drawOccluder(context);  // draw 0, the "giraffe": opaque, depth written
        const size_t alive = fountain_.write(staging_);
        vertices_.update(std::span<const Particle>(staging_));  // Map(WRITE_DISCARD) + memcpy
        context.setInputLayout(&layout_);
        context.setVertexBuffer(0, &vertices_);
        context.setPrimitiveTopology(Topology::PointList);
        // Draw 1: the sparks, additive, depth test on and depth write off (order-free).
        context.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
        context.setBlendState(BlendState::additive());
        context.draw(VsSpark{}, gs_, ps_, uint32_t(alive));
        drawSideView(context, color, uint32_t(alive));
    }

  protected:
    // The clock's rule (raster/scenes.hpp): whole steps of 1/60 s, one run once 1 − 10⁻⁴ of it is due.
    void advanceBy(double seconds) override {
        time_ += seconds;
        pending_ += seconds;
        while (pending_ >= kStep * (1.0 - 1e-4)) {
            fountain_.step();
            pending_ -= kStep;
        }
    }

  private:
    static SceneOptions occluderOptions(SceneOptions o) {
        o.count = 0;  // ParticleSceneData's own particles are not drawn
        return o;
    }

    // Draws 2 and 3: the panel, a square of a third of the image's height in its lower right corner,
    // dark blue, then every particle in it as a soft grey dot, (0.4, 0.4, 0.4) at its centre, added up:
    // white where three or more sparks sit together.
    void drawSideView(Context& context, RenderTarget& color, uint32_t alive) {
        const float side = std::floor(float(color.height()) / 3.0f);
        context.setViewport({float(color.width()) - side, float(color.height()) - side, side, side, 0, 1});
        context.setDepthStencilState(DepthStencilState::disabled());
        context.setBlendState(BlendState::opaque());
        context.setInputLayout(&side_layout_);
        context.setVertexBuffer(0, &panel_);
        context.setPrimitiveTopology(Topology::TriangleList);
        context.draw(VsClip{}, PsConstant{{0.02f, 0.03f, 0.08f, 1.0f}}, 6);
        context.setInputLayout(&layout_);  // the particles' POSITION
        context.setVertexBuffer(0, &vertices_);
        context.setPrimitiveTopology(Topology::PointList);
        context.setBlendState(BlendState::additive());
        context.draw(VsSide{}, GsDot{2.0f * kDotRadius / side}, PsDot{}, alive);
    }

    static constexpr InputElementDesc kSideElements[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0, InputClassification::PerVertexData, 0}};

    ParticleSceneData data_;  // the occluder, the camera, the fire texture
    Fountain fountain_;
    InputLayout layout_, side_layout_{kSideElements};
    std::vector<Particle> staging_;  // what Map would return
    VertexBuffer vertices_, panel_;
    GsSpark gs_;
    PsSpark ps_;
    double time_ = 0.0, pending_ = 0.0;
};

}  // namespace

RASTER_LAB("particle-system", "Lab: a particle system - emitter, effectors, life cycle (lecture 11, part 3)",
           ParticleSystemLab, defaultCamera("particles"))
