// raster bench particles|fog|fire|<lab>: renders a scene K times and prints the median frame time,
// in the one-line format ../shared/anchors/compare.sh reads, after the fast path's error against the
// reference pipeline. An animated scene (fire) moves on by kBenchFrameSeconds before each frame,
// inside the timing: a frame is then the simulation's step, the upload and the drawing.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "commands.hpp"
#include "options.hpp"
#include "raster/image_compare.hpp"
#include "raster/scenes.hpp"

namespace raster::tools {
namespace {

struct BenchArgs {
    std::string scene;
    SceneOptions options;
    uint32_t frames = 20, threads = 0;
    std::string out;
    bool reference = false, plain = false, noError = false;
};

// An animated scene's time per benchmark frame: one fixed step of the fire's simulation.
constexpr double kBenchFrameSeconds = 1.0 / 60.0;

int runBench(const BenchArgs& args) {
    const SceneOptions& options = args.options;
    const uint32_t frames = args.frames, threads = args.threads;
    std::unique_ptr<Scene> scene = makeScene(args.scene, options);
    Context context({threads, args.reference, args.plain});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);

    scene->render(context, color, depth);  // warm-up
    std::vector<double> ms;
    for (uint32_t f = 0; f < frames; ++f) {
        const auto t0 = std::chrono::steady_clock::now();
        if (scene->animated()) scene->advance(kBenchFrameSeconds);
        scene->render(context, color, depth);
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    if (!args.out.empty()) color.savePng(args.out);

    const PipelineStatistics& stats = context.frameStatistics();
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::printf(
        "threads=%u reference=%d min_ms=%.3f max_ms=%.3f ps_invocations_per_frame=%llu "
        "at_ceiling_per_frame=%llu transparent_skipped_per_frame=%llu rectangles_per_frame=%llu "
        "peak_rss_mb=%.1f\n",
        context.threads(), int(args.reference), ms.front(), ms.back(),
        (unsigned long long)(stats.psInvocations / (frames + 1)),
        (unsigned long long)(stats.fragmentsBlendSaturated / (frames + 1)),
        (unsigned long long)(stats.fragmentsTransparentSkipped / (frames + 1)),
        (unsigned long long)(stats.rectanglesRecognized / (frames + 1)), double(usage.ru_maxrss) / 1024.0);
    if (!args.noError && !args.reference) {
        Context ref_context({threads, true});
        RenderTarget ref_color(options.width, options.height);
        DepthTarget ref_depth(options.width, options.height);
        scene->render(ref_context, ref_color, ref_depth);
        const ImageDifference e =
            compareImages({color.toRgba8(), color.width(), color.height()},
                          {ref_color.toRgba8(), color.width(), color.height()}, CompareChannels::Rgb);
        std::printf("error_vs_reference mean_abs=%.4f max_diff=%d within_1=%.6f\n", e.meanAbs, e.max,
                    e.share(e.within1));
    }
    std::printf("raster %s %ux%u ms_per_frame_median=%.3f frames=%u\n", args.scene.c_str(), options.width,
                options.height, ms[ms.size() / 2], frames);
    return 0;
}

}  // namespace

Command addBench(CLI::App& app) {
    CLI::App* command = addCommand(app, "bench", "time a scene: a benchmark scene of SCENES.md, the fire, a lab");
    auto args = std::make_shared<BenchArgs>();
    addSceneName(*command, args->scene)->required();
    addSizeOptions(*command, args->options);
    addContentOptions(*command, args->options);
    addTimeOptions(*command, args->options);
    command->add_option("--texture", args->options.texture, "particles, fire: a PNG instead of the generated fire");
    addWholeNumber(*command, "--frames", args->frames, 1, 100'000, "timed frames, after one warm-up frame");
    addThreadsOption(*command, args->threads);
    command->add_option("--out", args->out, "write the last frame to this PNG file");
    command->add_flag("--reference", args->reference, "run the reference pipeline");
    command->add_flag("--plain", args->plain,
                      "every primitive through the plain path (fill/quads.hpp): for stepping in a debugger");
    command->add_flag("--no-error", args->noError, "skip the error against the reference pipeline");
    command->footer(
        "Prints the fast pipeline's error against the reference pipeline (skip with --no-error), then\n"
        "'raster <scene> <W>x<H> ms_per_frame_median=<t> frames=<K>'. An animated scene (fire) starts\n"
        "at --time and moves on by 1/60 s before each frame, inside the timing.");
    return {command, [args] { return runBench(*args); }};
}

}  // namespace raster::tools
