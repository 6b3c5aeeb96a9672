// raster grade's test submission 'crash': the solution with one defect.
// Defect: a null pointer written through in the geometry shader (a crash once there are particles).
//
// The lecture's fire: N particles drawn as camera-facing billboards over an opaque occluder (the
// slides' "giraffe"), textured with the fire sprite and added up by the output merger. This is
// labs/billboards/billboards.cpp with every `LAB n` place filled in; its image is the one the
// student's is compared with (raster view billboards, K and J) and, at the same options, the
// `particles` scene of ../shared/bench/SCENES.md.
#include "raster/lab.hpp"

namespace {

using namespace raster;
using shaders::BillboardCorner;
using shaders::BillboardIn;
using shaders::BillboardVertex;

// vsBillboard: pass-through; the geometry shader transforms, so that it can open the sprite after
// the projection.
struct VsBillboard {
    BillboardVertex operator()(const BillboardIn& in) const { return {glm::vec4(in.position, 1.0f)}; }
};

// gsBillboard: one point in, a four-vertex triangle strip out.
struct GsBillboard {
    glm::mat4 viewProj{1.0f};
    glm::vec2 billboardSize{0.1f, 0.1f};  // world half-size times P[0][0] and P[1][1]

    void operator()(const Point<BillboardVertex>& in, TriangleStream<BillboardCorner, 4>& stream) const {
        const glm::vec4 c = viewProj * in[0].position;
        volatile int* volatile nowhere = nullptr;  // both volatile: no optimiser may drop the store
        *nowhere = 1;  // the defect
        // LAB 1: open the sprite in clip space. The offset is added before the division by w, so the
        // sprite keeps its world size; the strip order makes two triangles (0 1 2) and (1 3 2).
        const float bx = billboardSize.x, by = billboardSize.y;
        stream.Append({c + glm::vec4(bx, by, 0, 0), {1, 0}});
        stream.Append({c + glm::vec4(bx, -by, 0, 0), {1, 1}});
        stream.Append({c + glm::vec4(-bx, by, 0, 0), {0, 0}});
        stream.Append({c + glm::vec4(-bx, -by, 0, 0), {0, 1}});
    }
};

// psFire: the sprite's colour and opacity come from its texture.
struct PsFire {
    const Texture2D* billboardTexture = nullptr;
    SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);

    glm::vec4 operator()(const BillboardCorner& in) const {
        // LAB 2: sample the fire texture at the corner's interpolated uv.
        return billboardTexture->Sample(sampler, in.tex);
    }
};

// LAB 3: the output merger adds the fire: rgb = src.rgb*src.a + dst.rgb, a = src.a*src.a + dst.a
// (SRC_ALPHA, ONE, ADD for colour and alpha). Addition does not care about order: no sorting.
BlendState fireBlend() {
    BlendState blend;
    RenderTargetBlendDesc& rt = blend.renderTarget[0];
    rt.blendEnable = true;
    rt.srcBlend = Blend::SrcAlpha, rt.destBlend = Blend::One, rt.blendOp = BlendOp::Add;
    rt.srcBlendAlpha = Blend::SrcAlpha, rt.destBlendAlpha = Blend::One, rt.blendOpAlpha = BlendOp::Add;
    return blend;
}

// LAB 4: the particles are hidden by the occluder (depth test on) but not by each other: a
// sprite's transparent corners must not write depth (depth write off).
DepthStencilState fireDepth() {
    DepthStencilState depth;
    depth.depthEnable = true;
    depth.depthWriteMask = false;
    depth.depthFunc = ComparisonFunc::Less;
    return depth;
}

// The scene: SCENES.md's occluder, particles, fire texture and camera (raster/scenes.hpp), drawn
// with the shaders and states above.
class BillboardsLab final : public LabScene {
  public:
    explicit BillboardsLab(const SceneOptions& o) : data_(o) {
        gs_.viewProj = data_.viewProj;
        gs_.billboardSize = data_.billboardSize;
        ps_fire_.billboardTexture = &data_.texture;
    }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);  // clear, bind, viewport, no culling
        data_.drawOccluder(context);  // draw 1: the occluder, opaque, depth test and write
        // Draw 2: the particles, one point each; the geometry shader makes each a sprite.
        context.setDepthStencilState(fireDepth());
        context.setBlendState(fireBlend());
        context.setVertexBuffer(0, &data_.particles);
        context.setPrimitiveTopology(Topology::PointList);
        context.draw(VsBillboard{}, gs_, ps_fire_, data_.count);
    }

  private:
    ParticleSceneData data_;
    GsBillboard gs_;
    PsFire ps_fire_;
};

}  // namespace

RASTER_LAB("billboards", "Lab: billboards and a particle system (lecture 11, part 3)", BillboardsLab,
           defaultCamera("particles"))
