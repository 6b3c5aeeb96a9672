// Stage 5, primitive setup: the viewport transform, snapping to the rasteriser's fixed point,
// face culling, and everything the rasteriser needs per primitive computed once.
//
// Rules (Direct3D 11):
//  - viewport: x_s = (x/w + 1)/2 · width + topLeftX, y_s = (1 − y/w)/2 · height + topLeftY
//    (row 0 on top), z_s = minDepth + z/w · (maxDepth − minDepth); computed in double, so that
//    the fast and the reference pipeline snap to the same positions;
//  - positions snap to 16.8 fixed point (1/256 pixel), round to nearest even;
//  - a triangle is front-facing when clockwise on screen, unless frontCounterClockwise;
//    zero area after snapping is never drawn;
//  - pixel centres are at (i + 0.5, j + 0.5): pixel (i, j) is a candidate when its centre lies in
//    the primitive's box and in the clip rectangle (render target ∩ viewport ∩ scissor).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "raster/shader.hpp"
#include "raster/states.hpp"

namespace raster {

constexpr int kSubpixelBits = 8;
constexpr int32_t kSubpixelOne = 1 << kSubpixelBits;    // 1 pixel in 16.8
constexpr int32_t kSubpixelHalf = kSubpixelOne / 2;     // a pixel centre's offset

struct ViewportTransform {
    double sx = 0, ox = 0, sy = 0, oy = 0, sz = 0, oz = 0;
    float minDepth = 0, maxDepth = 1;

