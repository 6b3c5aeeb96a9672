// The deferred path, for opaque draws (blending off, depth written: FillTraits::kDeferrable): a pixel
// ends with the shader's output for the last of its fragments that passed the depth test, so a first
// pass runs the depth test alone and notes, per pixel, which triangle (its place in the tile's list)
// that fragment came from; a second shades those fragments only. The same bits as shading in order,
// since an eight-wide shader has no side effects, cannot discard and cannot write depth; the
// fragments a later one replaced are never shaded (counted as fragmentsOverdrawSkipped). Taken for
// tiles of two triangles or more (nothing to save with one) and none of another kind, whose 4×2
// blocks all lie inside the tile.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <utility>
#include <vector>

#include "raster/fastpath/block_coverage.hpp"
#include "raster/fastpath/interpolate_wide.hpp"
#include "raster/fastpath/merge_wide.hpp"
#include "raster/fill/tile.hpp"

namespace raster {

// A tile of one draw's triangles, depth first, then shaded fragment by visible fragment.
template <class T>
class DeferredTile {
    using V = typename T::Vertex;
    using Real = typename T::RealType;
    using Depth = typename T::DepthPolicyType;
    using Color = typename T::ColorPolicyType;
    using Shader = std::remove_cvref_t<decltype(std::declval<T&>().wideShader)>;

  public:
    // What shading a block of triangle n needs, found when the walk meets n (mostly once per run of
    // blocks: neighbours usually show the same triangle).
    struct Shown {
        const TriangleSetup* t;
        const V* verts[3];
        TriangleInterpolant<Real> ti;
        BlockLaneOffsets lanes;
    };

    [[gnu::always_inline]] explicit DeferredTile(T& tile)
        : t_(tile),
          rect_(tile.rect),
          merge_(tile.draw.depth, tile.draw.color),
          shader_(tile.wideShader) {}

    // The tile's triangles, or 0 where the tile does not qualify (a primitive of another kind, or a
    // tile not made of whole 4×2 blocks).
    static uint32_t countTriangles(const T& tile) {
        const PixelRect& rect = tile.rect;
        if (rect.x0 % 4 != 0 || (rect.x1 + 1) % 4 != 0 || rect.y0 % 2 != 0 || (rect.y1 + 1) % 2 != 0)
            return 0;
        uint32_t triangles = 0;
        for (uint32_t c = 0; c < tile.draw.chunkCount; ++c) {
            for (const uint32_t entry : tile.draw.chunks[c].bins[tile.index]) {
                if (binKind(entry) != BinKind::Triangle) return 0;
                ++triangles;
            }
        }
        return triangles;
    }

    // Depth pass: owner_ holds, per pixel, the last triangle whose fragment passed; returns how many
    // fragments passed in all.
    [[gnu::always_inline]] uint64_t depthPass(uint32_t triangles) {
        std::fill_n(&owner_[0][0], kTileSize * kTileSize, ~0u);
        listed().resize(triangles);
        uint64_t passed = 0;
        const float min_depth = t_.draw.minDepth, max_depth = t_.draw.maxDepth;
        uint32_t n = 0;
        for (uint32_t c = 0; c < t_.draw.chunkCount; ++c) {
            const detail::Chunk<V>& chunk = t_.draw.chunks[c];
            for (const uint32_t entry : chunk.bins[t_.index]) {
                const TriangleSetup& t = chunk.triangles[binIndex(entry)];
                const uint32_t id = n++;
                listed()[id] = {&chunk, &t};
                if (t_.bounds.occluded(t_.nearestDepth(t), t_.st)) continue;
                rasterizeTriangleBlocks(
                    t, edgeSteps(t), rect_,
                    [&](int32_t x, int32_t y, uint32_t mask, const int64_t(&e)[3][8]) {
                        const Float8 z = interpolateDepthWide(t, e, min_depth, max_depth);
                        const uint32_t live = t_.depthTestBlock(merge_.depth(), x, y, z, mask);
                        if (!live) return;
                        merge_.depth().writeWide(x, y, z, live);
                        passed += uint64_t(std::popcount(live));
                        uint32_t* row = &owner_[y - rect_.y0][x - rect_.x0];
                        simd::I32x8 ids = loadBlock(row, row + kTileSize).v;
                        ids = select(Mask8::fromBits(live), Int8(int32_t(id)), Int8(ids)).v;
                        std::memcpy(row, &ids, 16);
                        std::memcpy(row + kTileSize, reinterpret_cast<const char*>(&ids) + 16, 16);
                    });
            }
        }
        return passed;
    }

