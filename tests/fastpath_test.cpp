// The fast twins of the stage rules (raster/fastpath/), each against the rule it accelerates, at the
// level of the functions themselves, as simd_ops_test does for the SIMD layer:
//  - block_coverage.hpp: the 4×2 block walk covers exactly the lanes rasterizeTriangle covers, and
//    hands out the edge functions edgeAt gives, for random, thin and tile-straddling triangles;
//  - rectangle.hpp: a billboard strip set up as a rectangle covers exactly the pixels of its two
//    triangles, is culled exactly when its first triangle is, and carries the triangles' attributes;
//  - interpolate_wide.hpp: attributes interpolated eight wide are the scalar rule's bits per lane;
//  - merge_wide.hpp: a block's (and a pair's) depth write and blend store the bytes of the output
//    merger's steps lane by lane, with either choice for no-op lanes, and count the no-ops alike.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "raster/fastpath/block_coverage.hpp"
#include "raster/fastpath/interpolate_wide.hpp"
#include "raster/fastpath/merge_policy.hpp"
#include "raster/fastpath/merge_wide.hpp"
#include "raster/fastpath/rectangle.hpp"
#include "raster/stages/5_setup.hpp"
#include "raster/stages/7_rasterizer.hpp"
#include "raster/stages/8_pixel_shader.hpp"

