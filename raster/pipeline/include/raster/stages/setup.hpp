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
// coversPixelCentre (stages/rasterizer.hpp), which applies the rules of this file and of
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

inline bool isTopLeft(int32_t dx, int32_t dy) { return dy < 0 || (dy == 0 && dx > 0); }

inline SetupResult setupTriangle(const ScreenVertex (&s)[3], const uint32_t (&vertex)[3], uint32_t primitive_id,
                                 const RasterizerState& rs, const PixelRect& clip, TriangleSetup& t) {
    int64_t area2 = int64_t(s[1].x - s[0].x) * (s[2].y - s[0].y) - int64_t(s[1].y - s[0].y) * (s[2].x - s[0].x);
    if (area2 == 0) return SetupResult::Degenerate;
    const bool clockwise = area2 > 0;  // y grows downwards on screen
    t.frontFacing = rs.frontCounterClockwise ? !clockwise : clockwise;
    if ((rs.cullMode == CullMode::Back && !t.frontFacing) || (rs.cullMode == CullMode::Front && t.frontFacing))
        return SetupResult::Culled;
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

// A camera-facing billboard, as the lecture's gsBillboard opens it in clip space, is a strip of two
// triangles (v0, v1, v2), (v1, v3, v2) whose corners share x and y pairwise after snapping, with one
// z and one w. Such a strip is set up once as a rectangle: it covers exactly the pixels the two
// triangles would (by the top-left rule: centres on the left and top edges in, on the right and
// bottom edges out; the shared diagonal belongs to one triangle, so the union is the rectangle),
// with one depth, and since w is constant its perspective-correct attributes are affine in screen
// space: value(x, y) = base + (x − x0)·stepX + (y − y0)·stepY, all three precomputed in double.
// Only strips whose attributes satisfy a0 + a3 = a1 + a2 exactly (one plane for both triangles)
// qualify; anything else is drawn as two triangles.
struct RectSetup {
    PixelRect box;       // covered pixels, inside the clip rectangle
    float z;
    uint32_t vertex;     // base, stepX, stepY: three records in the chunk's vertex pool
    uint32_t primitiveId;
};

// Tries to set up the strip v[0..3] as a rectangle. On success fills r (r.vertex left to the
// caller) and base/step_x/step_y, and returns true; `culled` tells a rectangle removed by culling.
template <class V>
bool setupRectangle(const V* const (&v)[4], const ScreenVertex (&s)[4], uint32_t primitive_id,
                    const RasterizerState& rs, const PixelRect& clip, RectSetup& r, V& base, V& step_x, V& step_y,
                    bool& culled) {
    culled = false;
    for (int i = 1; i < 4; ++i)
        if (v[i]->position.z != v[0]->position.z || v[i]->position.w != v[0]->position.w) return false;
    // Which corner lies along x and which along y from v0 (the other pair is the diagonal).
    int cx, cy;
    if (s[0].x == s[1].x && s[2].x == s[3].x && s[0].y == s[2].y && s[1].y == s[3].y)
        cx = 2, cy = 1;
    else if (s[0].x == s[2].x && s[1].x == s[3].x && s[0].y == s[1].y && s[2].y == s[3].y)
        cx = 1, cy = 2;
    else
        return false;
    const int64_t width = int64_t(s[cx].x) - s[0].x, height = int64_t(s[cy].y) - s[0].y;
    if (width == 0 || height == 0) return false;
    const float* a0 = asFloats(*v[0]);
    const float* a1 = asFloats(*v[1]);
    const float* a2 = asFloats(*v[2]);
    const float* a3 = asFloats(*v[3]);
    for (uint32_t i = 4; i < kVertexFloats<V>; ++i)
        if (a0[i] + a3[i] != a1[i] + a2[i]) return false;
    // Triangle (v0, v1, v2)'s winding decides facing for both (the strip keeps winding).
    const int64_t area2 =
        int64_t(s[1].x - s[0].x) * (s[2].y - s[0].y) - int64_t(s[1].y - s[0].y) * (s[2].x - s[0].x);
    const bool clockwise = area2 > 0;
    const bool front = rs.frontCounterClockwise ? !clockwise : clockwise;
    if ((rs.cullMode == CullMode::Back && !front) || (rs.cullMode == CullMode::Front && front)) {
        culled = true;
        return true;
    }
    const int32_t xl = std::min(s[0].x, s[cx].x), xr = std::max(s[0].x, s[cx].x);
    const int32_t yt = std::min(s[0].y, s[cy].y), yb = std::max(s[0].y, s[cy].y);
    r.box = {std::max(clip.x0, firstPixel(xl)), std::max(clip.y0, firstPixel(yt)),
             std::min(clip.x1, firstPixel(xr) - 1), std::min(clip.y1, firstPixel(yb) - 1)};
    r.z = s[0].z;
    r.primitiveId = primitive_id;
    // Pixel centre (box.x0 + ½, box.y0 + ½) relative to v0, in pixels.
    const double fx = (double(r.box.x0) * kSubpixelOne + kSubpixelHalf - s[0].x) / double(width);
    const double fy = (double(r.box.y0) * kSubpixelOne + kSubpixelHalf - s[0].y) / double(height);
    const double px = double(kSubpixelOne) / double(width), py = double(kSubpixelOne) / double(height);
    const float* ax = asFloats(*v[cx]);
    const float* ay = asFloats(*v[cy]);
    float* b = asFloats(base);
    float* dx = asFloats(step_x);
    float* dy = asFloats(step_y);
    for (uint32_t i = 4; i < kVertexFloats<V>; ++i) {
        const double ex = double(ax[i]) - a0[i], ey = double(ay[i]) - a0[i];
        b[i] = float(a0[i] + ex * fx + ey * fy);
        dx[i] = float(ex * px);
        dy[i] = float(ey * py);
    }
    base.position = glm::vec4(float(r.box.x0) + 0.5f, float(r.box.y0) + 0.5f, r.z, v[0]->position.w);
    step_x.position = glm::vec4(1, 0, 0, 0);
    step_y.position = glm::vec4(0, 1, 0, 0);
    return true;
}

}  // namespace raster
