// raster bench soft-particles (bench_soft.cpp): the smoke scene's off-screen particles, run time
// against error, full resolution against ½ and ¼, with and without the edge fix.
#pragma once

#include <string>

#include "raster/scenes.hpp"

namespace raster::tools {

inline constexpr const char* kSoftParticlesBench = "soft-particles";

// options.count set: that count only; unset: 1000, 3000, 10000, 30000 and 100000 particles. Each
// row: the median of `frames` renders of one frame; the errors against the full-resolution frame.
// outDir not empty: the figures' PNGs (full, ½, ½ with the fix, the ×4 difference images) of the
// first count, written there.
int runSoftParticlesBench(const SceneOptions& options, uint32_t frames, unsigned threads,
                          const std::string& outDir);

}  // namespace raster::tools
