// Stage 6, between setup and rasterisation: binning. The screen is cut into kTileSize² tiles; each
// primitive is appended to the bin of every tile its box touches, unless the tile lies wholly
// outside one of its edges. Tiles are then rendered independently, in parallel, each reading
// its bins in primitive order, which is why the image does not depend on the thread count.
#pragma once

#include <algorithm>
#include <cstdint>

#include "raster/stages/5_setup.hpp"

namespace raster {

constexpr int32_t kTileSize = 64;  // pixels; even, so 2×2 quads never straddle two tiles

struct TileGrid {
    PixelRect clip;  // the draw's clip rectangle
    int32_t tilesX = 0, tilesY = 0;
    int32_t originX = 0, originY = 0;  // pixel of tile (0,0)'s top-left corner (even)

    explicit TileGrid(const PixelRect& c = {}) : clip(c) {
        if (c.empty()) return;
        originX = c.x0 & ~1;
        originY = c.y0 & ~1;
        tilesX = (c.x1 - originX) / kTileSize + 1;
        tilesY = (c.y1 - originY) / kTileSize + 1;
    }
    uint32_t count() const { return uint32_t(tilesX * tilesY); }
    PixelRect tileRect(uint32_t tile) const {
        const int32_t tx = int32_t(tile) % tilesX, ty = int32_t(tile) / tilesX;
        PixelRect r{originX + tx * kTileSize, originY + ty * kTileSize, 0, 0};
        r.x1 = std::min(clip.x1, r.x0 + kTileSize - 1);
        r.y1 = std::min(clip.y1, r.y0 + kTileSize - 1);
        r.x0 = std::max(r.x0, clip.x0);
        r.y0 = std::max(r.y0, clip.y0);
        return r;
    }
};

// A bin entry: the primitive kind in the top two bits (0 for a rectangle, see fastpath/rectangle.hpp), its
// index in the chunk below.
enum class BinKind : uint32_t { Rectangle = 0, Point = 1, Line = 2, Triangle = 3 };
inline uint32_t binEntry(BinKind kind, uint32_t index) {
    return (uint32_t(kind) << 30) | index;
}
inline uint32_t binEntry(PrimitiveKind kind, uint32_t index) {
    return binEntry(BinKind(kind), index);
}
inline BinKind binKind(uint32_t entry) {
    return BinKind(entry >> 30);
}
inline uint32_t binIndex(uint32_t entry) {
    return entry & 0x3FFFFFFFu;
}

// Calls push(tile) for each tile the box touches. Returns the number of tiles pushed.
template <class Push>
uint32_t binBox(const PixelRect& box, const TileGrid& grid, Push&& push) {
    const int32_t tx0 = (box.x0 - grid.originX) / kTileSize, tx1 = (box.x1 - grid.originX) / kTileSize;
    const int32_t ty0 = (box.y0 - grid.originY) / kTileSize, ty1 = (box.y1 - grid.originY) / kTileSize;
    for (int32_t ty = ty0; ty <= ty1; ++ty)
        for (int32_t tx = tx0; tx <= tx1; ++tx) push(uint32_t(ty * grid.tilesX + tx));
    return uint32_t((tx1 - tx0 + 1) * (ty1 - ty0 + 1));
}

// As binBox, but skips tiles that lie wholly outside an edge of the triangle: an edge function
// is linear, so its largest value over a tile's pixel centres is at one corner.
template <class Push>
void binTriangle(const TriangleSetup& t, const TileGrid& grid, Push&& push, uint64_t& binned,
                 uint64_t& rejected) {
    const PixelRect& box = t.box;
    const int32_t tx0 = (box.x0 - grid.originX) / kTileSize, tx1 = (box.x1 - grid.originX) / kTileSize;
    const int32_t ty0 = (box.y0 - grid.originY) / kTileSize, ty1 = (box.y1 - grid.originY) / kTileSize;
    if (tx0 == tx1 && ty0 == ty1) {
        push(uint32_t(ty0 * grid.tilesX + tx0));
        ++binned;
        return;
    }
    for (int32_t ty = ty0; ty <= ty1; ++ty) {
        for (int32_t tx = tx0; tx <= tx1; ++tx) {
            const PixelRect r = grid.tileRect(uint32_t(ty * grid.tilesX + tx));
            bool outside = false;
            for (int k = 0; k < 3 && !outside; ++k) {
                const int k1 = (k + 1) % 3;
                const bool rises_x = t.y[k1] <= t.y[k], rises_y = t.x[k1] >= t.x[k];  // dE/dx >= 0, dE/dy >= 0
                const int64_t px = pixelCentre(rises_x ? r.x1 : r.x0), py = pixelCentre(rises_y ? r.y1 : r.y0);
                outside = edgeFunction(t.x[k], t.y[k], t.x[k1], t.y[k1], px, py) + t.bias[k] < 0;
            }
            if (outside) {
                ++rejected;
            } else {
                push(uint32_t(ty * grid.tilesX + tx));
                ++binned;
            }
        }
    }
}

}  // namespace raster
