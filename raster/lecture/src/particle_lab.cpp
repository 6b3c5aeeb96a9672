// The particle-system lab's scene (raster/labs/particle_system.hpp): the fountain that steps the
// student's functions, the upload, the billboards' shaders and the side view.
#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "raster/labs/particle_system.hpp"
#include "raster/teaching_draw.hpp"

namespace raster::particle_lab {

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

Fountain::Fountain(uint32_t count, uint32_t seed, Answers answers)
    : answers_(answers), seed_(seed), particles_(count), births_(count, 0), wait_(count) {
    for (uint32_t i = 0; i < count; ++i) wait_[i] = kFountain.lifespanMax * random01(seed, i, 0, 15);
}

void Fountain::step() {
    for (uint32_t i = 0; i < particles_.size(); ++i) {
        Particle& p = particles_[i];
        const auto rebirth = [&](Particle& q) {
            answers_.emit(q, kFountain, birthRandom(seed_, i, ++births_[i]));
        };
        if (wait_[i] > 0.0f) {  // not yet born: count down, be born when the wait is over
            wait_[i] -= kStepF;
            if (wait_[i] <= 0.0f) answers_.emit(p, kFountain, birthRandom(seed_, i, 0));
            continue;
        }
        answers_.live(p, kAir, kStepF, rebirth);
    }
}

size_t Fountain::write(std::vector<Particle>& staging) const {
    staging.clear();
    for (size_t i = 0; i < particles_.size(); ++i) {
        if (wait_[i] > 0.0f) continue;
        Particle v = particles_[i];
        const Look look = answers_.lookOverLife(std::clamp(v.age / v.lifespan, 0.0f, 1.0f));
        v.size *= look.size;
        v.colour = glm::vec4(look.colour, look.opacity);
        staging.push_back(v);
    }
    return staging.size();
}

namespace {

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

constexpr InputElementDesc kSideElements[] = {
    {"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0, InputClassification::PerVertexData, 0}};

SceneOptions occluderOptions(SceneOptions o) {
    o.count = 0;  // ParticleSceneData's own particles are not drawn
    return o;
}

}  // namespace

struct ParticleSystemScene::State {
    State(const SceneOptions& o, Answers answers)
        : data(occluderOptions(o)), fountain(o.count.value_or(kDefaultCount), o.seed, answers) {}

    ParticleSceneData data;  // the occluder, the camera, the fire texture
    Fountain fountain;
    InputLayout layout, side_layout{kSideElements};
    std::vector<Particle> staging;  // what Map would return
    VertexBuffer vertices, panel;
    GsSpark gs;
    PsSpark ps;
    double time = 0.0, pending = 0.0;
};

ParticleSystemScene::ParticleSystemScene(const SceneOptions& o, Answers answers)
    : state_(std::make_unique<State>(o, answers)) {
    State& s = *state_;
    const glm::mat4 proj = sceneProjection(o);
    s.gs.viewProj = s.data.viewProj;
    s.gs.projScale = {proj[0][0], proj[1][1]};
    s.ps.texture = &s.data.texture;
    const auto elements = particleInputLayout();  // raster::Particle's, from offsetof
    s.layout = InputLayout(elements);
    const glm::vec3 panel[6] = {{-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    s.panel = VertexBuffer::create(std::span<const glm::vec3>(panel));
    s.vertices = VertexBuffer::create(std::vector<Particle>{});
    advanceBy(o.time.value_or(kDefaultTime));  // the clock's start: the steps before the first frame
}

ParticleSystemScene::~ParticleSystemScene() = default;

double ParticleSystemScene::time() const {
    return state_->time;
}

void ParticleSystemScene::advanceBy(double seconds) {
    State& s = *state_;
    s.time += seconds;
    s.pending += seconds;
    while (s.pending >= kStep * (1.0 - 1e-4)) {
        s.fountain.step();
        s.pending -= kStep;
    }
}

void ParticleSystemScene::render(Context& context, RenderTarget& color, DepthTarget& depth) {
    State& s = *state_;
    beginSceneFrame(context, color, depth);
    s.data.drawOccluder(context);  // draw 0, the "giraffe": opaque, depth written
    const uint32_t alive = uint32_t(s.fountain.write(s.staging));
    s.vertices.update(std::span<const Particle>(s.staging));  // Map(WRITE_DISCARD) + memcpy
    context.setInputLayout(&s.layout);
    context.setVertexBuffer(0, &s.vertices);
    context.setPrimitiveTopology(Topology::PointList);
    // Draw 1: the sparks, additive, depth test on and depth write off (order-free).
    context.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
    context.setBlendState(BlendState::additive());
    context.draw(VsSpark{}, s.gs, s.ps, alive);
    // Draws 2 and 3: the panel, a square of a third of the image's height in its lower right corner,
    // dark blue, then every particle in it as a soft grey dot, (0.4, 0.4, 0.4) at its centre, added up:
    // white where three or more sparks sit together.
    const float side = std::floor(float(color.height()) / 3.0f);
    context.setViewport({float(color.width()) - side, float(color.height()) - side, side, side, 0, 1});
    context.setDepthStencilState(DepthStencilState::disabled());
    context.setBlendState(BlendState::opaque());
    context.setInputLayout(&s.side_layout);
    context.setVertexBuffer(0, &s.panel);
    context.setPrimitiveTopology(Topology::TriangleList);
    context.draw(VsClip{}, PsConstant{{0.02f, 0.03f, 0.08f, 1.0f}}, 6);
    context.setInputLayout(&s.layout);  // the particles' POSITION
    context.setVertexBuffer(0, &s.vertices);
    context.setPrimitiveTopology(Topology::PointList);
    context.setBlendState(BlendState::additive());
    context.draw(VsSide{}, GsDot{2.0f * kDotRadius / side}, PsDot{}, alive);
}

}  // namespace raster::particle_lab
