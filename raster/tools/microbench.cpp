// raster microbench [google benchmark flags]: per-stage microbenchmarks (Google Benchmark), each
// reporting a rate (items per second) for docs/PERFORMANCE.md:
//   Setup      toScreen + setupTriangle over 64k small random clip-space triangles   items = triangles
//   Binning    binTriangle of those setups into a 1280×720 TileGrid                  items = triangles
//   Coverage   rasterizeTriangle over one 64×64 tile, counting covered lanes          items = pixels
//   Fragments  a full-screen quad (2 triangles) at 1280×720 through a Context         items = pixels
//   Blend/Merge/Depth  the output merger's arithmetic over a 1280×720 buffer          items = pixels
//   Gs/FrontEnd  runGeometryShader(GsBillboard), and the particles scene at 64×36     items = points
//   Sample     Texture2D::Sample / SampleLevel                                          items = samples
//   Scene      whole frames of the two benchmark scenes at 1280×720                   items = frames
//   Particles  simulation steps, upload and depth sorts of 10^6 particles (microbench_particles.cpp)
//   Media      phase functions and ψ, float against Float8, per value (microbench_media.cpp)
// A program of its own, build/bin/raster-microbench, that `raster microbench` runs (microbench_command.cpp):
// its two full-screen draws instantiate the pipeline twice, a third of the time `raster` alone takes to
// compile, so the README's first command, which builds `raster`, does not build it. All data is made
// before the timed loops.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "options.hpp"
#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"
#include "raster/shaders/basic.hpp"
#include "lecture/fire_shaders.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shaders/billboard.hpp"

