// The smoke scene's world (scene_smoke.cpp), shared by `smoke` (the particles as billboards) and
// `smoke-volume` (the same particles splatted into a volume, scene_smoke_volume.cpp): the particle
// system and the opaque ground and box. Internal to the library.
#pragma once

#include <cstdint>
#include <vector>

#include "raster/particles.hpp"
#include "raster/pipeline.hpp"
#include "smoke_shaders.hpp"

namespace raster {

constexpr uint32_t kDefaultSmokeCount = 3000;
constexpr double kDefaultSmokeTime = 8.0;  // seconds: the plume has crossed the box and the mean lifespan

// The smoke's particle system for `count` particles (its emitter's rate, opacity scaled so that the
// plume's density does not depend on the count; count 0: nothing emitted) and `seed`.
ParticleSystemDesc smokeDesc(uint32_t count, uint64_t seed);
// The ground (y = 0) and the box the wind blows the smoke through, opaque, under PsSolid's sun: the
// first pass of both scenes.
struct SmokeGround {
    explicit SmokeGround(const glm::mat4& view_proj);
    // Clears the targets (beginSceneFrame) and draws the ground and the box with depth test and write.
    void render(Context& context, RenderTarget& color, DepthTarget& depth) const;

    VertexBuffer vertices;  // shaders::LitIn, each normal scaled by the surface's albedo
    uint32_t count = 0;
    InputLayout layout;
    shaders::VsLit vs;
    shaders::PsSolid ps;
};

}  // namespace raster
