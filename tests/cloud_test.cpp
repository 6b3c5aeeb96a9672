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

std::vector<uint8_t> renderBytes(const std::string& scene, const SceneOptions& options, uint32_t threads) {
    auto s = makeScene(scene, options);
    Context context({threads});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    s->render(context, color, depth);
    return {color.rgba8(), color.rgba8() + size_t(options.width) * options.height * 4};
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
    const std::vector<uint8_t> one = renderBytes("cloud", o, 1);
    EXPECT_EQ(renderBytes("cloud", o, 2), one);
    EXPECT_EQ(renderBytes("cloud", o, 8), one);
    // The ground alone: the fog scene from the cloud's camera. The cloud changes a good share of the
    // pixels and leaves the others exactly as the ground left them (its blend adds 0 there).
    SceneOptions ground = o;
    ground.camera = defaultCamera("cloud");
    const std::vector<uint8_t> fog = renderBytes("fog", ground, 1);
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
    EXPECT_EQ(renderBytes("cloud", file, 2), renderBytes("cloud", smallCloud(), 2));
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
