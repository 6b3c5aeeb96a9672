// raster bench particles|fog: renders a benchmark scene of SCENES.md K times and prints the median
// frame time, in the one-line format ../shared/anchors/compare.sh reads, after the fast path's
// error against the reference pipeline.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "commands.hpp"
#include "options.hpp"
#include "raster/scenes.hpp"
#include "view/compare_views.hpp"

namespace raster::tools {
namespace {

constexpr const char* kUsage =
    "usage: raster bench particles|fog [--width W] [--height H] [--count N] [--cubes M]\n"
    "                    [--fog constant|height] [--frames K] [--threads T] [--out image.png]\n"
    "                    [--texture fire.png] [--reference] [--no-error]\n"
    "  K timed frames (default 20) after one warm-up frame, on T threads (default: all cores).\n"
    "  Prints the fast pipeline's error against the reference pipeline (skip with --no-error), then\n"
    "  'raster <scene> <W>x<H> ms_per_frame_median=<t> frames=<K>'.\n";

}  // namespace

int bench(int argc, char** argv) {
    ArgReader args(argc, argv);
    if (args.done()) {
        std::fputs(kUsage, stderr);
        return 2;
    }
    const std::string scene_name(args.take());
    if (scene_name == "--help" || scene_name == "-h") {
        std::fputs(kUsage, stdout);
        return 0;
    }
    SceneOptions options;
    uint32_t frames = 20, threads = 0;
    std::string out;
    bool reference = false, error = true;
    while (!args.done()) {
        const std::string_view a = args.take();
        if (a == "--width") options.width = parseUint(a, args.value(a), 1, RenderTarget::kMaxSize);
        else if (a == "--height") options.height = parseUint(a, args.value(a), 1, RenderTarget::kMaxSize);
        else if (a == "--count") options.count = parseUint(a, args.value(a), 0, 50'000'000);
        else if (a == "--cubes") options.cubes = parseUint(a, args.value(a), 0, 1024);
        else if (a == "--frames") frames = parseUint(a, args.value(a), 1, 100000);
        else if (a == "--threads") threads = parseUint(a, args.value(a), 1, 1024);
        else if (a == "--out") out = args.value(a);
        else if (a == "--texture") options.texture = args.value(a);
        else if (a == "--reference") reference = true;
        else if (a == "--no-error") error = false;
        else if (a == "--fog") {
            const std::string_view f = args.value(a);
            RASTER_REQUIRE(f == "constant" || f == "height", InvalidArgument,
                           "--fog takes constant or height, not '" + std::string(f) + "'");
            options.heightFog = f == "height";
        } else if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            return 0;
        } else {
            throw Error(ErrorCode::InvalidArgument, "unknown option '" + std::string(a) + "'\n" + kUsage);
        }
    }
    std::unique_ptr<Scene> scene = makeScene(scene_name, options);
    Context context({threads, reference});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);

    scene->render(context, color, depth);  // warm-up
    std::vector<double> ms;
    for (uint32_t f = 0; f < frames; ++f) {
        const auto t0 = std::chrono::steady_clock::now();
        scene->render(context, color, depth);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    if (!out.empty()) color.savePng(out);

    const PipelineStatistics& stats = context.frameStatistics();
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::printf(
        "threads=%u reference=%d min_ms=%.3f max_ms=%.3f ps_invocations_per_frame=%llu "
        "at_ceiling_per_frame=%llu transparent_skipped_per_frame=%llu rectangles_per_frame=%llu "
        "peak_rss_mb=%.1f\n",
        context.threads(), int(reference), ms.front(), ms.back(),
        (unsigned long long)(stats.psInvocations / (frames + 1)),
        (unsigned long long)(stats.fragmentsBlendSaturated / (frames + 1)),
        (unsigned long long)(stats.fragmentsTransparentSkipped / (frames + 1)),
        (unsigned long long)(stats.rectanglesRecognized / (frames + 1)), double(usage.ru_maxrss) / 1024.0);
    if (error && !reference) {
        Context ref_context({threads, true});
        RenderTarget ref_color(options.width, options.height);
        DepthTarget ref_depth(options.width, options.height);
        scene->render(ref_context, ref_color, ref_depth);
        const ImageDifference e = compareImages(color.toRgba8(), ref_color.toRgba8(), color.width(), color.height(), 3);
        std::printf("error_vs_reference mean_abs=%.4f max_diff=%d within_1=%.6f\n", e.meanAbs, e.max,
                    double(e.within1) / double(e.pixels));
    }
    std::printf("raster %s %ux%u ms_per_frame_median=%.3f frames=%u\n", scene_name.c_str(), options.width,
                options.height, ms[ms.size() / 2], frames);
    return 0;
}

}  // namespace raster::tools
