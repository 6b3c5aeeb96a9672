// raster view: the step cursor and the script language on their own, then the viewer run headless
// (SDL's offscreen driver) against direct renders of the same scenes through the library: its
// screenshots must be the framebuffer, byte for byte, at every step. The viewer in a real X window
// is tests/viewer_xvfb_test.sh.
#include "view/viewer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "raster/image_io.hpp"
#include "raster/scenes.hpp"
#include "view/camera.hpp"

namespace raster::tools {
namespace {

constexpr uint32_t kWidth = 320, kHeight = 180;
constexpr uint32_t kParticles = 2000;  // enough to see, quick to replay at every step

void expectInvalidArgument(const std::function<void()>& f, std::initializer_list<std::string> parts) {
    try {
        f();
        ADD_FAILURE() << "expected Error(InvalidArgument), nothing was thrown";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        const std::string message = e.what();
        for (const std::string& part : parts)
            EXPECT_NE(message.find(part), std::string::npos)
                << "message \"" << message << "\" lacks \"" << part << "\"";
    }
}

// ---- The step cursor ---------------------------------------------------------------------------------

// Where the cursor is, as (draws, primitives) with -1 draws for the whole frame.
std::pair<int64_t, uint64_t> where(const StepCursor& c) {
    return c.whole() ? std::pair<int64_t, uint64_t>{-1, 0}
                     : std::pair<int64_t, uint64_t>{c.draws(), c.primitives()};
}

TEST(StepCursor, PrimitiveStepsWalkEveryPrefixAndBackExactly) {
    StepCursor c;
    c.setShape({2, 0, 3});  // a draw without primitives in the middle
    ASSERT_TRUE(c.whole());
    EXPECT_EQ(c.limit().draws, UINT32_MAX);
    std::vector<std::pair<int64_t, uint64_t>> forward;
    std::vector<Context::StepLimit> limits;
    for (int i = 0; i < 6; ++i) {
        c.nextPrimitive();
        forward.push_back(where(c));
        limits.push_back(c.limit());
    }
    // Draw 1 primitive by primitive, the empty draw in one step, then draw 3.
    const std::vector<std::pair<int64_t, uint64_t>> expected = {{1, 1}, {1, 2}, {2, 0},
                                                                {3, 1}, {3, 2}, {3, 3}};
    EXPECT_EQ(forward, expected);
    EXPECT_EQ(limits[0].draws, 1u);
    EXPECT_EQ(limits[0].primitives, 1u);
    EXPECT_EQ(limits[1].primitives, UINT64_MAX) << "a complete draw runs unlimited, as in the whole frame";
    EXPECT_EQ(limits[4].draws, 3u);
    EXPECT_EQ(limits[4].primitives, 2u);
    c.nextPrimitive();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{3, 3})) << "the end of the frame stays put";
    for (int i = 4; i >= 0; --i) {
        c.previousPrimitive();
        EXPECT_EQ(where(c), expected[size_t(i)]) << "step back " << 5 - i;
    }
    c.previousPrimitive();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{0, 0}));
    EXPECT_EQ(c.limit().draws, 0u);
    EXPECT_EQ(c.label(), "draw 0 of 3 (cleared targets)");
    c.previousPrimitive();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{0, 0}));
}

TEST(StepCursor, DrawStepsFinishOrLeaveTheDraw) {
    StepCursor c;
    c.setShape({2, 5});
    c.nextDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{1, 2}));
    EXPECT_EQ(c.label(), "draw 1 of 2, complete (2 primitives)");
    c.nextDraw();
    c.previousDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{1, 2}))
        << "forward twice and back once is forward once";
    c.nextPrimitive();
    c.nextPrimitive();
    EXPECT_EQ(c.label(), "draw 2 of 2, primitive 2 of 5");
    c.nextDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{2, 5})) << "N inside a draw finishes it";
    c.nextPrimitive();
    c.nextDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{2, 5})) << "N at the end stays";
    c.previousPrimitive();
    c.previousDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{1, 2}))
        << "P inside a draw goes to the end of the one before";
    c.showAll();
    c.previousDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{1, 2}))
        << "P from the whole frame steps back from its end";
    c.showAll();
    c.previousPrimitive();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{2, 4}));
    c.showAll();
    EXPECT_EQ(c.label(), "whole frame, 2 draws");
}

