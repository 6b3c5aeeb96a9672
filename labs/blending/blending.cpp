// Lab: blending, depth and sorting (lecture 11, part 3).
//
// The lecture's five blend and depth figures side by side, each a panel of one image: soft discs in
// front of and behind the opaque occluder (the slides' "giraffe"), coloured blue (far) to yellow
// (near) so that a wrong order shows. Top row, additive blending: "blending with the depth test on",
// "no depth test", "depth test stays, depth write off"; bottom row, "over": "wrong order" (as the
// particles are stored) and "sorting" (back to front).
//
// As handed out, this file compiles and runs, but every state is D3D11's default (blending off,
// depth test and write): five panels of opaque squares. Fill in the six places marked `LAB n`, in
// order; each changes the picture (labs/blending/README.md has the table):
//   LAB 1  additiveBlend      LAB 2  noDepthTest      LAB 3  depthTestNoWrite      LAB 4  overBlend
//   LAB 5  viewDepth, the sort key                    LAB 6  drawnBefore, the comparator
// Write the states out field by field (raster/states.hpp: BlendState, RenderTargetBlendDesc,
// DepthStencilState), as you would fill D3D11_BLEND_DESC and D3D11_DEPTH_STENCIL_DESC.
//
//   cmake --build build-lab --target raster_tool && build-lab/bin/raster view blending
//
// In the viewer, K shows the solution's image and J the difference; click a pixel for its history:
// each fragment's draw, depth test and blend.
#include "raster/labs/blending.hpp"

namespace {

using namespace raster;

// The particles, their quads and soft discs, the panels and the sort that calls your key and comparator
// are the lab's scaffolding: raster/lecture/include/raster/labs/blending.hpp.
using blending_lab::SortItem;

// ---- The states ---------------------------------------------------------------------------------

// LAB 1: additive blending (the fire's): the particle's colour, weighted by its alpha, added to
// what is behind it, for colour and alpha:
//   rgb = src.rgb * src.a + dst.rgb,   a = src.a * src.a + dst.a
// Used by the three panels of the top row. Does the order of the particles matter then?
// As handed out blending is off: each particle's quad replaces what is behind it, an opaque square.
BlendState additiveBlend() {
    BlendState blend;
    return blend;
}

// LAB 2: the figure "no depth test: even the giraffe does not occlude": no depth test at all (and
// then nothing is written to the depth buffer either). The top row's middle panel.
// As handed out: D3D11's default, test Less and write, the same as the first panel.
DepthStencilState noDepthTest() {
    DepthStencilState depth;
    return depth;
}

// LAB 3: "depth test stays, depth write off": the occluder must still hide the particles behind it,
// but a particle must not hide the ones drawn after it (its quad's transparent corners would cut
// them out in squares, as the first panel shows). The top row's right panel and both "over" panels.
// As handed out: test and write.
DepthStencilState depthTestNoWrite() {
    DepthStencilState depth;
    return depth;
}

// LAB 4: alpha blending, "over": the particle covers what is behind it by its alpha, for colour and
// alpha:
//   rgb = src.rgb * src.a + dst.rgb * (1 - src.a),   a = src.a * src.a + dst.a * (1 - src.a)
// The bottom row. Why does the order matter now, and which order is right?
// As handed out blending is off.
BlendState overBlend() {
    BlendState blend;
    return blend;
}

// ---- The sort -----------------------------------------------------------------------------------

// A particle to sort (blending_lab::SortItem): its index and its sort key, {uint32_t index; float depth;}.

// LAB 5: the sort key: how far `position` lies in front of the eye along the camera's forward axis
// `ahead` (unit length), in world units (the slide's `pos·ahead`, measured from the eye).
// As handed out every particle has depth 0: all tied, and the sort keeps the storage order.
float viewDepth(glm::vec3 position, glm::vec3 eye, glm::vec3 ahead) {
    (void)position, (void)eye, (void)ahead;
    return 0.0f;
}

// LAB 6: the comparator: true when `a` must be drawn before `b`, so that "over" is right. It must be
// a strict weak ordering, or std::sort is undefined behaviour; the slide's
//     return a.pos·ahead > b.pos·ahead + 0.01;
// is not one (try depths 0, 0.008 and 0.016). The lab checks your comparator on the particles before
// it sorts, and stops with the particles that break the rule.
// As handed out it sorts front to back: a valid ordering, the wrong one.
bool drawnBefore(const SortItem& a, const SortItem& b) {
    return a.depth < b.depth;
}

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
