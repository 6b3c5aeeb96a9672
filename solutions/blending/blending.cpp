// BEGIN NOTE
// Lab: blending, depth and sorting (lecture 11, part 3) - THE SOLUTION.
//
// The lecture's five blend and depth figures side by side, each a panel of one image: soft discs in
// front of and behind the opaque occluder (the slides' "giraffe"), coloured blue (far) to yellow
// (near) so that a wrong order shows. This is labs/blending/blending.cpp with every `LAB n` place
// filled in; its image is the one the student's is compared with (raster view blending, K and J).
// STAND-IN
//> // Lab: blending, depth and sorting (lecture 11, part 3).
//> //
//> // The lecture's five blend and depth figures side by side, each a panel of one image: soft discs in
//> // front of and behind the opaque occluder (the slides' "giraffe"), coloured blue (far) to yellow
//> // (near) so that a wrong order shows. Top row, additive blending: "blending with the depth test on",
//> // "no depth test", "depth test stays, depth write off"; bottom row, "over": "wrong order" (as the
//> // particles are stored) and "sorting" (back to front).
//> //
//> // As handed out, this file compiles and runs, but every state is D3D11's default (blending off,
//> // depth test and write): five panels of opaque squares. Fill in the six places marked `LAB n`, in
//> // order; each changes the picture (labs/blending/README.md has the table):
//> //   LAB 1  additiveBlend      LAB 2  noDepthTest      LAB 3  depthTestNoWrite      LAB 4  overBlend
//> //   LAB 5  viewDepth, the sort key                    LAB 6  drawnBefore, the comparator
//> // Write the states out field by field (raster/states.hpp: BlendState, RenderTargetBlendDesc,
//> // DepthStencilState), as you would fill D3D11_BLEND_DESC and D3D11_DEPTH_STENCIL_DESC.
//> //
//> //   cmake --build build-lab --target raster_tool && build-lab/bin/raster view blending
//> //
//> // In the viewer, K shows the solution's image and J the difference; click a pixel for its history:
//> // each fragment's draw, depth test and blend.
// END NOTE
#include "raster/labs/blending.hpp"

