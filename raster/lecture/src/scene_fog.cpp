// SCENES.md's fog: a ground plane and a lattice of cubes in height or constant fog, under the sky; and
// the lecture's fog figures (fog-constant, fog-black, fog-coloured, fog-height) in the same world made
// recognisable (FogWorldData), drawn with the same shaders, so that this file instantiates the pipeline
// for them once.
#include <array>
#include <string>
#include <vector>

#include "fog_ground.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shaders/basic.hpp"
#include "raster/shaders/fog.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

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

// The options' medium, where they set one (unset: the scene's own, bit for bit).
void applyFogOptions(const SceneOptions& o, shaders::FogMedium& fog) {
    if (o.fogSigma) fog.sigma = *o.fogSigma;
    if (o.fogSource) fog.q = *o.fogSource;
    if (o.fogFalloff) fog.b = -*o.fogFalloff;
}

class FogScene final : public Scene {
public:
    explicit FogScene(const SceneOptions& o) : world_(o) {}
    std::string_view name() const override { return "fog"; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        world_.render(context, color, depth, world_.psFog);
    }

private:
    FogGround world_;
};

// The lecture's fog figures (NOTES.md, part 2), each with the sky at infinite distance. Their media by
// default; the options' σ, q and falloff replace them.
struct FogFigure {
    std::string_view name;
    glm::vec3 sigma, source;  // 1/m; radiance per metre (the fog's colour q/σ)
    bool height;
    float falloff = 0.0f;     // B: the density falls as e^{−B·y}
};
// Grey-blue fog, the benchmark's colour (0.6, 0.65, 0.75), thinner than its constant fog so that the
// near cubes keep their colours; black fog the same without its source; coloured fog three times as
// dense and sand-coloured, so that the farther half of the lattice and the whole sky are the fog's
// colour; height fog the benchmark's.
constexpr glm::vec3 kFigureSigma{0.035f, 0.04f, 0.05f};
constexpr glm::vec3 kFigureColour{0.6f, 0.65f, 0.75f}, kColouredFogColour{0.85f, 0.55f, 0.25f};
constexpr std::array<FogFigure, 4> kFogFigures{{
    {"fog-constant", kFigureSigma, kFigureSigma * kFigureColour, false},
    {"fog-black", kFigureSigma, glm::vec3(0.0f), false},
    {"fog-coloured", 3.0f * glm::vec3(0.04f), 3.0f * glm::vec3(0.04f) * kColouredFogColour, false},
    {"fog-height", {0.06f, 0.07f, 0.09f}, glm::vec3(0.06f, 0.07f, 0.09f) * kFigureColour, true, 0.5f},
}};

const FogFigure& fogFigure(std::string_view name) {
    for (const FogFigure& figure : kFogFigures)
        if (figure.name == name) return figure;
    throw Error(ErrorCode::InvalidArgument, "no fog figure '" + std::string(name) + "'");
}

// One figure: the world's parts each drawn lit through the medium, then the sky (depth 1, LessEqual:
// only where nothing was drawn) at infinite distance. The same shader types as FogScene.
class FogFigureScene final : public Scene {
public:
    FogFigureScene(const FogFigure& figure, const SceneOptions& o) : figure_(figure), world_(o.cubes) {
        const SceneCamera camera = o.camera.value_or(kFogCamera);
        const glm::mat4 view_proj = sceneProjection(o) * sceneView(camera);
        shaders::FogMedium fog;
        fog.sigma = figure.sigma, fog.q = figure.source, fog.height = figure.height, fog.b = -figure.falloff;
        applyFogOptions(o, fog);
        vs_lit_.viewProj = view_proj;
        ps_fog_.fog = fog, ps_fog_.eye = camera.eye;
        ps_sky_.fog = fog, ps_sky_.eye = camera.eye;
        vs_sky_.eye = camera.eye, vs_sky_.invViewProj = glm::inverse(view_proj);
    }
    std::string_view name() const override { return figure_.name; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        context.setBlendState(BlendState::opaque());
        context.setPrimitiveTopology(Topology::TriangleList);
        context.setDepthStencilState({true, true, ComparisonFunc::Less});
        context.setInputLayout(&world_.layout);
        context.setVertexBuffer(0, &world_.lit);
        shaders::PsFog ps = ps_fog_;
        for (const FogWorldData::Part& part : world_.parts) {
            if (part.count == 0) continue;
            ps.albedo = part.albedo;
            context.draw(vs_lit_, ps, part.count, part.first);
        }
        context.setDepthStencilState({true, true, ComparisonFunc::LessEqual});
        context.setInputLayout(&world_.skyLayout);
        context.setVertexBuffer(0, &world_.sky);
        context.draw(vs_sky_, ps_sky_, 3);
    }

private:
    const FogFigure& figure_;
    FogWorldData world_;
    shaders::VsLit vs_lit_;
    shaders::PsFog ps_fog_;
    shaders::VsSky vs_sky_;
    shaders::PsSky ps_sky_;
};

}  // namespace

