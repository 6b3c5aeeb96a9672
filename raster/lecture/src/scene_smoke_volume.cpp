// The `smoke-volume` scene: the smoke scene's particle system (smoke_world.hpp: the same emitter,
// effectors, count, seed and clock, so the same particles at the same time as `smoke`) drawn as a
// volume instead of billboards. The living particles are splatted as cubic B-spline kernels into a
// voxel grid fitted around them (raster/media/particle_volume.hpp), and the grid is marched as the
// cloud is (raster/media/cloud_march.hpp): the sun's single scattering with shadow rays through the
// smoke, an isotropic ambient term, empty space skipped through a majorant grid. Over the smoke
// scene's ground and box, drawn first; the march stops at the surface each pixel's ray meets
// (raster/shaders/smoke_volume.hpp), so the box hides the smoke behind it.
//
// Animated: advancing the clock steps the particle system and splats the particles again.
// --voxels N sets the grid's longest axis (kDefaultSmokeVoxels; 8 to 1024), --count, --time and
// --seed as `smoke`.
#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "raster/media/particle_volume.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shaders/smoke_volume.hpp"
#include "scene_list.hpp"
#include "smoke_world.hpp"

namespace raster {

namespace {

// The smoke scene's light (shaders::PsSolid: the direction, a warm sun) as a volume light: grey smoke,
// mostly scattering, a little forward.
media::VolumeLight smokeLight() {
    media::VolumeLight light;
    light.toLight = shaders::PsSolid{}.light;
    light.sun = {14.0f, 13.0f, 12.0f};
    light.ambient = {0.22f, 0.22f, 0.25f};
    light.g = 0.2f;
    light.albedo = 0.9f;
    return light;
}

}  // namespace

SmokeVolume makeSmokeVolume(std::span<const Particle> particles, int longest) {
    const std::vector<media::ParticleSplat> splats =
        media::particleSplats(particles, kOpticalDepthPerOpacity, kRadiusPerSize);
    const media::SplatGrid grid = media::fitSplatGrid(splats, longest);
    SmokeVolume v;
    v.origin = grid.bounds.lo;
    v.voxelsPerMetre = float(grid.dims.x) / (grid.bounds.hi.x - grid.bounds.lo.x);  // cubic voxels
    // The grid holds extinction in 1/m; the march takes it per voxel.
    v.volume = media::makeCloudVolume(media::splatParticles(splats, grid), 1.0f / v.voxelsPerMetre, kSmokeCellVoxels);
    return v;
}

namespace {

class SmokeVolumeScene final : public Scene {
public:
    explicit SmokeVolumeScene(const SceneOptions& o)
        : system_(smokeDesc(o.count.value_or(kDefaultSmokeCount), o.seed)),
          voxels_(int(o.voxels.value_or(kDefaultSmokeVoxels))),
          ground_(sceneProjection(o) * sceneView(o.camera.value_or(kSmokeCamera))) {
        const SceneCamera camera = o.camera.value_or(kSmokeCamera);
        shaders::PsCloudMarch& march = ps_.march;
        march.invViewProj = glm::inverse(ground_.vs.viewProj);
        march.eye = camera.eye;
        march.light = smokeLight();
        time_ = o.time.value_or(kDefaultSmokeTime);
        system_.advance(time_);
        splat();
    }
    std::string_view name() const override { return "smoke-volume"; }
    bool animated() const override { return true; }
    double time() const override { return time_; }

    // The pixel shader's march at the pixel's centre, every evaluated sample recorded; distances in
    // metres from the eye. It ends where the last render's opaque pass left its depth (the ground or
    // the box); before a render at this size, at the volume's far side.
    std::optional<PixelMarch> pixelMarch(uint32_t x, uint32_t y, uint32_t width,
                                         uint32_t height) const override {
        const glm::vec2 ndc = shaders::pixelNdc(x, y, width, height);
        const glm::vec3 d = shaders::viewRay(ps_.march.invViewProj, ndc);
        const DepthTexture& depth = ps_.sceneDepth;
        const float z = depth.width() == width && depth.height() == height
                            ? depth.atPixel(float(x) + 0.5f, float(y) + 0.5f)
                            : 1.0f;  // a cleared depth: nothing in front of the volume's far side
        const auto [s0, s1] = ps_.marchInterval(d, ndc, z);
        PixelMarch march = ps_.march.tracedMarch(d, s0, s1);
        march.colour = glm::vec3(ps_.shade(d, ndc, z));  // premultiplied: the ground behind adds T·dst
        march.over = true;
        return march;
    }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        ground_.render(context, color, depth);
        triangle_.bind(context);
        BlendState over;
        over.renderTarget[0] = {true, Blend::One, Blend::InvSrcAlpha, BlendOp::Add,
                                Blend::One, Blend::InvSrcAlpha, BlendOp::Add, 0xF};
        context.setBlendState(over);
        ps_.sceneDepth = DepthTexture(depth);
        context.draw(vs_, ps_, 3);
    }

protected:
    void advanceBy(double seconds) override {
        system_.advance(seconds);
        time_ += seconds;
        splat();
    }

private:
    // The living particles into the volume, and the shader's frame to match.
    void splat() {
        smoke_ = makeSmokeVolume(system_.vertices(), voxels_);
        ps_.march.origin = smoke_.origin;
        ps_.march.voxelsPerMetre = smoke_.voxelsPerMetre;
        ps_.march.volume = &smoke_.volume;
    }

    ParticleSystem system_;
    int voxels_;
    double time_ = 0.0;
    SmokeVolume smoke_;
    SmokeGround ground_;
    FullScreenTriangle triangle_;
    shaders::VsMediaRay vs_;
    shaders::PsSmokeVolume ps_;
};

}  // namespace

std::unique_ptr<Scene> makeSmokeVolumeScene(const SceneOptions& options) {
    RASTER_REQUIRE(!options.voxels || (*options.voxels >= 8 && *options.voxels <= 1024), InvalidArgument,
                   "smoke-volume: " + std::to_string(options.voxels.value_or(0)) +
                       " voxels along the longest axis (8 to 1024)");
    return std::make_unique<SmokeVolumeScene>(options);
}

}  // namespace raster
