// SCENES.md's `media`: the lecture's ray marching through a metaball medium, lit by a directional light
// with shadow rays (raster/media/metaball_march.hpp), as one full-screen draw whose pixel shader marches
// each pixel's view ray (raster/shaders/media.hpp). Empty space is skipped exactly through a grid of
// kMediaGridCells³ cells over the medium's box (docs/PERFORMANCE.md, "media": the grid size measured).
#include <algorithm>
#include <memory>
#include <optional>
#include <vector>

#include "raster/pipeline_impl.hpp"
#include "raster/shaders/media.hpp"
#include "scene_light.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

using media::mediaSceneLight;
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
        const media::Box& box = volume_.box;
        ps_.light = optionsLight(mediaSceneLight(), o, 0.5f * (box.lo + box.hi));
        ps_.background = kMediaBackground;
    }
    std::string_view name() const override { return "media"; }

    // The pixel shader's march at the pixel's centre: ndc as the full-screen triangle interpolates it
    // there (y up), the shader's ray and settings, every evaluated sample recorded.
    std::optional<PixelMarch> pixelMarch(uint32_t x, uint32_t y, uint32_t width, uint32_t height) const override {
        const glm::vec3 d = shaders::viewRay(ps_.invViewProj, shaders::pixelNdc(x, y, width, height));
        PixelMarch march;
        const media::MarchResult r = media::marchMetaballs(*ps_.volume, ps_.light, ps_.settings, ps_.eye, d,
                                                           [&](const media::MarchSample& s) { march.samples.push_back(s); });
        const auto [t_near, t_far] = media::slabInterval(ps_.volume->box, ps_.eye, d);
        march.steps = ps_.settings.steps;
        march.t0 = std::max(t_near, 0.0f), march.t1 = t_far;
        march.ds = (march.t1 - march.t0) / float(march.steps);
        march.radiance = r.radiance, march.transmittance = r.transmittance, march.background = ps_.background;
        march.colour = glm::clamp(r.radiance + r.transmittance * ps_.background, 0.0f, 1.0f);
        march.densityEvaluations = r.densityEvaluations;
        return march;
    }

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