// ---- Scripts and options ---------------------------------------------------------------------------------

TEST(ViewerScript, ParsesKeysAndPointerTokens) {
    const std::vector<Action> a = parseScript(
        "  N p ] [ 0 d S f12 H F1 I r Esc q w shift+S Shift+Q PageUp "
        "click:160,90 drag:10,20,30,5 wheel:-2 resize:200x100 wait ");
    ASSERT_EQ(a.size(), 23u);
    EXPECT_EQ(a[0].verb, Verb::NextDraw);
    EXPECT_EQ(a[1].verb, Verb::PreviousDraw);
    EXPECT_EQ(a[2].verb, Verb::NextPrimitive);
    EXPECT_EQ(a[3].verb, Verb::PreviousPrimitive);
    EXPECT_EQ(a[4].verb, Verb::WholeFrame);
    EXPECT_EQ(a[5].verb, Verb::ToggleDepth);
    EXPECT_EQ(a[6].verb, Verb::Screenshot);
    EXPECT_EQ(a[7].verb, Verb::Screenshot);
    EXPECT_EQ(a[12].verb, Verb::Quit);
    EXPECT_EQ(a[13].verb, Verb::Quit);
    EXPECT_EQ(a[14].verb, Verb::Fly);
    EXPECT_EQ(a[14].x, 1);
    EXPECT_EQ(a[15].x, -1) << "Shift+S flies backwards";
    EXPECT_EQ(a[16].z, -1) << "Shift+Q flies down";
    EXPECT_EQ(a[17].z, 1);
    EXPECT_EQ(a[18].verb, Verb::Click);
    EXPECT_EQ(a[18].x, 160);
    EXPECT_EQ(a[18].y, 90);
    EXPECT_EQ(a[19].verb, Verb::Orbit);
    EXPECT_EQ(a[19].x, 20);
    EXPECT_EQ(a[19].y, -15);
    EXPECT_EQ(a[20].verb, Verb::Zoom);
    EXPECT_EQ(a[20].x, -2);
    EXPECT_EQ(a[21].verb, Verb::Resize);
    EXPECT_EQ(a[21].x, 200);
    EXPECT_EQ(a[21].y, 100);
    EXPECT_EQ(a[22].verb, Verb::Wait);
    EXPECT_TRUE(parseScript("").empty());
}

TEST(ViewerScript, ErrorsNameTheToken) {
    expectInvalidArgument([] { parseScript("N N X S"); }, {"unknown key 'X'"});
    expectInvalidArgument([] { parseScript("click:1"); }, {"'click:1'", "click:X,Y"});
    expectInvalidArgument([] { parseScript("click:1,2,3"); }, {"'click:1,2,3'"});
    expectInvalidArgument([] { parseScript("click:-1,2"); }, {"'click:-1,2'"});
    expectInvalidArgument([] { parseScript("click:a,b"); }, {"'click:a,b'"});
    expectInvalidArgument([] { parseScript("drag:1,2,3"); }, {"'drag:1,2,3'"});
    expectInvalidArgument([] { parseScript("wheel:"); }, {"'wheel:'"});
    expectInvalidArgument([] { parseScript("resize:0x10"); }, {"'resize:0x10'"});
    expectInvalidArgument([] { parseScript("Ctrl+N"); }, {"'Ctrl+N'"});
}

int runView(std::vector<std::string> args) {
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    return view(int(argv.size()), argv.data());
}

TEST(ViewerCommand, BadOptionsNameTheCulprit) {
    // All of these fail before SDL starts.
    expectInvalidArgument([] { runView({"smoke", "--headless"}); }, {"unknown scene 'smoke'"});
    expectInvalidArgument([] { runView({"particles", "--size", "0x10"}); }, {"--size width", "0"});
    expectInvalidArgument([] { runView({"particles", "--size", "320"}); }, {"--size", "'320'"});
    expectInvalidArgument([] { runView({"particles", "--size", "320x"}); }, {"--size height"});
    expectInvalidArgument([] { runView({"particles", "--bogus"}); }, {"'--bogus'"});
    expectInvalidArgument([] { runView({"particles", "--script"}); }, {"--script needs a value"});
    expectInvalidArgument([] { runView({"particles", "--headless", "--script", "N ] Z"}); }, {"'Z'"});
    expectInvalidArgument([] { runView({"fog", "--fog", "thick"}); }, {"'thick'"});
    expectInvalidArgument([] { runView({"fog", "--screenshot-dir", ""}); }, {"--screenshot-dir"});
}

