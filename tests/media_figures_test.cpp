// The lecture's part-1 figures by ray marching (src/scene_media_figures.cpp, raster/media/figure_march.hpp):
// each renders the same bits at 1, 2 and 8 threads; absorption alone never brightens a pixel of the
// background, emission alone never darkens one; Henyey–Greenstein is brighter than isotropic where the
// view looks towards the light, and Rayleigh scatters forward and backward alike; Euler's panel is far
// from the converged one where the exponential panel is close, and Euler leaves [0, 1] only on rays
// whose μΔs exceeds 1 somewhere (where the exponential step never does).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "raster/media/figure_march.hpp"
#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"
#include "raster/shaders/media.hpp"
#include "scene_bytes.hpp"

using namespace raster;
using namespace raster::media;

namespace {

// The figures' medium: the media scene's six balls, extinction scale 1 (extinction() is the density).
MetaballVolume figureVolume() {
    return makeMetaballVolume(mediaSceneMetaballs(), mediaSceneBox(), 1.0f, 1);
}

// Rays from a ring of eyes around the box towards random points in it.
std::vector<std::pair<glm::vec3, glm::vec3>> raysThroughTheBox(int count) {
    std::vector<std::pair<glm::vec3, glm::vec3>> rays;
    uint32_t state = 12345;
    const auto uniform = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    for (int k = 0; k < count; ++k) {
        const float angle = 6.2831853f * uniform();
        const glm::vec3 eye{3.0f * std::cos(angle), 0.4f + uniform() - 0.5f, 3.0f * std::sin(angle)};
        const glm::vec3 target{1.4f * uniform() - 0.7f, 1.2f * uniform() - 0.4f, 1.4f * uniform() - 0.7f};
        rays.push_back({eye, glm::normalize(target - eye)});
    }
    return rays;
}

}  // namespace

TEST(MediaFigures, SameBitsAtOneTwoAndEightThreads) {
    for (const char* name : {"media-absorption", "media-emission", "media-scattering", "media-euler"}) {
        const SceneOptions options{.width = 213, .height = 120};
        const std::vector<uint8_t> one = renderSceneBytes(name, options, 1);
        EXPECT_EQ(renderSceneBytes(name, options, 2), one) << name << " at 2 threads";
        EXPECT_EQ(renderSceneBytes(name, options, 8), one) << name << " at 8 threads";
    }
}

namespace {

// The scene against itself with its medium's coefficient set to 0 (the background alone): how many
// channels moved against `sign` (+1: may only brighten, −1: may only darken), and how many pixels moved
// with it by more than 25/255 in red.
struct AgainstBackground {
    size_t wrongWay = 0, moved = 0, pixels = 0;
};
AgainstBackground compareWithBackground(const char* name, int sign) {
    SceneOptions options{.width = 320, .height = 180};
    const std::vector<uint8_t> image = renderSceneBytes(name, options, 2);
    (sign > 0 ? options.fogSource : options.fogSigma) = glm::vec3(0.0f);
    const std::vector<uint8_t> background = renderSceneBytes(name, options, 2);
    AgainstBackground r;
    r.pixels = image.size() / 4;
    for (size_t i = 0; i < image.size(); ++i) {
        const int change = sign * (int(image[i]) - int(background[i]));
        r.wrongWay += change < 0;
        r.moved += i % 4 == 0 && change > 25;
    }
    return r;
}

}  // namespace

// q = 0: no channel of any pixel brighter than the background's, and the medium darkens 5 % of the
// picture by more than 0.1.
TEST(MediaFigures, AbsorptionOnlyNeverBrightens) {
    const AgainstBackground r = compareWithBackground("media-absorption", -1);
    EXPECT_EQ(r.wrongWay, 0u);
    EXPECT_GT(r.moved, r.pixels / 20) << "the medium should darken at least 5 % of the pixels";
}

// μ = 0: no channel darker than the background's, and the glow brightens 5 % of the picture by more
// than 0.1.
TEST(MediaFigures, EmissionOnlyNeverDarkens) {
    const AgainstBackground r = compareWithBackground("media-emission", +1);
    EXPECT_EQ(r.wrongWay, 0u);
    EXPECT_GT(r.moved, r.pixels / 20) << "the medium should glow over at least 5 % of the pixels";
}

