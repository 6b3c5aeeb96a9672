// The `cloud` scene (raster/media/cloud_march.hpp, raster/shaders/cloud.hpp, src/scene_cloud.cpp), on a
// small grid: empty-space skipping gives the march's bits ray by ray, the terminations stay under
// their bound, the volume's memory is its voxels plus little, the scene renders the same bits at 1, 2
// and 8 threads and leaves the ground as it was where the cloud's box is not, a raw file of the
// generated cloud renders as the generated cloud, and a bad file is named. The ground under the cloud
// (shaders::PsCloudGround) is darkened by the cloud's transmittance towards the sun, and is the fog
// ground's bits where its shadow ray misses the cloud.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "raster/media/cloud_march.hpp"
#include "raster/shaders/cloud.hpp"
#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"
#include "scene_bytes.hpp"

using namespace raster;
using namespace raster::media;

namespace {

constexpr int kVoxels = 32;

VolumeLight testLight() {
    VolumeLight light;
    light.toLight = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
    light.sun = {22.0f, 21.0f, 19.0f};
    light.ambient = {0.30f, 0.36f, 0.46f};
    light.g = 0.3f;
    light.albedo = 0.95f;
    return light;
}

// The generated cloud at kVoxels³, 2.4 optical depths per voxel at its densest, with majorant
// cells of `cell` voxels.
CloudVolume testVolume(int cell = 4) { return makeCloudVolume(makeCloudGrid(kVoxels, 3), 0.3f, cell); }

// Rays from outside the box (random, and along the axes and diagonals) through the cloud.
struct Ray {
    glm::vec3 o, d;
};
std::vector<Ray> testRays(int count) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays;
    const glm::vec3 centre(kVoxels * 0.5f);
    for (int i = 0; i < count; ++i) {
        const glm::vec3 from = centre + glm::normalize(glm::vec3(u(rng), u(rng), u(rng))) * float(kVoxels);
        const glm::vec3 to = centre + glm::vec3(u(rng), u(rng), u(rng)) * (kVoxels * 0.4f);
        rays.push_back({from, glm::normalize(to - from)});
    }
    for (int a = 0; a < 3; ++a)
        for (float s : {-1.0f, 1.0f}) {
            glm::vec3 d(0.0f);
            d[a] = s;
            glm::vec3 o = centre + glm::vec3(0.37f, -0.21f, 0.13f) * float(kVoxels) * 0.3f;
            o[a] = centre[a] - s * float(kVoxels);
            rays.push_back({o, d});
        }
    rays.push_back({glm::vec3(-1.0f), glm::normalize(glm::vec3(1.0f))});  // through the corners
    return rays;
}

bool sameBits(const MarchResult& a, const MarchResult& b) {
    return std::memcmp(&a.radiance, &b.radiance, sizeof a.radiance) == 0 &&
           std::memcmp(&a.transmittance, &b.transmittance, sizeof a.transmittance) == 0;
}

SceneOptions smallCloud() {
    SceneOptions o;
    o.width = 160, o.height = 90, o.voxels = uint32_t(kVoxels), o.seed = 3;
    return o;
}

}  // namespace

TEST(CloudMarch, SkippingEmptySpaceChangesNoBit) {
    const CloudVolume v = testVolume();
    const VolumeLight light = testLight();
    CloudMarchSettings skip, full;
    full.skip = false;
    uint32_t hits = 0, saved = 0, total = 0;
    for (const Ray& r : testRays(3000)) {
        const MarchResult a = marchCloud(v, light, skip, r.o, r.d), b = marchCloud(v, light, full, r.o, r.d);
        ASSERT_TRUE(sameBits(a, b)) << "ray from (" << r.o.x << ", " << r.o.y << ", " << r.o.z << ")";
        hits += a.transmittance < 1.0f;
        saved += b.densityEvaluations - a.densityEvaluations, total += b.densityEvaluations;
    }
    EXPECT_GT(hits, 1000u) << "most rays should meet the cloud";
    EXPECT_GT(saved, total / 4) << "skipping should leave out a good share of the samples";
}

