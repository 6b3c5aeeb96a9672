// The fire scene (raster/lecture/src/scene_fire.cpp) and scene time (raster/scenes.hpp): a frame is a
// function of the options and the time, whatever the thread count and however the time was given;
// the particles only add light to the occluder, and it rises.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "raster/check.hpp"
#include "raster/scenes.hpp"

namespace raster {
namespace {

constexpr uint32_t kWidth = 320, kHeight = 180;

struct Frame {
    RenderTarget color{kWidth, kHeight};
    DepthTarget depth{kWidth, kHeight};
};

SceneOptions fireOptions(double time, uint64_t seed = 1, uint32_t count = 2000) {
    SceneOptions o{.width = kWidth, .height = kHeight, .count = count};
    o.time = time;
    o.seed = seed;
    return o;
}

Frame render(Scene& scene, unsigned threads = 2) {
    Frame f;
    Context context({threads});
    scene.render(context, f.color, f.depth);
    return f;
}

Frame renderFire(const SceneOptions& o, unsigned threads = 2) {
    return render(*makeScene("fire", o), threads);
}

// Σ over pixels and rgb channels of (a − b), and the number of channels where a < b.
struct Added {
    double sum = 0.0;
    uint64_t darker = 0;
};
Added lightAdded(const RenderTarget& a, const RenderTarget& b) {
    Added added;
    for (uint32_t i = 0; i < kWidth * kHeight; ++i)
        for (int c = 0; c < 3; ++c) {
            const int d = int(a.rgba8()[4 * i + c]) - int(b.rgba8()[4 * i + c]);
            added.sum += d;
            added.darker += d < 0;
        }
    return added;
}

// The row (0 on top) of the centroid of the light the particles add to the occluder-only frame.
double addedLightRow(const RenderTarget& fire, const RenderTarget& bare) {
    double weight = 0.0, row = 0.0;
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x)
            for (int c = 0; c < 3; ++c) {
                const size_t i = 4 * (size_t(y) * kWidth + x) + size_t(c);
                const double d = double(fire.rgba8()[i]) - double(bare.rgba8()[i]);
                weight += d, row += d * y;
            }
    return weight > 0.0 ? row / weight : -1.0;
}

TEST(FireScene, IsAnimatedAndStartsAtItsTime) {
    const std::unique_ptr<Scene> fire = makeScene("fire", fireOptions(1.25));
    EXPECT_TRUE(fire->animated());
    EXPECT_EQ(fire->time(), 1.25);
    fire->advance(0.5);
    EXPECT_EQ(fire->time(), 1.75);
    EXPECT_EQ(makeScene("fire", {.width = 8, .height = 8})->time(), kDefaultFireTime);
    for (const char* name : {"particles", "fog"})
        EXPECT_FALSE(makeScene(name, {.width = 8, .height = 8})->animated());
}

TEST(FireScene, BitIdenticalAtOneTwoAndEightThreads) {
    const SceneOptions o = fireOptions(1.5, 7);
    const Frame one = renderFire(o, 1), two = renderFire(o, 2), eight = renderFire(o, 8);
    EXPECT_TRUE(one.color == two.color);
    EXPECT_TRUE(one.color == eight.color);
    EXPECT_TRUE(one.depth == eight.depth);
    EXPECT_GT(lightAdded(one.color, renderFire(fireOptions(1.5, 7, 0)).color).sum, 0.0) << "an empty frame";
}

TEST(FireScene, SeedsDiffer) {
    EXPECT_FALSE(renderFire(fireOptions(1.5, 1)).color == renderFire(fireOptions(1.5, 2)).color);
    EXPECT_TRUE(renderFire(fireOptions(1.5, 2)).color == renderFire(fireOptions(1.5, 2)).color);
}

// The state is that of the whole fixed steps (1/60 s) in the clock's time, however the time came.
TEST(FireScene, AdvancingEqualsStartingLater) {
    const Frame at_one = renderFire(fireOptions(1.0));
    const std::unique_ptr<Scene> halves = makeScene("fire", fireOptions(0.5));
    halves->advance(0.5);
    EXPECT_TRUE(render(*halves).color == at_one.color) << "0.5 s + 0.5 s";
    const std::unique_ptr<Scene> frames = makeScene("fire", fireOptions(0.0));
    for (int k = 0; k < 120; ++k) frames->advance(1.0 / 120.0);  // half a step each
    EXPECT_TRUE(render(*frames).color == at_one.color) << "120 frames of 1/120 s";
    EXPECT_FALSE(render(*makeScene("fire", fireOptions(1.0 + 1.0 / 60.0))).color == at_one.color)
        << "one step later is another picture";
    // render() does not move time on.
    EXPECT_TRUE(render(*halves).color == at_one.color);
}

// Additive blending with depth writes off: every channel of every pixel is at least the occluder-only
// frame's (the fire with no particles), the depth buffer is the occluder's, and light is added.
TEST(FireScene, ParticlesOnlyAddLight) {
    const Frame bare = renderFire(fireOptions(2.0, 1, 0));
    const Frame fire = renderFire(fireOptions(2.0, 1, 4000));
    const Added added = lightAdded(fire.color, bare.color);
    EXPECT_EQ(added.darker, 0u);
    EXPECT_GT(added.sum, 255.0 * 500) << "at least 500 pixels' worth of light";
    EXPECT_TRUE(fire.depth == bare.depth) << "the particles wrote depth";
}

// Buoyancy: early on the light is low, near the emitter; later the flames have risen.
TEST(FireScene, LightRisesWithTime) {
    const RenderTarget bare = renderFire(fireOptions(0.0, 1, 0)).color;
    const double early = addedLightRow(renderFire(fireOptions(0.2)).color, bare);
    const double later = addedLightRow(renderFire(fireOptions(1.0)).color, bare);
    const double steady = addedLightRow(renderFire(fireOptions(3.0)).color, bare);
    ASSERT_GT(early, 0.0) << "no light at 0.2 s";
    EXPECT_LT(later, early - 5.0) << "rows: " << early << " then " << later;
    EXPECT_LT(steady, early - 5.0) << "rows: " << early << " then " << steady;
}

TEST(FireScene, StaticScenesIgnoreTime) {
    SceneOptions plain{.width = 64, .height = 36, .count = 50, .cubes = 2}, timed = plain;
    timed.time = 5.0;
    timed.seed = 9;
    for (const char* name : {"particles", "fog"}) {
        const std::unique_ptr<Scene> moved = makeScene(name, timed);
        moved->advance(2.0);
        EXPECT_EQ(moved->time(), 0.0);
        Context context({1});
        RenderTarget a(64, 36), b(64, 36);
        DepthTarget da(64, 36), db(64, 36);
        makeScene(name, plain)->render(context, a, da);
        moved->render(context, b, db);
        EXPECT_TRUE(a == b) << name;
    }
}

void expectInvalidArgument(const std::function<void()>& f, const std::string& part) {
    try {
        f();
        ADD_FAILURE() << "no error; expected one naming " << part;
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what() << " lacks " << part;
    }
}

TEST(FireScene, BadTimesAreRefused) {
    const double nan = std::numeric_limits<double>::quiet_NaN(),
                 inf = std::numeric_limits<double>::infinity();
    expectInvalidArgument([] { makeScene("fire", fireOptions(-1.0)); }, "start time -1");
    expectInvalidArgument([&] { makeScene("fire", fireOptions(nan)); }, "start time nan");
    expectInvalidArgument([&] { makeScene("fog", fireOptions(inf)); }, "start time inf");
    expectInvalidArgument([] { makeScene("fire", fireOptions(kMaxStartTime + 1.0)); }, "outside [0, 600 s]");
    const std::unique_ptr<Scene> fire = makeScene("fire", fireOptions(0.0));
    expectInvalidArgument([&] { fire->advance(-0.5); }, "advance by -0.5");
    expectInvalidArgument([&] { fire->advance(nan); }, "advance by nan");
    expectInvalidArgument([&] { makeScene("fog", {})->advance(inf); }, "scene 'fog'");
    EXPECT_EQ(fire->time(), 0.0) << "a refused advance moved the clock";
}

}  // namespace
}  // namespace raster
