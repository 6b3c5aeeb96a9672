// The benchmark scenes of ../shared/bench/SCENES.md: the fire texture, the particle sequence, scene
// construction, what the particles scene draws, and the fog medium's optical depth.
#include "raster/scenes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "raster/check.hpp"
#include "raster/shaders/fog.hpp"
#include "test_paths.hpp"

namespace raster {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// ---- The fire texture --------------------------------------------------------------------------------

std::array<int, 4> texelBytes(const Texture2D& t, int x, int y) {
    const glm::vec4 c = t.load(x, y);
    return {int(std::lround(c.r * 255.0f)), int(std::lround(c.g * 255.0f)), int(std::lround(c.b * 255.0f)),
            int(std::lround(c.a * 255.0f))};
}

TEST(Scenes, FireTextureMatchesTheFormula) {
    const Texture2D fire = makeFireTexture();
    ASSERT_EQ(fire.width(), 64u);
    ASSERT_EQ(fire.height(), 64u);
    EXPECT_EQ(fire.mipLevels(), 1u);
    EXPECT_EQ(fire.format(), Format::R8G8B8A8_UNORM);
    // By hand: texel (0, 0) is outside the disc (s = 0): (255, 63.75, 12.75, 0) → (255, 64, 13, 0).
    EXPECT_EQ(texelBytes(fire, 0, 0), (std::array<int, 4>{255, 64, 13, 0}));
    // Texel (31, 31): r = 2·hypot(1/128, 1/128) = 0.0220971, s = 0.9562939:
    // (255, 197.87, 49.33, 60.96) → (255, 198, 49, 61).
    EXPECT_EQ(texelBytes(fire, 31, 31), (std::array<int, 4>{255, 198, 49, 61}));
    // Every texel, from SCENES.md's formula.
    for (int j = 0; j < 64; ++j) {
        for (int i = 0; i < 64; ++i) {
            const double u = (i + 0.5) / 64, v = (j + 0.5) / 64;
            const double r = 2 * std::sqrt((u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5));
            const double s = std::clamp(1 - r, 0.0, 1.0) * std::clamp(1 - r, 0.0, 1.0);
            const double rgba[4] = {1, 0.25 + 0.55 * s, 0.05 + 0.15 * s, 0.25 * s};
            std::array<int, 4> expected;
            for (int c = 0; c < 4; ++c) expected[c] = int(std::floor(255 * rgba[c] + 0.5));
            ASSERT_EQ(texelBytes(fire, i, j), expected) << "texel " << i << "," << j;
        }
    }
    // Symmetric about the centre.
    EXPECT_EQ(texelBytes(fire, 10, 20), texelBytes(fire, 53, 43));
    EXPECT_EQ(texelBytes(fire, 10, 20), texelBytes(fire, 20, 10));
}

TEST(Scenes, FireTextureEqualsSharedPngByteForByte) {
    const std::string path = test::sharedDir() + "/bench/fire.png";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " does not exist";
    const Texture2D png = Texture2D::fromPng(path);
    const Texture2D fire = makeFireTexture();
    ASSERT_EQ(png.width(), 64u);
    ASSERT_EQ(png.height(), 64u);
    int differing = 0;
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) differing += texelBytes(png, i, j) != texelBytes(fire, i, j);
    EXPECT_EQ(differing, 0) << "texels of fire.png that differ from makeFireTexture()";
    EXPECT_TRUE(png == fire);
}

// ---- The particle sequence ---------------------------------------------------------------------------

