// The lecture's blend and depth figures (lecture 11, part 3) as scenes, and weighted blended OIT: one
// fixed set of soft round particles in front of and behind SCENES.md's opaque occluder (the "giraffe"),
// drawn with the states of raster/particle_blending.hpp:
//   blend-additive    additive, depth test on, depth write off: correct for fire
//   blend-depthwrite  additive with depth write on: particles cut out in squares by nearer ones' quads
//   blend-nodepth     additive, no depth test: the particles over the occluder too
//   blend-unsorted    "over" in the order the particles are stored: far ones cover near ones
//   blend-sorted      "over" sorted back to front: correct
//   blend-wboit       weighted blended OIT (accumulation and revealage targets, then a composite)
// A particle's colour goes from blue (far, z = −1.2) to yellow (near, z = +1.2), so that a wrong order
// shows as blue over yellow. Drawn through the teaching pipeline (raster/teaching_draw.hpp): no speed
// goal here, and the file compiles in seconds.
#include "scene_blending.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <span>
#include <string>
#include <vector>

#include "lecture/fire_particle_shaders.hpp"
#include "raster/particle_blending.hpp"
#include "raster/shaders/basic.hpp"
#include "raster/teaching_draw.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

// The figures, in the order sceneNames lists them.
enum class BlendFigure : uint8_t { Additive, AdditiveDepthWrite, NoDepth, Unsorted, Sorted, Weighted };

// World units. The occluder is the quad x in [−0.6, 0.6], y in [−1.2, 0.4] at z = 0.
constexpr glm::vec3 kBoxHalf{1.2f, 0.9f, 1.2f};
constexpr glm::vec3 kBoxCentre{0.0f, -0.2f, 0.0f};
constexpr float kParticleSize = 0.15f;  // the quad's half-width
constexpr float kOverOpacity = 0.75f;
constexpr float kAdditiveOpacity =
    0.35f;  // additive light piles up: fainter, so dense spots stay below white
constexpr glm::vec3 kFarColour{0.1f, 0.3f, 1.0f}, kNearColour{1.0f, 0.75f, 0.1f};

// A disc with a soft rim, white: alpha 0.95·min(1, 2·(1 − r²)) inside the quad's inscribed circle
// (r = 1 on it), 0 outside; flat over the inner 70 % of the radius, so that which disc covers which
// shows.
Texture2D makePuffTexture() {
    constexpr uint32_t kSize = 64;
    std::vector<uint8_t> texels(kSize * kSize * 4);
    for (uint32_t j = 0; j < kSize; ++j)
        for (uint32_t i = 0; i < kSize; ++i) {
            const double u = (i + 0.5) / kSize - 0.5, v = (j + 0.5) / kSize - 0.5;
            const double r2 = 4.0 * (u * u + v * v), s = std::clamp(2.0 * (1.0 - r2), 0.0, 1.0);
            uint8_t* t = &texels[4 * (j * kSize + i)];
            t[0] = t[1] = t[2] = 255;
            t[3] = uint8_t(std::lround(255.0 * 0.95 * s));
        }
    return Texture2D::fromRgba8(kSize, kSize, texels);
}

// A number in [0, 1) from (i, k): SplitMix64's finaliser, so that the particles lie at random, with
// no lattice (a low-discrepancy sequence's rows show in a picture), and the same on every machine.
float unitHash(uint32_t i, uint32_t k) {
    uint64_t z = (uint64_t(i) << 2 | k) * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return float(double(z ^ (z >> 31)) * 0x1p-64);
}

std::vector<Particle> blendParticles(uint32_t count, float opacity) {
    std::vector<Particle> particles(count);
    for (uint32_t i = 0; i < count; ++i) {
        const glm::vec3 unit = 2.0f * glm::vec3(unitHash(i, 0), unitHash(i, 1), unitHash(i, 2)) - 1.0f;
        Particle& p = particles[i];
        p.position = kBoxCentre + unit * kBoxHalf;
        p.size = kParticleSize;
        const float nearness = 0.5f * (unit.z + 1.0f);
        p.colour = glm::vec4(glm::mix(kFarColour, kNearColour, nearness), opacity);
    }
    return particles;
}

