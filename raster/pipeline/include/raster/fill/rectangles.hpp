// The rectangle path: a billboard that the setup recognised as a screen-aligned rectangle of one
// depth (stages/5_setup.hpp, setupRectangle) is shaded in 4×2 blocks by an eight-wide shader, two
// neighbouring blocks per call where the shader also takes Float8x2 (a pair). Its attributes are
// planes: attribute = (base + i·step_x) + j·step_y at pixel (x0 + i, y0 + j) of its box, the plain
// path's order (fill/quads.hpp, fillRectangleQuads), so the same bits lane by lane.
//
// What it skips, each giving the bits the plain path gives:
//  - the depth test, where the rectangle is in front of the whole tile or of a row pair
//    (fastpath/depth_bounds.hpp);
//  - blocks whose texels are all transparent under a blend that adds nothing for alpha 0
//    (fastpath/transparency.hpp);
//  - blocks already at the blend's ceiling (ColorFast::kCeiling, fastpath/merge_policy.hpp).
// Blocks on the tile's border, and targets without an eight-wide merge, go lane by lane through the
// plain output merger (Tile::merge).
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "raster/fastpath/merge_wide.hpp"
#include "raster/fastpath/rectangle.hpp"
#include "raster/fill/tile.hpp"

namespace raster {

// One rectangle in one tile. InFront: the rectangle passes the depth test in every pixel of the
// tile (TileDepthBounds::inFrontOfTile). A class of its own per InFront, both flattened into
// fillRectangleWide: in front, a block has no depth test and its lanes need no counting (they all
// pass; the shaded ones are what the skips leave), which measured 4–6 % of the 100 000-particle frame
// as per-block popcounts (docs/PERFORMANCE.md).
template <class T, bool InFront>
class RectangleBlocks {
    using V = typename T::Vertex;
    using Real = typename T::RealType;
    using Depth = typename T::DepthPolicyType;
    using Color = typename T::ColorPolicyType;
    using Shader = std::remove_cvref_t<decltype(std::declval<T&>().wideShader)>;
    static constexpr uint32_t kN = kVertexFloats<V>;
    // Every lane of the rectangle in the tile passes the depth test.
    static constexpr bool kAllPass = InFront || !(Depth::kEnabled && Depth::kWide);
    static constexpr bool kWideMerge = Depth::kWide && Color::kWide;
    static constexpr int kMaxBlocks = kTileSize / 4 + 1;
    static constexpr int kMaxRowPairs = kTileSize / 2 + 1;

  public:
    // What every block reads is copied into members: the targets are written through uint8_t and
    // float pointers, which may alias anything, so through `tile`, `r` or `base` the compiler would
    // load it again for every block. The shader too: its texture pointer and sampler then stay in
    // registers.
    [[gnu::always_inline]] RectangleBlocks(T& tile, const RectSetup& r, const float* base,
                                           const float* step_x, const float* step_y, Real z)
        : t_(tile),
          r_(r),
          base_(base),
          step_x_(step_x),
          step_y_(step_y),
          z_(z),
          tile_(tile.rect),
          merge_(tile.draw.depth, tile.draw.color),
          shader_(tile.wideShader),
          box_(intersect(r.box, tile_)),
          x0_(box_.x0),
          x1_(box_.x1),
          y0_(box_.y0),
          y1_(box_.y1),
          cx0_(x0_ & ~3),
          bx_(r.box.x0),
          by_(r.box.y0),
          z8_(float(z)) {
        for (uint32_t k = 0; k < kN; ++k)
            plane_[k] = Float8(base[k]), plane_x_[k] = Float8(step_x[k]), plane_y_[k] = Float8(step_y[k]);
    }

    [[gnu::always_inline]] void run() {
        columnParts();
        bool done = false;
        if constexpr (kWideMerge) done = wholeBlocks();
        rows_in_front_ = false;
        if (!done) borderBlocks();
        count();
    }