    // Shading pass: walks the tile's blocks, not the triangles: a block is shaded once per triangle
    // it shows, with that triangle's lanes live, and needs no rasterising. Its edge functions are
    // edgeAt's at the block's lane 0 plus the per-lane steps, the same exact integers
    // rasterizeTriangleBlocks steps to, so the same bits. Returns the fragments shaded.
    [[gnu::always_inline]] uint64_t shadePass() {
        uint64_t shaded = 0;
        for (int32_t y = rect_.y0; y <= rect_.y1; y += 2) {
            for (int32_t x = rect_.x0; x <= rect_.x1; x += 4) {
                const uint32_t* row = &owner_[y - rect_.y0][x - rect_.x0];
                const simd::I32x8 ids = loadBlock(row, row + kTileSize).v;
                uint32_t pending = ~Mask8{ids == -1}.bits() & 0xFFu;
                if constexpr (T::kPairs) {
                    if (shadePairOfBlocks(x, y, row, ids, pending, shaded)) {
                        x += 4;
                        continue;
                    }
                }
                while (pending) {
                    const uint32_t n = uint32_t(ids[std::countr_zero(pending)]);
                    const uint32_t live = Mask8{ids == int32_t(n)}.bits();
                    pending &= ~live;
                    show(n);
                    alignas(32) int64_t e[3][8];
                    edgesAt(x, y, e);
                    const Float8 z = interpolateDepthWide(*shown_->t, e, t_.draw.minDepth, t_.draw.maxDepth);
                    const glm::vec<4, Float8> c =
                        t_.shadeBlockWide(shader_, shown_->ti, e, shown_->verts, x, y, z, live);
                    merge_.colour(x, y, live, c);
                    shaded += uint64_t(std::popcount(live));
                }
            }
        }
        return shaded;
    }

    // Lanes the shading pass merged whose blend changed nothing (none under the replace blend that
    // makes a draw deferrable; counted all the same, as every path counts them).
    uint64_t noOps() const { return merge_.noOps(); }

  private:
    // The tile's triangles by their place in its list, for the shading pass.
    static std::vector<std::pair<const detail::Chunk<V>*, const TriangleSetup*>>& listed() {
        static thread_local std::vector<std::pair<const detail::Chunk<V>*, const TriangleSetup*>> list;
        return list;
    }
    void show(uint32_t n) {
        if (n == shown_id_) return;
        const auto [chunk, t] = listed()[n];
        shown_.emplace(Shown{
            t,
            {&chunk->vertices[t->vertex[0]], &chunk->vertices[t->vertex[1]], &chunk->vertices[t->vertex[2]]},
            TriangleInterpolant<Real>(*t),
            BlockLaneOffsets(edgeSteps(*t))});
        shown_id_ = n;
    }
    void edgesAt(int32_t x, int32_t y, int64_t (&e)[3][8]) const {
        for (int k = 0; k < 3; ++k) {
            const int64_t e0 = edgeAt(*shown_->t, k, x, y);
            const simd::I64x4 top = e0 + shown_->lanes.top[k];
            const simd::I64x4 bottom = e0 + shown_->lanes.bottom[k];
            std::memcpy(&e[k][0], &top, sizeof top);
            std::memcpy(&e[k][4], &bottom, sizeof bottom);
        }
    }
    // A block showing one triangle whose right neighbour shows that one only too (most blocks inside
    // a triangle): both through one Float8x2 call. False where the two blocks are not such a pair.
    [[gnu::always_inline]] bool shadePairOfBlocks(int32_t x, int32_t y, const uint32_t* row,
                                                  const simd::I32x8& ids, uint32_t pending,
                                                  uint64_t& shaded) {
        if (!pending || x + 4 > rect_.x1) return false;
        const int32_t n = ids[std::countr_zero(pending)];
        const uint32_t live_left = Mask8{ids == n}.bits();
        const simd::I32x8 next = loadBlock(row + 4, row + 4 + kTileSize).v;
        const uint32_t live_right = Mask8{next == n}.bits();
        if (live_left != pending || live_right == 0 || live_right != (~Mask8{next == -1}.bits() & 0xFFu))
            return false;
        show(uint32_t(n));
        Wide<V> in[2];
        for (int h = 0; h < 2; ++h) {
            alignas(32) int64_t e[3][8];
            edgesAt(x + 4 * h, y, e);
            const Float8 z = interpolateDepthWide(*shown_->t, e, t_.draw.minDepth, t_.draw.maxDepth);
            interpolateAttributesWide(shown_->ti, e, shown_->verts, x + 4 * h, y, z, in[h]);
        }
        const glm::vec<4, Float8x2> c = t_.shadePairWide(shader_, in[0], in[1], live_left, live_right);
        merge_.colour(x, y, live_left, detail::blockOf(c, 0));
        merge_.colour(x + 4, y, live_right, detail::blockOf(c, 1));
        shaded += uint64_t(std::popcount(live_left) + std::popcount(live_right));
        return true;
    }

    T& t_;
    const PixelRect rect_;
    // The depth pass writes depth itself (it notes owners as it goes); the shading pass blends
    // through the merge.
    WideMerge<Depth, Color, NoOpLanes::Written> merge_;
    const Shader shader_;
    // owner_[row][column] within the tile: the triangle whose fragment the pixel shows; ~0 where no
    // fragment of this draw passed.
    alignas(32) uint32_t owner_[kTileSize][kTileSize];
    std::optional<Shown> shown_;
    uint32_t shown_id_ = ~0u;
};

// Fills the tile deferred if it qualifies (see above); false, with nothing done, where it does not.
template <class T>
RASTER_FLATTEN bool fillDeferredTile(T& tile) {
    if constexpr (T::kDeferrable) {
        const uint32_t triangles = DeferredTile<T>::countTriangles(tile);
        if (triangles < 2) return false;
        DeferredTile<T> deferred(tile);
        const uint64_t passed = deferred.depthPass(triangles);
        const uint64_t shaded = deferred.shadePass();
        tile.countOverdrawSkipped(passed - shaded);
        tile.countBlendNoOps(deferred.noOps());
        return true;
    } else {
        return false;
    }
}

}  // namespace raster