TEST(CloudMarch, TerminationsStayUnderTheirBound) {
    const CloudVolume v = testVolume();
    const VolumeLight light = testLight();
    CloudMarchSettings fast, exact;
    exact.minTransmittance = 0.0f, exact.shadowMaxDepth = INFINITY, exact.shadowBudget = 0.0f;
    const float bound = cloudErrorBound(light, fast);
    EXPECT_LT(bound, 1.0f / 255.0f);
    float worst = 0.0f;
    uint64_t fast_work = 0, exact_work = 0;
    for (const Ray& r : testRays(3000)) {
        const MarchResult a = marchCloud(v, light, fast, r.o, r.d), b = marchCloud(v, light, exact, r.o, r.d);
        for (float background : {0.0f, 1.0f})
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs((a.radiance[c] + a.transmittance * background) -
                                                 (b.radiance[c] + b.transmittance * background)));
        fast_work += a.densityEvaluations, exact_work += b.densityEvaluations;
    }
    EXPECT_LE(worst, bound);
    EXPECT_GT(worst, 0.0f) << "the terminations should change something";
    EXPECT_LT(fast_work, exact_work / 2) << "and save at least half the density evaluations";
}

TEST(CloudVolume, MemoryWithinVoxelsPlus15Percent) {
    // 16 majorant cells per axis, as 256³ voxels in cells of 16 have.
    const CloudVolume v = makeCloudVolume(makeCloudGrid(64, 1), 1.0f, 4);
    EXPECT_EQ(v.voxelBytes(), 64ull * 64 * 64 * 4);
    EXPECT_EQ(v.majorant.bound.size(), 16u * 16 * 16);
    EXPECT_LE(double(v.memoryBytes()), double(v.voxelBytes()) * 1.15);
    EXPECT_GT(v.memoryBytes(), v.voxelBytes() + v.majorant.bound.size() * sizeof(float));
}

TEST(CloudScene, SameBitsAtOneTwoAndEightThreadsOverTheGround) {
    const SceneOptions o = smallCloud();
    const std::vector<uint8_t> one = renderSceneBytes("cloud", o, 1);
    EXPECT_EQ(renderSceneBytes("cloud", o, 2), one);
    EXPECT_EQ(renderSceneBytes("cloud", o, 8), one);
    // The ground alone: the fog scene from the cloud's camera. The cloud changes a good share of the
    // pixels and leaves the others exactly as the ground left them (its blend adds 0 there).
    SceneOptions ground = o;
    ground.camera = defaultCamera("cloud");
    const std::vector<uint8_t> fog = renderSceneBytes("fog", ground, 1);
    size_t changed = 0;
    for (size_t p = 0; p < one.size(); p += 4) changed += std::memcmp(&one[p], &fog[p], 4) != 0;
    EXPECT_GT(changed, one.size() / 4 / 50);
    EXPECT_LT(changed, one.size() / 4 / 2);
}

