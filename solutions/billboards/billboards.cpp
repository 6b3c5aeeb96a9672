// BEGIN NOTE
// Lab: billboards and a particle system (lecture 11, part 3) - THE SOLUTION.
//
// The lecture's fire: N particles drawn as camera-facing billboards over an opaque occluder (the
// slides' "giraffe"), textured with the fire sprite and added up by the output merger. This is
// labs/billboards/billboards.cpp with every `LAB n` place filled in; its image is the one the
// student's is compared with (raster view billboards, K and J) and, at the same options, the
// `particles` scene of ../shared/bench/SCENES.md.
// STAND-IN
//> // Lab: billboards and a particle system (lecture 11, part 3).
//> //
//> // The lecture's fire: N particles drawn as camera-facing billboards over an opaque occluder (the
//> // slides' "giraffe"), textured with the fire sprite and added up by the output merger.
//> //
//> // As handed out, this file compiles and runs but draws only the occluder. Fill in the four places
//> // marked `LAB n`, in order; each one changes the picture:
//> //   LAB 1  gsBillboard opens the sprite: four corners around the particle, in clip space.
//> //   LAB 2  psFire samples the fire texture.
//> //   LAB 3  the blend state adds the fire to what is behind it.
//> //   LAB 4  the depth state lets the occluder hide particles, but not particles each other.
//> //
//> //   cmake --build build --target raster_tool && build/bin/raster view billboards
//> //
//> // In the viewer, K shows the solution's image and J the difference from it (with the share of
//> // pixels that differ); click a pixel for its history: which sprites touched it, in what order, and
//> // what the depth test and the blend did. `raster render billboards` writes billboards.png.
//> // Look at labs/billboards/README.md for what each step should show.
// END NOTE
#include "raster/labs/billboards.hpp"

namespace {

using namespace raster;
using shaders::BillboardCorner;
using shaders::BillboardVertex;

// The vertex formats (BillboardIn, BillboardVertex, BillboardCorner: raster/shaders/billboard.hpp), the
// pass-through vertex shader (shaders::VsBillboard) and the scene that draws your shaders with your
// states are the lab's scaffolding: raster/lecture/include/raster/labs/billboards.hpp.

// gsBillboard: one point in, a four-vertex triangle strip out.
struct GsBillboard {
    glm::mat4 viewProj{1.0f};
    glm::vec2 billboardSize{0.1f, 0.1f};  // world half-size times P[0][0] and P[1][1]

    void operator()(const Point<BillboardVertex>& in, TriangleStream<BillboardCorner, 4>& stream) const {
        const glm::vec4 c = viewProj * in[0].position;
        // BEGIN LAB 1
        // slide: gs-billboard
        // LAB 1: open the sprite in clip space. The offset is added before the division by w, so the
        // sprite keeps its world size; the strip order makes two triangles (0 1 2) and (1 3 2).
        const float bx = billboardSize.x, by = billboardSize.y;
        stream.Append({c + glm::vec4(bx, by, 0, 0), {1, 0}});
        stream.Append({c + glm::vec4(bx, -by, 0, 0), {1, 1}});
        stream.Append({c + glm::vec4(-bx, by, 0, 0), {0, 0}});
        stream.Append({c + glm::vec4(-bx, -by, 0, 0), {0, 1}});
        // end slide: gs-billboard
        // STAND-IN
        //> // LAB 1: open the sprite after the projection (the lecture's method (c)). Emit four corners
        //> // c + (±billboardSize.x, ±billboardSize.y, 0, 0) as a triangle strip, in the slide's order:
        //> //   (+x, +y) uv (1, 0),  (+x, -y) uv (1, 1),  (-x, +y) uv (0, 0),  (-x, -y) uv (0, 1).
        //> // Why is the offset added to clip-space x and y, before the rasteriser divides by w?
        //> // As handed out all four corners sit on the centre: two triangles of no area, nothing drawn.
        //> stream.Append({c, {1, 0}});
        //> stream.Append({c, {1, 1}});
        //> stream.Append({c, {0, 0}});
        //> stream.Append({c, {0, 1}});
        // END LAB 1
    }
};

// psFire: the sprite's colour and opacity come from its texture.
struct PsFire {
    const Texture2D* billboardTexture = nullptr;
    SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);

    glm::vec4 operator()(const BillboardCorner& in) const {
        // BEGIN LAB 2
        // LAB 2: sample the fire texture at the corner's interpolated uv.
        return billboardTexture->Sample(sampler, in.tex);
        // STAND-IN
        //> // LAB 2: return the fire texture's colour at the interpolated uv (billboardTexture, sampler:
        //> // see raster/texture.hpp for Sample). As handed out every sprite is a flat orange square.
        //> (void)in;
        //> return {1.0f, 0.5f, 0.1f, 1.0f};
        // END LAB 2
    }
};

// BEGIN LAB 3
// slide: additive-blend
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
// end slide: additive-blend
// STAND-IN
//> // LAB 3: the output merger must add the fire to what is behind it:
//> //   rgb = src.rgb * src.a + dst.rgb,   a = src.a * src.a + dst.a
//> // Set render target 0's description (raster/states.hpp, RenderTargetBlendDesc) to do that. Does the
//> // order in which the particles are drawn matter then?
//> // As handed out blending is off: each sprite replaces what is behind it.
//> BlendState fireBlend() {
    //> BlendState blend;
    //> return blend;
//> }
// END LAB 3

// BEGIN LAB 4
// LAB 4: the particles are hidden by the occluder (depth test on) but not by each other: a
// sprite's transparent corners must not write depth (depth write off).
DepthStencilState fireDepth() {
    DepthStencilState depth;
    depth.depthEnable = true;
    depth.depthWriteMask = false;
    depth.depthFunc = ComparisonFunc::Less;
    return depth;
}
// STAND-IN
//> // LAB 4: the occluder must hide the particles behind it, but a particle must not hide the ones
//> // behind it (its corners are transparent, and the fire adds up). Which of the depth state's fields
//> // (raster/states.hpp, DepthStencilState) gives that?
//> // As handed out the particles are tested and written like opaque geometry.
//> DepthStencilState fireDepth() {
    //> DepthStencilState depth;
    //> return depth;
//> }
// END LAB 4

// The scene: SCENES.md's occluder, particles, fire texture and camera (raster/scenes.hpp), drawn
// with the shaders and states above.
class BillboardsLab final : public billboards_lab::BillboardsScene<GsBillboard, PsFire> {
  public:
    explicit BillboardsLab(const SceneOptions& o) : BillboardsScene(o, fireBlend(), fireDepth()) {}
};

}  // namespace

RASTER_LAB("billboards", "Lab: billboards and a particle system (lecture 11, part 3)", BillboardsLab,
           defaultCamera("particles"))
