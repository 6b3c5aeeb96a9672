// raster bench soft-particles: see bench_soft.hpp and docs/SOFT_PARTICLES.md.
//
// The error of an off-screen frame is measured against the full-resolution frame of the same
// options (the same particles, sorted the same way), with image_compare.hpp: the mean LDR-FLIP
// error, the RGB root-mean-square difference in 8-bit steps, and the halo: the mean FLIP error and
// the largest channel difference within 4 pixels of a depth discontinuity of the full-resolution
// depth (depthEdgeBand, steps of more than 10 % of the view depth) against the same elsewhere.
#include "bench_soft.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "bench_timing.hpp"
#include "raster/image_compare.hpp"
#include "raster/pipeline.hpp"
#include "raster/soft_particles.hpp"

namespace raster::tools {
namespace {

constexpr uint32_t kBandRadius = 4;  // pixels: the halo of a ¼-resolution composite is ~2 texels = 8 px wide
constexpr float kBandStep = 0.1f;    // relative view-depth step of a discontinuity

struct Mode {
    const char* name;
    OffscreenParticles offscreen;
};

struct Frame {
    RenderTarget color;
    DepthTarget depth;
    double msMedian = 0;
};

Frame renderTimed(const SceneOptions& options, const OffscreenParticles& offscreen, uint32_t frames,
                  Context& context) {
    std::unique_ptr<Scene> scene = makeSmokeScene(options, offscreen);
    // A float frame: with many faint particles, "over" into RGBA8 rounds each particle's step away
    // (1/255 is more than a 100 000-particle puff's share), which would count as the off-screen
    // path's error; in float the full-resolution frame is the reference it should be.
    Frame f{RenderTarget(options.width, options.height, Format::R32G32B32A32_FLOAT),
            DepthTarget(options.width, options.height)};
    // The same simulation state each frame (no advance), after a warm-up frame.
    const std::vector<double> ms = timeFrames(*scene, context, f.color, f.depth, frames, 0.0);
    f.msMedian = ms[ms.size() / 2];
    return f;
}

struct Errors {
    double flip = 0, rmse = 0;
    double bandFlip = 0, outsideFlip = 0;  // mean FLIP error in the band around discontinuities, and off it
    int bandMax = 0, outsideMax = 0;       // largest channel difference there, 8-bit steps
    double bandShare = 0;                  // of the pixels, in the band
};

Errors measure(const RenderTarget& reference, const RenderTarget& image, const std::vector<uint8_t>& band) {
    const std::vector<uint8_t> a = reference.toRgba8(), b = image.toRgba8();
    const uint32_t w = image.width(), h = image.height();
    const ComparisonResult flip = compareFlip({a, w, h}, {b, w, h});
    const DifferenceMap map = differenceMap({a, w, h}, {b, w, h}, CompareChannels::Rgb);
    Errors e;
    e.flip = flip.figure;
    double squares = 0, band_sum = 0, outside_sum = 0;
    size_t band_count = 0;
    for (size_t i = 0; i < size_t(w) * h; ++i) {
        for (int c = 0; c < 3; ++c) squares += std::pow(double(a[4 * i + c]) - double(b[4 * i + c]), 2.0);
        if (band[i]) {
            ++band_count, band_sum += flip.error[i];
            e.bandMax = std::max(e.bandMax, int(map.largest[i]));
        } else {
            outside_sum += flip.error[i];
            e.outsideMax = std::max(e.outsideMax, int(map.largest[i]));
        }
    }
    const size_t n = size_t(w) * h;
    e.rmse = std::sqrt(squares / double(3 * n));
    e.bandFlip = band_count ? band_sum / double(band_count) : 0.0;
    e.outsideFlip = n > band_count ? outside_sum / double(n - band_count) : 0.0;
    e.bandShare = double(band_count) / double(n);
    return e;
}

// |a − b| per channel, times 4 (clamped), opaque: where the off-screen frame differs.
void saveDifference(const RenderTarget& a, const RenderTarget& b, const std::string& path) {
    RenderTarget d(a.width(), a.height());
    for (uint32_t y = 0; y < a.height(); ++y)
        for (uint32_t x = 0; x < a.width(); ++x) {
            const glm::vec4 diff = glm::min(glm::abs(a.load(x, y) - b.load(x, y)) * 4.0f, glm::vec4(1.0f));
            d.store(x, y, {diff.x, diff.y, diff.z, 1.0f});
        }
    d.savePng(path);
}

}  // namespace

int runSoftParticlesBench(const SceneOptions& base, uint32_t frames, unsigned threads,
                          const std::string& outDir) {
    const std::vector<uint32_t> counts = base.count ? std::vector<uint32_t>{*base.count}
                                                    : std::vector<uint32_t>{1000, 3000, 10000, 30000, 100000};
    const Mode modes[] = {{"full", {1, false}},
                          {"half", {2, false}},
                          {"half_fix", {2, true}},
                          {"quarter", {4, false}},
                          {"quarter_fix", {4, true}}};
    Context context({threads});
    const DepthLinearizer linearizer;
    std::printf("# raster bench soft-particles %ux%u, %u threads, median of %u frames; errors against full\n",
                base.width, base.height, context.threads(), frames);
    std::printf(
        "# count mode factor edge_fix ms_median flip_mean rmse band_flip outside_flip band_max outside_max "
        "band_share\n");
    for (const uint32_t count : counts) {
        SceneOptions options = base;
        options.count = count;
        Frame full;
        std::vector<uint8_t> band;
        for (const Mode& mode : modes) {
            Frame f = renderTimed(options, mode.offscreen, frames, context);
            if (mode.offscreen.factor == 1) band = depthEdgeBand(f.depth, linearizer, kBandStep, kBandRadius);
            const Errors e = measure(mode.offscreen.factor == 1 ? f.color : full.color, f.color, band);
            std::printf("%u %s %u %d %.3f %.5f %.3f %.5f %.5f %d %d %.4f\n", count, mode.name,
                        mode.offscreen.factor, int(mode.offscreen.edgeFix), f.msMedian, e.flip, e.rmse,
                        e.bandFlip, e.outsideFlip, e.bandMax, e.outsideMax, e.bandShare);
            std::fflush(stdout);
            if (!outDir.empty() && count == counts.front()) {
                f.color.savePng(outDir + "/smoke_" + mode.name + ".png");
                if (mode.offscreen.factor > 1)
                    saveDifference(full.color, f.color, outDir + "/smoke_" + mode.name + "_diff.png");
            }
            if (mode.offscreen.factor == 1) full = std::move(f);
        }
    }
    return 0;
}

}  // namespace raster::tools