namespace raster::tools {

void registerMediaBenchmarks();     // microbench_media.cpp
void registerParticleBenchmarks();  // microbench_particles.cpp

namespace {

constexpr uint32_t kWidth = 1280, kHeight = 720;
constexpr size_t kPixels = size_t(kWidth) * kHeight;
constexpr uint32_t kTriangles = 64 * 1024;

const PixelRect kScreen{0, 0, int32_t(kWidth) - 1, int32_t(kHeight) - 1};

RasterizerState noCull() {
    RasterizerState rs;
    rs.cullMode = CullMode::None;  // set up both windings: no triangle leaves early as culled
    return rs;
}

// ---- 1. Triangle setup ------------------------------------------------------------------------------

// 64k triangles a few pixels across (edges up to ~16 px), anywhere on a 1280×720 screen, at random
// depths (w in [0.5, 4]), random winding.
const std::vector<glm::vec4>& clipTriangles() {
    static const std::vector<glm::vec4> triangles = [] {
        std::mt19937 rng(1234);
        std::uniform_real_distribution<float> centre(-0.98f, 0.98f), offset(-8.0f, 8.0f), w(0.5f, 4.0f),
            z(0.05f, 0.95f);
        std::vector<glm::vec4> v;
        v.reserve(3 * kTriangles);
        for (uint32_t t = 0; t < kTriangles; ++t) {
            const float cx = centre(rng), cy = centre(rng), cw = w(rng), cz = z(rng);
            for (int k = 0; k < 3; ++k) {
                const float x = cx + offset(rng) * 2.0f / kWidth, y = cy + offset(rng) * 2.0f / kHeight;
                v.emplace_back(x * cw, y * cw, cz * cw, cw);
            }
        }
        return v;
    }();
    return triangles;
}

void BM_Setup(benchmark::State& state) {
    const std::vector<glm::vec4>& v = clipTriangles();
    const ViewportTransform vp(Viewport{0, 0, float(kWidth), float(kHeight), 0, 1});
    const RasterizerState rs = noCull();
    uint64_t ok = 0;
    for (auto _ : state) {
        for (uint32_t i = 0; i < kTriangles; ++i) {
            const ScreenVertex s[3] = {toScreen(v[3 * i], vp), toScreen(v[3 * i + 1], vp), toScreen(v[3 * i + 2], vp)};
            const uint32_t idx[3] = {3 * i, 3 * i + 1, 3 * i + 2};
            TriangleSetup t;
            ok += setupTriangle(s, idx, i, rs, kScreen, t) == SetupResult::Ok;
            benchmark::DoNotOptimize(t);
        }
    }
    benchmark::DoNotOptimize(ok);
    state.SetItemsProcessed(int64_t(state.iterations()) * kTriangles);
    state.counters["ok_share"] = double(ok) / double(uint64_t(state.iterations()) * kTriangles);
}

// The triangles of clipTriangles() that set up (all but the degenerate and empty ones).
const std::vector<TriangleSetup>& setups() {
    static const std::vector<TriangleSetup> out = [] {
        const std::vector<glm::vec4>& v = clipTriangles();
        const ViewportTransform vp(Viewport{0, 0, float(kWidth), float(kHeight), 0, 1});
        std::vector<TriangleSetup> r;
        for (uint32_t i = 0; i < kTriangles; ++i) {
            const ScreenVertex s[3] = {toScreen(v[3 * i], vp), toScreen(v[3 * i + 1], vp), toScreen(v[3 * i + 2], vp)};
            const uint32_t idx[3] = {3 * i, 3 * i + 1, 3 * i + 2};
            TriangleSetup t;
            if (setupTriangle(s, idx, i, noCull(), kScreen, t) == SetupResult::Ok) r.push_back(t);
        }
        return r;
    }();
    return out;
}

// ---- 2. Tile binning --------------------------------------------------------------------------------

void BM_Binning(benchmark::State& state) {
    const std::vector<TriangleSetup>& ts = setups();
    const TileGrid grid(kScreen);
    std::vector<std::vector<uint32_t>> bins(grid.count());
    uint64_t binned = 0, rejected = 0;
    for (auto _ : state) {
        for (auto& b : bins) b.clear();  // keeps capacity, as the pipeline's chunks do
        for (uint32_t i = 0; i < uint32_t(ts.size()); ++i)
            binTriangle(
                ts[i], grid, [&](uint32_t tile) { bins[tile].push_back(binEntry(PrimitiveKind::Triangle, i)); },
                binned, rejected);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(ts.size()));
    state.counters["tiles_per_tri"] = double(binned) / double(uint64_t(state.iterations()) * ts.size());
}

// ---- 3. Coverage ------------------------------------------------------------------------------------

const PixelRect kTile{0, 0, kTileSize - 1, kTileSize - 1};

TriangleSetup setupInTile(const glm::dvec2 (&p)[3]) {
    ScreenVertex s[3];
    // Depth varies (0.4, 0.5, 0.6): a triangle of one depth would take interpolateDepth's shortcut.
    for (int k = 0; k < 3; ++k) s[k] = {snap(p[k].x), snap(p[k].y), 0.4f + 0.1f * float(k), 1.0f};
    const uint32_t idx[3] = {0, 1, 2};
    TriangleSetup t;
    RASTER_CHECK(setupTriangle(s, idx, 0, noCull(), kTile, t) == SetupResult::Ok);
    return t;
}

// 256 triangles of 20 px area (equilateral, random rotation and sub-pixel position) inside the tile.
std::vector<TriangleSetup> smallTriangles() {
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> centre(6.0, 58.0), angle(0.0, 6.283185307179586);
    const double r = std::sqrt(4.0 * 20.0 / (3.0 * std::sqrt(3.0)));  // circumradius of area 20
    std::vector<TriangleSetup> out;
    while (out.size() < 256) {
        const glm::dvec2 c(centre(rng), centre(rng));
        const double a = angle(rng);
        glm::dvec2 p[3];
        for (int k = 0; k < 3; ++k) {
            const double ak = a + k * 2.0943951023931953;
            p[k] = c + r * glm::dvec2(std::cos(ak), std::sin(ak));
        }
        out.push_back(setupInTile(p));
    }
    return out;
}

// One triangle that covers the whole tile (its hypotenuse runs outside the far corner).
std::vector<TriangleSetup> largeTriangles() {
    const glm::dvec2 p[3] = {{-1.0, -1.0}, {130.0, -1.0}, {-1.0, 130.0}};
    return {setupInTile(p)};
}

void BM_Coverage(benchmark::State& state, std::vector<TriangleSetup> (*make)()) {
    const std::vector<TriangleSetup> ts = make();
    std::vector<EdgeSteps> steps;
    for (const TriangleSetup& t : ts) steps.push_back(edgeSteps(t));
    uint64_t pixels = 0, quads = 0;
    for (auto _ : state) {
        for (size_t i = 0; i < ts.size(); ++i)
            rasterizeTriangle(ts[i], steps[i], kTile, [&](const Quad& q) {
                pixels += uint64_t(std::popcount(q.mask));
                ++quads;
            });
        benchmark::DoNotOptimize(pixels);
        benchmark::DoNotOptimize(quads);
    }
    const double tris = double(state.iterations()) * double(ts.size());
    state.SetItemsProcessed(int64_t(pixels));
    state.counters["quads"] = benchmark::Counter(double(quads), benchmark::Counter::kIsRate);
    state.counters["tris"] = benchmark::Counter(tris, benchmark::Counter::kIsRate);
    state.counters["px_per_tri"] = double(pixels) / tris;
}

// ---- 4. Fragments through a Context ---------------------------------------------------------------

struct QuadIn {
    glm::vec3 position;
    glm::vec2 tex;
    RASTER_INPUT_SIGNATURE(QuadIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(tex, "TEXCOORD", 0))
};

struct VsQuad {
    shaders::BillboardCorner operator()(const QuadIn& in) const { return {glm::vec4(in.position, 1.0f), in.tex}; }
};

// A full-screen quad, two triangles, blending and depth off.
struct FullScreenQuad {
    VertexBuffer vertices;
    InputLayout positionLayout, texturedLayout;
    RenderTarget color{kWidth, kHeight};
    Context context;

