// The `cloud` scene: a voxel cloud (media::makeCloudGrid, or a volume file) lit by the sun with single
// scattering, shadow rays and ambient light (raster/media/cloud_march.hpp), over the fog scene's ground
// and sky. The ground is the fog scene's world (FogGround: its draws and state), drawn first with the
// fog scene's ground shader made to take the cloud's shadow (shaders::PsCloudGround: the sun attenuated
// by the cloud's transmittance along each surface point's shadow ray); the cloud is then one
// full-screen draw whose pixel shader marches each pixel's view ray (raster/shaders/cloud.hpp), blended
// over it premultiplied.
//
// Depth: the cloud is drawn without a depth test, over whatever the ground pass left. That is correct
// wherever the cloud's box lies in front of the surface each ray hits: the box's bottom (kCloudBottom)
// is above the cubes' tops (y = 1) and the ground (y = 0), so for an eye above the cubes (every camera
// the scene and the viewer start from) a ray reaches the box before any surface or never meets both.
// An eye placed among the cubes can see the cloud drawn over a cube that hides it.
//
// `cloud-point`: the same cloud at night, lit from below by a point light (kPointLight: a lamp under
// it) with inverse-square falloff and shadow rays that end at the light, over a plain
// night sky; no ground and no fog.
//
// --light and --light-intensity (SceneOptions::light) put another light in place of either scene's
// (scene_light.hpp), the cloud's centre the point whose irradiance a light of the other kind keeps;
// `cloud`'s ground is then lit by it too (PsCloudGround: the sun's direction, or the point light with
// its falloff and the cloud's shadow).
//
// Empty space is skipped through a majorant grid of kCloudCellVoxels³-voxel cells
// (docs/PERFORMANCE.md, "cloud": the cell size measured).
#include <algorithm>
#include <memory>
#include <optional>
#include <string>

#include "fog_ground.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shaders/cloud.hpp"
#include "scene_light.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

constexpr glm::vec3 kCloudCentre{0.0f, 3.6f, -4.0f};  // world, metres
constexpr float kCloudSize = 4.8f;                      // the volume's longest side, metres
constexpr float kCloudBottom = kCloudCentre.y - 0.5f * kCloudSize;
static_assert(kCloudBottom > 1.0f, "the cloud's box must lie above the cubes (header: depth)");
constexpr float kPeakExtinction = 12.0f;  // the densest voxel's extinction, 1/m
constexpr uint32_t kDefaultCloudVoxels = 256;
// cloud-point's light: under the cloud, in front of its middle, warm (a lamp below it); its radiant
// intensity per steradian (RGB), so that the irradiance at r metres is kPointIntensity/r².
constexpr glm::vec3 kPointLight{-0.5f, 1.6f, -2.6f};  // world, metres
constexpr glm::vec3 kPointIntensity{50.0f, 40.0f, 27.0f};
constexpr glm::vec3 kMoonlight{0.02f, 0.025f, 0.04f};  // cloud-point's ambient radiance
constexpr glm::vec4 kNightSky{0.015f, 0.02f, 0.045f, 1.0f};

// The sun of the ground's shading (PsFog's light), the sky's blue as ambient light.
media::VolumeLight cloudLight() {
    media::VolumeLight light;
    light.toLight = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
    light.sun = {22.0f, 21.0f, 19.0f};
    light.ambient = {0.30f, 0.36f, 0.46f};
    light.g = 0.3f;
    light.albedo = 0.95f;
    return light;
}

// The volume file of the options, or the generated cloud. A file's densities are scaled so that its
// densest voxel has kPeakExtinction, as the generated cloud's has; its voxels are taken as cubes, the
// longest side kCloudSize, centred on kCloudCentre.
media::VoxelGrid cloudGrid(const SceneOptions& o) {
    if (o.volume.empty()) return media::makeCloudGrid(int(o.voxels.value_or(kDefaultCloudVoxels)), o.seed);
    const bool nvdb = o.volume.size() >= 5 && o.volume.compare(o.volume.size() - 5, 5, ".nvdb") == 0;
    return nvdb ? media::loadNanoVdbGrid(o.volume)
                : media::loadRawVoxelGrid(o.volume, media::VoxelBox{glm::vec3(-1.0f), glm::vec3(1.0f)});
}

// cloud-point's light, world metres: the lamp under the cloud, dim moonlight as ambient.
media::VolumeLight pointLight() {
    media::VolumeLight light = cloudLight();
    light.kind = media::LightKind::point;
    light.position = kPointLight;
    light.intensity = kPointIntensity;
    light.ambient = kMoonlight;
    return light;
}

// A light in the march's voxel units: a point light's position mapped as the world is, its intensity
// times voxelsPerMetre² (I_v/r_v² = I/r² with r_v = r·voxelsPerMetre); a direction stays as it is.
media::VolumeLight inVoxels(media::VolumeLight light, const glm::vec3& origin, float voxels_per_metre) {
    if (light.kind != media::LightKind::point) return light;
    light.position = (light.position - origin) * voxels_per_metre;
    light.intensity = light.intensity * (voxels_per_metre * voxels_per_metre);
    return light;
}

