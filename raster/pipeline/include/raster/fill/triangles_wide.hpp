// The eight-wide triangle path: a triangle's 4×2 blocks (stages/7_rasterizer.hpp's
// rasterizeTriangleBlocks) go through the depth test, the shader and the blend eight lanes at a time;
// blocks on the tile's border go quad by quad through the plain steps (fill/tile.hpp). Taken where
// the shader runs eight wide and the depth and colour policies have eight-wide forms
// (FillTraits::kWideMerge). The same arithmetic lane by lane as fill/quads.hpp, so the same bits.
#pragma once

#include <array>
#include <bit>
#include <cstdint>

#include "raster/fastpath/block_coverage.hpp"
#include "raster/fastpath/interpolate_wide.hpp"
#include "raster/fastpath/merge_wide.hpp"
#include "raster/fill/tile.hpp"

namespace raster {

namespace detail {

// One border block of a triangle (not wholly inside the tile): its two 2×2 quads, lane by lane.
template <class T>
void shadeBorderBlock(T& tile, const TriangleSetup& t, const TriangleInterpolant<typename T::RealType>& ti,
                      const typename T::Vertex* const (&verts)[3], int32_t x, int32_t y, uint32_t mask,
                      const int64_t (&e)[3][8]) {
    using Real = typename T::RealType;
    using V = typename T::Vertex;
    const float min_depth = tile.draw.minDepth, max_depth = tile.draw.maxDepth;
    for (int half = 0; half < 2; ++half) {
        const int b = 2 * half;  // block lanes b, b+1, b+4, b+5 form the quad
        const uint32_t qmask = ((mask >> b) & 3u) | (((mask >> (b + 4)) & 3u) << 2);
        if (!qmask) continue;
        const int32_t qx = x + b;
        // Helper lanes may lie outside the block's mask: their edge functions are extrapolated.
        auto edges = [&](int lane) {
            const int bl = b + (lane & 1) + 4 * (lane >> 1);
            return std::array<int64_t, 3>{e[0][bl], e[1][bl], e[2][bl]};
        };
        tile.shadeQuad(
            qx, y, qmask,
            [&](int lane) {
                const auto el = edges(lane);
                return interpolateDepth<Real>(t, el[0], el[1], el[2], min_depth, max_depth);
            },
            [&](int lane, Real zl, V& in) {
                const auto el = edges(lane);
                interpolateAttributes(ti, barycentrics(ti, el[0], el[1], el[2]), verts, qx + (lane & 1),
                                      y + (lane >> 1), zl, in);
            });
    }
}

}  // namespace detail

template <class T>
RASTER_FLATTEN void fillTriangleWide(T& tile, const TriangleSetup& t,
                                     const TriangleInterpolant<typename T::RealType>& ti,
                                     const EdgeSteps& steps, const typename T::Vertex* const (&verts)[3]) {
    using V = typename T::Vertex;
    using Depth = typename T::DepthPolicyType;
    using Color = typename T::ColorPolicyType;
    if constexpr (T::kWideMerge) {
        // What every block reads, in locals: the targets are written through uint8_t and float
        // pointers, which may alias anything, so through `tile` the compiler would load it again for
        // every block. The merge holds the depth and colour policies (fastpath/merge_wide.hpp).
        const PixelRect rect = tile.rect;
        WideMerge<Depth, Color, NoOpLanes::Skipped> merge(tile.draw.depth, tile.draw.color);
        const auto shader = tile.wideShader;
        const float min_depth = tile.draw.minDepth, max_depth = tile.draw.maxDepth;
        uint64_t saturated = 0;
        // With a Float8x2 shader an inner block waits, interpolated, for the rasteriser's next
        // block: if that is its right neighbour, the two are shaded in one call (shadePairWide).
        // Blocks of one triangle cover distinct pixels, so delaying one's tests and writes past
        // its neighbour's changes no bit.
        struct Waiting {
            bool held;
            int32_t x, y;
            uint32_t live;
            Float8 z;
            Wide<V> in;
        };
        [[maybe_unused]] Waiting waiting{};
        [[maybe_unused]] auto flush = [&] {
            if constexpr (T::kPairs) {
                if (!waiting.held) return;
                merge.block(waiting.x, waiting.y, waiting.z, waiting.live,
                            tile.shadeInputWide(shader, waiting.in, waiting.live));
                waiting.held = false;
            }
        };
        rasterizeTriangleBlocks(
            t, steps, rect, [&](int32_t x, int32_t y, uint32_t mask, const int64_t(&e)[3][8]) {
                if (!(x >= rect.x0 && x + 3 <= rect.x1 && y >= rect.y0 && y + 1 <= rect.y1)) {
                    detail::shadeBorderBlock(tile, t, ti, verts, x, y, mask, e);
                    return;
                }
                const Float8 z = interpolateDepthWide(t, e, min_depth, max_depth);
                uint32_t live = mask;
                if constexpr (Depth::kEnabled) {
                    live = tile.depthTestBlock(merge.depth(), x, y, z, mask);
                    if (!live) return;
                }
                // A block whose pixels are all at the blend's ceiling is not shaded (fill/rectangles.hpp).
                if constexpr (Color::kCeiling) {
                    if (merge.color().template atCeiling<1>(x, y)) {
                        saturated += uint64_t(std::popcount(live));
                        return;
                    }
                }
                if constexpr (T::kPairs) {
                    Wide<V> in;
                    interpolateAttributesWide(ti, e, verts, x, y, z, in);
                    if (waiting.held && waiting.y == y && waiting.x + 4 == x) {
                        const glm::vec<4, Float8x2> c =
                            tile.shadePairWide(shader, waiting.in, in, waiting.live, live);
                        merge.pair(waiting.x, y, waiting.z, z, waiting.live, live, c);
                        waiting.held = false;
                    } else {
                        flush();
                        waiting = Waiting{true, x, y, live, z, in};
                    }
                } else {
                    merge.block(x, y, z, live, tile.shadeBlockWide(shader, ti, e, verts, x, y, z, live));
                }
            });
        flush();
        tile.countBlendNoOps(merge.noOps());
        tile.countSaturated(saturated);
    }
}

}  // namespace raster
