// Accelerates stage 9, the output merger (stages/9_output_merger.hpp; Tile::depthTestAndBlend for one
// fragment): its depth write and blend for the eight lanes of a 4×2 block inside a tile at once. The
// one wide merge of every eight-wide fill path — fill/triangles_wide.hpp, fill/rectangles.hpp and
// fill/deferred.hpp — whose depth test ran before the shader (Tile::depthTestBlock); `live` holds the
// lanes that passed it.
//
// A lane whose blend cannot change its pixel (Color::noOpWide: the additive blend at alpha 0) is
// counted as fragmentsBlendNoOp, and then, as the path chooses (the same bytes either way):
//  - NoOpLanes::Skipped: left out of the colour write, and a block of no-ops is not stored at all.
//    Triangles: their blocks are rarely all no-ops, and a skipped store is a skipped load too.
//  - NoOpLanes::Written: written with the others, adding zero, so that a whole block is stored
//    without a lane select and a block of no-ops costs a blend rather than a mispredicted branch.
//    Rectangles: a third of the particle scene's blocks are all alpha 0 (docs/PERFORMANCE.md).
// tests/fastpath_test.cpp (WideMerge) checks both against depthTestAndBlend lane by lane.
#pragma once

#include <bit>
#include <cstdint>

#include <glm/glm.hpp>

#include "raster/simd.hpp"

namespace raster {

namespace detail {
// Block h (0 left, 1 right) of a Float8x2 shader's colour.
inline glm::vec<4, Float8> blockOf(const glm::vec<4, Float8x2>& c, int h) {
    return {c.x.h[h], c.y.h[h], c.z.h[h], c.w.h[h]};
}
}  // namespace detail

enum class NoOpLanes { Skipped, Written };

// One path's merges in one tile, with the depth and colour policies copied in: the targets are written
// through uint8_t and float pointers, which may alias anything, so read through the draw they would be
// loaded again for every block. No-op lanes are counted here and handed to the tile's statistics once
// (Tile::countBlendNoOps(noOps())).
template <class Depth, class Color, NoOpLanes kNoOpLanes>
class WideMerge {
  public:
    WideMerge(const Depth& depth, const Color& color) : depth_(depth), color_(color) {}

    const Depth& depth() const { return depth_; }
    const Color& color() const { return color_; }
    // Lanes merged since construction whose blend changed nothing.
    uint64_t noOps() const { return no_ops_; }

    // Block (x, y): depth z written and colour c blended in the lanes of `live`.
    [[gnu::always_inline]] void block(int32_t x, int32_t y, Float8 z, uint32_t live, const glm::vec<4, Float8>& c) {
        depth_.writeWide(x, y, z, live);
        colour(x, y, live, c);
    }
    // The blend alone, for lanes whose depth is written already (fill/deferred.hpp's depth pass).
    [[gnu::always_inline]] void colour(int32_t x, int32_t y, uint32_t live, const glm::vec<4, Float8>& c) {
        const uint32_t no_op = color_.noOpWide(c) & live;
        no_ops_ += uint64_t(std::popcount(no_op));
        if constexpr (kNoOpLanes == NoOpLanes::Written)
            color_.writeWide(x, y, c, live);
        else if (live & ~no_op)
            color_.writeWide(x, y, c, live & ~no_op);
    }
    // Blocks (x, y) and (x + 4, y) of one Float8x2 shader call, depths z0 and z1: as block() on each,
    // left first. Where no-op lanes are written and the target has a 16-lane blend
    // (ColorFast::writeWidePair), the colour goes through it: the pair's 16-lane colour then stays in
    // its register, which two eight-lane blends split (docs/PERFORMANCE.md).
    [[gnu::always_inline]] void pair(int32_t x, int32_t y, Float8 z0, Float8 z1, uint32_t live0, uint32_t live1,
                                     const glm::vec<4, Float8x2>& c) {
        if constexpr (kNoOpLanes == NoOpLanes::Written && Color::kWidePair) {
            depth_.writeWide(x, y, z0, live0);
            depth_.writeWide(x + 4, y, z1, live1);
            const uint32_t live = live0 | (live1 << 8);
            no_ops_ += uint64_t(std::popcount(color_.writeWidePair(x, y, c, live) & live));
        } else {
            block(x, y, z0, live0, detail::blockOf(c, 0));
            block(x + 4, y, z1, live1, detail::blockOf(c, 1));
        }
    }

  private:
    const Depth depth_;
    const Color color_;
    uint64_t no_ops_ = 0;
};

}  // namespace raster
