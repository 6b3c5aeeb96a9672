// The lecture's fire (lecture 11, part 3) over the occluder, animated: a particle system
// (raster/particles.hpp) with a disc emitter under the flames, buoyancy, curl-noise turbulence and
// drag; colour, opacity and size over each particle's life. Each frame the living particles are
// uploaded into a vertex buffer (writeVertices: the Map(WRITE_DISCARD) + memcpy of the lecture,
// laid out by particleInputLayout()) and drawn as points that the geometry shader opens into
// camera-facing quads (src/lecture/fire_particle_shaders.hpp), blended additively with the depth
// test on and depth writes off, so the occluder hides what is behind it and the order is free.
#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "lecture/fire_particle_shaders.hpp"
#include "raster/particles.hpp"
#include "raster/pipeline_impl.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

// The fast path shades the particles eight and sixteen pixels a call (shader.hpp).
static_assert(WidePixelShader<shaders::PsFireParticle> && PairPixelShader<shaders::PsFireParticle>);

// World units, seconds. The flames stand in front of the occluder (z = 0) so that it is lit behind
// them; the fire's base, the emitter, is near the occluder's foot (y = −1.2).
constexpr glm::vec3 kFireBase{0.0f, -1.0f, 0.45f};
constexpr float kFireRadius = 0.22f;
constexpr float kLifespanMin = 0.8f, kLifespanMax = 1.4f;
// The share of the slots alive in the steady state: rate · mean lifespan = kAliveShare · count.
constexpr float kAliveShare = 0.75f;

// The flames' look, tuned by eye at 1280×720 for kDefaultFireCount particles; with more, each is
// fainter (opacity · kDefaultFireCount / count), so the fire's brightness does not depend on count.
Emitter fireEmitter(uint32_t count) {
    Emitter e = Emitter::disc(kFireBase, {0, 1, 0}, kFireRadius);
    e.rate = kAliveShare * float(count) / (0.5f * (kLifespanMin + kLifespanMax));
    e.velocity = {{0, 1, 0}, 0.3f, 0.3f, 0.6f};
    e.lifespanMin = kLifespanMin, e.lifespanMax = kLifespanMax;
    e.sizeMin = 0.09f, e.sizeMax = 0.14f;
    // Small at birth, grown by a quarter of its life, shrinking as the flame tapers.
    e.sizeOverLife = Curve{{0.0f, 0.5f}, {0.25f, 1.0f}, {1.0f, 0.35f}};
    // A tint on the fire texture (its texels are orange, (1, 0.8, 0.2) at the centre): blue and green
    // above 1 make the young core yellow-white, then red, then a dark ember.
    e.colourOverLife = ColourGradient{{0.0f, {1.0f, 1.1f, 2.2f}},
                                      {0.2f, {1.0f, 0.85f, 1.2f}},
                                      {0.5f, {1.0f, 0.45f, 0.35f}},
                                      {0.8f, {0.7f, 0.15f, 0.08f}},
                                      {1.0f, {0.2f, 0.04f, 0.02f}}};
    const float gain = std::min(1.0f, float(kDefaultFireCount) / float(std::max(count, 1u)));
    e.opacityOverLife = Curve{{0.0f, 0.0f}, {0.08f, 0.6f * gain}, {0.5f, 0.5f * gain}, {1.0f, 0.0f}};
    return e;
}

ParticleSystemDesc fireDesc(uint32_t count, uint64_t seed) {
    ParticleSystemDesc desc;
    desc.maxParticles = std::max(count, 1u);  // 0 particles: one slot, no emission
    desc.seed = seed;
    // No time is ever dropped: a scene's frame is a function of its clock (scenes.hpp).
    desc.maxStepsPerAdvance = UINT32_MAX;
    Emitter emitter = fireEmitter(count);
    if (count == 0) emitter.rate = 0.0f;
    desc.emitters = {emitter};
    desc.effectors = {
        Buoyancy{{0, 1, 0}, 3.5f, 0.2f},  // hot gas rises, less as it cools
        Drag{1.5f},                       // terminal speed 2.3 m/s at birth
        // Eddies about 0.45 units across, scrolled downward in noise space so that they seem to
        // climb with the flames; they carry the particles without changing their velocity.
        Turbulence{0.7f, 2.2f, {0.0f, -1.2f, 0.0f}, 0.0f, 0},
    };
    return desc;
}

class FireScene final : public Scene {
  public:
    explicit FireScene(const SceneOptions& o)
        : data_(occluderOnly(o, kFireCamera)), system_(fireDesc(o.count.value_or(kDefaultFireCount), o.seed)) {
        const glm::mat4 proj = sceneProjection(o);
        gs_.viewProj = data_.viewProj;
        gs_.projScale = {proj[0][0], proj[1][1]};
        ps_.fireTexture = &data_.texture;
        const auto elements = particleInputLayout();
        layout_ = InputLayout(elements);
        const uint32_t slots = system_.capacity();
        allocateOrThrow("the upload of " + std::to_string(slots) + " fire particles",
                        byteCount(slots, sizeof(Particle)), [&] { staging_.resize(slots); });
        vertices_ = VertexBuffer::create(std::vector<Particle>{});
        time_ = o.time.value_or(kDefaultFireTime);
        system_.advance(time_);
    }
    std::string_view name() const override { return "fire"; }
    bool animated() const override { return true; }
    double time() const override { return time_; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        data_.drawOccluder(context);  // draw 1, the "giraffe": opaque, depth written
        // The upload: the living particles as the lecture's struct, into the vertex buffer.
        const size_t alive = system_.writeVertices(std::span<Particle>(staging_));
        vertices_.update(std::span<const Particle>(staging_.data(), alive));
        if (alive == 0) return;
        // Draw 2: additive, depth test on, depth write off.
        context.setInputLayout(&layout_);
        context.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
        context.setBlendState(BlendState::additive());
        context.setVertexBuffer(0, &vertices_);
        context.setPrimitiveTopology(Topology::PointList);
        context.draw(shaders::VsFireParticle{}, gs_, ps_, uint32_t(alive));
    }

  protected:
    void advanceBy(double seconds) override {
        system_.advance(seconds);
        time_ += seconds;
    }

  private:
    ParticleSceneData data_;  // the occluder, the camera, the fire texture
    ParticleSystem system_;
    InputLayout layout_;
    std::vector<Particle> staging_;  // maxParticles, what Map would return
    VertexBuffer vertices_;
    shaders::GsFireParticle gs_;
    shaders::PsFireParticle ps_;
    double time_ = 0.0;
};

}  // namespace

std::unique_ptr<Scene> makeFireScene(const SceneOptions& options) {
    return std::make_unique<FireScene>(options);
}

}  // namespace raster
