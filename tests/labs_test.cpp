// The labs (labs/, solutions/, raster/lab.hpp): each registers a scene and its solution; the student's
// file draws a wrong picture as handed out, and the solution draws the lecture's.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>

#include "raster/lab.hpp"

namespace raster {
namespace {

RenderTarget renderScene(const std::string& name, const SceneOptions& options) {
    Context context;
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    makeScene(name, options)->render(context, color, depth);
    return color;
}

size_t differingPixels(const RenderTarget& a, const RenderTarget& b) {
    size_t n = 0;
    for (size_t i = 0; i < size_t(a.width()) * a.height(); ++i)
        n += !std::equal(a.rgba8() + 4 * i, a.rgba8() + 4 * i + 4, b.rgba8() + 4 * i);
    return n;
}

void expectInvalidArgument(const auto& f, const std::string& part) {
    try {
        f();
        ADD_FAILURE() << "no error; expected one naming '" << part << "'";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what() << " lacks " << part;
    }
}

TEST(Labs, BillboardsIsRegisteredWithItsSolution) {
    const std::vector<std::string> names = sceneNames();
    EXPECT_EQ(names[0], "fire");
    EXPECT_EQ(names[1], "particles");
    EXPECT_EQ(names[2], "fog");
    EXPECT_NE(std::find(names.begin(), names.end(), "billboards"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "billboards@solution"), names.end());
    EXPECT_EQ(solutionSceneOf("billboards"), "billboards@solution");
    EXPECT_EQ(solutionSceneOf("billboards@solution"), "") << "a solution has no solution of its own";
    EXPECT_EQ(solutionSceneOf("particles"), "");
    EXPECT_EQ(solutionSceneOf("smoke"), "");
    const SceneCamera lab = defaultCamera("billboards"), lecture = defaultCamera("particles");
    EXPECT_EQ(lab.eye, lecture.eye);
    EXPECT_EQ(lab.target, lecture.target);
    ASSERT_NE(findRegisteredScene("billboards"), nullptr);
    EXPECT_NE(findRegisteredScene("billboards")->title.find("billboards"), std::string::npos);
    EXPECT_EQ(findRegisteredScene("particles"), nullptr) << "the lecture's own scenes are not registered";
    for (const char* name : {"billboards", "billboards@solution"})
        EXPECT_EQ(makeScene(name, {.width = 8, .height = 8, .count = 1})->name(), name);
}

// The solution is the lecture's particle scene of SCENES.md written as a lab (a scalar pixel shader
// where the scene's is eight wide): bit for bit the same image, at the benchmark's camera and another.
TEST(Labs, BillboardsSolutionDrawsTheLecturesParticles) {
    SceneOptions o{.width = 320, .height = 180, .count = 3000};
    const RenderTarget solution = renderScene("billboards@solution", o);
    EXPECT_EQ(differingPixels(solution, renderScene("particles", o)), 0u);
    o.camera = SceneCamera{{2.5f, 1.0f, 2.5f}, {0, -0.2f, 0}};
    EXPECT_EQ(differingPixels(renderScene("billboards@solution", o), renderScene("particles", o)), 0u);
    // Not trivially so: the particles are there (the image is not the occluder's alone).
    o.camera.reset();
    EXPECT_GT(differingPixels(solution, renderScene("particles", {.width = 320, .height = 180, .count = 0})),
              size_t(320 * 180 / 10));
}

// As handed out the lab draws the occluder and none of the particles (its geometry shader emits
// strips of no area). Skipped once a student has started on the file: this checks the hand-out.
TEST(Labs, BillboardsAsHandedOutDrawsOnlyTheOccluder) {
    std::ifstream in(std::string(RASTER_SOURCE_DIR) + "/labs/billboards/billboards.cpp");
    ASSERT_TRUE(in) << "labs/billboards/billboards.cpp is missing";
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    for (const char* start :
         {"stream.Append({c, {1, 0}});", "return {1.0f, 0.5f, 0.1f, 1.0f};",
          "    BlendState blend;\n    return blend;", "    DepthStencilState depth;\n    return depth;"})
        if (text.find(start) == std::string::npos)
            GTEST_SKIP() << "the lab has been edited (no '" << start << "')";
    const SceneOptions o{.width = 320, .height = 180, .count = 3000};
    const RenderTarget lab = renderScene("billboards", o);
    EXPECT_EQ(differingPixels(lab, renderScene("particles", {.width = 320, .height = 180, .count = 0})), 0u);
    EXPECT_GT(differingPixels(lab, renderScene("billboards@solution", o)), size_t(320 * 180 / 10))
        << "the picture a student starts from must be visibly wrong";
}

TEST(SceneRegistry, RefusesBadEntriesAndServesGoodOnes) {
    const auto make = [](const std::string& name, const SceneOptions& o) -> std::unique_ptr<Scene> {
        struct Empty final : LabScene {
            void render(Context& context, RenderTarget& color, DepthTarget&) override {
                context.clearRenderTarget(color, {0.25f, 0.5f, 0.75f, 1});
            }
        };
        (void)o;
        auto scene = std::make_unique<Empty>();
        scene->setName(name);
        return scene;
    };
    expectInvalidArgument([&] { registerScene({"", "t", {}, make}); }, "1..64 characters");
    expectInvalidArgument([&] { registerScene({"Lab One", "t", {}, make}); }, "'Lab One' may hold only");
    expectInvalidArgument(
        [&] {
            registerScene({"billboards", "t", {}, make});
        },
        "'billboards' is registered twice");
    expectInvalidArgument([&] { registerScene({"fog", "t", {}, make}); }, "'fog' is registered twice");
    expectInvalidArgument([&] { registerScene({"no-factory", "t", {}, nullptr}); }, "without a factory");
    EXPECT_EQ(findRegisteredScene("no-factory"), nullptr) << "a refused entry is not kept";

    const SceneCamera camera{{1, 2, 3}, {0, 0, 0}};
    registerScene({"registry-test", "a test scene", camera, make});
    EXPECT_EQ(defaultCamera("registry-test").eye, camera.eye);
    const RenderTarget image = renderScene("registry-test", {.width = 4, .height = 2});
    EXPECT_EQ(image.rgba8()[0], 64);  // 0.25 * 255 = 63.75
    EXPECT_EQ(image.rgba8()[2], 191);
    expectInvalidArgument([&] { makeScene("registry-test", {.width = 0, .height = 2}); }, "0x2");
    expectInvalidArgument([&] { makeScene("smoke", {}); }, "billboards");  // the error lists the labs
}

}  // namespace
}  // namespace raster