TEST(Scenes, ParticlePositionFollowsTheR3Sequence) {
    // c_k = frac(0.5 + i·a_k), a = (0.8191725133961645, 0.6710436067037894, 0.5497004779019704),
    // position = ((2c1 − 1)·1.5, (2c2 − 1)·1.0, (2c3 − 1)·1.5).
    EXPECT_EQ(particlePosition(0), glm::vec3(0.0f));  // c = (0.5, 0.5, 0.5)
    // i = 1: c = (0.3191725133961645, 0.1710436067037894, 0.0497004779019704).
    const glm::vec3 p1 = particlePosition(1);
    EXPECT_FLOAT_EQ(p1.x, float(-0.5424824598115065));
    EXPECT_FLOAT_EQ(p1.y, float(-0.6579127865924212));
    EXPECT_FLOAT_EQ(p1.z, float(-1.3508985662940888));
    // i = 2: c = (0.138345026792329, 0.8420872134075788, 0.5994009558039408).
    const glm::vec3 p2 = particlePosition(2);
    EXPECT_FLOAT_EQ(p2.x, float(-1.084964919623013));
    EXPECT_FLOAT_EQ(p2.y, float(0.6841744268151576));
    EXPECT_FLOAT_EQ(p2.z, float(0.2982028674118224));
    // i = 7: 0.5 + 7·a = (6.2342075937731515, 5.197305246926526, 4.347903345313793).
    const glm::vec3 p7 = particlePosition(7);
    EXPECT_FLOAT_EQ(p7.x, float(-0.7973772186805455));
    EXPECT_FLOAT_EQ(p7.y, float(-0.605389506146948));
    EXPECT_FLOAT_EQ(p7.z, float(-0.456289964058621));
    // All inside the box, and no two of the first thousand alike.
    std::vector<glm::vec3> seen;
    for (uint32_t i = 0; i < 1000; ++i) {
        const glm::vec3 p = particlePosition(i);
        EXPECT_LE(std::abs(p.x), 1.5f);
        EXPECT_LE(std::abs(p.y), 1.0f);
        EXPECT_LE(std::abs(p.z), 1.5f);
        seen.push_back(p);
    }
    std::sort(seen.begin(), seen.end(), [](const glm::vec3& a, const glm::vec3& b) { return a.x < b.x; });
    for (size_t i = 1; i < seen.size(); ++i) EXPECT_NE(seen[i], seen[i - 1]);
}

// ---- Construction --------------------------------------------------------------------------------------

void expectInvalidArgument(const std::function<void()>& f, const std::string& part) {
    try {
        f();
        ADD_FAILURE() << "expected Error(InvalidArgument)";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what() << " lacks " << part;
    }
}

TEST(Scenes, MakeSceneRefusesBadArguments) {
    expectInvalidArgument([] { makeScene("smog", {}); }, "smog");
    expectInvalidArgument([] { makeScene("", {}); }, "unknown scene");
    expectInvalidArgument([] { makeScene("particles", {.width = 0, .height = 720}); }, "0x720");
    expectInvalidArgument([] { makeScene("fog", {.width = 1280, .height = 0}); }, "1280x0");
    expectInvalidArgument([] { makeScene("fog", {.width = RenderTarget::kMaxSize + 1, .height = 4}); }, "16385");
    expectInvalidArgument([] { makeScene("fog", {.width = 8, .height = 8, .cubes = 1025}); }, "1025");
    const std::vector<std::string> names = sceneNames();
    EXPECT_NE(std::find(names.begin(), names.end(), "particles"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "fog"), names.end());
    for (const std::string& n : names) EXPECT_EQ(makeScene(n, {.width = 8, .height = 8, .count = 1, .cubes = 1})->name(), n);
}

// ---- The particles scene ------------------------------------------------------------------------------

struct Image {
    RenderTarget color;
    DepthTarget depth;
};

Image renderParticles(uint32_t count) {
    auto scene = makeScene("particles", {.width = 320, .height = 180, .count = count});
    Context ctx;
    Image im{RenderTarget(320, 180), DepthTarget(320, 180)};
    scene->render(ctx, im.color, im.depth);
    return im;
}

std::array<int, 4> pixelBytes(const RenderTarget& t, uint32_t x, uint32_t y) {
    const uint8_t* p = t.rgba8() + 4 * (size_t(y) * t.width() + x);
    return {p[0], p[1], p[2], p[3]};
}

TEST(Scenes, ParticlesWithoutParticlesShowOnlyTheOccluder) {
    const Image im = renderParticles(0);
    EXPECT_EQ(pixelBytes(im.color, 160, 90), (std::array<int, 4>{89, 140, 64, 255}));
    EXPECT_EQ(pixelBytes(im.color, 0, 0), (std::array<int, 4>{0, 0, 0, 255}));
    EXPECT_EQ(pixelBytes(im.color, 319, 179), (std::array<int, 4>{0, 0, 0, 255}));
    // Only those two colours anywhere; the occluder's depth where it is, 1 elsewhere.
    int occluder = 0;
    for (uint32_t y = 0; y < 180; ++y) {
        for (uint32_t x = 0; x < 320; ++x) {
            const auto c = pixelBytes(im.color, x, y);
            const bool isOccluder = c == std::array<int, 4>{89, 140, 64, 255};
            ASSERT_TRUE(isOccluder || c == (std::array<int, 4>{0, 0, 0, 255})) << x << "," << y;
            occluder += isOccluder;
            if (isOccluder) {
                EXPECT_LT(im.depth.load(x, y), 1.0f);
            } else {
                EXPECT_EQ(im.depth.load(x, y), 1.0f);
            }
        }
    }
    // The occluder is 1.2 × 1.6 world units at distance ~4 in a 60° view: a few thousand pixels.
    EXPECT_GT(occluder, 2000);
    EXPECT_LT(occluder, 320 * 180 / 2);
}

