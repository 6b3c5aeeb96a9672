// Particle volumes (raster/media/particle_volume.hpp, src/particle_volume.cpp) and the `smoke-volume`
// scene (src/scene_smoke_volume.cpp, raster/shaders/smoke_volume.hpp): the kernel carries its mass
// (analytically and on the grid), peaks at the centre and ends at its radius, splats add, the grid is
// the same bits for any thread count and slab size, no particles make an empty volume that the march
// skips whole, bad input is named; the scene is the same bits at 1, 2 and 8 threads, is the smoke
// scene's ground where there are no particles, and ends its march at the surface.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "raster/media/cloud_march.hpp"
#include "raster/media/particle_volume.hpp"
#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"
#include "raster/shaders/smoke_volume.hpp"
#include "raster/thread_pool.hpp"
#include "scene_bytes.hpp"
#include "smoke_world.hpp"

using namespace raster;
using namespace raster::media;

namespace {

// A grid of 0.1 m cubes, 24 a side, centred on the origin.
SplatGrid testGrid(int n = 24) {
    SplatGrid g;
    g.dims = glm::ivec3(n);
    g.bounds = {glm::vec3(-0.05f * float(n)), glm::vec3(0.05f * float(n))};
    return g;
}

double gridMass(const VoxelGrid& v) {
    const glm::vec3 cell = v.cellSize();
    const glm::ivec3 n = v.dims();
    double sum = 0.0;
    for (int k = 0; k < n.z; ++k)
        for (int j = 0; j < n.y; ++j)
            for (int i = 0; i < n.x; ++i) sum += double(v.voxel(i, j, k));
    return sum * double(cell.x) * double(cell.y) * double(cell.z);
}

std::vector<ParticleSplat> randomSplats(int count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> at(-1.3f, 1.3f), radius(0.0f, 0.5f), mass(0.0f, 0.2f);
    std::vector<ParticleSplat> splats;
    for (int i = 0; i < count; ++i) splats.push_back({{at(rng), at(rng), at(rng)}, radius(rng), mass(rng)});
    return splats;
}

bool sameBits(const VoxelGrid& a, const VoxelGrid& b) {
    const glm::ivec3 n = a.dims();
    return n == b.dims() &&
           std::memcmp(a.floatData(), b.floatData(), size_t(n.x) * n.y * n.z * sizeof(float)) == 0;
}

// The message of the Error that f throws (empty if it throws none).
template <class F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        return e.what();
    }
    return "";
}

SceneOptions smallSmoke() {
    SceneOptions o;
    o.width = 160, o.height = 90, o.voxels = 48u;
    return o;
}

}  // namespace

// ∫W dV = ∫₀^R 4πr²·W(r) dr = 1 (Simpson's rule in double, 2·10⁴ intervals: its error ~1e-16 on each
// polynomial piece, the pieces meeting at r = R/2, an interval boundary).
TEST(SplatKernel, IntegratesToOneAnalytically) {
    for (const double radius : {0.01, 0.3, 1.0, 7.5}) {
        const int n = 20000;
        const double h = radius / n;
        double sum = 0.0;
        for (int i = 0; i <= n; ++i) {
            const double r = i * h;
            const double f = 4.0 * M_PI * r * r * splatKernel(r, radius);
            sum += f * (i == 0 || i == n ? 1.0 : i % 2 == 1 ? 4.0 : 2.0);
        }
        EXPECT_NEAR(sum * h / 3.0, 1.0, 1e-12) << "R = " << radius;
    }
}

TEST(SplatKernel, PeaksAtTheCentreFallsAndEndsAtItsRadius) {
    const float radius = 0.4f;
    EXPECT_FLOAT_EQ(splatKernel(0.0f, radius), 8.0f / (float(M_PI) * radius * radius * radius));
    float previous = splatKernel(0.0f, radius);
    for (int i = 1; i <= 1000; ++i) {
        const float w = splatKernel(radius * float(i) / 1000.0f, radius);
        EXPECT_LT(w, previous) << "r = " << radius * float(i) / 1000.0f;
        previous = w;
    }
    for (int i = 0; i <= 1000; ++i) EXPECT_EQ(splatKernel(radius * (1.0f + float(i) / 1000.0f), radius), 0.0f);
    // The two pieces meet at r = R/2 (value 2/(πR³)).
    EXPECT_NEAR(splatKernel(0.5 * 0.4 - 1e-12, 0.4), splatKernel(0.5 * 0.4 + 1e-12, 0.4), 1e-9);
}

