// Accelerates stage 7, rasterisation (stages/7_rasterizer.hpp): rasterizeTriangle's coverage, the same
// integer edge functions and top-left bias, walked in 4×2 blocks for the eight-wide pixel shader.
// A block's eight lanes are its lane 0's edge values plus a per-triangle offset (exact int64), rows
// of blocks that no lane can cover are skipped by exact integer division, and blocks wholly inside
// need no compare. The covered lanes are exactly rasterizeTriangle's: tests/fastpath_test.cpp
// (BlockCoverage) checks lane by lane, edge values included, on random and degenerate triangles.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "raster/simd.hpp"
#include "raster/stages/7_rasterizer.hpp"

namespace raster {

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
    const PixelRect area = intersect(t.box, tile);
    if (area.empty()) return;
    const int32_t x0 = area.x0, x1 = area.x1, y0 = area.y0, y1 = area.y1;
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

}  // namespace raster
