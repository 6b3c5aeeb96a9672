// The frame timing of raster bench (bench.cpp, bench_blend.cpp, bench_soft.cpp): one warm-up frame, then K timed ones.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <vector>

#include "raster/scenes.hpp"

namespace raster::tools {

// Renders one warm-up frame, then `frames` timed frames, an animated scene moved on by
// `advanceSeconds` before each, inside the timing. The frame times in milliseconds, sorted: the median
// is [size / 2].
inline std::vector<double> timeFrames(Scene& scene, Context& context, RenderTarget& color, DepthTarget& depth,
                                      uint32_t frames, double advanceSeconds) {
    scene.render(context, color, depth);  // warm-up
    std::vector<double> ms;
    for (uint32_t f = 0; f < frames; ++f) {
        const auto t0 = std::chrono::steady_clock::now();
        if (scene.animated()) scene.advance(advanceSeconds);
        scene.render(context, color, depth);
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms;
}

}  // namespace raster::tools
