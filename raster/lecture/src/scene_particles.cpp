// SCENES.md's particles: the occluder (the lecture's "giraffe") and N fire billboards, additive.
#include <cmath>

#include "lecture/fire_shaders.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shaders/basic.hpp"
#include "raster/shaders/billboard.hpp"
#include "scene_list.hpp"

namespace raster {

Texture2D makeFireTexture() {
    constexpr uint32_t kSize = 64;
    std::vector<uint8_t> texels(kSize * kSize * 4);
    for (uint32_t j = 0; j < kSize; ++j) {
        for (uint32_t i = 0; i < kSize; ++i) {
            const double u = (i + 0.5) / kSize, v = (j + 0.5) / kSize;
            const double r = 2.0 * std::hypot(u - 0.5, v - 0.5);
            const double s = std::pow(std::clamp(1.0 - r, 0.0, 1.0), 2.0);
            const double rgba[4] = {1.0, 0.25 + 0.55 * s, 0.05 + 0.15 * s, 0.25 * s};
            for (int c = 0; c < 4; ++c) texels[4 * (j * kSize + i) + c] = uint8_t(std::lround(255.0 * rgba[c]));
        }
    }
    return Texture2D::fromRgba8(kSize, kSize, texels);
}

glm::vec3 particlePosition(uint32_t i) {
    static constexpr double kA[3] = {0.8191725133961645, 0.6710436067037894, 0.5497004779019704};
    static constexpr double kExtent[3] = {1.5, 1.0, 1.5};
    glm::vec3 p;
    for (int k = 0; k < 3; ++k) {
        double c = 0.5 + double(i) * kA[k];
        c -= std::floor(c);
        p[k] = float((2.0 * c - 1.0) * kExtent[k]);
    }
    return p;
}

ParticleSceneData::ParticleSceneData(const SceneOptions& o)
    : texture(o.texture.empty() ? makeFireTexture() : Texture2D::fromPng(o.texture)),
      count(o.count.value_or(kDefaultParticleCount)) {
    const glm::mat4 proj = sceneProjection(o);
    viewProj = proj * sceneView(o.camera.value_or(kParticlesCamera));
    const float h = 0.08f;
    billboardSize = {h * proj[0][0], h * proj[1][1]};
    occluderColor = glm::vec4(89, 140, 64, 255) / 255.0f;
    const std::vector<glm::vec3> triangles = {{-0.6f, -1.2f, 0}, {0.6f, -1.2f, 0}, {0.6f, 0.4f, 0},
                                              {-0.6f, -1.2f, 0}, {0.6f, 0.4f, 0},  {-0.6f, 0.4f, 0}};
    occluder = VertexBuffer::create(triangles);
    std::vector<glm::vec3> positions;
    allocateOrThrow("the positions of " + std::to_string(count) + " particles", byteCount(count, sizeof(glm::vec3)),
                    [&] { positions.resize(count); });
    for (uint32_t i = 0; i < count; ++i) positions[i] = particlePosition(i);
    particles = VertexBuffer::create(positions);
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
    layout = InputLayout(desc);
}

namespace {
// The occluder's shader, compiled for the one state it is drawn with (specialised_states.hpp).
struct PsOccluder : shaders::PsConstant {
    using SpecialisedStates = raster::SpecialisedStates<Specialise<DepthState::Less, BlendMode::Replace>>;
};
}  // namespace

void ParticleSceneData::drawOccluder(Context& context) const {
    shaders::VsTransform vs;
    vs.viewProj = viewProj;
    PsOccluder ps;
    ps.color = occluderColor;
    context.setInputLayout(&layout);
    context.setDepthStencilState({true, true, ComparisonFunc::Less});
    context.setBlendState(BlendState::opaque());
    context.setVertexBuffer(0, &occluder);
    context.setPrimitiveTopology(Topology::TriangleList);
    context.draw(vs, ps, 6);
}

namespace {

class ParticlesScene final : public Scene {
public:
    explicit ParticlesScene(const SceneOptions& o) : data_(o) {
        gs_.viewProj = data_.viewProj;
        gs_.billboardSize = data_.billboardSize;
        ps_fire_.billboardTexture = &data_.texture;
    }
    std::string_view name() const override { return "particles"; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        data_.drawOccluder(context);  // draw 1, the "giraffe"
        // Draw 2: the particles, additive, depth test on, depth write off.
        context.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
        context.setBlendState(BlendState::additive());
        context.setVertexBuffer(0, &data_.particles);
        context.setPrimitiveTopology(Topology::PointList);
        context.draw(shaders::VsBillboard{}, gs_, ps_fire_, data_.count);
    }

private:
    ParticleSceneData data_;
    shaders::GsBillboard gs_;
    shaders::PsFire ps_fire_;
};

}  // namespace

std::unique_ptr<Scene> makeParticlesScene(const SceneOptions& options) {
    return std::make_unique<ParticlesScene>(options);
}

}  // namespace raster
