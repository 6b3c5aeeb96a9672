// The `media` scene (SCENES.md; raster/media/metaball_march.hpp, raster/shaders/media.hpp): every skip
// method gives the definition's bits ray by ray, the eight-wide density is the scalar one lane by
// lane, the scene agrees with a float64 rendering of SCENES.md's definition, and renders the same bits
// at 1, 2 and 8 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <random>
#include <vector>

#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"
#include "raster/shaders/media.hpp"
#include "scene_bytes.hpp"

using namespace raster;
using namespace raster::media;

namespace {

constexpr glm::vec3 kEye{0.0f, 0.4f, 3.0f};

MetaballVolume sceneVolume(int cells = 16) {
    return makeMetaballVolume(mediaSceneMetaballs(), mediaSceneBox(), 4.0f, cells);
}

VolumeLight sceneLight() {
    VolumeLight light;
    light.toLight = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
    light.sun = {14.0f, 13.0f, 11.0f};
    light.ambient = {0.10f, 0.12f, 0.18f};
    light.g = 0.4f;
    light.albedo = 0.9f;
    return light;
}

glm::mat4 sceneInverseViewProj(uint32_t w, uint32_t h) {
    const glm::mat4 view = glm::lookAtRH(kEye, glm::vec3(0.0f, 0.2f, 0.0f), glm::vec3(0, 1, 0));
    const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(60.0f), float(w) / float(h), 0.1f, 100.0f);
    return glm::inverse(proj * view);
}

glm::vec2 pixelNdc(uint32_t x, uint32_t y, uint32_t w, uint32_t h) {
    return {(float(x) + 0.5f) / float(w) * 2.0f - 1.0f, 1.0f - (float(y) + 0.5f) / float(h) * 2.0f};
}

bool sameBits(const MarchResult& a, const MarchResult& b) {
    return std::memcmp(&a.radiance, &b.radiance, sizeof a.radiance) == 0 &&
           std::memcmp(&a.transmittance, &b.transmittance, sizeof a.transmittance) == 0;
}

// SCENES.md's definition in double, written from the text (not from the library).
glm::dvec3 definitionPixel(const glm::dmat4& inv_vp, glm::dvec2 ndc) {
    const glm::dvec4 a = inv_vp * glm::dvec4(ndc, 0.0, 1.0), c = inv_vp * glm::dvec4(ndc, 1.0, 1.0);
    const glm::dvec3 d = glm::normalize(glm::dvec3(c) / c.w - glm::dvec3(a) / a.w), eye(kEye);
    const glm::dvec3 lo(-1.2, -0.8, -1.2), hi(1.2, 1.2, 1.2), l = glm::normalize(glm::dvec3(0.4, 1.0, 0.3));
    const auto balls = mediaSceneMetaballs();
    auto mu = [&](glm::dvec3 x) {
        double rho = 0.0;
        for (const Metaball& b : balls) {
            const glm::dvec3 v = x - glm::dvec3(b.centre);
            const double u = glm::dot(v, v) / (double(b.radius) * double(b.radius));
            if (u < 1.0) rho += (1.0 - u) * (1.0 - u);
        }
        return 4.0 * rho;
    };
    auto slab = [&](glm::dvec3 o, glm::dvec3 dir) {
        const glm::dvec3 ta = (lo - o) / dir, tb = (hi - o) / dir;
        const glm::dvec3 tmin = glm::min(ta, tb), tmax = glm::max(ta, tb);
        return glm::dvec2(std::max({tmin.x, tmin.y, tmin.z}), std::min({tmax.x, tmax.y, tmax.z}));
    };
    const glm::dvec3 background(0.08, 0.10, 0.16), sun(14, 13, 11), ambient(0.10, 0.12, 0.18);
    const glm::dvec2 t = slab(eye, d);
    const double t0 = std::max(t.x, 0.0), t1 = t.y, g = 0.4;
    glm::dvec3 L(0.0);
    double T = 1.0;
    if (t1 > t0) {
        const double cos_theta = glm::dot(d, l);
        const double phase = (1 - g * g) / (4 * M_PI * std::pow(1 + g * g - 2 * g * cos_theta, 1.5));
        const double ds = (t1 - t0) / 32;
        for (int i = 0; i < 32; ++i) {
            const glm::dvec3 x = eye + d * (t0 + (i + 0.5) * ds);
            const double m = mu(x);
            if (m <= 0.0) continue;
            const double dl = slab(x, l).y / 6;
            double tau = 0.0;
            for (int j = 0; j < 6; ++j) tau += mu(x + l * ((j + 0.5) * dl)) * dl;
            const double t_step = std::exp(-m * ds);
            L += T * 0.9 * (phase * std::exp(-tau) * sun + ambient) * (1.0 - t_step);
            T *= t_step;
        }
    }
    return glm::clamp(L + T * background, 0.0, 1.0);
}

}  // namespace

