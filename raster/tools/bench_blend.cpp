// raster bench blend-figures: the lecture's blend and depth figures (the blend-* scenes) timed one after
// another, the median of K frames each, and weighted blended OIT and unsorted "over" compared with
// sorted "over" (the correct picture): mean and largest difference over RGB, and, with --out DIR, each
// figure's PNG and the two differences as heat maps (grade/heat_map.cpp's ramp, 32 steps full scale).
#include "bench_blend.hpp"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_timing.hpp"
#include "grade/report.hpp"
#include "raster/image_compare.hpp"
#include "raster/image_io.hpp"
#include "raster/scenes.hpp"

namespace raster::tools {

namespace {

constexpr const char* kFigures[] = {"blend-additive", "blend-depthwrite", "blend-nodepth",
                                    "blend-unsorted", "blend-sorted",     "blend-wboit"};
constexpr int kHeatFullScale = 32;  // steps of 1/255 shown at the ramp's end

struct Rendered {
    std::vector<uint8_t> rgba;
    double medianMs = 0.0;
};

Rendered timeFigure(const char* name, const SceneOptions& options, uint32_t frames, Context& context) {
    std::unique_ptr<Scene> scene = makeScene(name, options);
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    const std::vector<double> ms = timeFrames(*scene, context, color, depth, frames, 0.0);
    return {color.toRgba8(), ms[ms.size() / 2]};
}

}  // namespace

int runBlendFigures(const SceneOptions& options, uint32_t frames, uint32_t threads,
                    const std::string& outDir) {
    Context context({threads});
    std::vector<Rendered> figures;
    for (const char* name : kFigures) {
        figures.push_back(timeFigure(name, options, frames, context));
        std::printf("raster %s %ux%u ms_per_frame_median=%.3f frames=%u\n", name, options.width,
                    options.height, figures.back().medianMs, frames);
        if (!outDir.empty())
            writePngRgba8(outDir + "/" + name + ".png", options.width, options.height, figures.back().rgba);
    }
    const Rendered& sorted = figures[4];
    for (size_t k : {size_t(5), size_t(3)}) {
        const Rgba8View a{figures[k].rgba, options.width, options.height};
        const Rgba8View b{sorted.rgba, options.width, options.height};
        const ImageDifference d = compareImages(a, b, CompareChannels::Rgb);
        std::printf("raster %s vs blend-sorted mean_abs=%.4f max_diff=%d differing=%.4f over_3=%.4f\n",
                    kFigures[k], d.meanAbs, d.max, d.share(d.differing), 1.0 - d.share(d.within3));
        if (!outDir.empty()) {
            const ImageRgba8 heat = grade::heatMap(differenceMap(a, b, CompareChannels::Rgb), kHeatFullScale,
                                                   {.colourBar = true});
            writePngRgba8(outDir + "/" + kFigures[k] + "-diff.png", heat.width, heat.height, heat.pixels);
        }
    }
    return 0;
}

}  // namespace raster::tools
