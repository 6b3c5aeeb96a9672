#include "raster/scenes.hpp"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/shaders/basic.hpp"
#include "raster/shaders/billboard.hpp"
#include "raster/shaders/fog.hpp"

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

namespace {

glm::mat4 projection(const SceneOptions& o) {
    return glm::perspectiveRH_ZO(glm::radians(60.0f), float(o.width) / float(o.height), 0.1f, 100.0f);
}

glm::mat4 lookAt(const SceneCamera& c) { return glm::lookAtRH(c.eye, c.target, glm::vec3(0, 1, 0)); }

// SCENES.md's cameras.
const SceneCamera kParticlesCamera{{0, 0.3f, 4}, {0, 0, 0}};
const SceneCamera kFogCamera{{0, 1.5f, 6}, {0, 0.5f, -10}};

void beginFrame(Context& context, RenderTarget& color, DepthTarget& depth) {
    context.clearRenderTarget(color, {0, 0, 0, 1});
    context.clearDepthTarget(depth, 1.0f);
    context.setRenderTargets(&color, &depth);
    context.setViewport({0, 0, float(color.width()), float(color.height()), 0, 1});
    RasterizerState rs;
    rs.cullMode = CullMode::None;
    context.setRasterizerState(rs);
}

class ParticlesScene final : public Scene {
public:
    explicit ParticlesScene(const SceneOptions& o) : texture_(o.texture.empty() ? makeFireTexture()
                                                                                   : Texture2D::fromPng(o.texture)) {
        const glm::mat4 view = lookAt(o.camera.value_or(kParticlesCamera));
        const glm::mat4 proj = projection(o);
        const glm::mat4 view_proj = proj * view;
        const std::vector<glm::vec3> occluder = {{-0.6f, -1.2f, 0}, {0.6f, -1.2f, 0}, {0.6f, 0.4f, 0},
                                                 {-0.6f, -1.2f, 0}, {0.6f, 0.4f, 0},  {-0.6f, 0.4f, 0}};
        occluder_ = VertexBuffer::create(occluder);
        std::vector<glm::vec3> particles(o.count);
        for (uint32_t i = 0; i < o.count; ++i) particles[i] = particlePosition(i);
        particles_ = VertexBuffer::create(particles);
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
        layout_ = InputLayout(desc);
        vs_occluder_.viewProj = view_proj;
        ps_occluder_.color = glm::vec4(89, 140, 64, 255) / 255.0f;
        gs_.viewProj = view_proj;
        const float h = 0.08f;
        gs_.billboardSize = {h * proj[0][0], h * proj[1][1]};
        ps_fire_.billboardTexture = &texture_;
        count_ = o.count;
    }
    std::string_view name() const override { return "particles"; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginFrame(context, color, depth);
        context.setInputLayout(&layout_);
        // Draw 1: the occluder ("giraffe"), opaque, depth test and write.
        context.setDepthStencilState({true, true, ComparisonFunc::Less});
        context.setBlendState(BlendState::opaque());
        context.setVertexBuffer(0, &occluder_);
        context.setPrimitiveTopology(Topology::TriangleList);
        context.draw(vs_occluder_, ps_occluder_, 6);
        // Draw 2: the particles, additive, depth test on, depth write off.
        context.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
        context.setBlendState(BlendState::additive());
        context.setVertexBuffer(0, &particles_);
        context.setPrimitiveTopology(Topology::PointList);
        context.draw(shaders::VsBillboard{}, gs_, ps_fire_, count_);
    }

private:
    Texture2D texture_;
    VertexBuffer occluder_, particles_;
    InputLayout layout_;
    shaders::VsTransform vs_occluder_;
    shaders::PsConstant ps_occluder_;
    shaders::GsBillboard gs_;
    shaders::PsFire ps_fire_;
    uint32_t count_ = 0;
};

struct LitVertexData {
    glm::vec3 position, normal;
};

void pushTriangle(std::vector<LitVertexData>& v, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 n) {
    v.push_back({a, n}), v.push_back({b, n}), v.push_back({c, n});
}

// A cube of half-extent h at c, 12 triangles with flat normals, in SCENES.md's order.
void pushCube(std::vector<LitVertexData>& v, glm::vec3 c, float h) {
    auto p = [&](float x, float y, float z) { return c + glm::vec3(x, y, z) * h; };
    glm::vec3 n(1, 0, 0);
    pushTriangle(v, p(1, -1, -1), p(1, 1, -1), p(1, 1, 1), n), pushTriangle(v, p(1, -1, -1), p(1, 1, 1), p(1, -1, 1), n);
    n = {-1, 0, 0};
    pushTriangle(v, p(-1, -1, -1), p(-1, 1, 1), p(-1, 1, -1), n);
    pushTriangle(v, p(-1, -1, -1), p(-1, -1, 1), p(-1, 1, 1), n);
    n = {0, 1, 0};
    pushTriangle(v, p(-1, 1, -1), p(-1, 1, 1), p(1, 1, 1), n), pushTriangle(v, p(-1, 1, -1), p(1, 1, 1), p(1, 1, -1), n);
    n = {0, -1, 0};
    pushTriangle(v, p(-1, -1, -1), p(1, -1, 1), p(-1, -1, 1), n);
    pushTriangle(v, p(-1, -1, -1), p(1, -1, -1), p(1, -1, 1), n);
    n = {0, 0, 1};
    pushTriangle(v, p(-1, -1, 1), p(1, -1, 1), p(1, 1, 1), n), pushTriangle(v, p(-1, -1, 1), p(1, 1, 1), p(-1, 1, 1), n);
    n = {0, 0, -1};
    pushTriangle(v, p(-1, -1, -1), p(1, 1, -1), p(1, -1, -1), n);
    pushTriangle(v, p(-1, -1, -1), p(-1, 1, -1), p(1, 1, -1), n);
}

class FogScene final : public Scene {
public:
    explicit FogScene(const SceneOptions& o) {
        const SceneCamera camera = o.camera.value_or(kFogCamera);
        const glm::vec3 eye = camera.eye;
        const glm::mat4 view = lookAt(camera);
        const glm::mat4 view_proj = projection(o) * view;
        std::vector<LitVertexData> v;
        const glm::vec3 up(0, 1, 0);
        pushTriangle(v, {-40, 0, 8}, {40, 0, 8}, {40, 0, -80}, up);
        pushTriangle(v, {-40, 0, 8}, {40, 0, -80}, {-40, 0, -80}, up);
        for (uint32_t ix = 0; ix < o.cubes; ++ix)
            for (uint32_t iz = 0; iz < o.cubes; ++iz)
                pushCube(v, {(float(ix) - float(o.cubes - 1) / 2.0f) * 4.0f, 0.5f, -float(iz) * 4.0f - 2.0f}, 0.5f);
        geometry_ = VertexBuffer::create(v);
        vertex_count_ = uint32_t(v.size());
        const InputElementDesc lit[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                        {"NORMAL", 0, Format::R32G32B32_FLOAT, 0, 12}};
        lit_layout_ = InputLayout(lit);
        const std::vector<glm::vec2> sky = {{-1, -1}, {3, -1}, {-1, 3}};
        sky_ = VertexBuffer::create(sky);
        const InputElementDesc sky_desc[] = {{"POSITION", 0, Format::R32G32_FLOAT, 0, 0}};
        sky_layout_ = InputLayout(sky_desc);

        shaders::FogMedium fog;
        fog.height = o.heightFog;
        vs_lit_.viewProj = view_proj;
        ps_fog_.fog = fog;
        ps_fog_.eye = eye;
        ps_sky_.fog = fog;
        ps_sky_.eye = eye;
        vs_sky_.eye = eye;
        vs_sky_.invViewProj = glm::inverse(view_proj);
    }
    std::string_view name() const override { return "fog"; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginFrame(context, color, depth);
        context.setBlendState(BlendState::opaque());
        context.setPrimitiveTopology(Topology::TriangleList);
        context.setDepthStencilState({true, true, ComparisonFunc::Less});
        context.setInputLayout(&lit_layout_);
        context.setVertexBuffer(0, &geometry_);
        context.draw(vs_lit_, ps_fog_, vertex_count_);
        context.setDepthStencilState({true, true, ComparisonFunc::LessEqual});
        context.setInputLayout(&sky_layout_);
        context.setVertexBuffer(0, &sky_);
        context.draw(vs_sky_, ps_sky_, 3);
    }

private:
    VertexBuffer geometry_, sky_;
    InputLayout lit_layout_, sky_layout_;
    uint32_t vertex_count_ = 0;
    shaders::VsLit vs_lit_;
    shaders::PsFog ps_fog_;
    shaders::VsSky vs_sky_;
    shaders::PsSky ps_sky_;
};

}  // namespace