namespace raster {
namespace {

constexpr int32_t kSize = 160;                          // the clip rectangle's side in pixels
constexpr PixelRect kClip{0, 0, kSize - 1, kSize - 1};  // three tiles of 64 a side, the last partial

template <class T>
struct Corner {
    glm::vec<4, T> position;
    glm::vec<4, T> color;
};

// The tiles of kClip, as the binner cuts them.
std::vector<PixelRect> tiles() {
    std::vector<PixelRect> out;
    for (int32_t y = 0; y < kSize; y += 64)
        for (int32_t x = 0; x < kSize; x += 64)
            out.push_back(intersect(PixelRect{x, y, x + 63, y + 63}, kClip));
    return out;
}

// A 16.8 coordinate somewhere around the clip rectangle (a fifth of them beyond it).
int32_t randomFixed(std::mt19937& rng) {
    std::uniform_int_distribution<int32_t> d(-32 * kSubpixelOne, (kSize + 32) * kSubpixelOne);
    return d(rng);
}

ScreenVertex randomVertex(std::mt19937& rng) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    return {randomFixed(rng), randomFixed(rng), unit(rng), 0.5f + unit(rng)};
}

// The rule itself: pixel (x, y) of the tile is covered when every biased edge function is >= 0.
std::vector<int> bruteForce(const TriangleSetup& t, const PixelRect& tile) {
    std::vector<int> count(size_t(kSize) * kSize, 0);
    const PixelRect area = intersect(t.box, tile);
    for (int32_t y = area.y0; y <= area.y1; ++y)
        for (int32_t x = area.x0; x <= area.x1; ++x) {
            bool in = true;
            for (int k = 0; k < 3; ++k) in = in && edgeAt(t, k, x, y) + t.bias[k] >= 0;
            count[size_t(y) * kSize + size_t(x)] += in;
        }
    return count;
}

// Random triangles: general ones, slivers (two vertices a few subpixels apart) and ones with a
// horizontal or vertical edge (the top-left rule's ties).
void randomTriangle(std::mt19937& rng, int trial, ScreenVertex (&s)[3]) {
    for (ScreenVertex& v : s) v = randomVertex(rng);
    if (trial % 4 == 1) s[1].x = s[0].x + int32_t(rng() % 7) - 3, s[1].y = s[0].y + int32_t(rng() % 7) - 3;
    if (trial % 4 == 2) s[1].y = s[0].y;
    if (trial % 4 == 3) s[2].x = s[0].x & ~(kSubpixelOne - 1), s[0].x = s[2].x;  // on pixel edges
}

TEST(BlockCoverage, CoversExactlyTheRulesLanesWithItsEdgeFunctions) {
    std::mt19937 rng(20261205);
    const std::vector<PixelRect> grid = tiles();
    const uint32_t vertex[3] = {0, 1, 2};
    int covered = 0, set_up = 0;
    for (int trial = 0; trial < 1500; ++trial) {
        ScreenVertex s[3];
        randomTriangle(rng, trial, s);
        TriangleSetup t;
        if (setupTriangle(s, vertex, 0, RasterizerState{}, kClip, t) != SetupResult::Ok) continue;
        ++set_up;
        const EdgeSteps steps = edgeSteps(t);
        for (const PixelRect& tile : grid) {
            const std::vector<int> expect = bruteForce(t, tile);
            std::vector<int> quads(expect.size(), 0), blocks(expect.size(), 0);
            rasterizeTriangle(t, steps, tile, [&](const Quad& q) {
                for (int l = 0; l < 4; ++l)
                    if (q.mask >> l & 1) ++quads[size_t(q.y + l / 2) * kSize + size_t(q.x + l % 2)];
            });
            rasterizeTriangleBlocks(
                t, steps, tile, [&](int32_t x, int32_t y, uint32_t mask, const int64_t(&e)[3][8]) {
                    for (int l = 0; l < 8; ++l) {
                        const int32_t px = x + l % 4, py = y + l / 4;
                        for (int k = 0; k < 3; ++k)
                            ASSERT_EQ(e[k][l], edgeAt(t, k, px, py)) << "trial " << trial << " lane " << l;
                        if (mask >> l & 1) {
                            ASSERT_TRUE(px >= tile.x0 && px <= tile.x1 && py >= tile.y0 && py <= tile.y1);
                            ++blocks[size_t(py) * kSize + size_t(px)];
                        }
                    }
                });
            ASSERT_EQ(quads, expect) << "rasterizeTriangle, trial " << trial;
            ASSERT_EQ(blocks, expect) << "rasterizeTriangleBlocks, trial " << trial;
            for (int c : expect) covered += c;
        }
    }
    EXPECT_GT(set_up, 600);       // about half the random triangles survive setup
    EXPECT_GT(covered, 1000000);  // and together they cover many pixels
}

// The strip (v0, v1, v2), (v1, v3, v2) of an axis-aligned rectangle, as gsBillboard makes it, in
// clip space with w = 1; `flip` mirrors it (the other winding).
struct Strip {
    Corner<float> v[4];
    ScreenVertex s[4];
};
Strip randomStrip(std::mt19937& rng, bool flip, const ViewportTransform& vp) {
    std::uniform_real_distribution<float> ndc(-1.2f, 1.2f), unit(0.0f, 1.0f);
    float x0 = ndc(rng), x1 = ndc(rng), y0 = ndc(rng), y1 = ndc(rng);
    if (flip) std::swap(x0, x1);
    const float z = unit(rng);
    const glm::vec2 xy[4] = {{x0, y1}, {x1, y1}, {x0, y0}, {x1, y0}};
    // Colour is a plane in (x, y) so that a0 + a3 = a1 + a2 exactly (small integers).
    Strip st;
    for (int i = 0; i < 4; ++i) {
        const float a = float(i & 1), b = float(i >> 1);
        st.v[i] = {glm::vec4(xy[i], z, 1.0f), glm::vec4(a, b, a + b, 2.0f + a - b)};
        st.s[i] = toScreen(st.v[i].position, vp);
    }
    return st;
}

TEST(RectangleFastPath, CoversAndCullsAsItsTwoTrianglesAndCarriesTheirAttributes) {
    std::mt19937 rng(42);
    const ViewportTransform vp(Viewport{0, 0, float(kSize), float(kSize), 0, 1});
    const std::vector<PixelRect> grid = tiles();
    int rectangles = 0, culled_seen = 0;
    for (int trial = 0; trial < 600; ++trial) {
        const Strip st = randomStrip(rng, trial % 2 == 1, vp);
        const Corner<float>* const v[4] = {&st.v[0], &st.v[1], &st.v[2], &st.v[3]};
        RasterizerState rs;
        rs.cullMode = trial % 3 == 0 ? CullMode::Back : trial % 3 == 1 ? CullMode::Front : CullMode::None;
        RectSetup r;
        Corner<float> base, step_x, step_y;
        bool culled = false;
        if (!setupRectangle(v, st.s, 0, rs, kClip, r, base, step_x, step_y, culled)) continue;  // zero width
        ++rectangles;
        TriangleSetup t[2];
        const uint32_t idx[3] = {0, 1, 2};
        const ScreenVertex a[3] = {st.s[0], st.s[1], st.s[2]}, b[3] = {st.s[1], st.s[3], st.s[2]};
        const SetupResult ra = setupTriangle(a, idx, 0, rs, kClip, t[0]);
        const SetupResult rb = setupTriangle(b, idx, 0, rs, kClip, t[1]);
        ASSERT_EQ(culled, ra == SetupResult::Culled) << "trial " << trial;
        ASSERT_EQ(culled, rb == SetupResult::Culled) << "trial " << trial;
        culled_seen += culled;
        if (culled) continue;
        for (const PixelRect& tile : grid) {
            std::vector<int> expect(size_t(kSize) * kSize, 0), got(expect.size(), 0);
            for (int k = 0; k < 2; ++k) {
                if ((k == 0 ? ra : rb) != SetupResult::Ok) continue;
                const std::vector<int> c = bruteForce(t[k], tile);
                for (size_t i = 0; i < c.size(); ++i) expect[i] += c[i];
            }
            rasterizeRect(r.box, tile, [&](int32_t x, int32_t y, uint32_t mask) {
                for (int l = 0; l < 4; ++l)
                    if (mask >> l & 1) ++got[size_t(y + l / 2) * kSize + size_t(x + l % 2)];
            });
            ASSERT_EQ(got, expect) << "trial " << trial;
        }
        // The attributes' plane at each covered pixel against perspective-correct interpolation in
        // double on the triangle holding it (w = 1: the two agree up to float rounding).
        if (ra != SetupResult::Ok || r.box.empty()) continue;
        const TriangleInterpolant<double> ti(t[0]);
        const Corner<float>* const tv[3] = {v[0], t[0].vertex[1] == 1 ? v[1] : v[2],
                                            t[0].vertex[1] == 1 ? v[2] : v[1]};
        const PixelRect area = intersect(t[0].box, r.box);
        for (int32_t y = area.y0; y <= area.y1; ++y)
            for (int32_t x = area.x0; x <= area.x1; ++x) {
                bool in = true;
                for (int k = 0; k < 3; ++k) in = in && edgeAt(t[0], k, x, y) + t[0].bias[k] >= 0;
                if (!in) continue;
                Corner<float> scalar;
                interpolateAttributes(
                    ti, barycentrics(ti, edgeAt(t[0], 0, x, y), edgeAt(t[0], 1, x, y), edgeAt(t[0], 2, x, y)),
                    tv, x, y, 0.0, scalar);
                const glm::vec4 plane =
                    base.color + float(x - r.box.x0) * step_x.color + float(y - r.box.y0) * step_y.color;
                for (int c = 0; c < 4; ++c)
                    ASSERT_NEAR(plane[c], scalar.color[c], 1e-4f) << "trial " << trial;
            }
    }
    EXPECT_GT(rectangles, 400);
    EXPECT_GT(culled_seen, 100);
}

TEST(InterpolateWide, AttributesAreTheScalarRulesBitsLaneByLane) {
    std::mt19937 rng(7);
    const uint32_t vertex[3] = {0, 1, 2};
    std::uniform_real_distribution<float> value(-100.0f, 100.0f);
    int lanes = 0;
    for (int trial = 0; trial < 300; ++trial) {
        ScreenVertex s[3];
        randomTriangle(rng, trial, s);
        TriangleSetup t;
        if (setupTriangle(s, vertex, 0, RasterizerState{}, kClip, t) != SetupResult::Ok) continue;
        Corner<float> corners[3];
        for (Corner<float>& c : corners)
            c = {glm::vec4(0.0f), glm::vec4(value(rng), value(rng), value(rng), value(rng))};
        const Corner<float>* const v[3] = {&corners[0], &corners[1], &corners[2]};
        const TriangleInterpolant<float> ti(t);
        rasterizeTriangleBlocks(
            t, edgeSteps(t), kClip, [&](int32_t x, int32_t y, uint32_t mask, const int64_t(&e)[3][8]) {
                const Float8 z = interpolateDepthWide(t, e, 0.0f, 1.0f);
                Wide<Corner<float>> wide;
                interpolateAttributesWide(ti, e, v, x, y, z, wide);
                for (int l = 0; l < 8; ++l) {
                    if (!(mask >> l & 1)) continue;
                    const int32_t px = x + l % 4, py = y + l / 4;
                    const float zl = interpolateDepth<float>(t, e[0][l], e[1][l], e[2][l], 0.0f, 1.0f);
                    Corner<float> scalar;
                    interpolateAttributes(ti, barycentrics(ti, e[0][l], e[1][l], e[2][l]), v, px, py, zl,
                                          scalar);
                    const float* expect = asFloats(scalar);
                    const Float8* got = reinterpret_cast<const Float8*>(&wide);
                    for (uint32_t i = 0; i < kVertexFloats<Corner<float>>; ++i)
                        ASSERT_EQ(std::bit_cast<uint32_t>(got[i][l]), std::bit_cast<uint32_t>(expect[i]))
                            << "trial " << trial << " lane " << l << " float " << i;
                    ++lanes;
                }
            });
    }
    EXPECT_GT(lanes, 100000);
}

// ---- merge_wide.hpp ---------------------------------------------------------------------------------

// Colours for eight lanes: alpha 0 in about a third (the additive blend's no-ops), NaN and values
// outside [0, 1] now and then (the blend saturates them).
glm::vec<4, Float8> randomColours(std::mt19937& rng) {
    std::uniform_real_distribution<float> unit(-0.25f, 1.25f);
    std::uniform_int_distribution<int> kind(0, 11);
    float lanes[4][8];
    for (int l = 0; l < 8; ++l) {
        for (int k = 0; k < 4; ++k) lanes[k][l] = unit(rng);
        const int which = kind(rng);
        if (which < 4) lanes[3][l] = 0.0f;
        if (which == 4) lanes[l % 3][l] = std::numeric_limits<float>::quiet_NaN();
    }
    auto channel = [&](int k) {
        simd::F32x8 v;
        std::memcpy(&v, lanes[k], sizeof v);
        return Float8(v);
    };
    return {channel(0), channel(1), channel(2), channel(3)};
}

Float8 randomDepths(std::mt19937& rng) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    simd::F32x8 v;
    for (int l = 0; l < 8; ++l) v[l] = unit(rng);
    return Float8(v);
}