    explicit ViewportTransform(const Viewport& v = {})
        : sx(v.width * 0.5), ox(v.topLeftX + v.width * 0.5), sy(-v.height * 0.5), oy(v.topLeftY + v.height * 0.5),
          sz(double(v.maxDepth) - v.minDepth), oz(v.minDepth), minDepth(v.minDepth), maxDepth(v.maxDepth) {}
};

// 16.8 fixed-point snap, round half to even (the default FP rounding mode).
inline int32_t snap(double screen) { return int32_t(std::nearbyint(screen * kSubpixelOne)); }

// Floor division for the fixed-point → pixel conversions (works for negative numerators).
inline int32_t floorDiv(int64_t a, int64_t b) { return int32_t(a >= 0 ? a / b : -((-a + b - 1) / b)); }

struct ScreenVertex {
    int32_t x, y;  // 16.8
    float z;       // viewport depth
    float invW;
};

// A clip-space position's window x and y in pixels (x right, y down), before snapping: the values
// toScreen snaps, and what a lab's coverage test is given (CoverageTriangle).
inline double windowX(const glm::vec4& clip, const ViewportTransform& vp) {
    return double(clip.x) * (1.0 / double(clip.w)) * vp.sx + vp.ox;
}
inline double windowY(const glm::vec4& clip, const ViewportTransform& vp) {
    return double(clip.y) * (1.0 / double(clip.w)) * vp.sy + vp.oy;
}

inline ScreenVertex toScreen(const glm::vec4& clip, const ViewportTransform& vp) {
    const double inv_w = 1.0 / double(clip.w);
    return {snap(windowX(clip, vp)), snap(windowY(clip, vp)), float(double(clip.z) * inv_w * vp.sz + vp.oz),
            float(inv_w)};
}

// A triangle as a coverage test is given it (the rasterizer lab, Context::setCoverageTest): its
// vertices' window positions in pixels, unsnapped, in the order the draw gave them (x right, y down;
// pixel (i, j) spans [i, i + 1) × [j, j + 1), its centre at (i + ½, j + ½)).
struct CoverageTriangle {
    double x[3], y[3];
};
// Whether the triangle covers pixel (px, py)'s centre. The library's answer is
// coversPixelCentre (stages/7_rasterizer.hpp), which applies the rules of this file and of
// TriangleSetup: snap each coordinate to 16.8 fixed point (X = nearbyint(256·x), ties to even);
// take the centre in the same units, (256·px + 128, 256·py + 128); order the vertices clockwise on
// screen (swap vertices 1 and 2 when twice the signed area is negative); the centre is covered when
// every edge function E_k (64-bit integers, 16.16 units) is > 0, or = 0 on a top or left edge.
// Why: after the snap everything is exact integer arithmetic, so two triangles sharing an edge
// evaluate the very same edge function (negated) at every centre, and the top-left rule gives a
// centre exactly on it to exactly one of them: no pixel of a mesh is drawn twice or left out.
using CoverageTest = bool (*)(const CoverageTriangle& triangle, int32_t px, int32_t py);

// Pixels whose centres lie within [lo, hi] (16.8 coordinates).
inline int32_t firstPixel(int32_t lo) { return floorDiv(int64_t(lo) - kSubpixelHalf + kSubpixelOne - 1, kSubpixelOne); }
inline int32_t lastPixel(int32_t hi) { return floorDiv(int64_t(hi) - kSubpixelHalf, kSubpixelOne); }

// Pixel p's centre, p + ½, in 16.8 fixed point.
inline int64_t pixelCentre(int32_t p) { return int64_t(p) * kSubpixelOne + kSubpixelHalf; }

// The edge function of the directed edge (x0, y0) → (x1, y1) at the point (px, py), every coordinate
// in 16.8 fixed point: (x1 − x0)·(py − y0) − (y1 − y0)·(px − x0), in 16.16 units, exact in int64.
// It is twice the signed area of the triangle (x0, y0), (x1, y1), (px, py): positive when the point
// lies on the inner side of a clockwise triangle's edge (y grows downwards). Setup's area, the
// rasteriser's coverage and the binner's tile test all evaluate this one function.
inline int64_t edgeFunction(int64_t x0, int64_t y0, int64_t x1, int64_t y1, int64_t px, int64_t py) {
    return (x1 - x0) * (py - y0) - (y1 - y0) * (px - x0);
}

// A triangle ready to rasterise. Vertices are ordered so that twice the signed area is positive;
// edge k runs from vertex k to vertex k+1 and its edge function
//   E_k(p) = (x[k+1] − x[k])·(p.y − y[k]) − (y[k+1] − y[k])·(p.x − x[k])      (16.16 units)
// is positive inside. The top-left rule: a pixel centre on an edge is inside only if the edge is
// a top edge (horizontal, the triangle below it: dy = 0, dx > 0) or a left edge (dy < 0);
// bias[k] is 0 for those and −1 otherwise, and a centre is covered iff E_k + bias[k] >= 0 for
// all k. The barycentric weight of vertex k is E_{k+1}/area2 (vertex 0 faces edge 1).
struct TriangleSetup {
    int32_t x[3], y[3];
    int64_t area2;
    double invArea2;     // 1 / area2, for depth (see interpolateDepth)
    int64_t bias[3];
    float z[3], invW[3];
    // z[0], z[1] and z[2] are one finite, non-zero float (same bits): depth is z[0] everywhere
    // (interpolateDepth). The sky at the far plane, a billboard drawn as two triangles.
    bool flatDepth;
    uint32_t vertex[3];  // indices of the clip-space vertices in the chunk's vertex pool
    uint32_t primitiveId;
    PixelRect box;       // candidate pixels, already inside the clip rectangle
    bool frontFacing;
};


enum class SetupResult : uint8_t { Ok, Culled, Degenerate, NoPixels };

// Face culling (D3D11): a triangle whose twice-signed area is positive is clockwise on screen and
// front-facing, unless frontCounterClockwise; CullMode::Back removes back faces, Front front faces.
// Triangles and billboard rectangles (fastpath/rectangle.hpp) are culled by these two.
inline bool isFrontFacing(int64_t area2, const RasterizerState& rs) {
    const bool clockwise = area2 > 0;
    return rs.frontCounterClockwise ? !clockwise : clockwise;
}
inline bool isCulled(bool front_facing, CullMode mode) {
    return (mode == CullMode::Back && !front_facing) || (mode == CullMode::Front && front_facing);
}

inline bool isTopLeft(int32_t dx, int32_t dy) { return dy < 0 || (dy == 0 && dx > 0); }

inline SetupResult setupTriangle(const ScreenVertex (&s)[3], const uint32_t (&vertex)[3], uint32_t primitive_id,
                                 const RasterizerState& rs, const PixelRect& clip, TriangleSetup& t) {
    const int64_t area2 = edgeFunction(s[0].x, s[0].y, s[1].x, s[1].y, s[2].x, s[2].y);
    if (area2 == 0) return SetupResult::Degenerate;
    const bool clockwise = area2 > 0;
    t.frontFacing = isFrontFacing(area2, rs);
    if (isCulled(t.frontFacing, rs.cullMode)) return SetupResult::Culled;
    const int order[3] = {0, clockwise ? 1 : 2, clockwise ? 2 : 1};
    for (int k = 0; k < 3; ++k) {
        const ScreenVertex& v = s[order[k]];
        t.x[k] = v.x, t.y[k] = v.y, t.z[k] = v.z, t.invW[k] = v.invW;
        t.vertex[k] = vertex[order[k]];
    }
    t.area2 = clockwise ? area2 : -area2;
    t.invArea2 = 1.0 / double(t.area2);
    t.flatDepth = std::bit_cast<uint32_t>(t.z[0]) == std::bit_cast<uint32_t>(t.z[1]) &&
                  std::bit_cast<uint32_t>(t.z[0]) == std::bit_cast<uint32_t>(t.z[2]) && std::isfinite(t.z[0]) &&
                  t.z[0] != 0.0f;
    for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        t.bias[k] = isTopLeft(t.x[k1] - t.x[k], t.y[k1] - t.y[k]) ? 0 : -1;
    }
    t.primitiveId = primitive_id;
    t.box.x0 = std::max(clip.x0, firstPixel(std::min({t.x[0], t.x[1], t.x[2]})));
    t.box.x1 = std::min(clip.x1, lastPixel(std::max({t.x[0], t.x[1], t.x[2]})));
    t.box.y0 = std::max(clip.y0, firstPixel(std::min({t.y[0], t.y[1], t.y[2]})));
    t.box.y1 = std::min(clip.y1, lastPixel(std::max({t.y[0], t.y[1], t.y[2]})));
    return t.box.empty() ? SetupResult::NoPixels : SetupResult::Ok;
}

