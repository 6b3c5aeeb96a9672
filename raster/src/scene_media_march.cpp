// SCENES.md's `media`: the lecture's ray marching through a metaball medium, lit by a directional light
// with shadow rays (raster/media/metaball_march.hpp), as one full-screen draw whose pixel shader marches
// each pixel's view ray (raster/shaders/media.hpp). Empty space is skipped exactly through a grid of
// kMediaGridCells³ cells over the medium's box (docs/PERFORMANCE.md, "media": the grid size measured).
#include <memory>

#include "raster/pipeline_impl.hpp"
#include "raster/shaders/media.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

// The light, background and phase of SCENES.md's `media`.
media::VolumeLight mediaSceneLight() {
    media::VolumeLight light;
    light.toLight = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
    light.sun = {14.0f, 13.0f, 11.0f};
    light.ambient = {0.10f, 0.12f, 0.18f};
    light.g = 0.4f;
    light.albedo = 0.9f;
    return light;
}
constexpr glm::vec3 kMediaBackground{0.08f, 0.10f, 0.16f};

class MediaMarchScene final : public Scene {
public:
    explicit MediaMarchScene(const SceneOptions& o)
        : volume_(media::makeMetaballVolume(media::mediaSceneMetaballs(), media::mediaSceneBox(), 4.0f,
                                            kMediaGridCells)) {
        const SceneCamera camera = o.camera.value_or(kMediaMarchCamera);
        ps_.invViewProj = glm::inverse(sceneProjection(o) * sceneView(camera));
        ps_.eye = camera.eye;
        ps_.volume = &volume_;
        ps_.light = mediaSceneLight();
        ps_.background = kMediaBackground;
    }
    std::string_view name() const override { return "media"; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        triangle_.bind(context);
        context.draw(vs_, ps_, 3);
    }

private:
    media::MetaballVolume volume_;
    FullScreenTriangle triangle_;
    shaders::VsMediaRay vs_;
    shaders::PsMediaMarch ps_;
};

}  // namespace

std::unique_ptr<Scene> makeMediaMarchScene(const SceneOptions& options) {
    return std::make_unique<MediaMarchScene>(options);
}

}  // namespace raster