    explicit FullScreenQuad(unsigned threads) : context({threads, false}) {
        const std::vector<QuadIn> v = {{{-1, -1, 0.5f}, {0, 1}}, {{-1, 1, 0.5f}, {0, 0}}, {{1, 1, 0.5f}, {1, 0}},
                                       {{-1, -1, 0.5f}, {0, 1}}, {{1, 1, 0.5f}, {1, 0}},  {{1, -1, 0.5f}, {1, 1}}};
        vertices = VertexBuffer::create(v);
        const InputElementDesc pos[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
        const InputElementDesc tex[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                        {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, 12}};
        positionLayout = InputLayout(pos);
        texturedLayout = InputLayout(tex);
        color.clear({0, 0, 0, 1});
        context.setRenderTargets(&color, nullptr);
        context.setViewport({0, 0, float(kWidth), float(kHeight), 0, 1});
        context.setRasterizerState(noCull());
        context.setBlendState(BlendState::opaque());
        context.setDepthStencilState(DepthStencilState::disabled());
        context.setPrimitiveTopology(Topology::TriangleList);
        context.setVertexBuffer(0, &vertices);
    }
};

template <class VS, class PS>
void runFragments(benchmark::State& state, FullScreenQuad& q, const VS& vs, const PS& ps) {
    q.context.draw(vs, ps, 6);  // warm-up (scratch buffers, thread pool)
    if (q.context.drawStatistics().psInvocations != kPixels) {
        state.SkipWithError("the full-screen quad did not shade every pixel exactly once");
        return;
    }
    for (auto _ : state) {
        q.context.draw(vs, ps, 6);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kPixels));
}

void BM_FragmentsConstant(benchmark::State& state) {
    FullScreenQuad q(unsigned(state.range(0)));
    q.context.setInputLayout(&q.positionLayout);
    shaders::PsConstant ps;
    ps.color = {0.9f, 0.5f, 0.2f, 1.0f};
    runFragments(state, q, shaders::VsTransform{}, ps);
}

void BM_FragmentsFire(benchmark::State& state) {
    FullScreenQuad q(unsigned(state.range(0)));
    q.context.setInputLayout(&q.texturedLayout);
    const Texture2D fire = makeFireTexture();
    shaders::PsFire ps;
    ps.billboardTexture = &fire;
    runFragments(state, q, VsQuad{}, ps);
}

// ---- 5. Blend and depth -----------------------------------------------------------------------------

constexpr size_t kSources = 4096;  // a power of two

std::vector<glm::vec4> randomColors(uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> c(-0.1f, 1.1f);  // some out of [0, 1], to exercise the clamps
    std::vector<glm::vec4> out(kSources);
    for (glm::vec4& v : out) v = {c(rng), c(rng), c(rng), c(rng)};
    return out;
}

template <class Blender>
void BM_BlendFast(benchmark::State& state) {
    const std::vector<glm::vec4> src = randomColors(7);
    std::vector<uint8_t> buffer(4 * kPixels, 64);
    uint8_t* pixels = buffer.data();
    for (auto _ : state) {
        for (size_t i = 0; i < kPixels; ++i) Blender::apply(pixels + 4 * i, src[i & (kSources - 1)]);
        benchmark::ClobberMemory();
    }
    benchmark::DoNotOptimize(pixels);
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kPixels));
}

