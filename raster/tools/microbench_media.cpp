// raster microbench's participating-media benchmarks (registered by microbench.cpp's registerAll): the
// phase functions and ψ over 4096 values, one value at a time in float against eight at a time in
// Float8 (raster/media/; the goal for the phase functions is at least 4× the scalar rate per value).
//
//   raster microbench --benchmark_filter=Media      (items = values)
//
// The scalar loops are kept scalar: this file is compiled without the auto-vectoriser
// (raster/tools/CMakeLists.txt), which would otherwise turn a loop of inlined float calls into vector
// code itself, and the figure would not be what a scalar shader pays per value. Float8 is vector code
// as written, which the option does not touch.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "raster/media/exprel.hpp"
#include "raster/media/phase_functions.hpp"
#include "raster/simd.hpp"

namespace raster::tools {
namespace {

constexpr size_t kValues = 4096;

struct MediaInputs {
    std::vector<float> cosTheta, u, g, x;
    MediaInputs() {
        std::mt19937 rng(46);
        std::uniform_real_distribution<float> unit(0, 1), signed_unit(-1, 1), wide(-30, 30);
        for (size_t i = 0; i < kValues; ++i) {
            cosTheta.push_back(signed_unit(rng)), u.push_back(unit(rng));
            g.push_back(0.95f * signed_unit(rng)), x.push_back(wide(rng));
        }
    }
};

const MediaInputs& inputs() {
    static const MediaInputs in;
    return in;
}

// f(i, in) → float for each value, one at a time.
template <class F>
void runScalar(benchmark::State& state, F f) {
    const MediaInputs& in = inputs();
    std::vector<float> out(kValues);
    for (auto _ : state) {
        for (size_t i = 0; i < kValues; ++i) out[i] = f(i, in);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kValues));
}

// f(i, in) → Float8 for values i … i + 7.
template <class F>
void runWide(benchmark::State& state, F f) {
    const MediaInputs& in = inputs();
    std::vector<float> out(kValues);
    for (auto _ : state) {
        for (size_t i = 0; i < kValues; i += 8) f(i, in).store(out.data() + i);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kValues));
}

Float8 at(const std::vector<float>& v, size_t i) {
    return Float8::load(v.data() + i);
}

void BM_HenyeyGreensteinScalar(benchmark::State& state) {
    runScalar(state, [](size_t i, const MediaInputs& in) {
        return media::henyeyGreenstein(in.g[i], in.cosTheta[i]);
    });
}
void BM_HenyeyGreensteinWide(benchmark::State& state) {
    runWide(state, [](size_t i, const MediaInputs& in) {
        return media::henyeyGreenstein(at(in.g, i), at(in.cosTheta, i));
    });
}
void BM_RayleighScalar(benchmark::State& state) {
    runScalar(state, [](size_t i, const MediaInputs& in) { return media::rayleigh(in.cosTheta[i]); });
}
void BM_RayleighWide(benchmark::State& state) {
    runWide(state, [](size_t i, const MediaInputs& in) { return media::rayleigh(at(in.cosTheta, i)); });
}
void BM_SampleHenyeyGreensteinScalar(benchmark::State& state) {
    runScalar(state, [](size_t i, const MediaInputs& in) {
        return media::sampleHenyeyGreenstein(in.g[i], in.u[i]);
    });
}
void BM_SampleHenyeyGreensteinWide(benchmark::State& state) {
    runWide(state, [](size_t i, const MediaInputs& in) {
        return media::sampleHenyeyGreenstein(at(in.g, i), at(in.u, i));
    });
}
void BM_PsiScalar(benchmark::State& state) {
    runScalar(state, [](size_t i, const MediaInputs& in) { return media::psi(in.x[i]); });
}
void BM_PsiWide(benchmark::State& state) {
    runWide(state, [](size_t i, const MediaInputs& in) { return media::psi(at(in.x, i)); });
}

}  // namespace

void registerMediaBenchmarks() {
    using benchmark::RegisterBenchmark;
    RegisterBenchmark("Media/henyey_greenstein_scalar", BM_HenyeyGreensteinScalar);
    RegisterBenchmark("Media/henyey_greenstein_x8", BM_HenyeyGreensteinWide);
    RegisterBenchmark("Media/rayleigh_scalar", BM_RayleighScalar);
    RegisterBenchmark("Media/rayleigh_x8", BM_RayleighWide);
    RegisterBenchmark("Media/sample_henyey_greenstein_scalar", BM_SampleHenyeyGreensteinScalar);
    RegisterBenchmark("Media/sample_henyey_greenstein_x8", BM_SampleHenyeyGreensteinWide);
    RegisterBenchmark("Media/psi_scalar", BM_PsiScalar);
    RegisterBenchmark("Media/psi_x8", BM_PsiWide);
}

}  // namespace raster::tools