TEST(SceneCamera, DefaultIsTheScenesOwnAndBadOnesAreRefused) {
    for (const std::string& name : sceneNames()) {
        SceneOptions plain{.width = 64, .height = 36, .count = 100, .cubes = 2};
        SceneOptions explicit_camera = plain;
        explicit_camera.camera = defaultCamera(name);
        Context ctx;
        RenderTarget a(64, 36), b(64, 36);
        DepthTarget da(64, 36), db(64, 36);
        makeScene(name, plain)->render(ctx, a, da);
        makeScene(name, explicit_camera)->render(ctx, b, db);
        EXPECT_TRUE(a == b) << name;
        EXPECT_TRUE(da == db) << name;
    }
    expectInvalidArgument([] { defaultCamera("smoke"); }, {"'smoke'"});
    SceneOptions bad{.width = 8, .height = 8};
    bad.camera = SceneCamera{{1, 2, 3}, {1, 2, 3}};
    expectInvalidArgument([&] { makeScene("particles", bad); }, {"camera eye (1.0", "target (1.0"});
    bad.camera = SceneCamera{{0, 5, 0}, {0, 0, 0}};
    expectInvalidArgument([&] { makeScene("fog", bad); }, {"one above the other"});
}

// ---- The viewer, headless ------------------------------------------------------------------------------

class ViewerTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        dir_ = std::filesystem::temp_directory_path() /
               ("raster_viewer_test_" + name + "_" + std::to_string(getpid()));
        std::filesystem::remove_all(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    ViewerOptions options(const std::string& script, const std::string& scene = "particles") const {
        ViewerOptions o;
        o.scene = scene;
        o.sceneOptions = {.width = kWidth, .height = kHeight, .count = kParticles, .cubes = 4};
        o.headless = true;
        o.script = parseScript(script);
        o.screenshotDir = dir_.string();
        return o;
    }

    // Runs the script headless; returns the viewer's screenshots, decoded.
    std::vector<ImageRgba8> run(const std::string& script, const std::string& scene = "particles") {
        Viewer viewer(options(script, scene));
        viewer.run();
        last_messages_ = viewer.messages();
        if (viewer.shownFrame()) last_log_ = viewer.shownFrame()->drawLog;
        last_camera_ = viewer.camera();
        std::vector<ImageRgba8> shots;
        for (const std::string& path : viewer.screenshots()) shots.push_back(readImageRgba8(path));
        last_paths_ = viewer.screenshots();
        return shots;
    }

    // The scene rendered straight through the library.
    static RenderTarget direct(const Context::StepLimit& limit, const std::string& scene = "particles",
                               std::optional<SceneCamera> camera = std::nullopt, uint32_t width = kWidth,
                               uint32_t height = kHeight) {
        SceneOptions o{.width = width, .height = height, .count = kParticles, .cubes = 4};
        o.camera = camera;
        Context ctx;
        ctx.setStepLimit(limit);
        RenderTarget color(width, height);
        DepthTarget depth(width, height);
        makeScene(scene, o)->render(ctx, color, depth);
        return color;
    }

    static void expectSameImage(const ImageRgba8& shot, const RenderTarget& expected,
                                const std::string& what) {
        ASSERT_EQ(shot.width, expected.width()) << what;
        ASSERT_EQ(shot.height, expected.height()) << what;
        EXPECT_TRUE(shot.pixels == expected.toRgba8()) << what << ": the screenshot is not the framebuffer";
    }

    std::filesystem::path dir_;
    std::vector<std::string> last_messages_, last_paths_;
    std::vector<PipelineStatistics> last_log_;
    SceneCamera last_camera_{};
};

std::vector<char> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_F(ViewerTest, WholeFrameScreenshotIsTheFramebuffer) {
    for (const std::string scene : {"particles", "fog"}) {
        const std::vector<ImageRgba8> shots = run("0 S", scene);
        ASSERT_EQ(shots.size(), 1u) << scene;
        const RenderTarget expected = direct({}, scene);
        expectSameImage(shots[0], expected, scene);
        // Byte for byte the file RenderTarget::savePng writes: no overlay, no conversion.
        const std::string reference = (dir_ / (scene + "-direct.png")).string();
        expected.savePng(reference);
        EXPECT_EQ(fileBytes(last_paths_[0]), fileBytes(reference)) << scene;
        EXPECT_NE(last_paths_[0].find(scene + "-0001.png"), std::string::npos) << last_paths_[0];
    }
}