namespace {

using namespace raster;

// The particles, their quads and soft discs, the panels and the sort that calls your key and comparator
// are the lab's scaffolding: raster/lecture/include/raster/labs/blending.hpp.
using blending_lab::SortItem;

// ---- The states ---------------------------------------------------------------------------------

// BEGIN LAB 1
// LAB 1: additive blending, for colour and alpha: SRC_ALPHA, ONE, ADD.
BlendState additiveBlend() {
    BlendState blend;
    RenderTargetBlendDesc& rt = blend.renderTarget[0];
    rt.blendEnable = true;
    rt.srcBlend = Blend::SrcAlpha, rt.destBlend = Blend::One, rt.blendOp = BlendOp::Add;
    rt.srcBlendAlpha = Blend::SrcAlpha, rt.destBlendAlpha = Blend::One, rt.blendOpAlpha = BlendOp::Add;
    return blend;
}
// STAND-IN
//> // LAB 1: additive blending (the fire's): the particle's colour, weighted by its alpha, added to
//> // what is behind it, for colour and alpha:
//> //   rgb = src.rgb * src.a + dst.rgb,   a = src.a * src.a + dst.a
//> // Used by the three panels of the top row. Does the order of the particles matter then?
//> // As handed out blending is off: each particle's quad replaces what is behind it, an opaque square.
//> BlendState additiveBlend() {
    //> BlendState blend;
    //> return blend;
//> }
// END LAB 1

// BEGIN LAB 2
// LAB 2: no depth test (and so no depth write): every fragment reaches the blend.
DepthStencilState noDepthTest() {
    DepthStencilState depth;
    depth.depthEnable = false;
    depth.depthWriteMask = false;
    return depth;
}
// STAND-IN
//> // LAB 2: the figure "no depth test: even the giraffe does not occlude": no depth test at all (and
//> // then nothing is written to the depth buffer either). The top row's middle panel.
//> // As handed out: D3D11's default, test Less and write, the same as the first panel.
//> DepthStencilState noDepthTest() {
    //> DepthStencilState depth;
    //> return depth;
//> }
// END LAB 2

// BEGIN LAB 3
// LAB 3: the depth test stays (the occluder hides what is behind it), the depth write goes (a quad's
// transparent corners must not hide the particles drawn after it).
DepthStencilState depthTestNoWrite() {
    DepthStencilState depth;
    depth.depthEnable = true;
    depth.depthWriteMask = false;
    depth.depthFunc = ComparisonFunc::Less;
    return depth;
}
// STAND-IN
//> // LAB 3: "depth test stays, depth write off": the occluder must still hide the particles behind it,
//> // but a particle must not hide the ones drawn after it (its quad's transparent corners would cut
//> // them out in squares, as the first panel shows). The top row's right panel and both "over" panels.
//> // As handed out: test and write.
//> DepthStencilState depthTestNoWrite() {
    //> DepthStencilState depth;
    //> return depth;
//> }
// END LAB 3

// BEGIN LAB 4
// LAB 4: "over": SRC_ALPHA, INV_SRC_ALPHA, ADD, for colour and alpha.
BlendState overBlend() {
    BlendState blend;
    RenderTargetBlendDesc& rt = blend.renderTarget[0];
    rt.blendEnable = true;
    rt.srcBlend = Blend::SrcAlpha, rt.destBlend = Blend::InvSrcAlpha, rt.blendOp = BlendOp::Add;
    rt.srcBlendAlpha = Blend::SrcAlpha, rt.destBlendAlpha = Blend::InvSrcAlpha,
    rt.blendOpAlpha = BlendOp::Add;
    return blend;
}
// STAND-IN
//> // LAB 4: alpha blending, "over": the particle covers what is behind it by its alpha, for colour and
//> // alpha:
//> //   rgb = src.rgb * src.a + dst.rgb * (1 - src.a),   a = src.a * src.a + dst.a * (1 - src.a)
//> // The bottom row. Why does the order matter now, and which order is right?
//> // As handed out blending is off.
//> BlendState overBlend() {
    //> BlendState blend;
    //> return blend;
//> }
// END LAB 4

// ---- The sort -----------------------------------------------------------------------------------

// A particle to sort (blending_lab::SortItem): its index and its sort key, {uint32_t index; float depth;}.

// BEGIN LAB 5
// LAB 5: the view depth, along the camera's forward axis (`ahead`, unit length), from the eye.
float viewDepth(glm::vec3 position, glm::vec3 eye, glm::vec3 ahead) {
    return glm::dot(position - eye, ahead);
}
// STAND-IN
//> // LAB 5: the sort key: how far `position` lies in front of the eye along the camera's forward axis
//> // `ahead` (unit length), in world units (the slide's `pos·ahead`, measured from the eye).
//> // As handed out every particle has depth 0: all tied, and the sort keeps the storage order.
//> float viewDepth(glm::vec3 position, glm::vec3 eye, glm::vec3 ahead) {
    //> (void)position, (void)eye, (void)ahead;
    //> return 0.0f;
//> }
// END LAB 5

// BEGIN LAB 6
// LAB 6: back to front, the farthest first: a plain comparison of the keys, a strict weak ordering.
bool drawnBefore(const SortItem& a, const SortItem& b) {
    return a.depth > b.depth;
}
// STAND-IN
//> // LAB 6: the comparator: true when `a` must be drawn before `b`, so that "over" is right. It must be
//> // a strict weak ordering, or std::sort is undefined behaviour; the slide's
//> //     return a.pos·ahead > b.pos·ahead + 0.01;
//> // is not one (try depths 0, 0.008 and 0.016). The lab checks your comparator on the particles before
//> // it sorts, and stops with the particles that break the rule.
//> // As handed out it sorts front to back: a valid ordering, the wrong one.
//> bool drawnBefore(const SortItem& a, const SortItem& b) {
    //> return a.depth < b.depth;
//> }
// END LAB 6

// ---- The scene (the lab's own: nothing to write below) -------------------------------------------

// The five panels, each with the states above; the sorted one drawn in drawnBefore's order of viewDepth.
class BlendingLab final : public blending_lab::BlendingScene {
  public:
    explicit BlendingLab(const SceneOptions& o)
        : BlendingScene(o, figures(), viewDepth, drawnBefore) {}

  private:
    static std::vector<blending_lab::Figure> figures() {
        return blending_lab::lectureFigures(additiveBlend(), noDepthTest(), depthTestNoWrite(), overBlend());
    }
};

}  // namespace

RASTER_LAB("blending", "Lab: blending, depth and sorting (lecture 11, part 3)", BlendingLab,
           blending_lab::kBlendingCamera)