// The panels isotropic | Rayleigh | HG see the same cloud under the same light: where the pixel's view
// ray is within 15° of the direction towards the light and the cloud is there (the panels differ), HG's
// forward lobe is brighter than isotropic at every pixel and by more than 0.25 on average.
TEST(MediaFigures, HenyeyGreensteinIsBrighterThanIsotropicTowardsTheLight) {
    const uint32_t w = 480, h = 180, panel = w / 3;
    const std::vector<uint8_t> image = renderSceneBytes("media-scattering", {.width = w, .height = h}, 2);
    SceneOptions panel_options{.width = panel, .height = h};
    const SceneCamera camera = defaultCamera("media-scattering");
    const glm::mat4 inv_vp = glm::inverse(sceneProjection(panel_options) * sceneView(camera));
    const glm::vec3 to_light = glm::normalize(glm::vec3(0.12f, 0.2f, -1.0f));  // the scene's light
    size_t towards = 0, dimmer = 0;
    double sum_difference = 0.0;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < panel; ++x) {
            const glm::vec2 ndc{(float(x) + 0.5f) / float(panel) * 2.0f - 1.0f, 1.0f - (float(y) + 0.5f) / float(h) * 2.0f};
            if (glm::dot(shaders::viewRay(inv_vp, ndc), to_light) < std::cos(glm::radians(15.0f))) continue;
            const uint8_t* iso = &image[4 * (size_t(y) * w + x)];
            const uint8_t* hg = &image[4 * (size_t(y) * w + x + 2 * panel)];
            if (iso[0] == hg[0] && iso[1] == hg[1] && iso[2] == hg[2]) continue;  // no cloud there
            ++towards;
            for (int c = 0; c < 3; ++c) dimmer += hg[c] < iso[c], sum_difference += hg[c] - iso[c];
        }
    ASSERT_GT(towards, size_t(panel) * h / 50) << "the cloud should cover the view towards the light";
    EXPECT_EQ(dimmer, 0u);
    EXPECT_GT(sum_difference / (3.0 * double(towards)), 0.25 * 255.0);
}

// Rayleigh is symmetric: with the sun alone and no background, the march is linear in p, so each ray's
// Rayleigh-to-isotropic ratio is p_R(cos θ)/p_iso — the same with the light at l and at −l (cos θ and
// −cos θ). Henyey–Greenstein's ratio is far larger forwards than backwards.
TEST(MediaFigures, RayleighScattersForwardAndBackwardAlike) {
    const MetaballVolume volume = figureVolume();
    FigureMedium medium;
    medium.absorption = glm::vec3(0.3f), medium.scattering = glm::vec3(5.7f);
    const FigureMarch march{StepRule::exponential, 64, 8};
    size_t rays = 0;
    double worst_rayleigh = 0.0, least_hg = INFINITY;
    for (const auto& [eye, d] : raysThroughTheBox(300)) {
        const glm::vec3 l = glm::normalize(d + glm::vec3(0.1f, 0.25f, -0.15f));  // towards the light: cos θ ≈ 0.95
        const auto ratio = [&](PhaseFunction phase, const glm::vec3& to_light) {
            FigureMedium m = medium;
            m.phase = phase, m.g = 0.7f;
            const VolumeLight light{to_light, glm::vec3(1.0f), glm::vec3(0.0f)};
            const float a = marchFigure(volume, m, light, march, eye, d, glm::vec3(0.0f)).x;
            m.phase = PhaseFunction::isotropic;
            return double(a) / double(marchFigure(volume, m, light, march, eye, d, glm::vec3(0.0f)).x);
        };
        const float forward = marchFigure(volume, medium, {l, glm::vec3(1.0f), glm::vec3(0.0f)}, march, eye, d,
                                          glm::vec3(0.0f)).x;
        const float backward = marchFigure(volume, medium, {-l, glm::vec3(1.0f), glm::vec3(0.0f)}, march, eye, d,
                                           glm::vec3(0.0f)).x;
        if (!(forward > 1e-3f && backward > 1e-3f)) continue;  // too little lit medium on this ray
        ++rays;
        const double r_forward = ratio(PhaseFunction::rayleigh, l), r_backward = ratio(PhaseFunction::rayleigh, -l);
        const double c = glm::dot(d, l);
        worst_rayleigh = std::max({worst_rayleigh, std::fabs(r_forward / r_backward - 1.0),
                                   std::fabs(r_forward / (0.75 * (1.0 + c * c)) - 1.0)});
        least_hg = std::min(least_hg, ratio(PhaseFunction::henyeyGreenstein, l) /
                                          ratio(PhaseFunction::henyeyGreenstein, -l));
    }
    ASSERT_GT(rays, 100u);
    EXPECT_LT(worst_rayleigh, 1e-5);
    EXPECT_GT(least_hg, 20.0) << "HG (g = 0.7) at cos θ ≈ ±0.95: p ratio ≈ 55";
}

