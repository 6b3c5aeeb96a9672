// The smoke scene's world (scene_smoke.cpp), shared by `smoke` (the particles as billboards) and
// `smoke-volume` (the same particles splatted into a volume, scene_smoke_volume.cpp): the particle
// system and the opaque ground and box. Internal to the library.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "raster/media/cloud_march.hpp"
#include "raster/particles.hpp"
#include "raster/pipeline.hpp"
#include "smoke_shaders.hpp"

namespace raster {

constexpr uint32_t kDefaultSmokeCount = 3000;
constexpr double kDefaultSmokeTime = 8.0;  // seconds: the plume has crossed the box and the mean lifespan

// smoke-volume's grid and splats (particle_volume.hpp): the grid's longest axis, voxels; a particle's
// support radius per unit of its size (the billboard's half-width); its optical depth averaged over its
// disc per unit of opacity; the majorant cells' edge, voxels.
constexpr uint32_t kDefaultSmokeVoxels = 192;
constexpr float kRadiusPerSize = 1.5f;
constexpr float kOpticalDepthPerOpacity = 0.3f;
constexpr int kSmokeCellVoxels = 8;

// The smoke's particle system for `count` particles (its emitter's rate, opacity scaled so that the
// plume's density does not depend on the count; count 0: nothing emitted) and `seed`.
ParticleSystemDesc smokeDesc(uint32_t count, uint64_t seed);
// The particles splatted into smoke-volume's volume (particle_volume.hpp: a grid of `longest` voxels
// along its longest axis fitted around them), in the march's voxel units (cloud_march.hpp): voxel =
// (world − origin)·voxelsPerMetre, the extinction per voxel.
struct SmokeVolume {
    media::CloudVolume volume;
    glm::vec3 origin{0.0f};  // world, metres: the voxels' corner (0, 0, 0)
    float voxelsPerMetre = 1.0f;
};
SmokeVolume makeSmokeVolume(std::span<const Particle> particles, int longest);

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