// The generic path: alpha blending (SrcAlpha, InvSrcAlpha, Add), no fast blender for it.
template <class Real>
void BM_MergeFragment(benchmark::State& state) {
    const std::vector<glm::vec4> src = randomColors(8);
    RenderTarget rt(kWidth, kHeight);
    rt.clear({0.25f, 0.5f, 0.75f, 1.0f});
    const RenderTargetBlendDesc d = BlendState::alphaBlend().target(0);
    const glm::vec4 src1(0.0f), factor(1.0f);
    for (auto _ : state) {
        size_t i = 0;
        for (uint32_t y = 0; y < kHeight; ++y)
            for (uint32_t x = 0; x < kWidth; ++x, ++i)
                mergeFragment<Real>(rt, x, y, d, src[i & (kSources - 1)], src1, factor);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kPixels));
}

// The depth test alone (no write, so the buffer stays random and about half the fragments pass).
void BM_DepthLess(benchmark::State& state) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> z(0.0f, 1.0f);
    std::vector<float> depth(kPixels), fragments(kSources);
    for (float& d : depth) d = z(rng);
    for (float& f : fragments) f = z(rng);
    uint64_t passed = 0;
    for (auto _ : state) {
        const float* d = depth.data();
        benchmark::DoNotOptimize(d);
        for (size_t i = 0; i < kPixels; ++i)
            passed += depthPassesT<ComparisonFunc::Less>(fragments[i & (kSources - 1)], d[i]);
        benchmark::DoNotOptimize(passed);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kPixels));
    state.counters["pass_share"] = double(passed) / (double(state.iterations()) * double(kPixels));
}

// ---- 6. Geometry shader and the front end -----------------------------------------------------------

constexpr uint32_t kParticles = 100'000;

// The particles scene's GsBillboard (same camera) over its first 100k particles. Arg quad = 0: the
// strip is cut into two triangles (the reference pipeline's way); 1: offered whole as a quad and
// taken (the fast pipeline's billboard rectangles).
void BM_GeometryShader(benchmark::State& state) {
    const bool take_quad = state.range(0) != 0;
    std::vector<shaders::BillboardVertex> points(kParticles);
    for (uint32_t i = 0; i < kParticles; ++i) points[i].position = glm::vec4(particlePosition(i), 1.0f);
    shaders::GsBillboard gs;
    const glm::mat4 view = glm::lookAtRH(glm::vec3(0, 0.3f, 4), glm::vec3(0), glm::vec3(0, 1, 0));
    const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(60.0f), float(kWidth) / float(kHeight), 0.1f, 100.0f);
    gs.viewProj = proj * view;
    gs.billboardSize = {0.08f * proj[0][0], 0.08f * proj[1][1]};
    auto stream = std::make_unique<GeometryShaderStream<shaders::GsBillboard>>();
    uint64_t primitives = 0;
    float sink = 0;
    for (auto _ : state) {
        for (uint32_t i = 0; i < kParticles; ++i) {
            const std::array<shaders::BillboardVertex, 1> in = {points[i]};
            runGeometryShader(
                gs, in, *stream,
                [&](PrimitiveKind, const shaders::BillboardCorner* const* v) {
                    ++primitives;
                    sink += v[0]->position.x + v[2]->tex.y;
                },
                [&](const shaders::BillboardCorner* const* quad) {
                    if (!take_quad) return false;
                    primitives += 2;
                    sink += quad[0]->position.x + quad[3]->tex.y;
                    return true;
                });
        }
        benchmark::DoNotOptimize(sink);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * kParticles);
    state.counters["prims_per_point"] = double(primitives) / (double(state.iterations()) * kParticles);
}