// The fire's shaders (src/lecture/fire_particle_shaders.hpp) under types of this file's own:
// scene_fire.cpp draws the fire's types through the template pipeline, and a draw's Context::execute
// for given shader types must be defined one way in the whole program (teaching_draw.hpp here,
// pipeline_impl.hpp there), or the linker keeps either.
struct VsParticle : shaders::VsFireParticle {};
struct GsParticle : shaders::GsFireParticle {};
struct PsParticle : shaders::PsFireParticle {};

// The accumulation pass of weighted blended OIT: premultiplied colour and alpha, both times the
// weight, into target 0; alpha into target 1, whose blend multiplies by 1 − alpha.
struct PsWeightedParticle {
    using Input = shaders::FireCorner;
    const Texture2D* texture = nullptr;
    SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);
    WeightFunction weight = WeightFunction::Eq8;  // docs/BLENDING.md: the best of the view-depth weights here

    std::array<glm::vec4, 2> operator()(const shaders::FireCorner& in) const {
        const glm::vec4 c = texture->Sample(sampler, in.tex) * in.colour;
        const float w = weightedBlendedWeight(weight, in.position.w, in.position.z, c.w);
        return {glm::vec4(glm::vec3(c) * (c.w * w), c.w * w), glm::vec4(c.w)};
    }
};

// The composite: the weighted average colour and the revealage, for weightedBlendedComposite().
struct PsWeightedComposite {
    using Input = shaders::PositionOnly;
    const RenderTarget* accumulation = nullptr;
    const RenderTarget* revealage = nullptr;

    glm::vec4 operator()(const shaders::PositionOnly& in) const {
        const uint32_t x = uint32_t(in.position.x), y = uint32_t(in.position.y);
        const glm::vec4 sum = accumulation->load(x, y);
        return {glm::vec3(sum) / std::max(sum.w, 1e-5f), revealage->load(x, y).x};
    }
};

struct FigureSpec {
    std::string_view name;
    BlendFigure figure;
};
constexpr FigureSpec kFigures[] = {
    {"blend-additive", BlendFigure::Additive}, {"blend-depthwrite", BlendFigure::AdditiveDepthWrite},
    {"blend-nodepth", BlendFigure::NoDepth},   {"blend-unsorted", BlendFigure::Unsorted},
    {"blend-sorted", BlendFigure::Sorted},     {"blend-wboit", BlendFigure::Weighted},
};

ParticleStates figureStates(BlendFigure figure) {
    switch (figure) {
        case BlendFigure::Additive:
            return ParticleStates::additive();
        case BlendFigure::AdditiveDepthWrite:
            return ParticleStates::additiveDepthWrite();
        case BlendFigure::NoDepth:
            return ParticleStates::additiveNoDepth();
        case BlendFigure::Unsorted:
        case BlendFigure::Sorted:
            return ParticleStates::over();
        case BlendFigure::Weighted:
            return {weightedBlendedAccumulation(), DepthStencilState::readOnly()};
    }
    return {};
}

bool isAdditive(BlendFigure f) {
    return f == BlendFigure::Additive || f == BlendFigure::AdditiveDepthWrite || f == BlendFigure::NoDepth;
}

