// The lecture's scenes, as ../shared/bench/SCENES.md defines them to the last constant:
// `particles` (fire billboards over an occluder) and `fog` (cubes on a ground plane in fog).
// `raster bench`, `raster render`, the viewer and the tests all draw them through this interface.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "raster/pipeline.hpp"
#include "raster/texture.hpp"

namespace raster {

// Where a scene is looked at from: a right-handed look-at with +y up and the scene's fixed 60° field
// of view. Each scene's SCENES.md camera is defaultCamera(name); the viewer orbits and flies from it.
struct SceneCamera {
    glm::vec3 eye, target;
};

struct SceneOptions {
    uint32_t width = 1280, height = 720;
    uint32_t count = 10000;   // particles
    uint32_t cubes = 16;      // fog: cubes per side
    bool heightFog = true;    // fog: "height" (true) or "constant"
    std::string texture;      // particles: a PNG to use instead of the generated fire texture
    // Overrides the scene's camera. Unset, the scene is exactly SCENES.md's (what `raster bench`
    // measures); set to defaultCamera(name), it renders the same image bit for bit.
    std::optional<SceneCamera> camera;
};

class Scene {
public:
    virtual ~Scene() = default;
    virtual std::string_view name() const = 0;
    // Clears the targets and draws one frame.
    virtual void render(Context& context, RenderTarget& color, DepthTarget& depth) = 0;
};

// Throws Error(InvalidArgument) for an unknown scene name or an option out of range.
std::unique_ptr<Scene> makeScene(std::string_view name, const SceneOptions& options);
std::vector<std::string> sceneNames();
// SCENES.md's camera of a scene. Throws Error(InvalidArgument) for an unknown scene name.
SceneCamera defaultCamera(std::string_view name);

// The fire texture of SCENES.md: 64×64 RGBA8, texel (i, j): u = (i+½)/64, v = (j+½)/64,
// r = 2·|(u,v) − ½|, s = clamp(1 − r, 0, 1)², RGBA = round(255·(1, 0.25 + 0.55s, 0.05 + 0.15s, 0.25s)).
Texture2D makeFireTexture();

// Particle i of SCENES.md's R3 low-discrepancy sequence (computed in double, rounded to float).
glm::vec3 particlePosition(uint32_t i);

}  // namespace raster