std::vector<std::string> sceneNames() { return {"particles", "fog"}; }

SceneCamera defaultCamera(std::string_view name) {
    if (name == "particles") return kParticlesCamera;
    if (name == "fog") return kFogCamera;
    throw Error(ErrorCode::InvalidArgument, "unknown scene '" + std::string(name) + "' (known: particles, fog)");
}

std::unique_ptr<Scene> makeScene(std::string_view name, const SceneOptions& options) {
    RASTER_REQUIRE(options.width > 0 && options.height > 0 && options.width <= RenderTarget::kMaxSize &&
                       options.height <= RenderTarget::kMaxSize,
                   InvalidArgument,
                   "image size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                       " is outside 1.." + std::to_string(RenderTarget::kMaxSize));
    if (options.camera) {
        const SceneCamera& c = *options.camera;
        const glm::vec3 view = c.target - c.eye;
        const auto text = [](glm::vec3 v) {
            return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
        };
        // Look-at needs a direction, and one that is not vertical (+y is its up).
        bool finite = true;
        for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(c.eye[k]) && std::isfinite(c.target[k]);
        RASTER_REQUIRE(finite && view.x * view.x + view.z * view.z > 1e-12f * glm::dot(view, view) &&
                           glm::dot(view, view) > 0.0f,
                       InvalidArgument,
                       "camera eye " + text(c.eye) + " and target " + text(c.target) +
                           " do not make a view direction (they must be finite, apart, and not one above the other)");
    }
    if (name == "particles") {
        RASTER_REQUIRE(options.count <= 50'000'000, InvalidArgument,
                       "particle count " + std::to_string(options.count) + " is above 50000000");
        return std::make_unique<ParticlesScene>(options);
    }
    if (name == "fog") {
        RASTER_REQUIRE(options.cubes <= 1024, InvalidArgument,
                       "cube count " + std::to_string(options.cubes) + " per side is above 1024");
        return std::make_unique<FogScene>(options);
    }
    throw Error(ErrorCode::InvalidArgument, "unknown scene '" + std::string(name) + "' (known: particles, fog)");
}

}  // namespace raster