// Eight densities at once: per lane the scalar extinction's bits, inside balls, at their edges and
// outside them.
TEST(MetaballVolume, EightWideDensityIsTheScalarOneLaneByLane) {
    const MetaballVolume v = sceneVolume();
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.3f, 1.3f);
    for (int round = 0; round < 2000; ++round) {
        float xs[8], ys[8], zs[8];
        for (int l = 0; l < 8; ++l) {
            xs[l] = u(rng), ys[l] = u(rng), zs[l] = u(rng);
            if (l == 7) {  // a point on a ball's surface, where u rounds either way
                const Metaball& b = v.balls[size_t(round) % 6];
                const glm::vec3 p = b.centre + glm::normalize(glm::vec3(xs[l], ys[l], zs[l])) * b.radius;
                xs[l] = p.x, ys[l] = p.y, zs[l] = p.z;
            }
        }
        const Float8 mu = v.extinction8(Float8::load(xs), Float8::load(ys), Float8::load(zs));
        for (int l = 0; l < 8; ++l) {
            const float scalar = v.extinction({xs[l], ys[l], zs[l]}, 0x3f);
            ASSERT_EQ(std::memcmp(&scalar, &mu.v[l], 4), 0) << round << " lane " << l;
            EXPECT_EQ(scalar, 4.0f * metaballDensity(v.balls, {xs[l], ys[l], zs[l]}));
        }
    }
}

// Skipping empty space changes no bit: for the scene's view rays (a 640×360 image) and for steep,
// grazing and random rays, the ball intervals and the grid walk (4³, 16³ and 64³ cells) give the
// march that evaluates everything, and each skips most of the work.
TEST(EmptySpaceSkipping, EverySkipMethodGivesTheDefinitionsBits) {
    const uint32_t w = 640, h = 360;
    const glm::mat4 inv_vp = sceneInverseViewProj(w, h);
    const VolumeLight light = sceneLight();
    std::vector<MetaballVolume> volumes;
    for (int cells : {4, 16, 64}) volumes.push_back(sceneVolume(cells));
    uint64_t evaluations[3] = {0, 0, 0};
    size_t differing = 0;
    auto check = [&](const glm::vec3& o, const glm::vec3& d) {
        MarchSettings settings;
        settings.skip = SkipMethod::none;
        const MarchResult all = marchMetaballs(volumes[1], light, settings, o, d);
        evaluations[0] += all.densityEvaluations;
        settings.skip = SkipMethod::balls;
        const MarchResult balls = marchMetaballs(volumes[1], light, settings, o, d);
        evaluations[1] += balls.densityEvaluations;
        differing += !sameBits(all, balls);
        settings.skip = SkipMethod::grid;
        for (size_t g = 0; g < volumes.size(); ++g) {
            const MarchResult grid = marchMetaballs(volumes[g], light, settings, o, d);
            if (g == 1) evaluations[2] += grid.densityEvaluations;
            differing += !sameBits(all, grid);
        }
    };
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) check(kEye, shaders::viewRay(inv_vp, pixelNdc(x, y, w, h)));
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int r = 0; r < 20000; ++r) {
        glm::vec3 o{u(rng) * 2.5f, u(rng) * 2.0f, u(rng) * 2.5f}, d{u(rng), u(rng), u(rng)};
        if (r % 4 == 0) d = glm::vec3(0.0f), d[r % 3] = r % 8 < 4 ? 1.0f : -1.0f;  // along an axis
        if (glm::length(d) == 0.0f) continue;
        check(o, glm::normalize(d));
    }
    EXPECT_EQ(differing, 0u);
    EXPECT_LT(evaluations[1] * 2, evaluations[0]) << "the ball intervals skip little";
    EXPECT_LT(evaluations[2] * 2, evaluations[0]) << "the grid skips little";
}

