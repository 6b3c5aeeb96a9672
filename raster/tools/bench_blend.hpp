// raster bench blend-figures (bench_blend.cpp): the blend-* scenes timed and compared with sorted "over".
#pragma once

#include <cstdint>
#include <string>

#include "raster/scenes.hpp"

namespace raster::tools {

// The subcommand's name, beside the scenes' names.
constexpr const char* kBlendFigures = "blend-figures";

// Times each blend-* scene at the options' size and count (median of `frames` after a warm-up) on
// `threads` threads (0: all), prints a line for each and the differences of blend-wboit and
// blend-unsorted from blend-sorted; with `outDir` set, writes the figures and the heat maps there.
int runBlendFigures(const SceneOptions& options, uint32_t frames, uint32_t threads,
                    const std::string& outDir);

}  // namespace raster::tools