// The panels Euler | exponential (the same few steps) | reference: Euler's mean distance from the
// reference is many times the exponential step's: at 480×180, 3.97 and 0.083 (of 255) per channel
// and pixel of the panel (48 times).
TEST(MediaFigures, EulerPanelIsFarFromTheReferenceWhereTheExponentialIsClose) {
    const uint32_t w = 480, h = 180, panel = w / 3;
    const std::vector<uint8_t> image = renderSceneBytes("media-euler", {.width = w, .height = h}, 2);
    double euler = 0.0, exponential = 0.0;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < panel; ++x)
            for (int c = 0; c < 3; ++c) {
                const auto at = [&](uint32_t k) { return double(image[4 * (size_t(y) * w + x + k * panel) + c]); };
                euler += std::fabs(at(0) - at(2)), exponential += std::fabs(at(1) - at(2));
            }
    euler /= 3.0 * panel * h, exponential /= 3.0 * panel * h;
    EXPECT_GT(euler, 20.0 * exponential) << "euler " << euler << ", exponential " << exponential;
    EXPECT_GT(euler, 2.0);
    EXPECT_LT(exponential, 0.5);
}

// media-euler's medium (q = 0.8·μ, dense) at its few steps: the exponential step keeps every ray's
// radiance between the background and 0.8; so does Euler where μΔs ≤ 1 at every step (its factor
// 1 − μΔs in [0, 1]: a convex combination); Euler leaves [0, 1] on rays where μΔs is larger, and some
// step has μΔs > 2. The reference (midpoint exponential, 512 steps) is converged: 1024 steps change
// it by less than 1e-3.
TEST(MediaFigures, EulerLeavesTheUnitIntervalOnlyWhereMuDeltaSExceedsOne) {
    const MetaballVolume volume = figureVolume();
    FigureMedium medium;
    medium.absorption = glm::vec3(12.0f), medium.emission = glm::vec3(9.6f);
    VolumeLight light;
    light.sun = glm::vec3(0.0f);
    const uint32_t steps = 8;
    size_t out_of_range = 0, stable_rays = 0;
    float largest_step = 0.0f;
    double reference_change = 0.0;
    const glm::vec3 background(0.3f);
    const auto rays = raysThroughTheBox(2000);
    for (size_t k = 0; k < rays.size(); ++k) {
        const auto& [eye, d] = rays[k];
        const auto [t_near, t_far] = slabInterval(volume.box, eye, d);
        const float t0 = std::max(t_near, 0.0f), ds = (t_far - t0) / float(steps);
        float max_step = 0.0f;  // the largest μΔs at Euler's samples (each step's far end)
        for (uint32_t i = 0; i < steps; ++i)
            max_step = std::max(max_step, 12.0f * volume.extinction(eye + d * (t0 + float(i + 1) * ds), 0x3f) * ds);
        largest_step = std::max(largest_step, max_step);
        const float e = marchFigure(volume, medium, light, {StepRule::euler, steps, 1}, eye, d, background).x;
        const float x = marchFigure(volume, medium, light, {StepRule::exponential, steps, 1}, eye, d, background).x;
        EXPECT_TRUE(x >= 0.3f - 1e-6f && x <= 0.8f + 1e-6f) << x;
        if (max_step <= 1.0f) {
            ++stable_rays;
            EXPECT_TRUE(e >= 0.3f - 1e-6f && e <= 0.8f + 1e-6f) << e << " at max μΔs " << max_step;
        }
        if (e < 0.0f || e > 1.0f) {
            ++out_of_range;
            EXPECT_GT(max_step, 1.0f);
        }
        if (k % 20 == 0) {  // every 20th ray: 1024 steps cost
            const float r512 = marchFigure(volume, medium, light, {StepRule::midpointExponential, 512, 1}, eye, d,
                                           background).x;
            const float r1024 = marchFigure(volume, medium, light, {StepRule::midpointExponential, 1024, 1}, eye, d,
                                            background).x;
            reference_change = std::max(reference_change, double(std::fabs(r512 - r1024)));
        }
    }
    EXPECT_GT(largest_step, 2.0f);
    EXPECT_GT(stable_rays, 100u);
    EXPECT_GT(out_of_range, 100u);
    EXPECT_LT(reference_change, 1e-3);
}