// The shadow ray sums only the balls its line passes near (shadowBallMask): for random points in the
// box and random, axis-aligned and grazing light directions, the same bits as summing every ball at
// every shadow sample, written out here from the definition.
TEST(ShadowRay, SkippingFarBallsChangesNoBit) {
    const MetaballVolume v = sceneVolume();
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    size_t differing = 0, skipped_some = 0, rays = 0;
    for (int r = 0; r < 200000; ++r) {
        const glm::vec3 x{u(rng) * 1.2f, 0.2f + u(rng), u(rng) * 1.2f};
        glm::vec3 l{u(rng), u(rng), u(rng)};
        if (r % 5 == 0) l = glm::vec3(0.0f), l[r % 3] = r % 10 < 5 ? 1.0f : -1.0f;
        if (r % 7 == 0) {  // towards a ball's rim: the line grazes it
            const Metaball& b = v.balls[size_t(r) % 6];
            l = b.centre + glm::normalize(glm::vec3(u(rng), u(rng), u(rng))) * b.radius - x;
        }
        if (glm::length(l) < 1e-3f) continue;
        VolumeLight light;
        light.toLight = glm::normalize(l);
        MarchSettings settings;
        settings.shadowSteps = r % 2 ? 6 : 11;
        MarchResult counts;
        const float exit = media::detail::exitDistance(v.box, x, light.toLight, 1.0f / light.toLight);
        const float tau = media::detail::shadowDepth(v, settings, x, light.toLight, exit, counts);
        const float dl = slabInterval(v.box, x, light.toLight).second / float(settings.shadowSteps);
        float expected = 0.0f;
        for (uint32_t j = 0; j < settings.shadowSteps; ++j)
            expected += v.extinction(x + light.toLight * ((float(j) + 0.5f) * dl), 0x3f) * dl;
        differing += std::memcmp(&tau, &expected, sizeof tau) != 0;
        skipped_some += media::detail::shadowBallMask(v, x, light.toLight) != 0x3fu;
        ++rays;
    }
    EXPECT_EQ(differing, 0u);
    EXPECT_GT(skipped_some, rays / 2) << "the mask should leave balls out";
}

