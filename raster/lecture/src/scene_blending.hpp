// The lecture's blend and depth figures as scenes (scene_blending.cpp): their names, camera and
// factory, for scenes.cpp. Internal to the library; users reach them through makeScene.
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "raster/scenes.hpp"

namespace raster {

// The blend figures' camera: nearer than SCENES.md's particles camera, so that the particles' box
// fills the view.
constexpr SceneCamera kBlendCamera{{0, 0.2f, 3.2f}, {0, -0.2f, 0}};
// The blend figures' particles when SceneOptions::count is unset.
constexpr uint32_t kDefaultBlendCount = 200;

// blend-additive, blend-depthwrite, blend-nodepth, blend-unsorted, blend-sorted, blend-wboit.
std::vector<std::string_view> blendingSceneNames();
// The blend figure called `name` (options already checked by makeScene), or nullptr when no figure is.
std::unique_ptr<Scene> makeBlendingScene(std::string_view name, const SceneOptions& options);

}  // namespace raster