TEST(CloudScene, RawFileOfTheGeneratedCloudRendersTheSame) {
    const std::string path =
        (std::filesystem::temp_directory_path() / rawVoxelFileName("raster_cloud_test", glm::ivec3(kVoxels),
                                                                   VoxelType::Float32))
            .string();
    saveRawVoxelGrid(path, makeCloudGrid(kVoxels, 3));
    SceneOptions file = smallCloud();
    file.volume = path;
    file.voxels.reset();
    EXPECT_EQ(renderSceneBytes("cloud", file, 2), renderSceneBytes("cloud", smallCloud(), 2));
    std::filesystem::resize_file(path, 1000);
    try {
        makeScene("cloud", file);
        ADD_FAILURE() << "a truncated volume file should be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::BadFile);
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
    std::filesystem::remove(path);
    file.volume = path + ".nvdb";
    EXPECT_THROW(makeScene("cloud", file), Error);
}

namespace {

// The test volume as the ground's cloud, voxels = world metres (origin 0, one voxel a metre), the fog
// scene's ground shading with its sun along testLight's direction.
shaders::PsCloudGround testGround(const CloudVolume& v) {
    shaders::PsCloudGround ps;
    ps.volume = &v;
    ps.ground.light = testLight().toLight;
    ps.ground.eye = {16.0f, 20.0f, 90.0f};
    return ps;
}

shaders::LitVertex groundVertex(const glm::vec3& p, const glm::vec3& n) { return {glm::vec4(0.0f), p, n}; }

// e^{−τ} along x + t·l by the definition: the midpoint rule in steps of 1/64 voxel over the whole
// box, no skipping, no termination, in double.
double referenceTransmittance(const CloudVolume& v, const glm::vec3& x, const glm::vec3& l) {
    const auto [t_near, t_far] = slabInterval(v.box, x, l);
    double tau = 0.0;
    const double dt = 1.0 / 64.0;
    for (double t = std::max(t_near, 0.0f) + dt / 2; t < t_far; t += dt) tau += v.extinction(x + l * float(t)) * dt;
    return std::exp(-tau);
}

}  // namespace

TEST(CloudGround, UnderTheCloudTheSunIsAttenuatedByItsTransmittance) {
    const CloudVolume v = testVolume();
    shaders::PsCloudGround ps = testGround(v);
    ps.ground.fog.sigma = glm::vec3(0.0f), ps.ground.fog.q = glm::vec3(0.0f);  // no fog: L = albedo·level
    const glm::vec3 l = ps.ground.light, up(0.0f, 1.0f, 0.0f);
    // Under the cloud's middle (the point whose shadow ray passes through the box's centre) and far
    // from it, on a ground facing up: L = albedo·(ambient + (1 − ambient)·(n·l)·V).
    const glm::vec3 under = glm::vec3(kVoxels * 0.5f) - l * float(2 * kVoxels), far = under + glm::vec3(100, 0, 0);
    const float lambert = glm::dot(up, l);
    const float v_march = cloudShadowTransmittance(v, ps.settings, under, l);
    const double v_ref = referenceTransmittance(v, under, l);
    EXPECT_LT(v_ref, 0.5) << "the point should lie in the cloud's shadow";
    EXPECT_NEAR(v_march, v_ref, 0.02) << "the march's shadow ray against the definition";
    EXPECT_EQ(cloudShadowTransmittance(v, ps.settings, far, l), 1.0f);
    const glm::vec4 lit_under = ps(groundVertex(under, up)), lit_far = ps(groundVertex(far, up));
    const float a = ps.ground.ambient;
    for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(lit_far[c], ps.ground.albedo[c] * (a + (1.0f - a) * lambert));
        EXPECT_FLOAT_EQ(lit_under[c], ps.ground.albedo[c] * (a + (1.0f - a) * lambert * v_march));
        EXPECT_LT(lit_under[c], lit_far[c]);
    }
    // The eight-wide shader gives each lane the scalar's bits.
    Float8 x, y, z;
    for (int lane = 0; lane < 8; ++lane) {
        const glm::vec3 p = under + glm::vec3(float(lane) * 2.5f, 0.0f, -float(lane));
        x.set(lane, p.x), y.set(lane, p.y), z.set(lane, p.z);
    }
    const shaders::LitVertexT<Float8> wide{glm::vec<4, Float8>(Float8(0.0f)), {x, y, z},
                                           {Float8(0.0f), Float8(1.0f), Float8(0.0f)}};
    const glm::vec<4, Float8> out = ps(wide);
    for (int lane = 0; lane < 8; ++lane) {
        const glm::vec4 one = ps(groundVertex({x[lane], y[lane], z[lane]}, up));
        for (int c = 0; c < 4; ++c) EXPECT_EQ(out[c][lane], one[c]) << "lane " << lane;
    }
}

TEST(CloudGround, WhereTheShadowRayMissesTheCloudItIsTheFogGroundsBits) {
    const CloudVolume v = testVolume();
    shaders::PsCloudGround ps = testGround(v);
    ps.ground.fog.height = false;  // constant fog (the height fog 40 voxels below y = 0 is opaque)
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int missed = 0, hit = 0;
    for (int i = 0; i < 4000; ++i) {
        // Around the point under the cloud's middle (the test above), 2 box sides below the box.
        const glm::vec3 p = glm::vec3(kVoxels * 0.5f) - ps.ground.light * float(2 * kVoxels) +
                            glm::vec3(u(rng) * 1.5f, u(rng) * 0.05f, u(rng) * 1.5f) * float(kVoxels);
        const glm::vec3 n = glm::normalize(glm::vec3(u(rng), u(rng) + 0.5f, u(rng)));
        const auto [t_near, t_far] = slabInterval(v.box, p, ps.ground.light);
        const bool misses = !(t_far > std::max(t_near, 0.0f)) || glm::dot(n, ps.ground.light) <= 0.0f;
        const glm::vec4 cloud = ps(groundVertex(p, n)), fog = ps.ground(groundVertex(p, n));
        if (misses) {
            ++missed;
            ASSERT_EQ(std::memcmp(&cloud, &fog, sizeof cloud), 0) << "at (" << p.x << ", " << p.y << ", " << p.z << ")";
        } else {
            hit += cloud.x < fog.x;
        }
    }
    EXPECT_GT(missed, 1000);
    EXPECT_GT(hit, 100) << "some points should lie in the shadow";
}