// The pixel shader's eight- and sixteen-wide calls give, lane by lane, the scalar call's bits (the
// pipeline shades whole blocks wide and may shade a pixel alone).
TEST(MediaShader, WideCallsAreTheScalarCallLaneByLane) {
    const MetaballVolume v = sceneVolume();
    shaders::PsMediaMarch ps;
    ps.invViewProj = sceneInverseViewProj(1280, 720);
    ps.eye = kEye;
    ps.volume = &v;
    ps.light = sceneLight();
    ps.background = {0.08f, 0.10f, 0.16f};
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int round = 0; round < 3000; ++round) {
        float x[16], y[16];
        for (int l = 0; l < 16; ++l) x[l] = u(rng), y[l] = u(rng);
        if (round % 3 == 0) x[round % 16] = 0.0f, y[(round + 5) % 16] = 0.0f;
        shaders::MediaRayVertexT<Float8x2> in;
        in.position = glm::vec<4, Float8x2>(Float8x2(0.0f));
        in.ndc = {Float8x2::load(x), Float8x2::load(y)};
        const glm::vec<4, Float8x2> wide = ps(in);
        shaders::MediaRayVertexT<Float8> in8;
        in8.position = glm::vec<4, Float8>(Float8(0.0f));
        in8.ndc = {Float8::load(x), Float8::load(y)};
        const glm::vec<4, Float8> wide8 = ps(in8);
        for (int l = 0; l < 16; ++l) {
            const glm::vec4 scalar = ps(shaders::MediaRayVertex{glm::vec4(0.0f), {x[l], y[l]}});
            for (int c = 0; c < 4; ++c) {
                const float w = wide[c][l];
                ASSERT_EQ(std::memcmp(&w, &scalar[c], 4), 0) << round << " lane " << l;
                if (l < 8) {
                    const float w8 = wide8[c][l];
                    ASSERT_EQ(std::memcmp(&w8, &scalar[c], 4), 0) << round << " lane " << l;
                }
            }
        }
    }
}

// The scene agrees with SCENES.md's definition computed in double: every pixel of a 320×180 and a
// 997×613 rendering within 1/255 (the fast exp's ulps and float rounding stay far below it).
TEST(MediaScene, AgreesWithTheDefinitionInDouble) {
    for (auto [w, h] : {std::pair<uint32_t, uint32_t>{320, 180}, {997, 613}}) {
        auto scene = makeScene("media", {.width = w, .height = h});
        Context context({2});
        RenderTarget color(w, h);
        DepthTarget depth(w, h);
        scene->render(context, color, depth);
        const glm::dmat4 inv_vp(sceneInverseViewProj(w, h));
        size_t off = 0, lit = 0;
        const uint32_t stride = w > 400 ? 3 : 1;
        for (uint32_t y = 0; y < h; y += stride)
            for (uint32_t x = 0; x < w; x += stride) {
                const glm::dvec3 ref = definitionPixel(inv_vp, glm::dvec2(pixelNdc(x, y, w, h)));
                const uint8_t* p = color.rgba8() + 4 * (size_t(y) * w + x);
                for (int c = 0; c < 3; ++c) off += std::abs(double(p[c]) - ref[c] * 255.0) > 1.0;
                lit += ref.x > 0.1;  // brighter than the background: the cloud
            }
        EXPECT_EQ(off, 0u) << w << "x" << h;
        EXPECT_GT(lit, size_t(w / stride) * (h / stride) / 20) << "the cloud should cover part of the picture";
    }
}

TEST(MediaScene, SameBitsAtOneTwoAndEightThreads) {
    auto scene = makeScene("media", {.width = 333, .height = 200});
    std::vector<uint8_t> first;
    for (uint32_t threads : {1u, 2u, 8u}) {
        Context context({threads});
        RenderTarget color(333, 200);
        DepthTarget depth(333, 200);
        scene->render(context, color, depth);
        std::vector<uint8_t> bytes(color.rgba8(), color.rgba8() + size_t(333) * 200 * 4);
        if (first.empty()) {
            first = bytes;
        } else {
            EXPECT_EQ(bytes, first) << threads << " threads";
        }
    }
}

namespace {

// Six balls: one of radius 0.05 m at the origin, the other five far outside the box (never sampled).
MetaballVolume smallBallVolume(float extinction_scale) {
    std::array<Metaball, 6> balls;
    balls[0] = {glm::vec3(0.0f), 0.05f};
    for (size_t k = 1; k < 6; ++k) balls[k] = {glm::vec3(50.0f + float(k), 50.0f, 50.0f), 0.01f};
    return makeMetaballVolume(balls, Box{glm::vec3(-0.1f), glm::vec3(0.1f)}, extinction_scale, 4);
}

VolumeLight pointLightAt(const glm::vec3& position, const glm::vec3& intensity, float g = 0.0f) {
    VolumeLight light;
    light.kind = LightKind::point;
    light.position = position, light.intensity = intensity;
    light.g = g, light.albedo = 0.8f;
    return light;
}

std::vector<uint8_t> renderMedia(const SceneOptions& o, uint32_t threads) {
    return renderSceneBytes("media", o, threads);
}

}  // namespace

