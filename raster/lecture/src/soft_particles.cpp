// The image-processing half of soft_particles.hpp: the depth downsample, the low-resolution edge
// mask and the full-resolution band around depth discontinuities. Plain loops: each reads or writes
// each pixel once, a small cost beside drawing the particles (docs/SOFT_PARTICLES.md).
#include "raster/soft_particles.hpp"

#include <algorithm>
#include <string>

#include "raster/check.hpp"

namespace raster {

DepthTarget downsampleDepth(const DepthTarget& full, uint32_t factor, DepthDownsample rule) {
    RASTER_REQUIRE(!full.empty(), InvalidArgument, "downsampleDepth of an empty depth target");
    RASTER_REQUIRE(factor > 0, InvalidArgument, "downsampleDepth by a factor of 0");
    const uint32_t w = full.width(), h = full.height();
    const uint32_t low_w = (w + factor - 1) / factor, low_h = (h + factor - 1) / factor;
    DepthTarget low(low_w, low_h);
    for (uint32_t j = 0; j < low_h; ++j) {
        float* out = low.data() + size_t(j) * low_w;
        const uint32_t y1 = std::min(h, (j + 1) * factor);
        for (uint32_t i = 0; i < low_w; ++i) {
            const uint32_t x0 = i * factor, x1 = std::min(w, x0 + factor);
            float d = full.data()[size_t(j) * factor * w + x0];  // Point: the block's top-left
            if (rule != DepthDownsample::Point)
                for (uint32_t y = j * factor; y < y1; ++y) {
                    const float* row = full.data() + size_t(y) * w;
                    for (uint32_t x = x0; x < x1; ++x)
                        d = rule == DepthDownsample::Farthest ? std::max(d, row[x]) : std::min(d, row[x]);
                }
            out[i] = d;
        }
    }
    return low;
}

std::vector<uint8_t> depthEdgeMask(const DepthTarget& nearest, const DepthTarget& farthest,
                                   const DepthLinearizer& linearizer, float relativeStep) {
    RASTER_REQUIRE(nearest.width() == farthest.width() && nearest.height() == farthest.height(),
                   InvalidArgument,
                   "depthEdgeMask of depth targets of two sizes, " + std::to_string(nearest.width()) + "x" +
                       std::to_string(nearest.height()) + " and " + std::to_string(farthest.width()) + "x" +
                       std::to_string(farthest.height()));
    const int w = int(nearest.width()), h = int(nearest.height());
    std::vector<uint8_t> edge(size_t(w) * size_t(h), 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float lo = 1.0f, hi = 0.0f;  // stored depths: view depth grows with d
            for (int j = std::max(0, y - 1); j <= std::min(h - 1, y + 1); ++j)
                for (int i = std::max(0, x - 1); i <= std::min(w - 1, x + 1); ++i) {
                    lo = std::min(lo, nearest.data()[size_t(j) * w + i]);
                    hi = std::max(hi, farthest.data()[size_t(j) * w + i]);
                }
            const float s_lo = linearizer.viewDepth(lo), s_hi = linearizer.viewDepth(hi);
            edge[size_t(y) * w + x] = s_hi - s_lo > relativeStep * s_lo ? 1 : 0;
        }
    return edge;
}

std::vector<uint8_t> depthEdgeBand(const DepthTarget& depth, const DepthLinearizer& linearizer,
                                   float relativeStep, uint32_t radius) {
    const int w = int(depth.width()), h = int(depth.height()), r = int(radius);
    std::vector<uint8_t> on(size_t(w) * size_t(h), 0), band(on.size(), 0);
    const auto s = [&](int x, int y) { return linearizer.viewDepth(depth.data()[size_t(y) * w + x]); };
    const auto step = [&](float a, float b) { return std::abs(a - b) > relativeStep * std::min(a, b); };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float here = s(x, y);
            if (x + 1 < w && step(here, s(x + 1, y))) on[size_t(y) * w + x] = on[size_t(y) * w + x + 1] = 1;
            if (y + 1 < h && step(here, s(x, y + 1))) on[size_t(y) * w + x] = on[size_t(y + 1) * w + x] = 1;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (!on[size_t(y) * w + x]) continue;
            for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
                std::fill(&band[size_t(j) * w + std::max(0, x - r)],
                          &band[size_t(j) * w + std::min(w - 1, x + r)] + 1, uint8_t(1));
        }
    return band;
}

}  // namespace raster