TEST_F(ViewerTest, ScreenshotsAreNumberedWithoutOverwriting) {
    run("S S");
    ASSERT_EQ(last_paths_.size(), 2u);
    EXPECT_EQ(std::filesystem::path(last_paths_[0]).filename(), "particles-0001.png");
    EXPECT_EQ(std::filesystem::path(last_paths_[1]).filename(), "particles-0002.png");
    run("S");
    ASSERT_EQ(last_paths_.size(), 1u);
    EXPECT_EQ(std::filesystem::path(last_paths_[0]).filename(), "particles-0003.png")
        << "an earlier run's shots stay";
    bool printed = false;
    for (const std::string& m : last_messages_)
        printed = printed || m.find("screenshot " + last_paths_[0]) == 0;
    EXPECT_TRUE(printed) << "the path is printed";
}

TEST_F(ViewerTest, NextDrawIsStepLimitOne) {
    const std::vector<ImageRgba8> shots = run("N S");
    ASSERT_EQ(shots.size(), 1u);
    expectSameImage(shots[0], direct({1}), "N");
    EXPECT_FALSE(shots[0].pixels == direct({}).toRgba8()) << "draw 1 alone must differ from the whole frame";
    ASSERT_EQ(last_log_.size(), 2u) << "the log has an entry per draw, skipped ones too";
    EXPECT_GT(last_log_[0].psInvocations, 0u) << "the occluder ran";
    EXPECT_EQ(last_log_[1], PipelineStatistics{}) << "the particles were skipped";
}

TEST_F(ViewerTest, ForwardTwiceBackOnceIsForwardOnce) {
    const std::vector<ImageRgba8> shots = run("N N P S N S P S");
    ASSERT_EQ(shots.size(), 3u);
    const RenderTarget one = direct({1});
    expectSameImage(shots[0], one, "N N P");
    expectSameImage(shots[1], direct({2}), "N N P N");
    expectSameImage(shots[2], one, "N N P N P");
    const std::vector<ImageRgba8> fog = run("N N P S", "fog");
    ASSERT_EQ(fog.size(), 1u);
    expectSameImage(fog[0], direct({1}, "fog"), "fog N N P");
}

TEST_F(ViewerTest, PrimitiveStepsWithinADraw) {
    // Forwards to the 40th particle and back to the 30th must be the 30th reached forwards.
    std::string forward = "N", back;
    for (int i = 0; i < 40; ++i) forward += " ]";
    for (int i = 0; i < 10; ++i) back += " [";
    const std::vector<ImageRgba8> a = run(forward + back + " S");
    const std::vector<PipelineStatistics> log_a = last_log_;
    std::string thirty = "N";
    for (int i = 0; i < 30; ++i) thirty += " ]";
    const std::vector<ImageRgba8> b = run(thirty + " S");
    ASSERT_EQ(a.size(), 1u);
    ASSERT_EQ(b.size(), 1u);
    const RenderTarget expected = direct({2, 30});
    expectSameImage(a[0], expected, "N, 40 ], 10 [");
    expectSameImage(b[0], expected, "N, 30 ]");
    EXPECT_FALSE(expected == direct({2, 29})) << "one particle more must show";
    // The statistics are those of the shown step: 30 particles of the second draw went through the GS.
    ASSERT_EQ(log_a.size(), 2u);
    EXPECT_EQ(log_a[1].gsInvocations, 30u);
    EXPECT_EQ(log_a[1].gsPrimitives, 60u);
    EXPECT_EQ(log_a[1].iaPrimitives, kParticles) << "the draw's input, whatever the limit";
    EXPECT_TRUE(log_a == last_log_);
    run("N ] ]");
    ASSERT_EQ(last_log_.size(), 2u);
    EXPECT_EQ(last_log_[1].gsInvocations, 2u);
    // "]" from the end of draw 1 is the first particle; "[" from the whole frame is all but the last.
    const std::vector<ImageRgba8> c = run("N ] S 0 [ S");
    ASSERT_EQ(c.size(), 2u);
    expectSameImage(c[0], direct({2, 1}), "N ]");
    expectSameImage(c[1], direct({2, kParticles - 1}), "0 [");
}