// On the grid: Σ voxels·cell volume = m within 0.5 % for splats 2 to 8 voxels in radius, anywhere
// between the voxels' centres (the midpoint rule on a C² kernel).
TEST(ParticleVolume, GridCarriesTheSplatsMass) {
    const SplatGrid grid = testGrid();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> offset(-0.05f, 0.05f), cells(2.0f, 8.0f);
    double worst = 0.0;
    for (int t = 0; t < 200; ++t) {
        const ParticleSplat s{{offset(rng), offset(rng), offset(rng)}, 0.1f * cells(rng), 0.7f};
        const double mass = gridMass(splatParticles(std::span(&s, 1), grid));
        worst = std::max(worst, std::abs(mass / 0.7 - 1.0));
    }
    EXPECT_LT(worst, 0.005);
    // A splat narrower than two voxels is widened to two (its mass kept), not lost between the centres.
    const ParticleSplat thin{{0.013f, -0.021f, 0.037f}, 0.01f, 0.7f};
    EXPECT_NEAR(gridMass(splatParticles(std::span(&thin, 1), grid)), 0.7, 0.7 * 0.005);
}

TEST(ParticleVolume, DensityIsLargestAtTheCentreAndZeroOutsideTheSupport) {
    const SplatGrid grid = testGrid();
    const ParticleSplat s{splatCentre(grid, 11, 12, 13), 0.55f, 0.4f};
    const VoxelGrid v = splatParticles(std::span(&s, 1), grid);
    EXPECT_EQ(v.voxel(11, 12, 13), v.maxDensity());
    EXPECT_FLOAT_EQ(v.voxel(11, 12, 13), 0.4f * splatKernel(0.0f, 0.55f));
    size_t inside = 0;
    for (int k = 0; k < 24; ++k)
        for (int j = 0; j < 24; ++j)
            for (int i = 0; i < 24; ++i) {
                const float r = glm::length(splatCentre(grid, i, j, k) - s.position);
                if (r >= 0.55f) {
                    EXPECT_EQ(v.voxel(i, j, k), 0.0f) << i << "," << j << "," << k;
                } else {
                    EXPECT_GT(v.voxel(i, j, k), 0.0f) << i << "," << j << "," << k;
                    EXPECT_LE(v.voxel(i, j, k), v.voxel(11, 12, 13));
                    ++inside;
                }
            }
    EXPECT_GT(inside, 500u);  // 4/3·π·5.5³ ≈ 697 voxels
}

// Voxel by voxel, the grid of A and B is the grid of A plus the grid of B (0 + a + b in splat order:
// the same float sum), and every voxel is splatDensity at its centre.
TEST(ParticleVolume, SplattingTwoParticlesIsTheSum) {
    const SplatGrid grid = testGrid();
    const std::vector<ParticleSplat> both = {{{0.1f, 0.0f, 0.05f}, 0.5f, 0.3f}, {{-0.2f, 0.1f, 0.0f}, 0.4f, 0.6f}};
    const VoxelGrid ab = splatParticles(both, grid);
    const VoxelGrid a = splatParticles(std::span(both).first(1), grid);
    const VoxelGrid b = splatParticles(std::span(both).last(1), grid);
    size_t overlap = 0;
    for (int k = 0; k < 24; ++k)
        for (int j = 0; j < 24; ++j)
            for (int i = 0; i < 24; ++i) {
                const float sum = a.voxel(i, j, k) + b.voxel(i, j, k);
                ASSERT_EQ(ab.voxel(i, j, k), sum) << i << "," << j << "," << k;
                ASSERT_EQ(ab.voxel(i, j, k), splatDensity(both, grid, splatCentre(grid, i, j, k)));
                overlap += a.voxel(i, j, k) > 0.0f && b.voxel(i, j, k) > 0.0f;
            }
    EXPECT_GT(overlap, 100u);
    EXPECT_NEAR(gridMass(ab), 0.9, 0.9 * 0.005);
}

TEST(ParticleVolume, SameBitsForAnyThreadCountAndSlab) {
    const std::vector<ParticleSplat> splats = randomSplats(400, 9);
    const SplatGrid grid = fitSplatGrid(splats, 40);
    const VoxelGrid one = splatParticles(splats, grid);
    EXPECT_GT(one.maxDensity(), 0.0f);
    for (const unsigned threads : {1u, 2u, 8u}) {
        ThreadPool pool(threads);
        for (const int slab : {1, 3, 4, 64}) EXPECT_TRUE(sameBits(splatParticles(splats, grid, &pool, slab), one))
            << threads << " threads, slabs of " << slab;
    }
}