// The ground scene's options: the cloud's camera and the fog options as given.
SceneOptions groundOptions(const SceneOptions& o) {
    SceneOptions ground = o;
    ground.camera = o.camera.value_or(kCloudCamera);
    return ground;
}

class CloudScene final : public Scene {
public:
    CloudScene(const SceneOptions& o, bool point) : point_(point), ground_(groundOptions(o)) {
        media::VoxelGrid grid = cloudGrid(o);
        const glm::ivec3 dims = grid.dims();
        const float longest = float(std::max({dims.x, dims.y, dims.z}));
        const float voxels_per_metre = longest / kCloudSize;
        const float peak = grid.maxDensity();
        // μ per voxel = ρ·(kPeakExtinction/ρ_max)/voxelsPerMetre; an empty grid stays empty.
        const float scale = peak > 0.0f ? kPeakExtinction / peak / voxels_per_metre : 0.0f;
        volume_ = media::makeCloudVolume(std::move(grid), scale, kCloudCellVoxels);
        const SceneCamera camera = o.camera.value_or(kCloudCamera);
        ps_.invViewProj = glm::inverse(sceneProjection(o) * sceneView(camera));
        ps_.eye = camera.eye;
        ps_.voxelsPerMetre = voxels_per_metre;
        ps_.origin = kCloudCentre - 0.5f * glm::vec3(dims) / voxels_per_metre;
        ps_.volume = &volume_;
        const media::VolumeLight light = optionsLight(point_ ? pointLight() : cloudLight(), o, kCloudCentre);
        ps_.light = inVoxels(light, ps_.origin, voxels_per_metre);
        ps_.fog.height = o.heightFog;
        if (o.fogSigma) ps_.fog.sigma = *o.fogSigma;
        if (o.fogSource) ps_.fog.q = *o.fogSource;
        if (o.fogFalloff) ps_.fog.b = -*o.fogFalloff;
        RASTER_CHECK(ground_.psFog.light == cloudLight().toLight);  // the ground's sun is the cloud's
        ground_ps_.ground = ground_.psFog;
        if (light.kind == media::LightKind::point) {
            const media::VolumeLight sun = cloudLight();
            const auto mean = [](const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; };
            ground_ps_.pointLight = true;
            ground_ps_.lightPosition = light.position;
            ground_ps_.relativeIntensity = mean(light.intensity) / mean(sun.sun);
        } else {
            ground_ps_.ground.light = light.toLight;
        }
        ground_ps_.origin = ps_.origin;
        ground_ps_.voxelsPerMetre = voxels_per_metre;
        ground_ps_.volume = &volume_;
        ground_ps_.settings = ps_.settings;
        if (point_) {
            ps_.fog.sigma = glm::vec3(0.0f), ps_.fog.q = glm::vec3(0.0f);  // rgb = L: no fog in front
        }
    }
    std::string_view name() const override { return point_ ? "cloud-point" : "cloud"; }

    // The pixel shader's march at the pixel's centre, every evaluated sample recorded; distances in
    // metres from the eye.
    std::optional<PixelMarch> pixelMarch(uint32_t x, uint32_t y, uint32_t width, uint32_t height) const override {
        const glm::vec3 d = shaders::viewRay(ps_.invViewProj, shaders::pixelNdc(x, y, width, height));
        const auto [s_near, s_far] = media::slabInterval(volume_.box, ps_.eyeVoxels(), d);
        PixelMarch march = ps_.tracedMarch(d, std::max(s_near, 0.0f), s_far);
        march.colour = glm::vec3(ps_.shade(d));  // premultiplied: the ground behind adds T·dst
        march.over = true;
        return march;
    }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        if (point_) {
            beginSceneFrame(context, color, depth);
            context.clearRenderTarget(color, kNightSky);
        } else {
            ground_.render(context, color, depth, ground_ps_);
        }
        triangle_.bind(context);
        BlendState over;
        over.renderTarget[0] = {true, Blend::One, Blend::InvSrcAlpha, BlendOp::Add,
                                Blend::One, Blend::InvSrcAlpha, BlendOp::Add, 0xF};
        context.setBlendState(over);
        context.draw(vs_, ps_, 3);
    }

private:
    bool point_;  // cloud-point
    FogGround ground_;
    media::CloudVolume volume_;
    shaders::PsCloudGround ground_ps_;
    FullScreenTriangle triangle_;
    shaders::VsMediaRay vs_;
    shaders::PsCloudMarch ps_;
};

}  // namespace

std::unique_ptr<Scene> makeCloudScene(std::string_view name, const SceneOptions& options) {
    RASTER_REQUIRE(!options.voxels || (*options.voxels >= 1 && *options.voxels <= 1024), InvalidArgument,
                   "cloud: " + std::to_string(options.voxels.value_or(0)) + " voxels per axis (1 to 1024)");
    return std::make_unique<CloudScene>(options, name == "cloud-point");
}

}  // namespace raster
