// The built-in scenes, one translation unit each so that a build compiles them side by side: the
// benchmark's (../shared/bench/SCENES.md) scene_particles.cpp and scene_fog.cpp, scene_fire.cpp,
// scene_smoke.cpp and scene_sprites.cpp (sprites, forest). Internal to the library;
// users reach them through makeScene (raster/scenes.hpp).
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "raster/scenes.hpp"

namespace raster {

// SCENES.md's cameras. constexpr, so initialised before any lab's registration reads one.
constexpr SceneCamera kParticlesCamera{{0, 0.3f, 4}, {0, 0, 0}};
constexpr SceneCamera kFogCamera{{0, 1.5f, 6}, {0, 0.5f, -10}};
// The fire's: SCENES.md's particles camera brought closer and lowered to the flames.
constexpr SceneCamera kFireCamera{{0, -0.1f, 2.5f}, {0, -0.55f, 0}};
// The smoke's: above the ground, looking down at the plume and the box it blows through.
constexpr SceneCamera kSmokeCamera{{0.4f, 1.1f, 2.8f}, {0.0f, 0.55f, -0.4f}};

// The sprites' (the sprites in the plane z = 0, 6 units ahead) and the forest's (outside the trees'
// disc of radius 7.5, at eye height; the scene orbits it about the vertical).
constexpr SceneCamera kSpritesCamera{{0, 0, 6}, {0, 0, 0}};
constexpr SceneCamera kForestCamera{{0, 1.7f, 11}, {0, 1.6f, 0}};
// The options of a ParticleSceneData that holds only the occluder (count 0: its own particles are not
// drawn) seen from `camera` unless the options set one: for the scenes that draw particles of their own.
inline SceneOptions occluderOnly(const SceneOptions& o, const SceneCamera& camera) {
    SceneOptions occluder = o;
    occluder.camera = o.camera.value_or(camera);
    occluder.count = 0;
    return occluder;
}

// A triangle that covers the viewport: clip-space corners (−1, −1), (3, −1), (−1, 3) as an R32G32
// POSITION (shaders::VsMediaRay's input), for the scenes whose pixel shader marches each pixel's ray.
// bind() sets it with the state such a draw needs: a triangle list, opaque, no depth test.
struct FullScreenTriangle {
    FullScreenTriangle();
    void bind(Context& context) const;
    VertexBuffer vertices;
    InputLayout layout;
};

// Options already checked by makeScene.
std::unique_ptr<Scene> makeParticlesScene(const SceneOptions& options);
std::unique_ptr<Scene> makeFogScene(const SceneOptions& options);
// The lecture's fog figures (scene_fog.cpp): fog-constant, fog-black, fog-coloured, fog-height, from
// kFogCamera; and part 1's closed form in three panels (scene_media.cpp), from kMediaCamera.
std::vector<std::string_view> fogFigureNames();
std::unique_ptr<Scene> makeFogFigureScene(std::string_view name, const SceneOptions& options);
constexpr SceneCamera kMediaCamera{{-2.0f, 2.4f, 5.6f}, {0.0f, 0.9f, 0.2f}};
std::unique_ptr<Scene> makeMediaClosedFormScene(const SceneOptions& options);
// SCENES.md's `media`: ray marching through metaballs (scene_media_march.cpp), from its camera, with
// a grid of kMediaGridCells³ for empty-space skipping.
constexpr SceneCamera kMediaMarchCamera{{0, 0.4f, 3}, {0, 0.2f, 0}};
constexpr int kMediaGridCells = 16;
std::unique_ptr<Scene> makeMediaMarchScene(const SceneOptions& options);
// The lecture's part-1 figures by ray marching (scene_media_figures.cpp): media-absorption and
// media-emission (one panel, kMediaFigureCamera), media-scattering and media-euler (three panels side
// by side, kMediaPanelCamera: farther, for the narrower panels).
constexpr SceneCamera kMediaFigureCamera{{0, 0.45f, 2.7f}, {0, 0.2f, 0}};
constexpr SceneCamera kMediaPanelCamera{{0, 0.45f, 4.4f}, {0, 0.2f, 0}};
std::vector<std::string_view> mediaFigureNames();
std::unique_ptr<Scene> makeMediaFigureScene(std::string_view name, const SceneOptions& options);
// A voxel cloud over the fog scene's ground, sun-lit (`cloud`), or lit from below by a point light
// at night (`cloud-point`) (scene_cloud.cpp), empty space skipped through majorant cells of
// kCloudCellVoxels³ voxels.
constexpr SceneCamera kCloudCamera{{0, 1.7f, 6}, {0, 3.0f, -4}};
constexpr int kCloudCellVoxels = 16;
std::unique_ptr<Scene> makeCloudScene(std::string_view name, const SceneOptions& options);
// The slides' diagrams, phase-polar and media-march-steps (scene_slide_figures.cpp), drawn in clip space.
std::vector<std::string_view> slideFigureNames();
std::unique_ptr<Scene> makeSlideFigureScene(std::string_view name, const SceneOptions& options);
std::unique_ptr<Scene> makeFireScene(const SceneOptions& options);
std::unique_ptr<Scene> makeSmokeScene(const SceneOptions& options);  // scene_smoke.cpp
// The smoke's particles splatted into a voxel volume and ray marched (scene_smoke_volume.cpp).
std::unique_ptr<Scene> makeSmokeVolumeScene(const SceneOptions& options);
std::unique_ptr<Scene> makeSpritesScene(const SceneOptions& options);
std::unique_ptr<Scene> makeForestScene(const SceneOptions& options);

}  // namespace raster