TEST(Scenes, ParticlesOnlyAddLight) {
    const Image base = renderParticles(0);
    const Image lit = renderParticles(2000);
    const auto centre = pixelBytes(lit.color, 160, 90);
    EXPECT_GE(centre[0], 89);
    EXPECT_GE(centre[1], 140);
    EXPECT_GE(centre[2], 64);
    EXPECT_GT(centre[0] + centre[1] + centre[2], 89 + 140 + 64) << "the centre should be brighter than the occluder";
    int brighter = 0;
    for (uint32_t y = 0; y < 180; ++y) {
        for (uint32_t x = 0; x < 320; ++x) {
            const auto a = pixelBytes(base.color, x, y), b = pixelBytes(lit.color, x, y);
            for (int c = 0; c < 4; ++c) ASSERT_GE(b[c], a[c]) << "pixel " << x << "," << y << " channel " << c;
            brighter += a != b;
        }
    }
    EXPECT_GT(brighter, 320 * 180 / 10);
    // Particles never write depth.
    EXPECT_TRUE(base.depth == lit.depth);
}

TEST(Scenes, ConstantFogSkyIsTheFogColour) {
    auto scene = makeScene("fog", {.width = 160, .height = 90, .cubes = 2, .heightFog = false});
    Context ctx;
    RenderTarget color(160, 90);
    DepthTarget depth(160, 90);
    scene->render(ctx, color, depth);
    // q/σ = (0.6, 0.65, 0.75) → (153, 165.75 → 166, 191.25 → 191).
    EXPECT_EQ(pixelBytes(color, 80, 0), (std::array<int, 4>{153, 166, 191, 255}));
    EXPECT_EQ(depth.load(80, 0), 1.0f);
}

// The benchmark scenes' pixel shaders name the states they are drawn with (specialised_states.hpp),
// so that each file compiles only those tile loops: every draw of theirs must still take a
// specialised loop, or the scene would silently run the generic one (the same image, slower).
TEST(Scenes, BenchmarkScenesDrawEveryDrawSpecialised) {
    for (const std::string name : {"particles", "fog", "fog-constant", "fire", "media"}) {
        auto scene = makeScene(name, {.width = 160, .height = 90, .count = 200, .cubes = 2});
        Context ctx;
        RenderTarget color(160, 90);
        DepthTarget depth(160, 90);
        ctx.resetFrameStatistics();
        scene->render(ctx, color, depth);
        const auto& log = ctx.drawStatisticsLog();
        ASSERT_FALSE(log.empty()) << name;
        for (size_t d = 0; d < log.size(); ++d)
            EXPECT_EQ(log[d].drawsSpecialised, 1u) << name << ", draw " << d << " took the generic tile loop";
        // The same draws traced, or on the plain path, read the state per fragment.
        Context plain(ContextOptions{.plain = true});
        plain.resetFrameStatistics();
        scene->render(plain, color, depth);
        for (const PipelineStatistics& s : plain.drawStatisticsLog()) EXPECT_EQ(s.drawsSpecialised, 0u) << name;
    }
}

// ---- The lecture's fog figures and part 1's closed form -----------------------------------------------

RenderTarget renderFigure(const std::string& name, SceneOptions o) {
    auto scene = makeScene(name, o);
    Context ctx;
    RenderTarget color(o.width, o.height);
    DepthTarget depth(o.width, o.height);
    scene->render(ctx, color, depth);
    return color;
}

void expectNear(const std::array<int, 4>& pixel, const std::array<int, 3>& rgb, int tolerance, const char* what) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(pixel[c], rgb[c], tolerance) << what << ", channel " << c;
}