namespace {

// A homogeneous cube of n³ voxels, μ = mu per voxel everywhere inside its box [0, n]³ (the trilinear
// field is constant: every voxel holds the same density), majorant cells of 4 voxels.
CloudVolume homogeneousVolume(int n, float mu) {
    const VoxelGrid grid(glm::ivec3(n), VoxelBox{glm::vec3(0.0f), glm::vec3(1.0f)},
                         std::vector<float>(size_t(n) * n * n, 1.0f));
    return makeCloudVolume(grid, mu, 4);
}

VolumeLight pointLightAt(const glm::vec3& position, const glm::vec3& intensity, float g = 0.0f) {
    VolumeLight light;
    light.kind = LightKind::point;
    light.position = position, light.intensity = intensity;
    light.g = g, light.albedo = 1.0f;
    return light;
}

// The march without terminations or skipped shadow rays: every shadow ray cast to its end.
CloudMarchSettings exactSettings() {
    CloudMarchSettings s;
    s.minTransmittance = 0.0f, s.shadowMaxDepth = INFINITY, s.shadowBudget = 0.0f;
    return s;
}

}  // namespace

TEST(PointLight, InverseSquareFalloffInAVacuum) {
    const glm::vec3 intensity{8.0f, 4.0f, 2.0f}, at{1.0f, 2.0f, 3.0f};
    const VolumeLight light = pointLightAt(at, intensity);
    for (float r : {0.5f, 1.0f, 2.0f, 10.0f, 1000.0f}) {
        const glm::vec3 dir = glm::normalize(glm::vec3(0.3f, -0.8f, 0.52f));
        const LightAtPoint seen = lightAt(light, at - dir * r);
        EXPECT_NEAR(seen.distance, r, r * 1e-6f);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(seen.irradiance[c], intensity[c] / (r * r), intensity[c] / (r * r) * 1e-5f);
        EXPECT_NEAR(glm::dot(seen.toLight, dir), 1.0f, 1e-6f) << "towards the light";
    }
    // Through an optically thin cube (1 − e^{−μ·4} = 4e-4): the scattered radiance falls with the
    // square of the light's distance, 1/4 at twice the distance.
    const CloudVolume v = homogeneousVolume(4, 1e-4f);
    const glm::vec3 eye{2.0f, 2.0f, 40.0f}, d{0.0f, 0.0f, -1.0f};
    auto radianceWithLightAt = [&](float r) {
        return marchCloud(v, pointLightAt(glm::vec3(2.0f) + glm::vec3(r, 0.0f, 0.0f), intensity), exactSettings(), eye, d)
            .radiance;
    };
    const glm::vec3 near = radianceWithLightAt(200.0f), far = radianceWithLightAt(400.0f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(far[c] / near[c], 0.25f, 0.25f * 1e-3f);
}

TEST(PointLight, ShadowRayThroughAHomogeneousSlabEndsAtTheLight) {
    // Every sample's shadow transmittance is e^{−μ·(its shadow ray's length inside the box)}: to the
    // box's exit for a light outside the box, to the light for one inside it.
    constexpr int kN = 16;
    constexpr float kMu = 0.05f;  // per voxel
    const CloudVolume v = homogeneousVolume(kN, kMu);
    const glm::vec3 eye{5.3f, 7.1f, 60.0f}, d = glm::normalize(glm::vec3(0.1f, 0.05f, -1.0f));
    for (const glm::vec3& light_at : {glm::vec3(8.0f, 40.0f, 9.0f), glm::vec3(9.0f, 11.0f, 6.5f)}) {
        const VolumeLight light = pointLightAt(light_at, glm::vec3(100.0f));
        uint32_t samples = 0;
        marchCloud(v, light, exactSettings(), eye, d, [&](const MarchSample& s) {
            const glm::vec3 x = eye + d * s.s, l = glm::normalize(light_at - x);
            const auto [t_near, t_far] = slabInterval(v.box, x, l);
            const float inside = std::min(t_far, glm::length(light_at - x));
            ASSERT_GT(inside, 0.0f);
            EXPECT_NEAR(s.shadowTransmittance, std::exp(-kMu * inside), 2e-6f) << "sample " << s.index;
            ++samples;
        });
        EXPECT_GT(samples, 4u);
    }
}

TEST(PointLight, PhaseAngleIsBetweenTheViewRayAndTheLightsDirection) {
    // A thin cube seen along d, the light far away (r = 2000 voxels, so l is nearly the same over the
    // cube) behind it (l = d: forward scattering towards the eye), beside it, and on the eye's side:
    // L ≈ albedo·p(d·l)·(I/r²)·(1 − e^{−μ·4}), and g > 0 makes the light behind the cube shine through.
    const CloudVolume v = homogeneousVolume(4, 1e-4f);
    const glm::vec3 centre(2.0f), eye = centre + glm::vec3(0.0f, 0.0f, 30.0f), d{0.0f, 0.0f, -1.0f};
    const float r = 2000.0f, intensity = 4e6f;
    for (float g : {0.7f, -0.5f}) {
        float radiance[3];
        int k = 0;
        for (const glm::vec3& l : {d, glm::vec3(1.0f, 0.0f, 0.0f), -d}) {
            const VolumeLight light = pointLightAt(centre + l * r, glm::vec3(intensity), g);
            radiance[k] = marchCloud(v, light, exactSettings(), eye, d).radiance.x;
            const float expected = henyeyGreenstein(g, glm::dot(d, l)) * intensity / (r * r) * -std::expm1(-4e-4f);
            EXPECT_NEAR(radiance[k], expected, expected * 2e-3f) << "g " << g << ", light " << k;
            ++k;
        }
        if (g > 0.0f) EXPECT_GT(radiance[0], 10.0f * radiance[2]) << "forward scattering: the light behind";
        else EXPECT_GT(radiance[2], 5.0f * radiance[0]) << "backward scattering: the light on the eye's side";
    }
}

TEST(PointLight, FarAwayItIsTheDirectionalLight) {
    // A point light R voxels away along toLight with intensity E·R² against the directional light of
    // irradiance E, through the generated cloud, every shadow ray cast: the same radiance to the
    // light's spread over the box (its direction varies by 32/R radians, its irradiance by 2·32/R).
    const CloudVolume v = testVolume();
    const VolumeLight sun = testLight();
    constexpr float kR = 1e5f;
    VolumeLight point = sun;
    point.kind = LightKind::point;
    point.position = glm::vec3(kVoxels * 0.5f) + sun.toLight * kR;
    point.intensity = sun.sun * (kR * kR);
    float worst = 0.0f, largest = 0.0f;
    for (const Ray& ray : testRays(300)) {
        const MarchResult a = marchCloud(v, sun, exactSettings(), ray.o, ray.d);
        const MarchResult b = marchCloud(v, point, exactSettings(), ray.o, ray.d);
        EXPECT_FLOAT_EQ(a.transmittance, b.transmittance);
        for (int c = 0; c < 3; ++c) {
            worst = std::max(worst, std::abs(a.radiance[c] - b.radiance[c]));
            largest = std::max(largest, a.radiance[c]);
        }
    }
    EXPECT_GT(largest, 0.5f);
    EXPECT_LT(worst, 2e-3f * largest);
}

TEST(CloudScene, PointLitCloudSameBitsAtOneTwoAndEightThreads) {
    const SceneOptions o = smallCloud();
    const std::vector<uint8_t> one = renderSceneBytes("cloud-point", o, 1);
    EXPECT_EQ(renderSceneBytes("cloud-point", o, 2), one);
    EXPECT_EQ(renderSceneBytes("cloud-point", o, 8), one);
    // The light under the cloud lights its underside: some pixels well above the night sky.
    uint32_t lit = 0;
    for (size_t p = 0; p < one.size(); p += 4) lit += one[p] > 60;
    EXPECT_GT(lit, one.size() / 4 / 200);
}

TEST(CloudScene, PointLightInTheSunsPlaceLightsTheGround) {
    // `cloud` with a point light 0.6 m above the ground near the eye: the same bits at 1, 2 and
    // 8 threads; the ground near it brighter than the same light at intensity 0 (the ambient term
    // alone), by more on the pixels nearer the light: its 1/r² falloff.
    SceneOptions o = smallCloud();
    o.light = SceneLight{true, {0.0f, 0.6f, 1.0f}};
    o.lightIntensity = glm::vec3(6.0f);
    const std::vector<uint8_t> lit = renderSceneBytes("cloud", o, 1);
    EXPECT_EQ(renderSceneBytes("cloud", o, 2), lit);
    EXPECT_EQ(renderSceneBytes("cloud", o, 8), lit);
    o.lightIntensity = glm::vec3(0.0f);
    const std::vector<uint8_t> dark = renderSceneBytes("cloud", o, 2);
    // The ground below the light: the bottom rows, middle columns; farther: the rows above them.
    auto brighter = [&](uint32_t y0, uint32_t y1) {
        double sum = 0.0;
        uint32_t n = 0;
        for (uint32_t y = y0; y < y1; ++y)
            for (uint32_t x = 60; x < 100; ++x, ++n) {
                const size_t p = (size_t(y) * o.width + x) * 4;
                sum += double(lit[p + 1]) - double(dark[p + 1]);
            }
        return sum / n;
    };
    const double near = brighter(80, 90), far = brighter(55, 62);
    EXPECT_GT(near, 8.0) << "the ground under the light should be lit";
    EXPECT_GT(near, 2.0 * far) << "nearer the light, brighter";
    for (size_t p = 0; p < lit.size(); ++p) ASSERT_GE(lit[p] + 1, dark[p]) << "a light that darkens, byte " << p;
}