  private:
    // attribute = (base + i·step_x) + j·step_y, the scalar path's order; j·step_y per row pair.
    [[gnu::always_inline]] void rowPart(int32_t y, Float8 (&row_part)[kN]) const {
        const Float8 lane_y(simd::F32x8{0, 0, 0, 0, 1, 1, 1, 1});
        const Float8 j = Float8(float(y - by_)) + lane_y;
        for (uint32_t k = 0; k < kN; ++k) row_part[k] = j * plane_y_[k];
    }
    // base + i·step_x of every block column of the rectangle in the tile, found once: the same for
    // every row pair, and the head of each block's dependency chain (the texture coordinates) is
    // then one add. Per attribute, so that those the shader never reads are never stored.
    [[gnu::always_inline]] void columnParts() {
        const Float8 lane_x(simd::F32x8{0, 1, 2, 3, 0, 1, 2, 3});
        for (int32_t x = cx0_, c = 0; x <= x1_; x += 4, ++c) {
            RASTER_DCHECK(c < kMaxBlocks);
            const Float8 i = Float8(float(x - bx_)) + lane_x;
            for (uint32_t k = 0; k < kN; ++k) column_part_[k][c] = plane_[k] + i * plane_x_[k];
        }
    }
    [[gnu::always_inline]] Wide<V> inputs(int32_t x, const Float8 (&row_part)[kN]) const {
        const int32_t c = (x - cx0_) >> 2;
        Float8 f[kN];
        for (uint32_t k = 0; k < kN; ++k) f[k] = column_part_[k][c] + row_part[k];
        Wide<V> in;
        static_assert(sizeof in == sizeof f);
        std::memcpy(static_cast<void*>(&in), f, sizeof f);
        return in;
    }
    // The lanes of row pair y inside the rectangle: the top row's (0x0F) if y ≥ y0, the bottom
    // row's (0xF0) if y + 1 ≤ y1.
    uint32_t rowLanes(int32_t y) const { return (y >= y0_ ? 0x0Fu : 0u) | (y + 1 <= y1_ ? 0xF0u : 0u); }

