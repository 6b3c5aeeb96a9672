// Which fill path each primitive of a tile takes, and why, in one place. Context::renderTiles
// (pipeline_impl.hpp) calls fillTile once per screen tile, on the thread that owns the tile.
//
//   the whole tile  → fill/deferred.hpp         opaque, depth-writing draw of ≥ 2 triangles only
//   each primitive, in bin order:
//     triangle      → fill/triangles_wide.hpp   eight-wide shader, depth test and blend
//                   → fill/quads.hpp            otherwise (and with DrawFill::plain)
//     rectangle     → fill/rectangles.hpp       eight-wide shader (billboards seen as rectangles)
//                   → fill/quads.hpp            otherwise
//     line, point   → fill/quads.hpp            always
//
// A triangle or rectangle wholly behind the tile's stored depth is skipped first
// (fastpath/depth_bounds.hpp). Every path gives the same bits as fill/quads.hpp.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "raster/fill/deferred.hpp"
#include "raster/fill/quads.hpp"
#include "raster/fill/rectangles.hpp"
#include "raster/fill/tile.hpp"
#include "raster/fill/triangles_wide.hpp"

namespace raster {

namespace detail {
// A tile visits its primitives sparsely, so their records miss the cache: fetch the setup two
// entries ahead, and the vertex records of the next rectangle, whose setup the previous entry
// fetched (measured: 8 % of the particle pass waited here).
template <class V>
[[gnu::always_inline]] inline void prefetchBinEntries(const Chunk<V>& chunk, const std::vector<uint32_t>& bin,
                                                      size_t k) {
    if (k + 2 < bin.size() && binKind(bin[k + 2]) == BinKind::Rectangle)
        __builtin_prefetch(&chunk.rects[binIndex(bin[k + 2])]);
    if (k + 1 < bin.size() && binKind(bin[k + 1]) == BinKind::Rectangle) {
        const V* next = &chunk.vertices[chunk.rects[binIndex(bin[k + 1])].vertex];
        __builtin_prefetch(next);
        __builtin_prefetch(reinterpret_cast<const char*>(next + 3) - 1);
    }
}
}  // namespace detail

template <class T>
void fillTile(T& tile) {
    using V = typename T::Vertex;
    using Real = typename T::RealType;
    const bool plain = tile.draw.plain;
    if constexpr (T::kDeferrable)
        if (!plain && fillDeferredTile(tile)) return;
    for (uint32_t c = 0; c < tile.draw.chunkCount; ++c) {
        const detail::Chunk<V>& chunk = tile.draw.chunks[c];
        const std::vector<uint32_t>& bin = chunk.bins[tile.index];
        for (size_t k = 0; k < bin.size(); ++k) {
            const uint32_t index = binIndex(bin[k]);
            detail::prefetchBinEntries(chunk, bin, k);
            switch (binKind(bin[k])) {
                case BinKind::Triangle: {
                    const TriangleSetup& t = chunk.triangles[index];
                    tile.notePrimitive(t.primitiveId);
                    if (tile.bounds.occluded(tile.nearestDepth(t), tile.st)) break;
                    const V* const verts[3] = {&chunk.vertices[t.vertex[0]], &chunk.vertices[t.vertex[1]],
                                               &chunk.vertices[t.vertex[2]]};
                    const TriangleInterpolant<Real> ti(t);
                    const EdgeSteps steps = edgeSteps(t);
                    if (T::kWideMerge && !plain)
                        fillTriangleWide(tile, t, ti, steps, verts);
                    else
                        fillTriangleQuads(tile, t, ti, steps, verts);
                    break;
                }
                case BinKind::Rectangle: {
                    const RectSetup& r = chunk.rects[index];
                    tile.notePrimitive(r.primitiveId);
                    const float* base = asFloats(chunk.vertices[r.vertex]);
                    const float* step_x = asFloats(chunk.vertices[r.vertex + 1]);
                    const float* step_y = asFloats(chunk.vertices[r.vertex + 2]);
                    const Real z = std::clamp(Real(r.z), Real(tile.draw.minDepth), Real(tile.draw.maxDepth));
                    if (tile.bounds.occluded(float(z), tile.st)) break;
                    if (T::kWide && !plain)
                        fillRectangleWide(tile, r, base, step_x, step_y, z,
                                          tile.bounds.inFrontOfTile(float(z)));
                    else
                        fillRectangleQuads(tile, r, base, step_x, step_y, z);
                    break;
                }
                case BinKind::Line: {
                    const LineSetup& l = chunk.lines[index];
                    tile.notePrimitive(l.primitiveId);
                    const V* const verts[2] = {&chunk.vertices[l.vertex[0]], &chunk.vertices[l.vertex[1]]};
                    fillLine(tile, l, verts);
                    break;
                }
                case BinKind::Point: {
                    const PointSetup& pt = chunk.points[index];
                    tile.notePrimitive(pt.primitiveId);
                    fillPoint(tile, pt, chunk.vertices[pt.vertex]);
                    break;
                }
            }
        }
    }
}

}  // namespace raster
