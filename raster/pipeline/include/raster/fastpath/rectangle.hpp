// Accelerates stages 5 and 7, setup and rasterisation (stages/5_setup.hpp, stages/7_rasterizer.hpp),
// for the lecture's camera-facing billboards: a four-vertex strip that is an axis-aligned rectangle
// on screen is set up once and walked as a rectangle instead of as two triangles. It covers exactly
// the pixels the two triangles' top-left rule gives, culls by the same test, and its attributes are
// the triangles' plane. tests/fastpath_test.cpp (RectangleFastPath) checks coverage and culling
// against setupTriangle + rasterizeTriangle, and the attributes against interpolateAttributes.
#pragma once

#include <algorithm>
#include <cstdint>

#include "raster/shader.hpp"
#include "raster/stages/5_setup.hpp"

namespace raster {

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
    const int64_t area2 = edgeFunction(s[0].x, s[0].y, s[1].x, s[1].y, s[2].x, s[2].y);
    if (isCulled(isFrontFacing(area2, rs), rs.cullMode)) {
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
    const double fx = double(pixelCentre(r.box.x0) - s[0].x) / double(width);
    const double fy = double(pixelCentre(r.box.y0) - s[0].y) / double(height);
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

// Calls visit(x, y, mask) for every 2×2 quad (x, y even) of the rectangle inside `tile`, mask
// holding the covered lanes.
template <class Visit>
void rasterizeRect(const PixelRect& box, const PixelRect& tile, Visit&& visit) {
    const PixelRect area = intersect(box, tile);
    if (area.empty()) return;
    const int32_t x0 = area.x0, x1 = area.x1, y0 = area.y0, y1 = area.y1;
    for (int32_t y = y0 & ~1; y <= y1; y += 2) {
        const uint32_t rows = (y >= y0 ? 0x3u : 0u) | (y + 1 <= y1 ? 0xCu : 0u);
        for (int32_t x = x0 & ~1; x <= x1; x += 2) {
            const uint32_t cols = (x >= x0 ? 0x5u : 0u) | (x + 1 <= x1 ? 0xAu : 0u);
            visit(x, y, rows & cols);
        }
    }
}

}  // namespace raster