TEST(PointLight, MetaballMarchFallsOffAsInverseSquare) {
    // An optically thin ball 0.05 m across (μ ≤ 1e-3/m: every shadow transmittance within 1e-4 of 1),
    // the isotropic phase 1/(4π), no ambient: L = Σ_i w_i·albedo·(1/4π)·I/r_i², w_i = T_i·(1 − e^{−μ_iΔs})
    // the share sample i scatters towards the eye and r_i its distance to the light (computed here
    // from the samples' positions, in double); and L·R² the same for every distance R of the light.
    const MetaballVolume v = smallBallVolume(1e-3f);
    const glm::vec3 eye{0.0f, 0.0f, 5.0f}, d{0.0f, 0.0f, -1.0f}, intensity{8.0f, 4.0f, 2.0f};
    const glm::vec3 side = glm::normalize(glm::vec3(1.0f, 0.6f, 0.2f));
    double scaled_first = 0.0;
    for (float r : {1.0f, 2.0f, 4.0f, 16.0f}) {
        for (int s : {1, -1}) {  // on either side of the ball
            const VolumeLight light = pointLightAt(side * (float(s) * r), intensity);
            double expected = 0.0;  // per unit intensity
            const MarchResult m = marchMetaballs(v, light, MarchSettings{}, eye, d, [&](const MarchSample& x) {
                const glm::dvec3 p = glm::dvec3(eye) + glm::dvec3(d) * double(x.s);
                const glm::dvec3 to_light = glm::dvec3(light.position) - p;
                const double w = double(x.transmittance) * -std::expm1(-double(x.opticalStep));
                expected += w * 0.8 / (4.0 * M_PI) / glm::dot(to_light, to_light);
            });
            ASSERT_GT(expected, 0.0);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(m.radiance[c], expected * intensity[c], expected * intensity[c] * 1e-3)
                    << "R " << r << " channel " << c;
            const double scaled = double(m.radiance.x) * r * r;
            if (scaled_first == 0.0) scaled_first = scaled;
            EXPECT_NEAR(scaled, scaled_first, scaled_first * 4e-3) << "L·R² at R " << r;
        }
    }
}

TEST(PointLight, MetaballShadowRayEndsAtTheLight) {
    // The light inside the ball, 0.01 m off the view ray: each sample's shadow transmittance is
    // e^{−τ} with τ the optical depth from the sample to the light alone (a fine sum here), not on to
    // the box's side; 64 shadow steps leave the midpoint rule's error far below the tolerance.
    const MetaballVolume v = smallBallVolume(100.0f);
    const glm::vec3 eye{0.0f, 0.0f, 5.0f}, d{0.0f, 0.0f, -1.0f}, at{0.0f, 0.01f, 0.0f};
    MarchSettings settings;
    settings.shadowSteps = 64;
    uint32_t checked = 0;
    double deepest = 0.0;
    marchMetaballs(v, pointLightAt(at, glm::vec3(1.0f)), settings, eye, d, [&](const MarchSample& s) {
        if (!(s.extinction > 0.0f)) return;
        const glm::vec3 x = eye + d * s.s;
        double tau = 0.0;
        constexpr int kSteps = 4096;
        for (int j = 0; j < kSteps; ++j)
            tau += double(v.extinction(x + (at - x) * ((float(j) + 0.5f) / float(kSteps)), 0x3fu)) / kSteps;
        tau *= double(glm::length(at - x));
        deepest = std::max(deepest, tau);
        EXPECT_NEAR(s.shadowTransmittance, std::exp(-tau), 2e-3) << "sample " << s.index;
        ++checked;
    });
    EXPECT_GT(checked, 3u);
    EXPECT_GT(deepest, 0.5) << "the shadow rays should cross some of the ball";
}

