// Stage 7, rasterisation: which pixel centres a primitive covers, within one tile.
//
// Triangles are walked in 2×2 quads aligned to even pixel coordinates (the pixel shader needs
// quads for derivatives). Coverage is exact integer arithmetic on the 16.8 edge functions of
// TriangleSetup with the top-left rule, so a pixel centre on an edge shared by two triangles is
// covered by exactly one of them. Lanes are numbered 0 top-left, 1 top-right, 2 bottom-left,
// 3 bottom-right.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "raster/simd.hpp"
#include "raster/stages/5_setup.hpp"

namespace raster {

struct Quad {
    int32_t x, y;     // pixel of lane 0 (both even)
    uint32_t mask;    // covered lanes, bit l for lane l
    int64_t e[3];     // edge functions at lane 0's centre
};

struct EdgeSteps {
    int64_t dx[3], dy[3];  // change of E_k per pixel step in x and in y
};

inline EdgeSteps edgeSteps(const TriangleSetup& t) {
    EdgeSteps s;
    for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        s.dx[k] = -int64_t(t.y[k1] - t.y[k]) * kSubpixelOne;
        s.dy[k] = int64_t(t.x[k1] - t.x[k]) * kSubpixelOne;
    }
    return s;
}

// Edge k's function E_k at pixel (px, py)'s centre (without the top-left bias).
inline int64_t edgeAt(const TriangleSetup& t, int k, int32_t px, int32_t py) {
    const int k1 = (k + 1) % 3;
    return edgeFunction(t.x[k], t.y[k], t.x[k1], t.y[k1], pixelCentre(px), pixelCentre(py));
}

// Calls visit(const Quad&) for every quad in `tile` with at least one covered lane, rows top to
// bottom, quads left to right.
template <class Visit>
void rasterizeTriangle(const TriangleSetup& t, const EdgeSteps& s, const PixelRect& tile, Visit&& visit) {
    const PixelRect area = intersect(t.box, tile);
    if (area.empty()) return;
    const int32_t x0 = area.x0, x1 = area.x1, y0 = area.y0, y1 = area.y1;
    const int32_t qx0 = x0 & ~1, qy0 = y0 & ~1;
    int64_t row[3];
    for (int k = 0; k < 3; ++k) row[k] = edgeAt(t, k, qx0, qy0) + t.bias[k];
    for (int32_t y = qy0; y <= y1; y += 2) {
        // Lanes outside [x0, x1] × [y0, y1] belong to another tile or lie outside the clip rectangle.
        const uint32_t rows = (y >= y0 ? 0x3u : 0u) | (y + 1 <= y1 ? 0xCu : 0u);
        int64_t e[3] = {row[0], row[1], row[2]};
        for (int32_t x = qx0; x <= x1; x += 2) {
            const uint32_t cols = (x >= x0 ? 0x5u : 0u) | (x + 1 <= x1 ? 0xAu : 0u);
            uint32_t mask = rows & cols;
            for (int k = 0; k < 3; ++k) {
                const int64_t e0 = e[k], e1 = e0 + s.dx[k], e2 = e0 + s.dy[k], e3 = e2 + s.dx[k];
                mask &= (e0 >= 0 ? 1u : 0u) | (e1 >= 0 ? 2u : 0u) | (e2 >= 0 ? 4u : 0u) | (e3 >= 0 ? 8u : 0u);
            }
            if (mask) visit(Quad{x, y, mask, {e[0] - t.bias[0], e[1] - t.bias[1], e[2] - t.bias[2]}});
            for (int k = 0; k < 3; ++k) e[k] += 2 * s.dx[k];
        }
        for (int k = 0; k < 3; ++k) row[k] += 2 * s.dy[k];
    }
}