// The sky at infinite distance: the fog's colour q/σ (constant, coloured), black without a source
// (black fog), darker overhead than at the horizon in fog that thins upward (height).
TEST(FogFigures, EachSkyIsTheFiguresLimitAtInfiniteDistance) {
    const SceneOptions o{.width = 160, .height = 90, .cubes = 4};
    const RenderTarget constant = renderFigure("fog-constant", o), black = renderFigure("fog-black", o);
    const RenderTarget coloured = renderFigure("fog-coloured", o), height = renderFigure("fog-height", o);
    expectNear(pixelBytes(constant, 80, 0), {153, 166, 191}, 1, "constant fog: q/sigma = (0.6, 0.65, 0.75)");
    expectNear(pixelBytes(coloured, 80, 0), {217, 140, 64}, 1, "coloured fog: (0.85, 0.55, 0.25)");
    for (uint32_t x = 0; x < 160; ++x) EXPECT_EQ(pixelBytes(black, x, 0), (std::array<int, 4>{0, 0, 0, 255}));
    const std::array<int, 4> zenith = pixelBytes(height, 80, 0), horizon = pixelBytes(height, 80, 30);
    EXPECT_LT(zenith[2] + 40, horizon[2]) << "height fog thins upward: less of it overhead";
    // Coloured fog hides the background: the farther half of the lattice is within 6 steps of the sky.
    int hidden = 0, row = 0;
    for (uint32_t y = 0; y < 90; ++y) {
        const std::array<int, 4> p = pixelBytes(coloured, 80, y);
        if (std::abs(p[0] - 217) + std::abs(p[1] - 140) + std::abs(p[2] - 64) <= 6) hidden += 1, row = int(y);
    }
    EXPECT_GT(row, 30) << "the fog's colour reaches below the horizon: the far ground is hidden";
    EXPECT_GT(hidden, 30);
}

TEST(FogFigures, TheOptionsReplaceTheMediumAndUnsetLeaveTheBenchmarkAsItWas) {
    SceneOptions clear{.width = 160, .height = 90, .cubes = 4};
    clear.fogSigma = glm::vec3(0.0f), clear.fogSource = glm::vec3(0.0f);
    const RenderTarget none = renderFigure("fog-constant", clear);
    EXPECT_EQ(pixelBytes(none, 80, 0), (std::array<int, 4>{0, 0, 0, 255})) << "no medium: the sky is black";
    // The benchmark's own medium given explicitly draws the same bits as none given.
    const shaders::FogMedium own;
    SceneOptions explicit_medium{.width = 160, .height = 90, .cubes = 4};
    explicit_medium.fogSigma = own.sigma, explicit_medium.fogSource = own.q, explicit_medium.fogFalloff = -own.b;
    EXPECT_TRUE(renderFigure("fog", explicit_medium) == renderFigure("fog", {.width = 160, .height = 90, .cubes = 4}));
    // A channel without extinction but with a source: its sky is q·∞, white, and finite elsewhere.
    SceneOptions green{.width = 160, .height = 90, .cubes = 4};
    green.fogSigma = glm::vec3(0.05f, 0.0f, 0.07f), green.fogSource = glm::vec3(0.03f, 0.004f, 0.05f);
    const RenderTarget g = renderFigure("fog-height", green);
    EXPECT_EQ(pixelBytes(g, 80, 40)[1] > 0, true);
    EXPECT_EQ(pixelBytes(renderFigure("fog-constant", green), 80, 0)[1], 255);
}

TEST(FogFigures, MakeSceneNamesABadMedium) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (const char* name : {"fog", "fog-height", "media-closed-form"}) {
        SceneOptions o{.width = 8, .height = 8, .cubes = 1};
        o.fogSigma = glm::vec3(0.1f, -1.0f, 0.1f);
        expectInvalidArgument([&] { makeScene(name, o); }, "fog sigma G: -1 is negative");
        o.fogSigma = glm::vec3(nan, 0.1f, 0.1f);
        expectInvalidArgument([&] { makeScene(name, o); }, "fog sigma R: nan is not a number");
        o.fogSigma.reset();
        o.fogSource = glm::vec3(0.1f, 0.1f, kInf);
        expectInvalidArgument([&] { makeScene(name, o); }, "fog source B: inf is infinite");
        o.fogSource.reset();
        o.fogFalloff = -0.5f;
        expectInvalidArgument([&] { makeScene(name, o); }, "fog falloff: -0.5 is negative");
        o.fogFalloff.reset();
        o.fogSigma = glm::vec3(1e-40f, 0.1f, 0.1f), o.fogSource = glm::vec3(1.0f);
        expectInvalidArgument([&] { makeScene(name, o); }, "is not a finite float");
    }
    EXPECT_EQ(fogValueProblem(1e39), "1e+39 is too large for a float");
    EXPECT_EQ(fogValueProblem(0.0), "");
}