    // A shaded block's live lanes into depth and colour, counted (targets with an eight-wide merge).
    // No-op lanes are written too (NoOpLanes::Written, fastpath/merge_wide.hpp): a block wholly
    // inside the rectangle is then stored without a lane select, and a block whose lanes are all
    // no-ops (texels of alpha 0, a third of the particle scene's) costs a blend, not the mispredicted
    // branch that skipped it (docs/PERFORMANCE.md: −3 %).
    [[gnu::always_inline]] void mergeBlock(int32_t x, int32_t y, const glm::vec<4, Float8>& c,
                                           uint32_t live) {
        if constexpr (kWideMerge) {
            if constexpr (!kAllPass) live_lanes_ += uint64_t(std::popcount(live));
            merge_.block(x, y, z8_, live, c);
        }
    }
    // mergeBlock for blocks x and x + 4 of a pair (WideMerge::pair: one 16-lane blend where the
    // target has one).
    [[gnu::always_inline]] void mergePair(int32_t x, int32_t y, const glm::vec<4, Float8x2>& c,
                                          uint32_t live0, uint32_t live1) {
        if constexpr (kWideMerge) {
            if constexpr (!kAllPass) live_lanes_ += uint64_t(std::popcount(live0) + std::popcount(live1));
            merge_.pair(x, y, z8_, z8_, live0, live1, c);
        }
    }
    // The lanes of a block inside the tile in `covered` that pass the depth test, counted (without
    // kAllPass; with it, all of them, counted per rectangle). rows_in_front_: the row pair being
    // shaded is in front of its pixels (TileDepthBounds::inFrontOfRows).
    [[gnu::always_inline]] uint32_t passing(int32_t x, int32_t y, uint32_t covered) {
        uint32_t live = covered;
        // Depth::kWide first, which kAllPass implies when false: the test inside names testWide,
        // which not every Depth has, and clang rejects it in a discarded branch whose condition
        // depends on InFront (ill-formed, no diagnostic required).
        if constexpr (Depth::kWide) {
            if constexpr (!kAllPass) {
                if (!rows_in_front_) live &= merge_.depth().testWide(x, y, z8_);
                passed_ += uint64_t(std::popcount(live));
            }
        }
        return live;
    }
    // Blocks whose pixels are all at the blend's ceiling are not shaded, their live lanes counted.
    // Why: dense additive particles saturate the middle of the cloud, and every fragment after that
    // changes nothing (100 000 particles at 1080p: 11 % of the fragments; docs/PERFORMANCE.md).
    // Tested after depth, so that the counts add up to the traced draw's, which shades every fragment.
    [[gnu::always_inline]] bool skipped(bool at_ceiling, uint32_t lanes) {
        if (at_ceiling) ceiling_ += uint64_t(std::popcount(lanes));
        return at_ceiling;
    }
    // One block inside the tile whose live lanes are known: shaded and merged unless at the ceiling.
    [[gnu::always_inline]] void shadeLive(int32_t x, int32_t y, uint32_t live, const Float8 (&row_part)[kN]) {
        if constexpr (kWideMerge) {
            if constexpr (Color::kCeiling)
                if (skipped(merge_.color().template atCeiling<1>(x, y), live)) return;
            ++blocks_;
            mergeBlock(x, y, shader_(inputs(x, row_part)), live);
        }
    }
    // One block inside the tile through depth, shader and blend at once, its lanes outside the
    // rectangle (not in `covered`) masked off.
    [[gnu::always_inline]] void shadeBlock(int32_t x, int32_t y, uint32_t covered,
                                           const Float8 (&row_part)[kN]) {
        if (const uint32_t live = passing(x, y, covered)) shadeLive(x, y, live, row_part);
    }
    // Blocks x and x + 4 of a row pair inside the tile through one Float8x2 call when both have live
    // lanes (else each alone); the same bits as shadeBlock on each. Why: a block's texture fetch is
    // one long dependency chain, and two of them interleaved keep the core busy where one leaves it
    // waiting (docs/PERFORMANCE.md).
    [[gnu::always_inline]] void shadePair(int32_t x, int32_t y, uint32_t covered0, uint32_t covered1,
                                          const Float8 (&row_part)[kN]) {
        if constexpr (kWideMerge && T::kPairs) {
            const uint32_t live0 = passing(x, y, covered0), live1 = passing(x + 4, y, covered1);
            if (!live0 || !live1) {
                if (live0) shadeLive(x, y, live0, row_part);
                if (live1) shadeLive(x + 4, y, live1, row_part);
                return;
            }
            // Both blocks at once (one branch, not two): a pair with one block at the ceiling is
            // shaded whole, which stores that block unchanged.
            if constexpr (Color::kCeiling)
                if (skipped(merge_.color().template atCeiling<2>(x, y), live0 | (live1 << 8))) return;
            const glm::vec<4, Float8x2> c2 =
                shader_(detail::zipBlocks<V>(inputs(x, row_part), inputs(x + 4, row_part)));
            blocks_ += 2;
            mergePair(x, y, c2, live0, live1);
        }
    }

    // Per row pair p, the blocks [k_begins[p], k_ends[p]) that may not be transparent, found for all
    // row pairs before any is shaded (four at a time, TransparentColumns::rowPairs): each is a chain
    // of dependent operations (texel rows, spans, columns) that the shading loop would wait for at
    // every row pair. The skipped blocks' lanes that pass the depth test are counted here. False
    // where the rectangle's texture coordinates do not allow it (nothing found, nothing skipped).
    [[gnu::always_inline]] bool transparentSpans(int32_t bx0, int32_t by0, int n_blocks,
                                                 const uint8_t* columns, uint8_t* k_begins, uint8_t* k_ends,
                                                 bool* row_fronts) {
        const detail::TransparentColumns& tc = t_.draw.transparentColumns;
        const auto planes = tc.planes(base_, step_x_, step_y_, r_.box.x1 - bx_ + 1, r_.box.y1 - by_ + 1);
        if (!planes.usable) return false;
        const int n_pairs = (y1_ - by0) / 2 + 1;
        RASTER_DCHECK(n_pairs <= kMaxRowPairs);
        constexpr int kRoom = kMaxRowPairs + detail::TransparentColumns::kRowPairsPadding;
        int32_t los[kRoom], his[kRoom];
        // The columns of [x0, x1] in blocks [0, k).
        const int32_t width = x1_ - x0_ + 1;
        auto columnsBefore = [&](int k) { return std::clamp(bx0 + 4 * k - x0_, 0, width); };
        tc.rowPairs(planes, by0 - by_, n_pairs, x0_ - bx_, x1_ - bx_, los, his);
        for (int32_t y = by0, p = 0; y <= y1_; y += 2, ++p) {
            const int32_t lo = los[p], hi = his[p];
            const int kb = lo > hi ? n_blocks : (lo + bx_ - bx0) >> 2;
            const int ke = lo > hi ? n_blocks : ((hi + bx_ - bx0) >> 2) + 1;
            k_begins[p] = uint8_t(kb), k_ends[p] = uint8_t(ke);
            // The skipped blocks' lanes that pass the depth test: in front of the row pair's pixels
            // from the span's ends (the columns of [x0, x1] outside blocks [kb, ke), times the rows),
            // else block by block.
            bool front = kAllPass;
            if constexpr (!kAllPass) front = row_fronts[p] = t_.bounds.inFrontOfRows(float(z_), y);
            if (front) {
                const int32_t n_rows = std::popcount(rowLanes(y)) / 4;
                const int32_t outside = columnsBefore(kb) + width - columnsBefore(std::max(kb, ke));
                transparent_ += uint64_t(n_rows * outside);
                if constexpr (!kAllPass) passed_ += uint64_t(n_rows * outside);
            } else {
                const uint32_t rows = rowLanes(y);
                auto countBlocks = [&](int s0, int s1) {
                    for (int s = s0; s < s1; ++s)
                        transparent_ += std::popcount(passing(bx0 + 4 * s, y, rows & columns[s]));
                };
                countBlocks(0, kb);
                countBlocks(std::max(kb, ke), n_blocks);
            }
        }
        return true;
    }