// Blocks (0, 0) and (4, 0) of an 8×2 target through WideMerge, against the output merger's steps for
// one fragment after a passed depth test (Tile::depthTestAndBlend: depth written, then blended unless
// the blend is a no-op), lane by lane.
template <class Blender, NoOpLanes kNoOps>
void expectWideMergeIsTheScalarSteps() {
    using Depth = DepthFixed<ComparisonFunc::Less, true>;
    using Color = ColorFast<Blender>;
    std::mt19937 rng(45);
    int no_op_lanes = 0;
    for (int round = 0; round < 2000; ++round) {
        std::vector<uint8_t> wide_rgba(64), rule_rgba(64);
        std::vector<float> wide_depth(16), rule_depth(16);
        for (size_t b = 0; b < 64; ++b) wide_rgba[b] = rule_rgba[b] = uint8_t(rng());
        for (size_t p = 0; p < 16; ++p) wide_depth[p] = rule_depth[p] = float(p) / 16.0f;
        WideMerge<Depth, Color, kNoOps> merge(Depth{wide_depth.data(), 8}, Color{wide_rgba.data(), 8});
        const Depth rule_d{rule_depth.data(), 8};
        const Color rule_c{rule_rgba.data(), 8};
        const uint32_t live0 = uint32_t(rng()) & 0xFFu, live1 = round % 7 == 0 ? 0u : uint32_t(rng()) & 0xFFu;
        const glm::vec<4, Float8> c0 = randomColours(rng), c1 = randomColours(rng);
        const Float8 z0 = randomDepths(rng), z1 = randomDepths(rng);
        if (round % 2 == 0) {
            merge.block(0, 0, z0, live0, c0);
            merge.block(4, 0, z1, live1, c1);
        } else {
            glm::vec<4, Float8x2> c;
            for (int k = 0; k < 4; ++k) c[k] = Float8x2(c0[k], c1[k]);
            merge.pair(0, 0, z0, z1, live0, live1, c);
        }
        uint64_t rule_no_ops = 0;
        for (int block = 0; block < 2; ++block) {
            const uint32_t live = block ? live1 : live0;
            const glm::vec<4, Float8>& c = block ? c1 : c0;
            const Float8& z = block ? z1 : z0;
            for (int l = 0; l < 8; ++l) {
                if (!(live >> l & 1u)) continue;
                const int32_t x = 4 * block + (l & 3), y = l >> 2;
                rule_d.write(x, y, z[l]);
                const glm::vec4 colour(c.x[l], c.y[l], c.z[l], c.w[l]);
                if (rule_c.isNoOp(colour))
                    ++rule_no_ops;
                else
                    rule_c.write(x, y, colour);
            }
        }
        no_op_lanes += int(rule_no_ops);
        ASSERT_EQ(wide_rgba, rule_rgba) << "round " << round;
        ASSERT_EQ(std::memcmp(wide_depth.data(), rule_depth.data(), 16 * sizeof(float)), 0) << "round " << round;
        ASSERT_EQ(merge.noOps(), rule_no_ops) << "round " << round;
    }
    if constexpr (Color::kAlphaZeroNoOp) {
        EXPECT_GT(no_op_lanes, 2000) << "the no-op lanes were exercised";
    }
}

TEST(WideMerge, AdditiveSkippingNoOpsStoresTheRulesBytes) {
    expectWideMergeIsTheScalarSteps<BlendAdditiveRgba8, NoOpLanes::Skipped>();
}
TEST(WideMerge, AdditiveWritingNoOpsStoresTheRulesBytes) {
    expectWideMergeIsTheScalarSteps<BlendAdditiveRgba8, NoOpLanes::Written>();
}
TEST(WideMerge, ReplaceStoresTheRulesBytes) {
    expectWideMergeIsTheScalarSteps<BlendReplaceRgba8, NoOpLanes::Skipped>();
    expectWideMergeIsTheScalarSteps<BlendReplaceRgba8, NoOpLanes::Written>();
}

}  // namespace
}  // namespace raster