// A point covers the one pixel whose centre lies in [x − ½, x + ½) × [y − ½, y + ½): D3D11 draws
// a point as a one-pixel square under the top-left rule.
struct PointSetup {
    int32_t px, py;
    float z;
    uint32_t vertex;
    uint32_t primitiveId;
};

inline bool setupPoint(const ScreenVertex& s, uint32_t vertex, uint32_t primitive_id, const PixelRect& clip,
                       PointSetup& p) {
    p.px = floorDiv(int64_t(s.x) + kSubpixelOne - 1, kSubpixelOne) - 1;
    p.py = floorDiv(int64_t(s.y) + kSubpixelOne - 1, kSubpixelOne) - 1;
    p.z = s.z;
    p.vertex = vertex;
    p.primitiveId = primitive_id;
    return p.px >= clip.x0 && p.px <= clip.x1 && p.py >= clip.y0 && p.py <= clip.y1;
}

// A line is drawn one pixel per step along its major axis (|dx| >= |dy|: x-major): the pixels
// whose centres' major coordinate lies in [start, end) — the last pixel is left to the next
// segment of a strip — and, on the minor axis, the pixel whose centre is nearest the line (a tie
// goes to the larger coordinate). This matches D3D11's aliased "diamond exit" rule except at
// the end points, where D3D's rule can add or drop one pixel: documented, not emulated.
struct LineSetup {
    int32_t x[2], y[2];
    float z[2], invW[2];
    uint32_t vertex[2];
    uint32_t primitiveId;
    bool xMajor;
    PixelRect box;
};

inline bool setupLine(const ScreenVertex (&s)[2], const uint32_t (&vertex)[2], uint32_t primitive_id,
                      const PixelRect& clip, LineSetup& l) {
    for (int k = 0; k < 2; ++k) {
        l.x[k] = s[k].x, l.y[k] = s[k].y, l.z[k] = s[k].z, l.invW[k] = s[k].invW;
        l.vertex[k] = vertex[k];
    }
    if (l.x[0] == l.x[1] && l.y[0] == l.y[1]) return false;
    l.primitiveId = primitive_id;
    l.xMajor = std::abs(int64_t(l.x[1]) - l.x[0]) >= std::abs(int64_t(l.y[1]) - l.y[0]);
    l.box.x0 = std::max(clip.x0, floorDiv(std::min(l.x[0], l.x[1]), kSubpixelOne) - 1);
    l.box.x1 = std::min(clip.x1, floorDiv(std::max(l.x[0], l.x[1]), kSubpixelOne) + 1);
    l.box.y0 = std::max(clip.y0, floorDiv(std::min(l.y[0], l.y[1]), kSubpixelOne) - 1);
    l.box.y1 = std::min(clip.y1, floorDiv(std::max(l.y[0], l.y[1]), kSubpixelOne) + 1);
    return !l.box.empty();
}

}  // namespace raster