    // Every 4×2 block of the rectangle inside the tile (always, but at a target or scissor edge that
    // is not a multiple of 4×2): one loop, no per-block tests but depth. The columns a block covers
    // depend on x alone, so they are found once. False where the blocks are not all inside the tile.
    [[gnu::always_inline]] bool wholeBlocks() {
        const int32_t bx0 = x0_ & ~3, by0 = y0_ & ~1;
        if (!(x0_ <= x1_ && y0_ <= y1_ && bx0 >= tile_.x0 && (x1_ | 3) <= tile_.x1 && by0 >= tile_.y0 &&
              (y1_ | 1) <= tile_.y1))
            return false;
        uint8_t columns[kMaxBlocks];
        const int n_blocks = (x1_ - bx0) / 4 + 1;
        RASTER_DCHECK(n_blocks <= kMaxBlocks);
        for (int k = 0; k < n_blocks; ++k) columns[k] = uint8_t(blockColumns(bx0 + 4 * k, x0_, x1_));
        [[maybe_unused]] uint8_t k_begins[kMaxRowPairs], k_ends[kMaxRowPairs];
        [[maybe_unused]] bool row_fronts[kMaxRowPairs];
        [[maybe_unused]] bool spans = false;
        if constexpr (T::kSkipTransparent)
            spans = transparentSpans(bx0, by0, n_blocks, columns, k_begins, k_ends, row_fronts);
        for (int32_t y = by0, p = 0; y <= y1_; y += 2, ++p) {
            const uint32_t rows = rowLanes(y);
            int k = 0, k_end = n_blocks;
            if constexpr (T::kSkipTransparent)
                if (spans) k = k_begins[p], k_end = k_ends[p];
            if (k >= k_end) continue;  // all transparent: no row part to compute
            if constexpr (!kAllPass) {
                if constexpr (T::kSkipTransparent)
                    rows_in_front_ = spans ? row_fronts[p] : t_.bounds.inFrontOfRows(float(z_), y);
                else
                    rows_in_front_ = t_.bounds.inFrontOfRows(float(z_), y);
            }
            Float8 row_part[kN];
            rowPart(y, row_part);
            if constexpr (T::kPairs)
                for (; k + 1 < k_end; k += 2)
                    shadePair(bx0 + 4 * k, y, rows & columns[k], rows & columns[k + 1], row_part);
            for (; k < k_end; ++k) shadeBlock(bx0 + 4 * k, y, rows & columns[k], row_part);
        }
        whole_lanes_ += uint64_t(x1_ - x0_ + 1) * uint64_t(y1_ - y0_ + 1);
        return true;
    }