TEST_F(ViewerTest, ClickPrintsColourAndDepth) {
    run("N click:160,90 ] ] click:160,90 click:5,5 click:400,10");
    const auto line = [&](const Context::StepLimit& limit, uint32_t x, uint32_t y) {
        Context ctx;
        ctx.setStepLimit(limit);
        RenderTarget color(kWidth, kHeight);
        DepthTarget depth(kWidth, kHeight);
        makeScene("particles", {.width = kWidth, .height = kHeight, .count = kParticles})
            ->render(ctx, color, depth);
        const uint8_t* p = color.rgba8() + 4 * (size_t(y) * kWidth + x);
        char text[160];
        std::snprintf(text, sizeof text, "pixel %u,%u: rgba %d %d %d %d, depth %.7g", x, y, p[0], p[1], p[2],
                      p[3], double(depth.load(x, y)));
        return std::string(text);
    };
    std::vector<std::string> clicks;
    for (const std::string& m : last_messages_)
        if (m.starts_with("pixel ") || m.starts_with("click ")) clicks.push_back(m);
    ASSERT_EQ(clicks.size(), 4u);
    EXPECT_EQ(clicks[0], line({1}, 160, 90));
    EXPECT_NE(clicks[0].find("rgba 89 140 64 255"), std::string::npos) << "the occluder: " << clicks[0];
    EXPECT_EQ(clicks[1], line({2, 2}, 160, 90));
    EXPECT_NE(clicks[0], clicks[1]) << "particle 0 sits in front of the occluder's centre";
    EXPECT_EQ(clicks[2], line({2, 2}, 5, 5));
    EXPECT_EQ(clicks[3], "click 400,10: outside the framebuffer");
}

TEST_F(ViewerTest, DepthViewShowsDepthAsGrey) {
    const std::vector<ImageRgba8> shots = run("D S D S");
    ASSERT_EQ(shots.size(), 2u);
    expectSameImage(shots[1], direct({}), "D D");
    const auto grey = [&](uint32_t x, uint32_t y) {
        const uint8_t* p = &shots[0].pixels[4 * (size_t(y) * kWidth + x)];
        EXPECT_EQ(p[0], p[1]);
        EXPECT_EQ(p[0], p[2]);
        return int(p[0]);
    };
    EXPECT_EQ(grey(2, 2), 255) << "cleared depth is white";
    EXPECT_LE(grey(160, 90), 224) << "the occluder is drawn depth, darker than the clear";
    // The occluder leans away from the eye above it: its top is nearer, so darker, than its bottom.
    EXPECT_LT(grey(160, 80), grey(160, 130));
}

TEST_F(ViewerTest, CameraOrbitsZoomsFliesAndResets) {
    const SceneCamera start = defaultCamera("particles");
    const std::vector<ImageRgba8> shots = run("drag:100,90,140,80 S wheel:2 S R S w shift+D e S");
    ASSERT_EQ(shots.size(), 4u);
    const SceneCamera orbited = orbit(start, 40, -10);
    expectSameImage(shots[0], direct({}, "particles", orbited), "after the drag");
    expectSameImage(shots[1], direct({}, "particles", zoom(orbited, 2)), "after the wheel");
    expectSameImage(shots[2], direct({}), "R resets to the scene's own camera");
    const SceneCamera flown = fly(fly(fly(start, 1, 0, 0), 0, 1, 0), 0, 0, 1);
    expectSameImage(shots[3], direct({}, "particles", flown), "after flying");
    EXPECT_EQ(last_camera_.eye, flown.eye);
    EXPECT_EQ(last_camera_.target, flown.target);
    EXPECT_FALSE(shots[0].pixels == shots[2].pixels);
}

TEST_F(ViewerTest, ResizeRendersAtTheWindowsSize) {
    const std::vector<ImageRgba8> shots = run("N resize:200x100 S");
    ASSERT_EQ(shots.size(), 1u);
    expectSameImage(shots[0], direct({1}, "particles", std::nullopt, 200, 100), "200x100");
}

}  // namespace
}  // namespace raster::tools