class BlendingScene final : public Scene {
  public:
    BlendingScene(std::string_view name, BlendFigure figure, const SceneOptions& o)
        : name_(name), figure_(figure), data_(occluderOnly(o, kBlendCamera)), order_(std::string(name)) {
        const SceneCamera camera = o.camera.value_or(kBlendCamera);
        eye_ = camera.eye;
        ahead_ = glm::normalize(camera.target - camera.eye);
        const glm::mat4 proj = sceneProjection(o);
        gs_.viewProj = data_.viewProj;
        gs_.projScale = {proj[0][0], proj[1][1]};
        puff_ = makePuffTexture();
        ps_.fireTexture = &puff_;
        ps_weighted_.texture = &puff_;
        const uint32_t count = o.count.value_or(kDefaultBlendCount);
        particles_ = blendParticles(count, isAdditive(figure) ? kAdditiveOpacity : kOverOpacity);
        vertices_ = VertexBuffer::create(particles_);
        const auto elements = particleInputLayout();
        layout_ = InputLayout(elements);
        indices_.resize(count);
        const std::vector<glm::vec3> screen = {
            {-1, -1, 0}, {3, -1, 0}, {-1, 3, 0}};  // one triangle over the view
        full_screen_ = VertexBuffer::create(screen);
    }
    std::string_view name() const override { return name_; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        data_.drawOccluder(context);  // draw 1: opaque, depth written
        if (particles_.empty()) return;
        const ParticleStates states = figureStates(figure_);
        const int targets = figure_ == BlendFigure::Weighted ? 2 : 1;
        if (figure_ == BlendFigure::Unsorted)
            std::iota(indices_.begin(), indices_.end(), 0u);  // as stored: the wrong order, on purpose
        else
            order_.arrange(states.blend, targets, particles_, eye_, ahead_, indices_);
        index_buffer_ = IndexBuffer::create(indices_);
        context.setInputLayout(&layout_);
        context.setVertexBuffer(0, &vertices_);
        context.setIndexBuffer(&index_buffer_);
        context.setPrimitiveTopology(Topology::PointList);
        context.setBlendState(states.blend);
        context.setDepthStencilState(states.depthStencil);
        if (figure_ == BlendFigure::Weighted) {
            drawWeighted(context, color, depth);
            return;
        }
        context.drawIndexed(VsParticle{}, gs_, ps_, uint32_t(indices_.size()));
    }

  private:
    // Draw 2 into the accumulation and revealage targets, draw 3 the composite over `color`.
    void drawWeighted(Context& context, RenderTarget& color, DepthTarget& depth) {
        if (accumulation_.width() != color.width() || accumulation_.height() != color.height()) {
            accumulation_ = RenderTarget(color.width(), color.height(), Format::R32G32B32A32_FLOAT);
            revealage_ = RenderTarget(color.width(), color.height(), Format::R32G32B32A32_FLOAT);
        }
        context.clearRenderTarget(accumulation_, {0, 0, 0, 0});
        context.clearRenderTarget(revealage_, {1, 1, 1, 1});
        RenderTarget* const targets[2] = {&accumulation_, &revealage_};
        context.setRenderTargets(targets, &depth);
        context.drawIndexed(VsParticle{}, gs_, ps_weighted_, uint32_t(indices_.size()));

        context.setRenderTargets(&color, nullptr);
        context.setInputLayout(&data_.layout);
        context.setVertexBuffer(0, &full_screen_);
        context.setPrimitiveTopology(Topology::TriangleList);
        context.setBlendState(weightedBlendedComposite());
        context.setDepthStencilState(DepthStencilState::disabled());
        context.draw(shaders::VsTransform{}, PsWeightedComposite{&accumulation_, &revealage_}, 3);
        context.setRenderTargets(&color, &depth);
    }

    std::string name_;
    BlendFigure figure_;
    ParticleSceneData data_;  // the occluder and the camera
    ParticleOrder order_;
    glm::vec3 eye_{0.0f}, ahead_{0.0f, 0.0f, -1.0f};
    Texture2D puff_;
    std::vector<Particle> particles_;
    std::vector<uint32_t> indices_;
    VertexBuffer vertices_, full_screen_;
    IndexBuffer index_buffer_;
    InputLayout layout_;
    GsParticle gs_;
    PsParticle ps_;
    PsWeightedParticle ps_weighted_;
    RenderTarget accumulation_, revealage_;
};

}  // namespace

std::vector<std::string_view> blendingSceneNames() {
    std::vector<std::string_view> names;
    for (const FigureSpec& f : kFigures) names.push_back(f.name);
    return names;
}

std::unique_ptr<Scene> makeBlendingScene(std::string_view name, const SceneOptions& options) {
    for (const FigureSpec& f : kFigures)
        if (f.name == name) return std::make_unique<BlendingScene>(f.name, f.figure, options);
    return nullptr;
}

}  // namespace raster
