// The built-in benchmark scenes (../shared/bench/SCENES.md), one translation unit each so that a
// build compiles them side by side: scene_particles.cpp and scene_fog.cpp. Internal to the library;
// users reach them through makeScene (raster/scenes.hpp).
#pragma once

#include <memory>

#include "raster/scenes.hpp"

namespace raster {

// SCENES.md's cameras. constexpr, so initialised before any lab's registration reads one.
constexpr SceneCamera kParticlesCamera{{0, 0.3f, 4}, {0, 0, 0}};
constexpr SceneCamera kFogCamera{{0, 1.5f, 6}, {0, 0.5f, -10}};

// Options already checked by makeScene.
std::unique_ptr<Scene> makeParticlesScene(const SceneOptions& options);
std::unique_ptr<Scene> makeFogScene(const SceneOptions& options);

}  // namespace raster