// Three panels of the same world and box: absorption only darkens what is behind the box, emission
// only brightens it, both tend to the medium's colour q/μ; outside the box the panels are the same.
TEST(MediaClosedForm, AbsorptionDarkensEmissionBrightensBothTendToTheColour) {
    const SceneOptions o{.width = 480, .height = 270, .cubes = 4};
    const RenderTarget image = renderFigure("media-closed-form", o);
    const auto sum = [&](uint32_t panel, uint32_t x, uint32_t y) {
        const std::array<int, 4> p = pixelBytes(image, 160 * panel + x, y);
        return p[0] + p[1] + p[2];
    };
    // The box's middle (the default camera looks at its centre) and a corner of the sky.
    EXPECT_LT(sum(0, 80, 150), sum(1, 80, 150) - 150);
    EXPECT_EQ(sum(0, 2, 2), sum(1, 2, 2));
    EXPECT_EQ(sum(1, 2, 2), sum(2, 2, 2));
    EXPECT_NE(sum(2, 80, 150), sum(0, 80, 150));
    SceneOptions clear = o;
    clear.fogSigma = glm::vec3(0.0f), clear.fogSource = glm::vec3(0.0f);
    const RenderTarget world = renderFigure("media-closed-form", clear);
    const std::array<int, 4> behind = pixelBytes(world, 80, 150);
    EXPECT_LT(sum(0, 80, 150), behind[0] + behind[1] + behind[2] - 100) << "absorption takes light away";
    EXPECT_GT(sum(1, 80, 150), behind[0] + behind[1] + behind[2] + 100) << "emission adds light";
    EXPECT_TRUE(pixelBytes(world, 80, 150) == pixelBytes(world, 160 + 80, 150)) << "no medium: the panels agree";
}

// ---- The fog medium -----------------------------------------------------------------------------------

// τ(s) = ∫0^s e^{b(y0 + dy·t)} dt by the midpoint rule with 10^5 steps, in double.
double bruteForceOpticalDepth(double b, double y0, double dy, double s) {
    constexpr int kSteps = 100000;
    const double h = s / kSteps;
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) sum += std::exp(b * (y0 + dy * (i + 0.5) * h));
    return sum * h;
}

TEST(FogMedium, HorizontalRayIsFiniteAndExact) {
    shaders::FogMedium fog;
    for (const float y0 : {0.0f, 1.5f, 4.0f}) {
        for (const float s : {0.5f, 10.0f, 300.0f}) {
            const double expected = std::exp(double(fog.b) * y0) * s;
            for (const float dy : {0.0f, -0.0f, 1e-9f, -1e-9f}) {
                const float tau = fog.opticalDepth(y0, dy, s);
                ASSERT_TRUE(std::isfinite(tau)) << "dy = " << dy;
                EXPECT_NEAR(tau / expected, 1.0, 1e-6) << "y0 = " << y0 << ", s = " << s << ", dy = " << dy;
            }
        }
    }
}

TEST(FogMedium, AgreesWithNumericalIntegration) {
    shaders::FogMedium fog;
    for (const float y0 : {0.2f, 1.5f, 5.0f}) {
        for (const float dy : {-0.95f, -0.3f, -0.01f, -2e-4f, 1e-4f, 0.05f, 0.5f, 0.99f}) {
            for (const float s : {3.0f, 20.0f}) {
                const double exact = bruteForceOpticalDepth(fog.b, y0, dy, s);
                const float tau = fog.opticalDepth(y0, dy, s);
                EXPECT_NEAR(tau / exact, 1.0, 1e-4) << "y0 = " << y0 << ", dy = " << dy << ", s = " << s;
            }
        }
    }
    // Either side of the series threshold |k·s| = 1e-4.
    for (const float ks : {0.99e-4f, 1.01e-4f, -0.99e-4f, -1.01e-4f}) {
        const float s = 10.0f, dy = ks / (fog.b * s);
        EXPECT_NEAR(fog.opticalDepth(1.0f, dy, s) / bruteForceOpticalDepth(fog.b, 1.0, dy, s), 1.0, 1e-6) << ks;
    }
}