// Whole scenes: one frame per iteration on range(0) threads. Items are frames, except for the
// front-end run (particles, 100k, at 64×36 so that shading is negligible), whose items are particles.
void runScene(benchmark::State& state, const char* name, const SceneOptions& options, int64_t items_per_frame) {
    std::unique_ptr<Scene> scene = makeScene(name, options);
    Context context({unsigned(state.range(0)), false});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    scene->render(context, color, depth);  // warm-up
    for (auto _ : state) {
        scene->render(context, color, depth);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * items_per_frame);
}

void BM_FrontEndParticles(benchmark::State& state) {
    SceneOptions o;
    o.width = 64, o.height = 36, o.count = kParticles;
    runScene(state, "particles", o, kParticles);
}

void BM_SceneParticles(benchmark::State& state) {
    SceneOptions o;  // 1280×720, 10k particles
    runScene(state, "particles", o, 1);
}

void BM_SceneFog(benchmark::State& state) {
    SceneOptions o;  // 1280×720, 16×16 cubes, height fog
    runScene(state, "fog", o, 1);
}

// ---- 7. Texture sampling ----------------------------------------------------------------------------

std::vector<glm::vec2> randomUvs() {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uv(-0.05f, 1.05f);  // a little outside, for the clamp
    std::vector<glm::vec2> out(kSources);
    for (glm::vec2& v : out) v = {uv(rng), uv(rng)};
    return out;
}

void BM_SampleBilinear(benchmark::State& state) {
    const Texture2D fire = makeFireTexture();
    const SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);
    const std::vector<glm::vec2> uv = randomUvs();
    glm::vec4 sum(0.0f);
    for (auto _ : state) {
        for (const glm::vec2& p : uv) sum += fire.Sample(sampler, p);
        benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(uv.size()));
}

// The eight-wide Sample the particles scene's PsFire runs on billboard rectangles.
void BM_SampleBilinearWide(benchmark::State& state) {
    const Texture2D fire = makeFireTexture();
    const SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);
    const std::vector<glm::vec2> uv = randomUvs();
    std::vector<glm::vec<2, Float8>> uv8(uv.size() / 8);
    for (size_t i = 0; i < uv8.size(); ++i)
        for (int l = 0; l < 8; ++l) uv8[i].x.set(l, uv[8 * i + l].x), uv8[i].y.set(l, uv[8 * i + l].y);
    glm::vec<4, Float8> sum(Float8(0.0f));
    for (auto _ : state) {
        for (const auto& p : uv8) {
            const glm::vec<4, Float8> c = fire.Sample(sampler, p);
            sum.x += c.x, sum.y += c.y, sum.z += c.z, sum.w += c.w;
        }
        benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(8 * uv8.size()));
}

void BM_SampleLevelTrilinear(benchmark::State& state) {
    constexpr uint32_t kSize = 256;
    std::mt19937 rng(3);
    std::vector<uint8_t> texels(4 * kSize * kSize);
    for (uint8_t& t : texels) t = uint8_t(rng());
    const Texture2D texture = Texture2D::fromRgba8(kSize, kSize, texels, true);
    const SamplerState sampler = SamplerState::linear(AddressMode::Clamp);
    const std::vector<glm::vec2> uv = randomUvs();
    std::vector<float> lod(uv.size());
    std::uniform_real_distribution<float> l(0.0f, float(texture.mipLevels() - 1));
    for (float& x : lod) x = l(rng);
    glm::vec4 sum(0.0f);
    for (auto _ : state) {
        for (size_t i = 0; i < uv.size(); ++i) sum += texture.SampleLevel(sampler, uv[i], lod[i]);
        benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(uv.size()));
}

