// SCENES.md's fog world (the ground plane and the lattice of cubes in fog, under the sky) and its
// draws, for the fog scene and for the scenes drawn over that world (the cloud's, whose ground is a
// variant of PsFog: its draw takes the ground's pixel shader). Internal to the library.
#pragma once

#include <cstdint>

#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"
#include "raster/shaders/fog.hpp"

namespace raster {

struct FogGround {
    explicit FogGround(const SceneOptions& o);  // scene_fog.cpp: the options' camera, cubes and medium

    // The frame: the ground and cubes lit by `ground` (depth Less), then the sky where nothing was
    // drawn (depth LessEqual). A TU that calls it includes raster/pipeline_impl.hpp.
    template <class GroundPs>
    void render(Context& context, RenderTarget& color, DepthTarget& depth, const GroundPs& ground) const {
        beginSceneFrame(context, color, depth);
        context.setBlendState(BlendState::opaque());
        context.setPrimitiveTopology(Topology::TriangleList);
        context.setDepthStencilState({true, true, ComparisonFunc::Less});
        context.setInputLayout(&litLayout);
        context.setVertexBuffer(0, &geometry);
        context.draw(vsLit, ground, vertexCount);
        context.setDepthStencilState({true, true, ComparisonFunc::LessEqual});
        context.setInputLayout(&skyLayout);
        context.setVertexBuffer(0, &sky);
        context.draw(vsSky, psSky, 3);
    }

    VertexBuffer geometry, sky;
    InputLayout litLayout, skyLayout;
    uint32_t vertexCount = 0;
    shaders::VsLit vsLit;
    shaders::PsFog psFog;  // the fog scene's ground shader
    shaders::VsSky vsSky;
    shaders::PsSky psSky;
};

}  // namespace raster
