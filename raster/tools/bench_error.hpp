// raster bench error: run time against error of the media integrators and accuracy knobs
// (bench_error.cpp; docs/ACCURACY.md, "Ray marching: run time against error").
#pragma once

#include <cstdint>
#include <string>

namespace raster::tools {

inline constexpr const char* kErrorBench = "error";

struct ErrorBenchArgs {
    std::string outDir = ".";
    uint32_t rays = 32;
    uint64_t seed = 0;
    uint32_t repeats = 3;
};

int runErrorBench(const ErrorBenchArgs& args);

}  // namespace raster::tools