TEST(PointLight, FarAwayItIsTheDirectionalLightInTheMediaScene) {
    // A point light R metres away along the scene's toLight, intensity E·R², against the directional
    // light E: the same radiance to the light's spread over the box (its direction varies by 2/R
    // radians, its irradiance by 2·2/R).
    const MetaballVolume v = sceneVolume();
    const VolumeLight sun = sceneLight();
    constexpr float kR = 1e4f;
    VolumeLight point = sun;
    point.kind = LightKind::point;
    point.position = sun.toLight * kR;
    point.intensity = sun.sun * (kR * kR);
    const glm::mat4 inv_vp = sceneInverseViewProj(64, 36);
    float worst = 0.0f, largest = 0.0f;
    for (uint32_t y = 0; y < 36; y += 3)
        for (uint32_t x = 0; x < 64; x += 3) {
            const glm::vec3 d = shaders::viewRay(inv_vp, pixelNdc(x, y, 64, 36));
            const MarchResult a = marchMetaballs(v, sun, MarchSettings{}, kEye, d);
            const MarchResult b = marchMetaballs(v, point, MarchSettings{}, kEye, d);
            EXPECT_EQ(a.transmittance, b.transmittance);
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, std::abs(a.radiance[c] - b.radiance[c]));
                largest = std::max(largest, a.radiance[c]);
            }
        }
    EXPECT_GT(largest, 0.3f);
    EXPECT_LT(worst, 2e-3f * largest);
}

TEST(MediaScene, LightOptionAsTheScenesOwnGivesItsBits) {
    // --light dir:0.4,1,0.3 is SCENES.md's light: the default picture's bits; another direction, or a
    // point light, changes it; a point light's picture is the same at 1, 2 and 8 threads.
    SceneOptions o{.width = 160, .height = 90};
    const std::vector<uint8_t> own = renderMedia(o, 2);
    o.light = SceneLight{false, {0.4f, 1.0f, 0.3f}};
    EXPECT_EQ(renderMedia(o, 2), own);
    o.light = SceneLight{false, {-0.4f, 1.0f, 0.3f}};
    EXPECT_NE(renderMedia(o, 2), own);
    o.light = SceneLight{true, {0.8f, 1.6f, 0.6f}};
    const std::vector<uint8_t> point = renderMedia(o, 1);
    EXPECT_NE(point, own);
    EXPECT_EQ(renderMedia(o, 2), point);
    EXPECT_EQ(renderMedia(o, 8), point);
}

TEST(MediaScene, LightOptionRefusedWhereNoVolumeLight) {
    SceneOptions o{.width = 16, .height = 16};
    o.light = SceneLight{true, {0.0f, 2.0f, 0.0f}};
    try {
        makeScene("fog", o);
        ADD_FAILURE() << "the fog scene took a volume light";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("light: scene 'fog' has no volume light"), std::string::npos) << e.what();
    }
    o.light = SceneLight{false, {0.0f, 0.0f, 0.0f}};
    try {
        makeScene("media", o);
        ADD_FAILURE() << "a direction of length 0 taken";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("light: the direction (0, 0, 0) has no length"), std::string::npos)
            << e.what();
    }
    const Box box = mediaSceneBox();
    o.light = SceneLight{true, 0.5f * (box.lo + box.hi)};  // the medium's centre, no intensity given
    EXPECT_THROW(makeScene("media", o), Error);
    o.lightIntensity = glm::vec3(1.0f);
    EXPECT_NO_THROW(makeScene("media", o));
}
