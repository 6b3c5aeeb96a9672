// SCENES.md's fog: a ground plane and a lattice of cubes in height or constant fog, under the sky.
#include <vector>

#include "raster/shaders/basic.hpp"
#include "raster/shaders/fog.hpp"
#include "raster/pipeline_impl.hpp"
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

}  // namespace

std::unique_ptr<Scene> makeFogScene(const SceneOptions& options) { return std::make_unique<FogScene>(options); }

}  // namespace raster
