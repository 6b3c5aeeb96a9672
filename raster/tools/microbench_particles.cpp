// raster microbench's particle benchmarks (registered by microbench.cpp's registerAll; a file of
// its own so that it does not wait on the pipeline's templates): one simulation step of 1 000 000
// particles (the goals: at most 5 ms under gravity, wind and drag on 2 cores; at most 40 ms with
// curl-noise turbulence; docs/PERFORMANCE.md), the upload, and the back-to-front sort of 1 000 000
// depths, radix against std::sort (goal: at least 5x faster).
//
//   raster microbench --benchmark_filter=Particles    (Arg: threads, or the key count for the sorts)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "particle_workload.hpp"
#include "raster/particle_sort.hpp"
#include "raster/particles.hpp"
#include "raster/thread_pool.hpp"

namespace raster::tools {
namespace {

constexpr uint32_t kCount = 1000000;

void stepMillion(benchmark::State& state, bool turbulence) {
    ThreadPool pool(unsigned(state.range(0)));
    ParticleSystem system(particleWorkload(kCount, turbulence), &pool);
    system.step();  // the burst: all 10⁶ born
    for (auto _ : state) system.step();
    state.SetItemsProcessed(int64_t(state.iterations()) * kCount);
    state.counters["alive"] = system.aliveCount();
}

void BM_StepGravityWindDrag(benchmark::State& state) { stepMillion(state, false); }
void BM_StepWithCurlNoise(benchmark::State& state) { stepMillion(state, true); }

void BM_WriteVertices(benchmark::State& state) {
    ThreadPool pool(unsigned(state.range(0)));
    ParticleSystem system(particleWorkload(kCount, false), &pool);
    system.step();
    std::vector<Particle> vertices(system.aliveCount());
    for (auto _ : state) benchmark::DoNotOptimize(system.writeVertices(vertices));
    state.SetItemsProcessed(int64_t(state.iterations()) * kCount);
}

std::vector<float> randomDepths(size_t n) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> depth(0.1f, 200.0f);
    std::vector<float> d(n);
    for (float& x : d) x = depth(rng);
    return d;
}

void sortDepths(benchmark::State& state, SortMethod method) {
    const std::vector<float> depths = randomDepths(size_t(state.range(0)));
    std::vector<uint32_t> order(depths.size());
    SortScratch scratch;
    for (auto _ : state) {
        sortBackToFront(depths, order, method, &scratch);
        benchmark::DoNotOptimize(order.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0));
}

void BM_SortRadix(benchmark::State& state) { sortDepths(state, SortMethod::Radix); }
void BM_SortPackedStdSort(benchmark::State& state) { sortDepths(state, SortMethod::Comparison); }
// What a first attempt writes: std::sort of indices with a comparator that reads the depths.
void BM_SortIndicesStdSort(benchmark::State& state) {
    const std::vector<float> depths = randomDepths(size_t(state.range(0)));
    std::vector<uint32_t> order(depths.size());
    for (auto _ : state) {
        std::iota(order.begin(), order.end(), 0u);
        std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
            return backToFrontBefore(depths[a], depths[b]) ||
                   (!backToFrontBefore(depths[b], depths[a]) && a < b);
        });
        benchmark::DoNotOptimize(order.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0));
}

}  // namespace

void registerParticleBenchmarks() {
    using benchmark::RegisterBenchmark;
    RegisterBenchmark("Particles/step_1M_gravity_wind_drag", BM_StepGravityWindDrag)
        ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
    RegisterBenchmark("Particles/step_1M_curl_noise", BM_StepWithCurlNoise)
        ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
    RegisterBenchmark("Particles/write_vertices_1M", BM_WriteVertices)
        ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
    RegisterBenchmark("Particles/sort_radix", BM_SortRadix)->RangeMultiplier(4)->Range(256, 1 << 20)->Arg(1000000);
    RegisterBenchmark("Particles/sort_packed_std_sort", BM_SortPackedStdSort)
        ->RangeMultiplier(4)->Range(256, 1 << 20)->Arg(1000000);
    RegisterBenchmark("Particles/sort_indices_std_sort", BM_SortIndicesStdSort)
        ->Arg(1000000)->Unit(benchmark::kMillisecond);
}

}  // namespace raster::tools