// The library's coverage rule as a CoverageTest (stages/5_setup.hpp): the triangle snapped and set up
// by setupTriangle (no culling, no clip rectangle), then the edge functions with the top-left bias at
// the pixel's centre, exactly as rasterizeTriangle decides. A triangle of no area covers nothing.
// The rasterizer lab's solution is the student's version of it (tests/labs_test.cpp compares them).
inline bool coversPixelCentre(const CoverageTriangle& triangle, int32_t px, int32_t py) {
    ScreenVertex s[3];
    for (int k = 0; k < 3; ++k) s[k] = {snap(triangle.x[k]), snap(triangle.y[k]), 0.0f, 1.0f};
    RasterizerState rs;
    rs.cullMode = CullMode::None;
    const PixelRect everywhere{INT32_MIN / 2, INT32_MIN / 2, INT32_MAX / 2, INT32_MAX / 2};
    const uint32_t vertex[3] = {0, 1, 2};
    TriangleSetup t;
    const SetupResult result = setupTriangle(s, vertex, 0, rs, everywhere, t);
    if (result == SetupResult::Degenerate) return false;
    for (int k = 0; k < 3; ++k)
        if (edgeAt(t, k, px, py) + t.bias[k] < 0) return false;
    return true;
}

// rasterizeTriangle with the coverage decided by covered(px, py) instead of the edge functions: every
// quad of the triangle's box inside `tile` is asked, lane by lane, and visited when a lane is
// covered (Quad::e still the edge functions at lane 0's centre, for interpolation). The teaching
// pipeline's draws with a lab's coverage test take it (fill/quads.hpp).
template <class Covered, class Visit>
void rasterizeTriangleCovered(const TriangleSetup& t, const PixelRect& tile, Covered&& covered,
                              Visit&& visit) {
    const int32_t x0 = std::max(t.box.x0, tile.x0), x1 = std::min(t.box.x1, tile.x1);
    const int32_t y0 = std::max(t.box.y0, tile.y0), y1 = std::min(t.box.y1, tile.y1);
    for (int32_t y = y0 & ~1; y <= y1; y += 2) {
        for (int32_t x = x0 & ~1; x <= x1; x += 2) {
            uint32_t mask = 0;
            for (int lane = 0; lane < 4; ++lane) {
                const int32_t lx = x + (lane & 1), ly = y + (lane >> 1);
                if (lx >= x0 && lx <= x1 && ly >= y0 && ly <= y1 && covered(lx, ly)) mask |= 1u << lane;
            }
            if (mask) visit(Quad{x, y, mask, {edgeAt(t, 0, x, y), edgeAt(t, 1, x, y), edgeAt(t, 2, x, y)}});
        }
    }
}

// Calls visit(px, py, t) for each pixel of the line inside `tile`, t being the pixel centre's
// position along the line (0 at vertex 0, 1 at vertex 1) projected on the major axis.
template <class Visit>
void rasterizeLine(const LineSetup& l, const PixelRect& tile, Visit&& visit) {
    const PixelRect area = intersect(l.box, tile);
    if (area.empty()) return;
    const int32_t x0 = area.x0, x1 = area.x1, y0 = area.y0, y1 = area.y1;
    const int m = l.xMajor ? 0 : 1;  // major axis
    const int64_t a0 = m == 0 ? l.x[0] : l.y[0], a1 = m == 0 ? l.x[1] : l.y[1];
    const int64_t b0 = m == 0 ? l.y[0] : l.x[0], b1 = m == 0 ? l.y[1] : l.x[1];
    const int32_t lo = m == 0 ? x0 : y0, hi = m == 0 ? x1 : y1;
    const int32_t minor_lo = m == 0 ? y0 : x0, minor_hi = m == 0 ? y1 : x1;
    for (int32_t i = lo; i <= hi; ++i) {
        const int64_t c = pixelCentre(i);
        // Half-open [start, end) in the direction of travel.
        const bool inside = a1 > a0 ? (c >= a0 && c < a1) : (c <= a0 && c > a1);
        if (!inside) continue;
        const double t = double(c - a0) / double(a1 - a0);
        const double minor = (double(b0) + t * double(b1 - b0)) / kSubpixelOne;  // pixels
        const int32_t j = int32_t(std::floor(minor));
        if (j < minor_lo || j > minor_hi) continue;
        if (m == 0)
            visit(i, j, t);
        else
            visit(j, i, t);
    }
}

}  // namespace raster