TEST(ParticleVolume, FittedGridHoldsEverySplatWhole) {
    std::vector<ParticleSplat> splats = randomSplats(50, 4);
    splats.push_back({{2.0f, -2.0f, 2.0f}, 0.0f, 0.1f});  // a point, at a corner: widened to two voxels
    const SplatGrid grid = fitSplatGrid(splats, 64);
    const glm::vec3 cell = grid.cellSize();
    EXPECT_EQ(std::max({grid.dims.x, grid.dims.y, grid.dims.z}), 64);
    EXPECT_FLOAT_EQ(cell.x, cell.y);
    EXPECT_FLOAT_EQ(cell.x, cell.z);
    double mass = 0.0;
    for (const ParticleSplat& s : splats) {
        mass += s.mass;
        const float r = grid.drawnRadius(s.radius);
        EXPECT_TRUE(glm::all(glm::lessThanEqual(grid.bounds.lo, s.position - r)));
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(grid.bounds.hi, s.position + r)));
    }
    EXPECT_NEAR(gridMass(splatParticles(splats, grid)), mass, mass * 0.005);
}

// No particles: a volume with no density, whose majorant is 0 everywhere, so that the march skips
// every sample (nothing evaluated) and leaves the ray as it was.
TEST(ParticleVolume, NoParticlesGiveAnEmptyVolumeTheMarchSkips) {
    const SplatGrid fitted = fitSplatGrid({}, 32);
    EXPECT_EQ(fitted.dims, glm::ivec3(1));
    const VoxelGrid grid = splatParticles({}, testGrid());
    EXPECT_EQ(grid.maxDensity(), 0.0f);
    const CloudVolume v = makeCloudVolume(grid, 1.0f, 8);
    for (const float bound : v.majorant.bound) EXPECT_EQ(bound, 0.0f);
    VolumeLight light;
    light.toLight = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
    for (int i = 0; i < 16; ++i) {
        const glm::vec3 eye(-5.0f, 3.0f + 0.5f * float(i), 7.0f);
        const MarchResult r = marchCloud(v, light, CloudMarchSettings{}, eye, glm::normalize(glm::vec3(12.0f) - eye));
        EXPECT_EQ(r.densityEvaluations, 0u);
        EXPECT_EQ(r.transmittance, 1.0f);
        EXPECT_EQ(r.radiance, glm::vec3(0.0f));
    }
}

TEST(ParticleVolume, BadInputIsNamed) {
    const SplatGrid grid = testGrid();
    std::vector<ParticleSplat> splats = randomSplats(3, 2);
    splats[1].position.y = NAN;
    EXPECT_NE(errorOf([&] { splatParticles(splats, grid); }).find("particle 1's position"), std::string::npos);
    EXPECT_NE(errorOf([&] { fitSplatGrid(splats, 32); }).find("particle 1's position"), std::string::npos);
    splats[1].position.y = 0.0f;
    splats[2].radius = -0.1f;
    EXPECT_NE(errorOf([&] { splatParticles(splats, grid); }).find("particle 2's radius (its size"), std::string::npos);
    splats[2].radius = 0.1f;
    splats[0].mass = INFINITY;
    EXPECT_NE(errorOf([&] { splatParticles(splats, grid); }).find("particle 0's mass"), std::string::npos);
    splats[0].mass = 0.1f;
    SplatGrid flat = grid;
    flat.dims.y = 0;
    EXPECT_NE(errorOf([&] { splatParticles(splats, flat); }).find("0 voxels along axis y"), std::string::npos);
    SplatGrid empty = grid;
    empty.bounds.hi.z = empty.bounds.lo.z;
    EXPECT_NE(errorOf([&] { splatParticles(splats, empty); }).find("empty or not finite along z"), std::string::npos);
    EXPECT_NE(errorOf([&] { splatParticles(splats, grid, nullptr, 0); }).find("0 z-slices"), std::string::npos);
    EXPECT_NE(errorOf([&] { fitSplatGrid(splats, 4); }).find("4 voxels along the longest axis"), std::string::npos);
    // From the particle system's upload: a negative size is the splat's negative radius.
    Particle p;
    p.size = -0.2f;
    EXPECT_NE(errorOf([&] { splatParticles(particleSplats(std::span(&p, 1), 1.0f), grid); }).find("radius"),
              std::string::npos);
    SceneOptions o = smallSmoke();
    o.voxels = 4u;
    EXPECT_NE(errorOf([&] { makeScene("smoke-volume", o); }).find("smoke-volume: 4 voxels"), std::string::npos);
    EXPECT_TRUE(errorOf([&] { splatParticles(splats, grid); }).empty());
}

