// Stage 6, rasterisation: which pixel centres a primitive covers, within one tile.
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
#include "raster/stages/setup.hpp"

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

inline int64_t edgeAt(const TriangleSetup& t, int k, int32_t px, int32_t py) {
    const int k1 = (k + 1) % 3;
    const int64_t cx = int64_t(px) * kSubpixelOne + kSubpixelHalf;
    const int64_t cy = int64_t(py) * kSubpixelOne + kSubpixelHalf;
    return int64_t(t.x[k1] - t.x[k]) * (cy - t.y[k]) - int64_t(t.y[k1] - t.y[k]) * (cx - t.x[k]);
}

// Calls visit(const Quad&) for every quad in `tile` with at least one covered lane, rows top to
// bottom, quads left to right.
template <class Visit>
void rasterizeTriangle(const TriangleSetup& t, const EdgeSteps& s, const PixelRect& tile, Visit&& visit) {
    const int32_t x0 = std::max(t.box.x0, tile.x0), x1 = std::min(t.box.x1, tile.x1);
    const int32_t y0 = std::max(t.box.y0, tile.y0), y1 = std::min(t.box.y1, tile.y1);
    if (x0 > x1 || y0 > y1) return;
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

// The library's coverage rule as a CoverageTest (stages/setup.hpp): the triangle snapped and set up
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

// A 4×2 block's edge functions relative to its lane 0's: per edge, the top row's four lanes and the
// bottom row's four, exact int64 (lane l at (l % 4, l / 4) pixels from lane 0).
struct BlockLaneOffsets {
    simd::I64x4 top[3], bottom[3];
    explicit BlockLaneOffsets(const EdgeSteps& s) {
        for (int k = 0; k < 3; ++k) {
            top[k] = simd::I64x4{0, s.dx[k], 2 * s.dx[k], 3 * s.dx[k]};
            bottom[k] = top[k] + s.dy[k];
        }
    }
};

// The same coverage walked in 4×2 blocks (x a multiple of 4, y even) for eight-wide shading:
// visit(x, y, mask, e) with lane l at (x + l % 4, y + l / 4), mask its covered lanes and e[k][l]
// the edge functions at each lane's centre (without the top-left bias).
namespace detail {
// Bit l set where lane l of the eight (two vectors of four) is >= 0.
inline uint32_t nonNegativeBits(simd::I64x4 top, simd::I64x4 bottom) {
    const simd::I64x4 t = top >= 0, b = bottom >= 0;  // clang's comparison gives long long lanes
    return simd::maskBits(t) | simd::maskBits(b) << 4;
}
}  // namespace detail

// The lanes of the 4×2 block at columns x..x + 3 whose column lies in [x0, x1], in both rows
// (lane bits as in simd.hpp: column c is bit c in the top row, c + 4 in the bottom). Two compares
// and a well-predicted branch for a block inside the span, which is nearly every block.
inline uint32_t blockColumns(int32_t x, int32_t x0, int32_t x1) {
    if (x >= x0 && x + 3 <= x1) [[likely]]
        return 0xFFu;
    const uint32_t left = (0xFu << std::clamp(x0 - x, 0, 4)) & 0xFu, right = 0xFu >> std::clamp(x + 3 - x1, 0, 4);
    return (left & right) * 0x11u;
}

template <class Visit>
void rasterizeTriangleBlocks(const TriangleSetup& t, const EdgeSteps& s, const PixelRect& tile, Visit&& visit) {
    const int32_t x0 = std::max(t.box.x0, tile.x0), x1 = std::min(t.box.x1, tile.x1);
    const int32_t y0 = std::max(t.box.y0, tile.y0), y1 = std::min(t.box.y1, tile.y1);
    if (x0 > x1 || y0 > y1) return;
    const int32_t bx0 = x0 & ~3, by0 = y0 & ~1;
    // The edge functions of a block's lanes are its lane 0's plus a per-triangle offset: exact
    // int64 arithmetic, four lanes to a vector (top row, bottom row).
    const BlockLaneOffsets lanes(s);
    simd::I64x4 bias[3];
    int64_t row[3];
    for (int k = 0; k < 3; ++k) {
        bias[k] = simd::I64x4{} + t.bias[k];
        row[k] = edgeAt(t, k, bx0, by0);
    }
    for (int32_t y = by0; y <= y1; y += 2) {
        const uint32_t rows = (y >= y0 ? 0x0Fu : 0u) | (y + 1 <= y1 ? 0xF0u : 0u);
        int64_t e0[3] = {row[0], row[1], row[2]};
        // Narrows [lo, hi] (block indices along the row) to the blocks whose chosen lane is ≥ 0
        // for every edge, lane_offset(k) placing that lane relative to the block's lane 0: exact
        // integer division where an edge crosses the row.
        auto narrow = [&](auto&& lane_offset, int64_t& lo, int64_t& hi) {
            for (int k = 0; k < 3 && lo <= hi; ++k) {
                const int64_t step = 4 * s.dx[k];  // per block
                const int64_t value = e0[k] + t.bias[k] + lane_offset(k);
                if (step > 0) {
                    if (value + lo * step < 0) lo = (-value + step - 1) / step;
                } else if (step < 0) {
                    if (value + hi * step < 0) hi = value < 0 ? -1 : value / -step;
                } else if (value < 0) {
                    hi = -1;
                }
            }
        };
        // The blocks of this row pair that some lane of could be covered: for each edge, a block's
        // largest lane is its right column (edge rising with x) or left column (falling), in the
        // row whose value is larger; the blocks outside have mask 0 and are not evaluated.
        int64_t first = 0, last = (x1 - bx0) / 4;
        narrow([&](int k) { return std::max<int64_t>(0, s.dy[k]) + (s.dx[k] > 0 ? 3 * s.dx[k] : 0); }, first, last);
        if (first > last) {
            for (int k = 0; k < 3; ++k) row[k] += 2 * s.dy[k];
            continue;
        }
        // Likewise the blocks whose smallest lane is ≥ 0 for every edge: all eight lanes inside,
        // so their mask needs no compares (big triangles: the sky, the ground).
        int64_t full_first = first, full_last = last;
        narrow([&](int k) { return std::min<int64_t>(0, s.dy[k]) + (s.dx[k] < 0 ? 3 * s.dx[k] : 0); }, full_first,
               full_last);
        const int32_t x_full0 = bx0 + int32_t(4 * full_first), x_full1 = bx0 + int32_t(4 * full_last);
        for (int k = 0; k < 3; ++k) e0[k] += first * 4 * s.dx[k];
        const int32_t x_end = bx0 + int32_t(4 * last);
        for (int32_t x = bx0 + int32_t(4 * first); x <= x_end; x += 4) {
            uint32_t mask = rows & blockColumns(x, x0, x1);
            const bool inside = x >= x_full0 && x <= x_full1;
            alignas(32) int64_t e[3][8];
            for (int k = 0; k < 3; ++k) {
                const simd::I64x4 top = e0[k] + lanes.top[k], bottom = e0[k] + lanes.bottom[k];
                std::memcpy(&e[k][0], &top, sizeof top);
                std::memcpy(&e[k][4], &bottom, sizeof bottom);
                if (!inside) mask &= detail::nonNegativeBits(top + bias[k], bottom + bias[k]);
            }
            if (mask) visit(x, y, mask, e);
            for (int k = 0; k < 3; ++k) e0[k] += 4 * s.dx[k];
        }
        for (int k = 0; k < 3; ++k) row[k] += 2 * s.dy[k];
    }
}

// Calls visit(x, y, mask) for every 2×2 quad (x, y even) of the rectangle inside `tile`, mask
// holding the covered lanes.
template <class Visit>
void rasterizeRect(const PixelRect& box, const PixelRect& tile, Visit&& visit) {
    const int32_t x0 = std::max(box.x0, tile.x0), x1 = std::min(box.x1, tile.x1);
    const int32_t y0 = std::max(box.y0, tile.y0), y1 = std::min(box.y1, tile.y1);
    if (x0 > x1 || y0 > y1) return;
    for (int32_t y = y0 & ~1; y <= y1; y += 2) {
        const uint32_t rows = (y >= y0 ? 0x3u : 0u) | (y + 1 <= y1 ? 0xCu : 0u);
        for (int32_t x = x0 & ~1; x <= x1; x += 2) {
            const uint32_t cols = (x >= x0 ? 0x5u : 0u) | (x + 1 <= x1 ? 0xAu : 0u);
            visit(x, y, rows & cols);
        }
    }
}

// Calls visit(px, py, t) for each pixel of the line inside `tile`, t being the pixel centre's
// position along the line (0 at vertex 0, 1 at vertex 1) projected on the major axis.
template <class Visit>
void rasterizeLine(const LineSetup& l, const PixelRect& tile, Visit&& visit) {
    const int32_t x0 = std::max(l.box.x0, tile.x0), x1 = std::min(l.box.x1, tile.x1);
    const int32_t y0 = std::max(l.box.y0, tile.y0), y1 = std::min(l.box.y1, tile.y1);
    if (x0 > x1 || y0 > y1) return;
    const int m = l.xMajor ? 0 : 1;  // major axis
    const int64_t a0 = m == 0 ? l.x[0] : l.y[0], a1 = m == 0 ? l.x[1] : l.y[1];
    const int64_t b0 = m == 0 ? l.y[0] : l.x[0], b1 = m == 0 ? l.y[1] : l.x[1];
    const int32_t lo = m == 0 ? x0 : y0, hi = m == 0 ? x1 : y1;
    const int32_t minor_lo = m == 0 ? y0 : x0, minor_hi = m == 0 ? y1 : x1;
    for (int32_t i = lo; i <= hi; ++i) {
        const int64_t c = int64_t(i) * kSubpixelOne + kSubpixelHalf;
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