    // The rectangle block by block, testing each against the tile: blocks inside it as in
    // wholeBlocks, blocks that straddle its edge (and every block where the targets or the shader
    // have no eight-wide merge) lane by lane through the plain output merger.
    [[gnu::always_inline]] void borderBlocks() {
        for (int32_t y = y0_ & ~1; y <= y1_; y += 2) {
            const uint32_t rows = rowLanes(y);
            Float8 row_part[kN];
            rowPart(y, row_part);
            const bool rows_in_tile = y >= tile_.y0 && y + 1 <= tile_.y1;
            for (int32_t x = x0_ & ~3; x <= x1_; x += 4) {
                if constexpr (kWideMerge) {
                    if (rows_in_tile && x >= tile_.x0 && x + 3 <= tile_.x1) {
                        const uint32_t covered = rows & blockColumns(x, x0_, x1_);
                        whole_lanes_ += uint64_t(std::popcount(covered));
                        shadeBlock(x, y, covered, row_part);
                        continue;
                    }
                }
                uint32_t live = 0;
                for (int l = 0; l < 8; ++l) {
                    const int32_t px = x + (l & 3), py = y + (l >> 2);
                    if (px >= x0_ && px <= x1_ && py >= y0_ && py <= y1_ && t_.earlyDepthPasses(px, py, z_))
                        live |= 1u << l;
                }
                if (!live) continue;
                const glm::vec<4, Float8> c = shader_(inputs(x, row_part));
                ++blocks_;
                live_lanes_ += uint64_t(std::popcount(live));
                for (uint32_t m = live; m; m &= m - 1) {
                    const int l = std::countr_zero(m);
                    t_.merge(x + (l & 3), y + (l >> 2), z_, glm::vec4(c.x[l], c.y[l], c.z[l], c.w[l]));
                }
            }
        }
    }

    // Statistics, per rectangle where they need not be counted per block. Helpers = 8·blocks − live;
    // lanes the early depth test killed = lanes of blocks taken whole − the lanes of those blocks
    // that passed it. With kAllPass every lane of a block taken whole passes, and the live lanes of
    // the shaded ones are the rest after the transparent and ceiling skips.
    void count() {
        if constexpr (kAllPass) live_lanes_ += whole_lanes_ - transparent_ - ceiling_, passed_ = whole_lanes_;
        t_.countShaded(live_lanes_, 8 * blocks_ - live_lanes_);
        t_.countEarlyDepthKilled(whole_lanes_ - passed_);
        t_.countBlendNoOps(merge_.noOps());
        t_.countSaturated(ceiling_);
        t_.countTransparentSkipped(transparent_);
    }

    T& t_;
    const RectSetup& r_;
    const float *base_, *step_x_, *step_y_;
    const Real z_;
    const PixelRect tile_;
    WideMerge<Depth, Color, NoOpLanes::Written> merge_;
    const Shader shader_;
    const PixelRect box_;              // the rectangle's box within the tile
    const int32_t x0_, x1_, y0_, y1_;  // box_'s
    const int32_t cx0_;                // the first block column's left pixel
    const int32_t bx_, by_;            // the box's top-left pixel: attribute plane origin
    Float8 plane_[kN], plane_x_[kN], plane_y_[kN];
    Float8 column_part_[kN][kMaxBlocks];  // columnParts(), block column c at pixel cx0_ + 4c
    const Float8 z8_;
    // Counted per block only what cannot be counted per rectangle (see count()).
    uint64_t blocks_ = 0, live_lanes_ = 0, ceiling_ = 0, whole_lanes_ = 0, passed_ = 0, transparent_ = 0;
    bool rows_in_front_ = false;
};

// A rectangle in one tile through an eight-wide shader (FillTraits::kWide); in_front: it passes the
// depth test in every pixel of the tile.
template <class T>
RASTER_FLATTEN void fillRectangleWide(T& tile, const RectSetup& r, const float* base, const float* step_x,
                                      const float* step_y, typename T::RealType z, bool in_front) {
    if constexpr (T::kWide) {
        if (in_front)
            RectangleBlocks<T, true>(tile, r, base, step_x, step_y, z).run();
        else
            RectangleBlocks<T, false>(tile, r, base, step_x, step_y, z).run();
    }
}

}  // namespace raster