FogGround::FogGround(const SceneOptions& o) {
    const SceneCamera camera = o.camera.value_or(kFogCamera);
    const glm::vec3 eye = camera.eye;
    const glm::mat4 view_proj = sceneProjection(o) * sceneView(camera);
    std::vector<LitVertexData> v;
    const glm::vec3 up(0, 1, 0);
    pushTriangle(v, {-40, 0, 8}, {40, 0, 8}, {40, 0, -80}, up);
    pushTriangle(v, {-40, 0, 8}, {40, 0, -80}, {-40, 0, -80}, up);
    for (uint32_t ix = 0; ix < o.cubes; ++ix)
        for (uint32_t iz = 0; iz < o.cubes; ++iz)
            pushCube(v, {(float(ix) - float(o.cubes - 1) / 2.0f) * 4.0f, 0.5f, -float(iz) * 4.0f - 2.0f}, 0.5f);
    geometry = VertexBuffer::create(v);
    vertexCount = uint32_t(v.size());
    const InputElementDesc lit[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                    {"NORMAL", 0, Format::R32G32B32_FLOAT, 0, 12}};
    litLayout = InputLayout(lit);
    const std::vector<glm::vec2> corners = {{-1, -1}, {3, -1}, {-1, 3}};
    sky = VertexBuffer::create(corners);
    const InputElementDesc sky_desc[] = {{"POSITION", 0, Format::R32G32_FLOAT, 0, 0}};
    skyLayout = InputLayout(sky_desc);

    shaders::FogMedium fog;
    fog.height = o.heightFog;
    applyFogOptions(o, fog);
    vsLit.viewProj = view_proj;
    psFog.fog = fog;
    psFog.eye = eye;
    psSky.fog = fog;
    psSky.eye = eye;
    vsSky.eye = eye;
    vsSky.invViewProj = glm::inverse(view_proj);
}

FogWorldData::FogWorldData(uint32_t cubes) {
    constexpr float kTile = 2.0f;
    constexpr glm::vec3 kLightTile{0.62f, 0.62f, 0.58f}, kDarkTile{0.36f, 0.37f, 0.40f};
    constexpr std::array<glm::vec3, 4> kCubeColours{
        {{0.80f, 0.30f, 0.24f}, {0.32f, 0.66f, 0.30f}, {0.28f, 0.44f, 0.84f}, {0.88f, 0.76f, 0.28f}}};
    std::vector<LitVertexData> v;
    const glm::vec3 up(0, 1, 0);
    for (int dark = 0; dark < 2; ++dark) {
        const uint32_t first = uint32_t(v.size());
        for (int i = 0; i < 40; ++i)
            for (int k = 0; k < 44; ++k) {
                if ((i + k) % 2 != dark) continue;
                const float x0 = -40.0f + kTile * float(i), z0 = 8.0f - kTile * float(k);
                const glm::vec3 a(x0, 0, z0), b(x0 + kTile, 0, z0), c(x0 + kTile, 0, z0 - kTile),
                    d(x0, 0, z0 - kTile);
                pushTriangle(v, a, b, c, up), pushTriangle(v, a, c, d, up);
            }
        parts.push_back({first, uint32_t(v.size()) - first, dark ? kDarkTile : kLightTile});
    }
    for (uint32_t colour = 0; colour < kCubeColours.size(); ++colour) {
        const uint32_t first = uint32_t(v.size());
        for (uint32_t ix = 0; ix < cubes; ++ix)
            for (uint32_t iz = 0; iz < cubes; ++iz)
                if ((ix + iz) % 4 == colour)
                    pushCube(v, {(float(ix) - float(cubes - 1) / 2.0f) * 4.0f, 0.5f, -float(iz) * 4.0f - 2.0f},
                             0.5f);
        parts.push_back({first, uint32_t(v.size()) - first, kCubeColours[colour]});
    }
    lit = VertexBuffer::create(v);
    const InputElementDesc lit_desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                         {"NORMAL", 0, Format::R32G32B32_FLOAT, 0, 12}};
    layout = InputLayout(lit_desc);
    const std::vector<glm::vec2> sky_corners = {{-1, -1}, {3, -1}, {-1, 3}};
    sky = VertexBuffer::create(sky_corners);
    const InputElementDesc sky_desc[] = {{"POSITION", 0, Format::R32G32_FLOAT, 0, 0}};
    skyLayout = InputLayout(sky_desc);
}

std::unique_ptr<Scene> makeFogScene(const SceneOptions& options) { return std::make_unique<FogScene>(options); }

std::vector<std::string_view> fogFigureNames() {
    std::vector<std::string_view> names;
    for (const FogFigure& figure : kFogFigures) names.push_back(figure.name);
    return names;
}

std::unique_ptr<Scene> makeFogFigureScene(std::string_view name, const SceneOptions& options) {
    return std::make_unique<FogFigureScene>(fogFigure(name), options);
}

}  // namespace raster
