// Accelerates the output merger's depth test for whole primitives: bounds on one tile's stored depth,
// read once per tile and draw, decide for a whole triangle or rectangle what the per-pixel test would.
//
//  - occluded: a primitive whose nearest depth fails against the tile's farthest stored depth fails
//    the depth test in every pixel of the tile, so it is not rasterised there at all.
//  - in front: under a draw that writes no depth the tile's stored depths stay put, so a rectangle of
//    one depth in front of the tile's nearest (or of one row pair's nearest) passes everywhere there
//    and its blocks need no test.
//
// Only DepthFixed under Less and LessEqual has such bounds (DepthFixed::kBoundsTile: a depth write
// only lowers the stored value). Not while tracing: a pixel's history must show the fragments the
// test rejected. What the bounds decide is what the test would decide, so images are the same bits.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

#include "raster/stages/5_setup.hpp"
#include "raster/stages/6_binner.hpp"
#include "raster/statistics.hpp"

namespace raster {

template <class Depth, bool kActive>
class TileDepthBounds {
  public:
    // Whether this depth policy has bounds at all (else every answer is "no").
    static constexpr bool kOccludes = [] {
        if constexpr (requires { Depth::kBoundsTile; })
            return Depth::kBoundsTile && kActive;
        else
            return false;
    }();
    static constexpr bool kInFront = [] {
        if constexpr (kOccludes)
            return !Depth::kWrite;
        else
            return false;
    }();

    TileDepthBounds(const Depth& depth, const PixelRect& rect)
        : depth_(depth), rect_(rect), first_row_pair_(rect.y0 & ~1) {}

    // True when a primitive whose nearest depth is `nearest` fails the depth test everywhere in the
    // tile (counted as a tile occluded).
    bool occluded([[maybe_unused]] float nearest, [[maybe_unused]] PipelineStatistics& st) {
        if constexpr (kOccludes) {
            if (!far_known_) far_ = depth_.farthest(rect_), far_known_ = true;
            if (Depth::occluded(nearest, far_)) {
                ++st.tilesOccluded;
                return true;
            }
        }
        return false;
    }
    // True when a fragment of depth z passes the depth test in every pixel of the tile.
    bool inFrontOfTile([[maybe_unused]] float z) {
        if constexpr (kInFront) {
            knowNear();
            return Depth::passesAll(z, tile_near_);
        }
        return false;
    }
    // The same for the row pair y, y + 1 (y even) of the tile.
    bool inFrontOfRows([[maybe_unused]] float z, [[maybe_unused]] int32_t y) {
        if constexpr (kInFront) {
            knowNear();
            return Depth::passesAll(z, row_near_[(y - first_row_pair_) >> 1]);
        }
        return false;
    }

  private:
    // The tile's and each row pair's nearest stored depth, from one pass over the tile's depth; the
    // tile's nearest is the least of its row pairs' (−∞ if any entry is NaN).
    void knowNear() {
        if constexpr (kInFront) {
            if (near_known_) return;
            tile_near_ = std::numeric_limits<float>::infinity();
            for (int32_t p = 0, y = first_row_pair_; y <= rect_.y1; y += 2, ++p) {
                row_near_[p] = depth_.nearest(
                    PixelRect{rect_.x0, std::max(y, rect_.y0), rect_.x1, std::min(y + 1, rect_.y1)});
                tile_near_ = std::min(tile_near_, row_near_[p]);
            }
            near_known_ = true;
        }
    }

    const Depth& depth_;
    PixelRect rect_;
    int32_t first_row_pair_;
    float far_ = 0.0f;
    bool far_known_ = false;
    bool near_known_ = false;
    float tile_near_ = 0.0f;
    float row_near_[kTileSize / 2 + 1];
};

}  // namespace raster
