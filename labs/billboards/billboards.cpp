// Lab: billboards and a particle system (lecture 11, part 3).
//
// The lecture's fire: N particles drawn as camera-facing billboards over an opaque occluder (the
// slides' "giraffe"), textured with the fire sprite and added up by the output merger.
//
// As handed out, this file compiles and runs but draws only the occluder. Fill in the four places
// marked `LAB n`, in order; each one changes the picture:
//   LAB 1  gsBillboard opens the sprite: four corners around the particle, in clip space.
//   LAB 2  psFire samples the fire texture.
//   LAB 3  the blend state adds the fire to what is behind it.
//   LAB 4  the depth state lets the occluder hide particles, but not particles each other.
//
//   cmake --build build --target raster_tool && build/bin/raster view billboards
//
// In the viewer, K shows the solution's image and J the difference from it (with the share of
// pixels that differ); click a pixel for its history: which sprites touched it, in what order, and
// what the depth test and the blend did. `raster render billboards` writes billboards.png.
// Look at labs/billboards/README.md for what each step should show.
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
        // LAB 1: open the sprite after the projection (the lecture's method (c)). Emit four corners
        // c + (±billboardSize.x, ±billboardSize.y, 0, 0) as a triangle strip, in the slide's order:
        //   (+x, +y) uv (1, 0),  (+x, -y) uv (1, 1),  (-x, +y) uv (0, 0),  (-x, -y) uv (0, 1).
        // Why is the offset added to clip-space x and y, before the rasteriser divides by w?
        // As handed out all four corners sit on the centre: two triangles of no area, nothing drawn.
        stream.Append({c, {1, 0}});
        stream.Append({c, {1, 1}});
        stream.Append({c, {0, 0}});
        stream.Append({c, {0, 1}});
    }
};

// psFire: the sprite's colour and opacity come from its texture.
struct PsFire {
    const Texture2D* billboardTexture = nullptr;
    SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);

    glm::vec4 operator()(const BillboardCorner& in) const {
        // LAB 2: return the fire texture's colour at the interpolated uv (billboardTexture, sampler:
        // see raster/texture.hpp for Sample). As handed out every sprite is a flat orange square.
        (void)in;
        return {1.0f, 0.5f, 0.1f, 1.0f};
    }
};

// LAB 3: the output merger must add the fire to what is behind it:
//   rgb = src.rgb * src.a + dst.rgb,   a = src.a * src.a + dst.a
// Set render target 0's description (raster/states.hpp, RenderTargetBlendDesc) to do that. Does the
// order in which the particles are drawn matter then?
// As handed out blending is off: each sprite replaces what is behind it.
BlendState fireBlend() {
    BlendState blend;
    return blend;
}

// LAB 4: the occluder must hide the particles behind it, but a particle must not hide the ones
// behind it (its corners are transparent, and the fire adds up). Which of the depth state's fields
// (raster/states.hpp, DepthStencilState) gives that?
// As handed out the particles are tested and written like opaque geometry.
DepthStencilState fireDepth() {
    DepthStencilState depth;
    return depth;
}

// The scene: SCENES.md's occluder, particles, fire texture and camera (raster/scenes.hpp), drawn
// with the shaders and states above.
class BillboardsLab final : public billboards_lab::BillboardsScene<GsBillboard, PsFire> {
  public:
    explicit BillboardsLab(const SceneOptions& o) : BillboardsScene(o, fireBlend(), fireDepth()) {}
};

}  // namespace

RASTER_LAB("billboards", "Lab: billboards and a particle system (lecture 11, part 3)", BillboardsLab,
           defaultCamera("particles"))