TEST(FogMedium, InfiniteDistance) {
    shaders::FogMedium fog;
    // Looking up (dy > 0, so k = b·dy < 0) into thinning fog: τ = e^{b·y0} / (−k).
    for (const float dy : {0.1f, 0.5f, 1.0f}) {
        const float y0 = 1.5f;
        const double expected = std::exp(double(fog.b) * y0) / -(double(fog.b) * dy);
        EXPECT_NEAR(fog.opticalDepth(y0, dy, kInf) / expected, 1.0, 1e-6) << dy;
        // It is the limit of the finite integral.
        EXPECT_NEAR(fog.opticalDepth(y0, dy, kInf) / bruteForceOpticalDepth(fog.b, y0, dy, 400.0 / dy), 1.0, 1e-4);
    }
    const glm::vec3 eye(0, 1.5f, 0), L0(0.3f, 0.2f, 0.1f);
    glm::vec3 fogColour;
    for (int c = 0; c < 3; ++c) fogColour[c] = fog.q[c] / fog.sigma[c];
    EXPECT_NEAR(fogColour.r, 0.6f, 1e-6f);
    EXPECT_NEAR(fogColour.g, 0.65f, 1e-6f);
    EXPECT_NEAR(fogColour.b, 0.75f, 1e-6f);
    // Looking down or horizontally, the fog never thins: τ = ∞ and the pixel is the fog colour.
    for (const glm::vec3 dir : {glm::vec3(0, -1, 0), glm::normalize(glm::vec3(1, -0.2f, 0)), glm::vec3(1, 0, 0),
                                glm::vec3(0, 0, -1)}) {
        EXPECT_EQ(fog.opticalDepth(eye.y, dir.y, kInf), kInf);
        const glm::vec3 L = fog.apply(L0, eye, dir, kInf);
        EXPECT_EQ(L, fogColour) << dir.x << "," << dir.y << "," << dir.z;
    }
    // Looking up, some of the background shows: between L0 = 0 and the fog colour.
    const glm::vec3 up = fog.apply(glm::vec3(0), eye, glm::normalize(glm::vec3(0, 1, -1)), kInf);
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(up[c], 0.0f);
        EXPECT_LT(up[c], fogColour[c]);
    }
}

TEST(FogMedium, ConstantFog) {
    shaders::FogMedium fog;
    fog.height = false;
    const glm::vec3 eye(0, 1.5f, 6), dir(0, -0.6f, -0.8f), L0(0.3f, 0.5f, 0.9f);
    EXPECT_EQ(fog.opticalDepth(7.0f, 0.3f, 12.5f), 12.5f);
    EXPECT_EQ(fog.apply(L0, eye, dir, 0.0f), L0) << "no distance, no fog";
    glm::vec3 fogColour;
    for (int c = 0; c < 3; ++c) fogColour[c] = fog.q[c] / fog.sigma[c];
    const glm::vec3 far = fog.apply(L0, eye, dir, 1e4f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(far[c], fogColour[c], 1e-6f) << c;
    // In between: L0·T + (q/σ)(1 − T), T = e^{−σs}.
    const float s = 7.0f;
    const glm::vec3 mid = fog.apply(L0, eye, dir, s);
    for (int c = 0; c < 3; ++c) {
        const double T = std::exp(-double(fog.sigma[c]) * s);
        EXPECT_NEAR(mid[c], L0[c] * T + fogColour[c] * (1 - T), 1e-6) << c;
    }
    // Thin fog keeps its digits: in front of black, a tiny distance s adds (q/σ)(1 − e^{−σs}) ≈ q·s,
    // which 1 − e^{−σs} computed as a plain difference would round to 0 or to a multiple of 2^-24.
    const float tiny = 1e-7f;
    const glm::vec3 thin = fog.apply(glm::vec3(0.0f), eye, dir, tiny);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(thin[c] / (fog.q[c] * tiny), 1.0, 1e-5) << c;
}

}  // namespace
}  // namespace raster
