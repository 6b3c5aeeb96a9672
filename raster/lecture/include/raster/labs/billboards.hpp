// The billboards lab's scene (labs/billboards/): everything but the student's shaders and states. The
// lab's file (and its solution, which fills the file's places) defines the geometry shader, the pixel
// shader, the blend state and the depth state, and registers a scene that hands them to
//
//   BillboardsScene<Gs, Ps>(options, blend, depth)
//
// SCENES.md's occluder, particles, fire texture and camera (ParticleSceneData, raster/scenes.hpp): draw 1
// the occluder, opaque; draw 2 the particles, one point each, through shaders::VsBillboard, the
// geometry shader that makes each a sprite, and the pixel shader, with `blend` and `depth`. What the
// scene hands each shader, by aggregate initialisation in this order of members:
//   Gs{viewProj, billboardSize}   reads Point<BillboardVertex>, appends BillboardCorner to a
//                                 TriangleStream<BillboardCorner, 4>
//   Ps{billboardTexture}          reads BillboardCorner
#pragma once

#include "raster/lab.hpp"

namespace raster::billboards_lab {

template <class Gs, class Ps>
class BillboardsScene : public LabScene {
  public:
    BillboardsScene(const SceneOptions& o, const BlendState& blend, const DepthStencilState& depth)
        : data_(o),
          gs_{data_.viewProj, data_.billboardSize},
          ps_{&data_.texture},
          blend_(blend),
          depth_(depth) {}

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);  // clear, bind, viewport, no culling
        data_.drawOccluder(context);             // draw 1: the occluder, opaque, depth test and write
        // Draw 2: the particles, one point each; the geometry shader makes each a sprite.
        context.setDepthStencilState(depth_);
        context.setBlendState(blend_);
        context.setVertexBuffer(0, &data_.particles);
        context.setPrimitiveTopology(Topology::PointList);
        context.draw(shaders::VsBillboard{}, gs_, ps_, data_.count);
    }

  private:
    ParticleSceneData data_;
    Gs gs_;
    Ps ps_;
    BlendState blend_;
    DepthStencilState depth_;
};

}  // namespace raster::billboards_lab