void registerAll() {
    using benchmark::RegisterBenchmark;
    RegisterBenchmark("Setup/triangles_64k", BM_Setup);
    RegisterBenchmark("Binning/triangles_64k_1280x720", BM_Binning);
    RegisterBenchmark("Coverage/small_20px", BM_Coverage, &smallTriangles);
    RegisterBenchmark("Coverage/large_tile", BM_Coverage, &largeTriangles);
    RegisterBenchmark("Fragments/constant_1280x720", BM_FragmentsConstant)
        ->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime();
    RegisterBenchmark("Fragments/psfire_1280x720", BM_FragmentsFire)
        ->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime();
    RegisterBenchmark("Blend/replace_rgba8", BM_BlendFast<BlendReplaceRgba8>);
    RegisterBenchmark("Blend/additive_rgba8", BM_BlendFast<BlendAdditiveRgba8>);
    RegisterBenchmark("Blend/merge_float_alpha", BM_MergeFragment<float>);
    RegisterBenchmark("Blend/merge_double_alpha", BM_MergeFragment<double>);
    RegisterBenchmark("Depth/less", BM_DepthLess);
    RegisterBenchmark("Gs/billboard_100k", BM_GeometryShader)->ArgName("quad")->Arg(0)->Arg(1);
    RegisterBenchmark("FrontEnd/particles_100k_64x36", BM_FrontEndParticles)
        ->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime();
    RegisterBenchmark("Sample/bilinear_fire64", BM_SampleBilinear);
    RegisterBenchmark("Sample/bilinear_fire64_x8", BM_SampleBilinearWide);
    RegisterBenchmark("Sample/level_trilinear_256", BM_SampleLevelTrilinear);
    RegisterBenchmark("Scene/particles_1280x720_10k", BM_SceneParticles)
        ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
    RegisterBenchmark("Scene/fog_1280x720_16x16", BM_SceneFog)
        ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
    registerParticleBenchmarks();
    registerMediaBenchmarks();
}

// args: the command line after "microbench", for Google Benchmark, which wants a program name first.
int runMicrobench(std::vector<std::string> args) {
    // 0.3 s per benchmark unless the command line says otherwise (a later flag wins): the whole
    // run then takes well under two minutes.
    args.insert(args.begin(), {"raster microbench", "--benchmark_min_time=0.3"});
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    int count = int(args.size());
    benchmark::Initialize(&count, argv.data());
    if (benchmark::ReportUnrecognizedArguments(count, argv.data())) return kUsageExit;
    registerAll();
#ifdef RASTER_MICROBENCH_TEST_BUILD
    // A build with the tests compiles this program as a test program (RASTER_TEST_OPTIMIZATION), so
    // that CI checks it compiles and runs without paying -O3 for it: such figures are not the library's.
    benchmark::AddCustomContext("raster_microbench_build", "test build at " RASTER_MICROBENCH_TEST_BUILD);
    std::fprintf(stderr,
                 "raster microbench: WARNING: this raster-microbench was compiled at %s for the test suite; "
                 "its times are not benchmark figures (configure without tests, e.g. .ci/build, or with "
                 "-DRASTER_TEST_OPTIMIZATION=)\n",
                 RASTER_MICROBENCH_TEST_BUILD);
#endif
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}

}  // namespace

}  // namespace raster::tools

// build/bin/raster-microbench, which `raster microbench` runs with its arguments
// (microbench_command.cpp).
int main(int argc, char** argv) {
    try {
        return raster::tools::runMicrobench(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "raster microbench: %s\n", e.what());
        return 1;
    }
}
