// ContextOptions::plain: every primitive through fill/quads.hpp, the generic depth test and blend,
// the depth test after the shader. The images must be the fast path's, bit for bit, wherever the fast
// path draws the same primitives (triangles, lines, points); billboards, which the plain path draws as
// the geometry shader's two triangles where the fast path draws one rectangle, within 1/255.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"

namespace {

using namespace raster;

struct Frame {
    RenderTarget color;
    DepthTarget depth;
    PipelineStatistics stats;
};

Frame render(const std::string& name, const SceneOptions& options, ContextOptions context_options) {
    auto scene = makeScene(name, options);
    Context ctx(context_options);
    Frame f{RenderTarget(options.width, options.height), DepthTarget(options.width, options.height), {}};
    ctx.resetFrameStatistics();
    scene->render(ctx, f.color, f.depth);
    f.stats = ctx.frameStatistics();
    return f;
}

// The largest difference of any RGBA8 channel, and how many pixels differ at all.
std::pair<int, int> difference(const RenderTarget& a, const RenderTarget& b) {
    int largest = 0, pixels = 0;
    for (size_t i = 0; i < size_t(a.width()) * a.height(); ++i) {
        int d = 0;
        for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(int(a.rgba8()[4 * i + c]) - int(b.rgba8()[4 * i + c])));
        largest = std::max(largest, d);
        pixels += d > 0;
    }
    return {largest, pixels};
}

TEST(PlainPath, FogIsTheFastPathsImageBitForBit) {
    for (bool height_fog : {false, true}) {
        const SceneOptions o{.width = 320, .height = 180, .cubes = 4, .heightFog = height_fog};
        const Frame fast = render("fog", o, {.threads = 2});
        const Frame plain = render("fog", o, {.threads = 2, .plain = true});
        EXPECT_EQ(difference(fast.color, plain.color), (std::pair<int, int>{0, 0})) << "height fog " << height_fog;
        EXPECT_TRUE(fast.depth == plain.depth);
        // The same fragments reach the pixels; the plain path tests depth after the shader, so the
        // ones the test kills are shaded first and counted as killed late.
        EXPECT_EQ(fast.stats.fragmentsLateDepthKilled, 0u);
        EXPECT_EQ(plain.stats.fragmentsEarlyDepthKilled, 0u);
        EXPECT_EQ(plain.stats.tilesOccluded, 0u) << "the plain path skips no tile";
        EXPECT_EQ(plain.stats.psInvocations - plain.stats.fragmentsLateDepthKilled,
                  fast.stats.psInvocations + fast.stats.fragmentsOverdrawSkipped)
            << "every fragment that passes is shaded on both paths";
    }
}

TEST(PlainPath, BillboardsAsTwoTrianglesWithinOneStep) {
    const SceneOptions o{.width = 320, .height = 180, .count = 500};
    const Frame fast = render("particles", o, {.threads = 2});
    const Frame plain = render("particles", o, {.threads = 2, .plain = true});
    EXPECT_GT(fast.stats.rectanglesRecognized, 0u);
    EXPECT_EQ(plain.stats.rectanglesRecognized, 0u) << "the plain path draws the geometry shader's triangles";
    const auto [largest, pixels] = difference(fast.color, plain.color);
    EXPECT_LE(largest, 1);
    EXPECT_LT(pixels, 320 * 180 / 100);
    EXPECT_TRUE(fast.depth == plain.depth) << "particles write no depth: the occluder's alone";
}

TEST(PlainPath, SameImageForAnyThreadCount) {
    const SceneOptions o{.width = 200, .height = 120, .count = 300};
    const Frame one = render("particles", o, {.threads = 1, .plain = true});
    const Frame eight = render("particles", o, {.threads = 8, .plain = true});
    EXPECT_EQ(difference(one.color, eight.color), (std::pair<int, int>{0, 0}));
}

}  // namespace
