// BEGIN NOTE
// Lab: inside the rasterizer (the pipeline's rasterizer stage: coverage, 16.8 fixed point, the
// top-left rule) - THE SOLUTION.
//
// Which pixels does a triangle cover? This file answers for the pipeline: labCovers is the coverage
// test the lab's draw runs with (Context::setCoverageTest), asked for every pixel centre of every
// triangle's bounding box. It is labs/rasterizer/rasterizer.cpp with every `LAB n` place filled in;
// its answers are the library's (stages/5_setup.hpp, stages/7_rasterizer.hpp), bit for bit.
// STAND-IN
//> // Lab: inside the rasterizer (the pipeline's rasterizer stage: coverage, 16.8 fixed point, the
//> // top-left rule). README.md says what to do and what to look at.
//> //
//> // Which pixels does a triangle cover? This file answers for the pipeline: labCovers is the coverage
//> // test the lab's draw runs with (Context::setCoverageTest), asked for every pixel centre of every
//> // triangle's bounding box. Fill in the `LAB n` places in order 1, 2, 3, 4; each changes the picture
//> // (README.md's table). Done, your answers are the library's for every triangle, bit for bit.
// END NOTE
#include <cmath>
#include <cstdint>
#include <utility>  // std::swap, for LAB 2

#include "raster/lab.hpp"

namespace {

using namespace raster;

// BEGIN LAB 4 (out of order)
// LAB 4: a window coordinate in pixels to 16.8 fixed point (1/256 pixel), rounded to the nearest,
// ties to even (std::nearbyint in the default rounding mode).
int64_t toFixed(double pixels) {
    return int64_t(std::nearbyint(pixels * 256.0));
}
// STAND-IN
//> // LAB 4 (do it last): a window coordinate in pixels to 16.8 fixed point, 1/256 pixel, rounded to the
//> // nearest, ties to even (std::nearbyint in the default rounding mode; std::lround would round a tie
//> // away from zero). The stand-in keeps the units but rounds to half pixels.
//> int64_t toFixed(double pixels) {
    //> return int64_t(std::nearbyint(pixels * 2.0)) * 128;
//> }
// END LAB 4

// BEGIN LAB 1
// LAB 1: the edge function of the edge a → b at p, all in 16.8: the cross product (b − a) × (p − a),
// positive when p lies to the right of a → b on the screen (y grows downwards). Exact in 64 bits.
int64_t edgeFunction(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t px, int64_t py) {
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}
// STAND-IN
//> // LAB 1: the edge function of the edge a → b at p, all in 16.8 (the result in 16.16): the 2D cross
//> // product of b − a and p − a, positive when p lies to the right of a → b on the screen (y grows
//> // downwards), zero on the edge's line. 64-bit products are exact here. The stand-in says every
//> // centre lies on every edge.
//> int64_t edgeFunction(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t px, int64_t py) {
    //> (void)ax, (void)ay, (void)bx, (void)by, (void)px, (void)py;
    //> return 0;
//> }
// END LAB 1

// BEGIN LAB 3
// LAB 3: a top edge is horizontal with the triangle below it, a left edge has the triangle to its
// right; for a clockwise triangle, an edge a → b is top when dy = 0 and dx > 0, left when dy < 0.
bool isTopOrLeft(int64_t dx, int64_t dy) {
    return dy < 0 || (dy == 0 && dx > 0);
}
// STAND-IN
//> // LAB 3: whether the edge a → b of a clockwise triangle (b − a = (dx, dy), y down) is a top edge
//> // (horizontal, the triangle below it) or a left edge (the triangle to its right). The stand-in says
//> // every edge is.
//> bool isTopOrLeft(int64_t dx, int64_t dy) {
    //> (void)dx, (void)dy;
    //> return true;
//> }
// END LAB 3

// The coverage test: whether the triangle covers the centre of pixel (px, py).
bool labCovers(const CoverageTriangle& triangle, int32_t px, int32_t py) {
    int64_t x[3], y[3];
    for (int k = 0; k < 3; ++k) x[k] = toFixed(triangle.x[k]), y[k] = toFixed(triangle.y[k]);
    // BEGIN LAB 2 (out of order)
    // LAB 2: every edge function is >= 0 inside a clockwise triangle; a counter-clockwise one
    // (twice its signed area, the edge function of vertex 2 against edge 0, is negative) becomes
    // clockwise by swapping vertices 1 and 2.
    if (edgeFunction(x[0], y[0], x[1], y[1], x[2], y[2]) < 0) std::swap(x[1], x[2]), std::swap(y[1], y[2]);
    // STAND-IN
    //> // LAB 2: every edge function is >= 0 inside a clockwise triangle (on the screen, y down), and
    //> // <= 0 inside a counter-clockwise one. Make every triangle clockwise here: its signed area
    //> // (twice it: the edge function of vertex 2 against edge 0) tells which it is. The stand-in
    //> // takes every triangle as clockwise.
    // END LAB 2
    const int64_t cx = int64_t(px) * 256 + 128, cy = int64_t(py) * 256 + 128;  // the centre, 16.8
    for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        const int64_t e = edgeFunction(x[k], y[k], x[k1], y[k1], cx, cy);
        // LAB 3: a centre exactly on an edge (e = 0) belongs to the triangle only when the edge is a
        // top or left one (isTopOrLeft), so that of two triangles sharing the edge exactly one covers it.
        if (e < 0 || (e == 0 && !isTopOrLeft(x[k1] - x[k], y[k1] - y[k]))) return false;
    }
    return true;
}

// The scene: the adversarial triangles of raster/scenes.hpp, added up (a pixel covered twice is
// brighter, one never covered stays dark), drawn through labCovers.
struct VsPassThrough {
    struct In {
        glm::vec4 position, color;
        RASTER_INPUT_SIGNATURE(In, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(color, "COLOR", 0))
    };
    struct Out {
        glm::vec4 position, color;
    };
    Out operator()(const In& in) const { return {in.position, in.color}; }
};

struct PsColor {
    glm::vec4 operator()(const VsPassThrough::Out& in) const { return in.color; }
};

class RasterizerLab final : public LabScene {
  public:
    explicit RasterizerLab(const SceneOptions& o) : data_(o) {}

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);  // clear, bind, viewport, no culling
        data_.bind(context);                     // the triangles, additive blending, no depth test
        context.setCoverageTest(&labCovers);
        context.draw(VsPassThrough{}, PsColor{}, data_.vertexCount);
    }

  private:
    CoverageSceneData data_;
};

}  // namespace

RASTER_LAB("rasterizer", "Lab: inside the rasterizer (coverage, 16.8 snapping, the top-left rule)",
           RasterizerLab, (raster::SceneCamera{{0, 0, 1}, {0, 0, 0}}))