// A particle's splat: R = its size, m = κ·opacity·πR² (header), in the particles' order.
TEST(ParticleVolume, ParticleSplatTakesSizeAndOpacity) {
    std::vector<Particle> particles(2);
    particles[0].position = {1, 2, 3}, particles[0].size = 0.2f, particles[0].colour.a = 0.5f;
    particles[1].position = {-1, 0, 0}, particles[1].size = 0.1f, particles[1].colour.a = 0.0f;
    const std::vector<ParticleSplat> s = particleSplats(particles, 3.0f);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s[0].position, glm::vec3(1, 2, 3));
    EXPECT_EQ(s[0].radius, 0.2f);
    EXPECT_FLOAT_EQ(s[0].mass, 3.0f * 0.5f * float(M_PI) * 0.04f);
    EXPECT_EQ(s[1].mass, 0.0f);
}

TEST(SmokeVolumeScene, SameBitsAtOneTwoAndEightThreads) {
    const SceneOptions o = smallSmoke();
    const std::vector<uint8_t> one = renderSceneBytes("smoke-volume", o, 1);
    EXPECT_EQ(renderSceneBytes("smoke-volume", o, 2), one);
    EXPECT_EQ(renderSceneBytes("smoke-volume", o, 8), one);
    // The smoke covers a good share of the picture, not all of it.
    SceneOptions none = o;
    none.count = 0u;
    const std::vector<uint8_t> ground = renderSceneBytes("smoke-volume", none, 1);
    size_t changed = 0;
    for (size_t p = 0; p < one.size(); p += 4) changed += std::memcmp(&one[p], &ground[p], 4) != 0;
    EXPECT_GT(changed, one.size() / 4 / 20);
    EXPECT_LT(changed, one.size() / 4 * 9 / 10);
}

// Without particles the volume is empty and adds nothing: the smoke scene's ground and box, bit for bit.
TEST(SmokeVolumeScene, WithoutParticlesItIsTheSmokeScenesGround) {
    SceneOptions o = smallSmoke();
    o.count = 0u;
    EXPECT_EQ(renderSceneBytes("smoke-volume", o, 2), renderSceneBytes("smoke", o, 2));
}

// The march ends at the surface behind the pixel: through a homogeneous medium of μ per voxel, the
// transmittance is e^{−μ·(surface − entry)}, the surface placed by the depth the shader reads.
TEST(SmokeVolumeScene, MarchEndsAtTheSurface) {
    const int n = 16;
    const CloudVolume v = makeCloudVolume(VoxelGrid(glm::ivec3(n), VoxelBox{glm::vec3(0.0f), glm::vec3(1.0f)},
                                                    std::vector<float>(size_t(n) * n * n, 1.0f)),
                                          0.05f, 8);
    shaders::PsSmokeVolume ps;
    shaders::PsCloudMarch& m = ps.march;
    const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(60.0f), 1.0f, 0.1f, 100.0f);
    const glm::mat4 view = glm::lookAtRH(glm::vec3(0.5f, 0.5f, 3.0f), glm::vec3(0.5f), glm::vec3(0, 1, 0));
    m.invViewProj = glm::inverse(proj * view);
    m.eye = glm::vec3(0.5f, 0.5f, 3.0f);
    m.voxelsPerMetre = float(n);
    m.volume = &v;
    m.light.sun = glm::vec3(0.0f), m.light.ambient = glm::vec3(0.0f);
    m.settings.minTransmittance = 0.0f;
    const glm::vec3 d(0.0f, 0.0f, -1.0f);  // the centre pixel's ray; the box from 2 m to 3 m ahead
    for (const float surface : {2.25f, 2.5f, 2.9f, 4.0f, 1.5f}) {
        const glm::vec4 clip = proj * view * glm::vec4(0.5f, 0.5f, 3.0f - surface, 1.0f);
        const glm::vec4 c = ps.shade(d, glm::vec2(0.0f), clip.z / clip.w);
        const float inside = std::clamp(surface, 2.0f, 3.0f) - 2.0f;  // metres of medium before it
        EXPECT_NEAR(1.0f - c.a, std::exp(-0.05f * float(n) * inside), 1e-4f) << "surface at " << surface;
    }
}

