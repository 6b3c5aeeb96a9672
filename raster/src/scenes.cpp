#include "raster/scenes.hpp"

#include <cmath>
#include <map>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/shaders/basic.hpp"
#include "lecture/fire_shaders.hpp"
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

glm::mat4 sceneProjection(const SceneOptions& o) {
    return glm::perspectiveRH_ZO(glm::radians(60.0f), float(o.width) / float(o.height), 0.1f, 100.0f);
}

glm::mat4 sceneView(const SceneCamera& c) { return glm::lookAtRH(c.eye, c.target, glm::vec3(0, 1, 0)); }

namespace {

// SCENES.md's cameras. constexpr, so initialised before any lab's registration reads one.
constexpr SceneCamera kParticlesCamera{{0, 0.3f, 4}, {0, 0, 0}};
constexpr SceneCamera kFogCamera{{0, 1.5f, 6}, {0, 0.5f, -10}};

}  // namespace

void beginSceneFrame(Context& context, RenderTarget& color, DepthTarget& depth) {
    context.clearRenderTarget(color, {0, 0, 0, 1});
    context.clearDepthTarget(depth, 1.0f);
    context.setRenderTargets(&color, &depth);
    context.setViewport({0, 0, float(color.width()), float(color.height()), 0, 1});
    RasterizerState rs;
    rs.cullMode = CullMode::None;
    context.setRasterizerState(rs);
}

ParticleSceneData::ParticleSceneData(const SceneOptions& o)
    : texture(o.texture.empty() ? makeFireTexture() : Texture2D::fromPng(o.texture)), count(o.count) {
    const glm::mat4 proj = sceneProjection(o);
    viewProj = proj * sceneView(o.camera.value_or(kParticlesCamera));
    const float h = 0.08f;
    billboardSize = {h * proj[0][0], h * proj[1][1]};
    occluderColor = glm::vec4(89, 140, 64, 255) / 255.0f;
    const std::vector<glm::vec3> triangles = {{-0.6f, -1.2f, 0}, {0.6f, -1.2f, 0}, {0.6f, 0.4f, 0},
                                              {-0.6f, -1.2f, 0}, {0.6f, 0.4f, 0},  {-0.6f, 0.4f, 0}};
    occluder = VertexBuffer::create(triangles);
    std::vector<glm::vec3> positions;
    allocateOrThrow("the positions of " + std::to_string(o.count) + " particles", byteCount(o.count, sizeof(glm::vec3)),
                    [&] { positions.resize(o.count); });
    for (uint32_t i = 0; i < o.count; ++i) positions[i] = particlePosition(i);
    particles = VertexBuffer::create(positions);
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
    layout = InputLayout(desc);
}

void ParticleSceneData::drawOccluder(Context& context) const {
    shaders::VsTransform vs;
    vs.viewProj = viewProj;
    shaders::PsConstant ps;
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
        const glm::mat4 view = sceneView(camera);
        const glm::mat4 view_proj = sceneProjection(o) * view;
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
        beginSceneFrame(context, color, depth);
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

// Filled before main by the labs' static registrations, so a function-local static: the order in
// which translation units initialise is unspecified. Read-only once main runs.
std::map<std::string, SceneEntry, std::less<>>& registry() {
    static std::map<std::string, SceneEntry, std::less<>> entries;
    return entries;
}

std::string knownScenes() {
    std::string text;
    for (const std::string& n : sceneNames()) text += (text.empty() ? "" : ", ") + n;
    return text;
}

[[noreturn]] void unknownScene(std::string_view name) {
    throw Error(ErrorCode::InvalidArgument, "unknown scene '" + std::string(name) + "' (known: " + knownScenes() + ")");
}

}  // namespace

void registerScene(SceneEntry entry) {
    const std::string& n = entry.name;
    RASTER_REQUIRE(!n.empty() && n.size() <= 64, InvalidArgument, "a registered scene needs a name of 1..64 characters");
    for (char c : n)
        RASTER_REQUIRE((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '@',
                       InvalidArgument, "scene name '" + n + "' may hold only a-z, 0-9, _, - and @");
    RASTER_REQUIRE(n != "particles" && n != "fog" && !registry().contains(n), InvalidArgument,
                   "scene '" + n + "' is registered twice (two labs of one name?)");
    RASTER_REQUIRE(entry.make != nullptr, InvalidArgument, "scene '" + n + "' is registered without a factory");
    registry().emplace(n, std::move(entry));
}

const SceneEntry* findRegisteredScene(std::string_view name) {
    const auto it = registry().find(name);
    return it == registry().end() ? nullptr : &it->second;
}

std::string solutionSceneOf(std::string_view name) {
    if (name.find('@') != std::string_view::npos) return {};
    std::string solution = std::string(name) + "@solution";
    return findRegisteredScene(solution) ? solution : std::string();
}

std::vector<std::string> sceneNames() {
    std::vector<std::string> names = {"particles", "fog"};
    for (const auto& [name, entry] : registry()) names.push_back(name);
    return names;
}

SceneCamera defaultCamera(std::string_view name) {
    if (name == "particles") return kParticlesCamera;
    if (name == "fog") return kFogCamera;
    if (const SceneEntry* entry = findRegisteredScene(name)) return entry->camera;
    unknownScene(name);
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
    const SceneEntry* entry = findRegisteredScene(name);
    if (!entry) unknownScene(name);
    std::unique_ptr<Scene> scene = entry->make(entry->name, options);
    RASTER_CHECK(scene && scene->name() == entry->name);
    return scene;
}

}  // namespace raster
