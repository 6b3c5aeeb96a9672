// Soft particles and off-screen particles (raster/soft_particles.hpp) and the `smoke` scene: the fade's
// values, the depth linearisation, the depth downsample's rules, no hard intersection line, the
// off-screen composite against full resolution, the edge halo before and after the fix, determinism.
// Draws only through the library's smoke scene, so this file compiles no pipeline.
#include "raster/soft_particles.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "raster/image_compare.hpp"
#include "raster/pipeline.hpp"

namespace raster {
namespace {

struct Frame {
    RenderTarget color;
    DepthTarget depth;
};

Frame renderSmoke(const SceneOptions& o, const OffscreenParticles& mode, unsigned threads = 2) {
    std::unique_ptr<Scene> scene = makeSmokeScene(o, mode);
    // Float, as raster bench soft-particles renders: faint layers are not rounded away one by one.
    Frame f{RenderTarget(o.width, o.height, Format::R32G32B32A32_FLOAT), DepthTarget(o.width, o.height)};
    Context context({threads});
    scene->render(context, f.color, f.depth);
    return f;
}

// ---- The fade and the depth it reads ---------------------------------------------------------------

TEST(SoftFade, ZeroAtContactOneBeyondTheFadeDistance) {
    const float fade = 0.25f, inverse = 1.0f / fade;
    EXPECT_EQ(softFade(3.0f, 3.0f, inverse), 0.0f);                 // touching the surface
    EXPECT_EQ(softFade(3.0f, 3.5f, inverse), 0.0f);                 // behind it
    EXPECT_FLOAT_EQ(softFade(3.0f, 3.0f - 0.125f, inverse), 0.5f);  // halfway: linear
    EXPECT_EQ(softFade(3.0f, 3.0f - fade, inverse), 1.0f);          // at the fade distance
    EXPECT_EQ(softFade(3.0f, 1.0f, inverse), 1.0f);                 // beyond it
    // Eight lanes give the scalar values.
    const Float8 scene(3.0f),
        particle(
            Float8::load(std::array<float, 8>{3.5f, 3.0f, 2.875f, 2.75f, 1.0f, 2.9f, 2.99f, 2.8f}.data()));
    const Float8 wide = softFade(scene, particle, inverse);
    const float expected[8] = {0.0f,
                               0.0f,
                               0.5f,
                               1.0f,
                               1.0f,
                               softFade(3.0f, 2.9f, inverse),
                               softFade(3.0f, 2.99f, inverse),
                               softFade(3.0f, 2.8f, inverse)};
    for (int i = 0; i < 8; ++i) EXPECT_EQ(wide.v[i], expected[i]) << "lane " << i;
}

TEST(DepthLinearizer, InvertsTheScenesProjection) {
    const glm::mat4 proj = sceneProjection({});
    const DepthLinearizer linearizer;  // the scenes' planes, 0.1 and 100
    for (const float s : {0.1f, 0.5f, 1.0f, 3.7f, 20.0f, 99.0f}) {
        const glm::vec4 clip = proj * glm::vec4(0.3f, -0.2f, -s, 1.0f);
        EXPECT_FLOAT_EQ(clip.w, s);  // a billboard's SV_Position.w is its view depth
        EXPECT_NEAR(linearizer.viewDepth(clip.z / clip.w), s, 2e-4f * s * s) << "view depth " << s;
    }
    EXPECT_FLOAT_EQ(linearizer.viewDepth(0.0f), 0.1f);
    EXPECT_NEAR(linearizer.viewDepth(1.0f), 100.0f, 100.0f * 2e-5f);  // n·f / n, rounded in float
}

TEST(DepthTexture, ReadsTheTexelUnderThePixelCentreClampedAndLoadsZeroOutside) {
    DepthTarget depth(3, 2);
    for (uint32_t y = 0; y < 2; ++y)
        for (uint32_t x = 0; x < 3; ++x) depth.store(x, y, 0.1f * float(1 + x + 3 * y));
    const DepthTexture t(depth);
    EXPECT_EQ(t.atPixel(1.5f, 1.5f), depth.load(1, 1));
    EXPECT_EQ(t.atPixel(2.5f, 0.5f), depth.load(2, 0));
    EXPECT_EQ(t.atPixel(7.5f, 5.5f), depth.load(2, 1));  // clamped
    EXPECT_EQ(t.load(3, 0), 0.0f);
    EXPECT_EQ(t.load(-1, 0), 0.0f);
    const Float8 x(Float8::load(std::array<float, 8>{0.5f, 1.5f, 2.5f, 3.5f, 0.5f, 1.5f, 2.5f, 3.5f}.data()));
    const Float8 y(Float8::load(std::array<float, 8>{0.5f, 0.5f, 0.5f, 0.5f, 1.5f, 1.5f, 1.5f, 1.5f}.data()));
    const Float8 wide = t.atPixel(x, y);
    for (int i = 0; i < 8; ++i) EXPECT_EQ(wide.v[i], t.atPixel(x.v[i], y.v[i])) << "lane " << i;
}

// ---- The downsample --------------------------------------------------------------------------------

TEST(DownsampleDepth, FarthestNearestAndPointOfEachBlockCutToTheTarget) {
    DepthTarget full(5, 3);
    const float d[3][5] = {
        {0.9f, 0.2f, 0.5f, 0.6f, 0.3f}, {0.4f, 0.8f, 0.1f, 0.7f, 1.0f}, {0.35f, 0.25f, 0.45f, 0.05f, 0.15f}};
    for (uint32_t y = 0; y < 3; ++y)
        for (uint32_t x = 0; x < 5; ++x) full.store(x, y, d[y][x]);
    const DepthTarget far = downsampleDepth(full, 2, DepthDownsample::Farthest);
    const DepthTarget near = downsampleDepth(full, 2, DepthDownsample::Nearest);
    const DepthTarget point = downsampleDepth(full, 2, DepthDownsample::Point);
    ASSERT_EQ(far.width(), 3u);  // ⌈5/2⌉ × ⌈3/2⌉
    ASSERT_EQ(far.height(), 2u);
    const float farthest[2][3] = {{0.9f, 0.7f, 1.0f}, {0.35f, 0.45f, 0.15f}};
    const float nearest[2][3] = {{0.2f, 0.1f, 0.3f}, {0.25f, 0.05f, 0.15f}};
    const float top_left[2][3] = {{0.9f, 0.5f, 0.3f}, {0.35f, 0.45f, 0.15f}};
    for (uint32_t j = 0; j < 2; ++j)
        for (uint32_t i = 0; i < 3; ++i) {
            EXPECT_EQ(far.load(i, j), farthest[j][i]) << i << "," << j;
            EXPECT_EQ(near.load(i, j), nearest[j][i]) << i << "," << j;
            EXPECT_EQ(point.load(i, j), top_left[j][i]) << i << "," << j;
        }
    EXPECT_THROW(downsampleDepth(full, 0), Error);
    EXPECT_THROW(downsampleDepth(DepthTarget(), 2), Error);
}

TEST(DepthEdgeMask, MarksTheThreeByThreeAroundAStepOnly) {
    DepthTarget far(6, 1), near(6, 1);
    const DepthLinearizer linearizer;
    for (uint32_t x = 0; x < 6; ++x) near.store(x, 0, x < 3 ? 0.95f : 0.999f);  // view depth ~2 then ~91
    far = near;
    const std::vector<uint8_t> edge = depthEdgeMask(near, far, linearizer, 0.1f);
    EXPECT_EQ(edge, (std::vector<uint8_t>{0, 0, 1, 1, 0, 0}));
    EXPECT_THROW(depthEdgeMask(near, DepthTarget(5, 1), linearizer, 0.1f), Error);
}

// ---- Soft against hard -----------------------------------------------------------------------------

// Where the smoke's contribution (the frame less the frame without particles) steps by more than
// kLineStep between vertical or horizontal neighbours, away from the opaque geometry's own edges
// (the empty frame's colour steps) and depth discontinuities: the pixels of the line along which a
// hard particle's plane cuts the ground or the box. Soft smoke changes too, but gradually.
constexpr int kLineStep = 5;  // 8-bit steps

size_t hardLinePixels(const Frame& smoke, const Frame& empty) {
    const uint32_t w = smoke.color.width(), h = smoke.color.height();
    const std::vector<uint8_t> band = depthEdgeBand(empty.depth, DepthLinearizer{}, 0.1f, 2);
    const std::vector<uint8_t> a = smoke.color.toRgba8(), b = empty.color.toRgba8();
    const auto contribution = [&](size_t i, int c) { return int(a[4 * i + c]) - int(b[4 * i + c]); };
    size_t count = 0;
    for (uint32_t y = 2; y + 3 < h; ++y)
        for (uint32_t x = 2; x + 3 < w; ++x) {
            bool geometry_edge = false;
            for (uint32_t j = y - 2; j <= y + 3 && !geometry_edge; ++j)
                for (uint32_t i = x - 2; i <= x + 3 && !geometry_edge; ++i)
                    geometry_edge =
                        band[size_t(j) * w + i] ||
                        std::memcmp(&b[4 * (size_t(j) * w + i)], &b[4 * (size_t(y) * w + x)], 3) != 0;
            if (geometry_edge) continue;
            const size_t i = size_t(y) * w + x;
            int step = 0;
            for (int c = 0; c < 3; ++c)
                step = std::max({step, std::abs(contribution(i + 1, c) - contribution(i, c)),
                                 std::abs(contribution(i + w, c) - contribution(i, c))});
            count += step > kLineStep;
        }
    return count;
}

TEST(SoftParticles, HaveNoHardIntersectionLine) {
    // Close, looking down at the plume's foot on the ground and its side against the box: puffs
    // large on screen, so that their own falloff steps by less than kLineStep. (From afar, small
    // puffs step by more on their own, soft or hard.)
    {
        SceneOptions o;
        o.width = 640, o.height = 360;
        o.camera = SceneCamera{{-1.0f, 1.6f, 0.8f}, {-1.0f, 0.0f, -0.5f}};
        SceneOptions none = o;
        none.count = 0;
        const Frame empty = renderSmoke(none, {});
        OffscreenParticles hard;
        hard.soft = false;
        const size_t soft_line = hardLinePixels(renderSmoke(o, {}), empty);
        const size_t hard_line = hardLinePixels(renderSmoke(o, hard), empty);
        std::printf("steps above %d: soft %zu pixels, hard %zu\n", kLineStep, soft_line, hard_line);
        // Measured: soft 0 pixels, hard 90.
        EXPECT_LE(soft_line, 10u) << "hard " << hard_line;
        EXPECT_GE(hard_line, 45u) << "soft " << soft_line;
        EXPECT_GE(hard_line, 10 * std::max<size_t>(soft_line, 1)) << "soft " << soft_line;
    }
}

// ---- Off-screen ------------------------------------------------------------------------------------

// Looking down at the plume's foot, the box out of view: the ground fills the picture, so its depth
// is continuous, with no occluder edge.
SceneOptions groundOnly() {
    SceneOptions o;
    o.width = 360, o.height = 360;
    o.camera = SceneCamera{{-1.4f, 1.5f, -0.2f}, {-1.4f, 0.0f, -0.6f}};
    return o;
}

ComparisonResult flip(const Frame& reference, const Frame& result) {
    const std::vector<uint8_t> a = reference.color.toRgba8(), b = result.color.toRgba8();
    return compareFlip({a, reference.color.width(), reference.color.height()},
                       {b, result.color.width(), result.color.height()});
}

TEST(OffscreenParticles, CompositeAtHalfMatchesFullResolutionWithoutOccluderEdges) {
    const SceneOptions o = groundOnly();
    const Frame full = renderSmoke(o, {});
    const std::vector<uint8_t> band = depthEdgeBand(full.depth, DepthLinearizer{}, 0.1f, 0);
    ASSERT_EQ(std::count(band.begin(), band.end(), 1), 0) << "the view must hold no depth edge";
    const Frame half = renderSmoke(o, {2, false});
    const Frame fixed = renderSmoke(o, {2, true});
    EXPECT_TRUE(half.color == fixed.color) << "no edge texel, so the fix must change nothing";
    const ComparisonResult e = flip(full, half);
    const ImageDifference d = compareImages({full.color.toRgba8(), o.width, o.height},
                                            {half.color.toRgba8(), o.width, o.height}, CompareChannels::Rgb);
    std::printf("half against full, no depth edge: mean FLIP %.4f, largest difference %d\n", e.figure, d.max);
    // Measured: mean FLIP 0.0009, largest channel difference 1 step (docs/SOFT_PARTICLES.md).
    EXPECT_LT(e.figure, 0.002);
    EXPECT_LE(d.max, 3);
    EXPECT_GT(d.differing, 0u) << "half resolution is not full resolution";
}

// The mean FLIP error within 4 pixels of a depth discontinuity.
double haloError(const Frame& full, const Frame& offscreen) {
    const ComparisonResult e = flip(full, offscreen);
    const std::vector<uint8_t> band = depthEdgeBand(full.depth, DepthLinearizer{}, 0.1f, 4);
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < band.size(); ++i)
        if (band[i]) sum += e.error[i], ++n;
    return n ? sum / double(n) : 0.0;
}

TEST(OffscreenParticles, EdgeHaloExceedsItsBoundBeforeTheFixAndFallsBelowAfter) {
    SceneOptions o;  // 1280×720, the default smoke
    const Frame full = renderSmoke(o, {});
    for (const uint32_t k : {2u, 4u}) {
        const double before = haloError(full, renderSmoke(o, {k, false}));
        const double after = haloError(full, renderSmoke(o, {k, true}));
        std::printf(
            "factor %u: halo (mean FLIP within 4 px of a depth edge) %.4f before the fix, %.4f after\n", k,
            before, after);
        // docs/SOFT_PARTICLES.md: the halo's mean FLIP error in the band is above 0.01 before the fix
        // at ½ and ¼ (measured 0.0151 and 0.0291), and below 0.003 after it (0.0008 and 0.0001).
        EXPECT_GT(before, 0.01) << "factor " << k;
        EXPECT_LT(after, 0.003) << "factor " << k;
        EXPECT_LT(after, before / 3) << "factor " << k;
    }
}

TEST(OffscreenParticles, BadModesAreRefused) {
    EXPECT_THROW(makeSmokeScene({}, {0, false}), Error);
    EXPECT_THROW(makeSmokeScene({}, {17, false}), Error);
    OffscreenParticles bad;
    bad.fadeDistance = 0.0f;
    EXPECT_THROW(makeSmokeScene({}, bad), Error);
}

// ---- The scene -------------------------------------------------------------------------------------

TEST(SmokeScene, IsRegisteredAfterTheFireAndAnimated) {
    const std::vector<std::string> names = sceneNames();
    ASSERT_GE(names.size(), 2u);
    EXPECT_EQ(names[0], "fire");
    EXPECT_EQ(names[1], "smoke");
    std::unique_ptr<Scene> scene = makeScene("smoke", {.width = 64, .height = 36});
    EXPECT_EQ(scene->name(), "smoke");
    EXPECT_TRUE(scene->animated());
    const double t0 = scene->time();
    scene->advance(0.5);
    EXPECT_DOUBLE_EQ(scene->time(), t0 + 0.5);
}

TEST(SmokeScene, BitIdenticalAtOneAndEightThreads) {
    SceneOptions o;
    o.width = 640, o.height = 360;
    for (const uint32_t k : {1u, 2u, 4u}) {
        const OffscreenParticles mode{k, k > 1};
        EXPECT_TRUE(renderSmoke(o, mode, 1).color == renderSmoke(o, mode, 8).color) << "factor " << k;
    }
    std::unique_ptr<Scene> a = makeScene("smoke", o), b = makeScene("smoke", o);
    a->advance(1.0 / 60.0);
    Context one({1}), eight({8});
    Frame fa{RenderTarget(o.width, o.height), DepthTarget(o.width, o.height)}, fb = fa;
    a->render(one, fa.color, fa.depth);
    b->render(eight, fb.color, fb.depth);
    EXPECT_FALSE(fa.color == fb.color) << "a frame later the smoke has moved";
    b->advance(1.0 / 60.0);
    b->render(eight, fb.color, fb.depth);
    EXPECT_TRUE(fa.color == fb.color);
}

}  // namespace
}  // namespace raster