// The scene's own volume (the smoke's particles at its default count and time, the default grid):
// its voxels plus little (the majorant and the objects), and the particles' mass whole.
TEST(SmokeVolumeScene, VolumeTakesItsVoxelsPlusLittleAndCarriesTheParticlesMass) {
    ParticleSystem system(smokeDesc(kDefaultSmokeCount, 0));
    system.advance(kDefaultSmokeTime);
    const std::vector<Particle> particles = system.vertices();
    const auto start = std::chrono::steady_clock::now();
    const SmokeVolume smoke = makeSmokeVolume(particles, int(kDefaultSmokeVoxels));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const CloudVolume& v = smoke.volume;
    const glm::ivec3 n = v.grid.dims();
    EXPECT_EQ(std::max({n.x, n.y, n.z}), int(kDefaultSmokeVoxels));
    EXPECT_EQ(v.voxelBytes(), uint64_t(n.x) * n.y * n.z * sizeof(float));
    EXPECT_LE(double(v.memoryBytes()), double(v.voxelBytes()) * 1.15);
    std::printf("smoke-volume: %zu particles, %dx%dx%d voxels, %llu bytes of voxels, %llu in all; splatted in %.0f ms\n",
                particles.size(), n.x, n.y, n.z, (unsigned long long)v.voxelBytes(),
                (unsigned long long)v.memoryBytes(), ms);
    double mass = 0.0;
    for (const ParticleSplat& s : particleSplats(particles, kOpticalDepthPerOpacity, kRadiusPerSize)) mass += s.mass;
    EXPECT_GT(mass, 0.0);
    EXPECT_NEAR(gridMass(v.grid), mass, mass * 0.005);
}

// `raster trace smoke-volume --pixel X,Y` and the viewer's march plot: a pixel's recorded march is the
// one its shader ran. Over the ground drawn without particles, the rendered pixel is the march's
// premultiplied colour plus T times that ground (the blend ONE, INV_SRC_ALPHA; within a unit of RGBA8);
// the samples' radiance sums to L, they lie in [t0, t1] in order; and the march ends at the surface
// the render left in the depth: before any render it runs to the volume's far side, further for the
// pixels whose ray meets the ground or the box inside the volume.
TEST(SmokeVolumeScene, PixelMarchIsTheRenderedPixelsMarch) {
    const SceneOptions o = smallSmoke();
    auto scene = makeScene("smoke-volume", o);
    std::vector<std::optional<PixelMarch>> unclipped;
    for (uint32_t y = 3; y < o.height; y += 7)
        for (uint32_t x = 2; x < o.width; x += 5) unclipped.push_back(scene->pixelMarch(x, y, o.width, o.height));
    Context context({2});
    RenderTarget color(o.width, o.height);
    DepthTarget depth(o.width, o.height);
    scene->render(context, color, depth);
    SceneOptions none = o;
    none.count = 0u;
    const std::vector<uint8_t> ground = renderSceneBytes("smoke-volume", none, 2);
    size_t marched = 0, cut = 0, k = 0;
    for (uint32_t y = 3; y < o.height; y += 7) {
        for (uint32_t x = 2; x < o.width; x += 5, ++k) {
            const std::optional<PixelMarch> m = scene->pixelMarch(x, y, o.width, o.height);
            ASSERT_TRUE(m.has_value() && unclipped[k].has_value());
            const size_t p = (size_t(y) * o.width + x) * 4;
            for (int c = 0; c < 3; ++c) {
                const float expected = m->colour[c] + m->transmittance * float(ground[p + size_t(c)]) / 255.0f;
                EXPECT_NEAR(float(color.rgba8()[p + size_t(c)]), 255.0f * std::min(expected, 1.0f), 1.01f)
                    << "pixel (" << x << ", " << y << ") channel " << c;
            }
            glm::vec3 sum(0.0f);
            float last = m->t0;
            for (const media::MarchSample& s : m->samples) {
                sum += s.added;
                EXPECT_GE(s.s, last * (1.0f - 1e-6f));
                EXPECT_LE(s.s, m->t1 * (1.0f + 1e-6f));
                last = s.s;
            }
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], m->radiance[c], 1e-4f + 1e-4f * m->radiance[c]);
            EXPECT_LE(m->t1, unclipped[k]->t1 * (1.0f + 1e-6f));
            marched += !m->samples.empty();
            cut += m->t1 > m->t0 && m->t1 < unclipped[k]->t1 * (1.0f - 1e-3f);
        }
    }
    EXPECT_GT(marched, k / 10) << "pixels whose ray meets smoke";
    EXPECT_GT(cut, 0u) << "pixels whose march the ground or box ends early";
}
