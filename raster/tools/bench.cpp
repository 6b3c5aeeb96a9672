// raster bench particles|fog|fire|<lab>: renders a scene K times and prints the median frame time,
// in the one-line format ../shared/anchors/compare.sh reads, after the fast path's error against the
// reference pipeline. An animated scene (fire) moves on by kBenchFrameSeconds before each frame,
// inside the timing: a frame is then the simulation's step, the upload and the drawing.
// raster bench particles-sim: times K fixed steps of the particle simulation alone
// (particle_workload.hpp) and prints the median step time. raster bench blend-figures times the blend
// figures and compares them (bench_blend.cpp). raster bench fog-accuracy measures the fog's closed
// forms in ulps over an adversarial grid (bench_fog_accuracy.cpp, docs/ACCURACY.md).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_blend.hpp"
#include "bench_error.hpp"
#include "bench_fog_accuracy.hpp"
#include "bench_soft.hpp"
#include "bench_timing.hpp"
#include "commands.hpp"
#include "options.hpp"
#include "particle_workload.hpp"
#include "raster/image_compare.hpp"
#include "raster/particles.hpp"
#include "raster/scenes.hpp"
#include "raster/thread_pool.hpp"

namespace raster::tools {
namespace {

struct BenchArgs {
    std::string scene;
    SceneOptions options;
    uint32_t frames = 20, threads = 0;
    std::string out;
    bool reference = false, plain = false, noError = false;
    bool turbulence = false;  // particles-sim: add curl-noise turbulence
    ErrorBenchArgs error;     // error: --out-dir, --rays, --seed
    bool quick = false, exhaustive = false;  // fog-accuracy
};

// An animated scene's time per benchmark frame: one fixed step of the fire's simulation.
constexpr double kBenchFrameSeconds = 1.0 / 60.0;

constexpr const char* kParticlesSim = "particles-sim";

// One step of the simulation K times after the burst's step (all particles born) and one more
// warm-up step; the median is what the goals of docs/PERFORMANCE.md ("Particle simulation and depth
// sort") name.
int runParticlesSim(const BenchArgs& args) {
    const uint32_t count = args.options.count.value_or(1'000'000);
    RASTER_REQUIRE(count > 0, InvalidArgument, "particles-sim needs --count of at least 1");
    ThreadPool pool(args.threads);
    ParticleSystem system(particleWorkload(count, args.turbulence), &pool);
    system.step();
    system.step();
    std::vector<double> ms;
    for (uint32_t k = 0; k < args.frames; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        system.step();
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    std::printf("threads=%u alive=%u min_ms=%.3f max_ms=%.3f\n", pool.size(), system.aliveCount(), ms.front(),
                ms.back());
    std::printf("raster particles-sim count=%u turbulence=%d ms_per_step_median=%.3f steps=%u\n", count,
                int(args.turbulence), ms[ms.size() / 2], args.frames);
    return 0;
}

int runBench(const BenchArgs& args) {
    if (args.scene == kParticlesSim) return runParticlesSim(args);
    if (args.scene == kErrorBench) {
        ErrorBenchArgs error = args.error;
        error.seed = args.options.seed;
        return runErrorBench(error);
    }
    if (args.scene == kBlendFigures)
        return runBlendFigures(args.options, args.frames, args.threads, args.out);
    if (args.scene == kFogAccuracyBench)
        return runFogAccuracyBench({args.out, args.quick, args.exhaustive, args.threads});
    if (args.scene == kSoftParticlesBench)
        return runSoftParticlesBench(args.options, args.frames, args.threads, args.out);
    const SceneOptions& options = args.options;
    const uint32_t frames = args.frames, threads = args.threads;
    std::unique_ptr<Scene> scene = makeScene(args.scene, options);
    Context context({threads, args.reference, args.plain});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    const std::vector<double> ms = timeFrames(*scene, context, color, depth, frames, kBenchFrameSeconds);
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
    CLI::App* command =
        addCommand(app, "bench", "time a scene: a benchmark scene of SCENES.md, the fire, a lab");
    auto args = std::make_shared<BenchArgs>();
    std::vector<std::string> names = sceneNames();
    names.push_back(kParticlesSim);
    names.push_back(kSoftParticlesBench);
    names.push_back(kBlendFigures);
    names.push_back(kErrorBench);
    names.push_back(kFogAccuracyBench);
    command
        ->add_option(
            "scene", args->scene,
            "particles, fog, a lab (raster render --list), particles-sim, blend-figures, soft-particles or "
            "fog-accuracy")
        ->check(CLI::IsMember(names))
        ->required();
    addSizeOptions(*command, args->options);
    addContentOptions(*command, args->options);
    addTimeOptions(*command, args->options);
    command->add_option("--texture", args->options.texture,
                        "particles, fire: a PNG instead of the generated fire");
    addWholeNumber(*command, "--frames", args->frames, 1, 100'000, "timed frames, after one warm-up frame");
    addThreadsOption(*command, args->threads);
    command->add_option("--out", args->out, "write the last frame to this PNG file");
    command->add_flag("--reference", args->reference, "run the reference pipeline");
    command->add_flag("--plain", args->plain,
                      "every primitive through the plain path (fill/quads.hpp): for stepping in a debugger");
    command->add_flag("--no-error", args->noError, "skip the error against the reference pipeline");
    command->add_flag("--turbulence", args->turbulence, "particles-sim: add curl-noise turbulence");
    command->add_option("--out-dir", args->error.outDir, "error: the folder for error.csv and error.png");
    addWholeNumber(*command, "--rays", args->error.rays, 1, 1'000'000, "error: rays per medium");
    command->add_flag("--quick", args->quick, "fog-accuracy: every other value of each axis of the grid");
    command->add_flag("--exhaustive", args->exhaustive, "fog-accuracy: psi at every float too (minutes)");
    command->footer(
        "Prints the fast pipeline's error against the reference pipeline (skip with --no-error), then\n"
        "'raster <scene> <W>x<H> ms_per_frame_median=<t> frames=<K>'. An animated scene (fire) starts\n"
        "at --time and moves on by 1/60 s before each frame, inside the timing.\n"
        "particles-sim times --frames steps of the particle simulation alone (--count particles, default\n"
        "1000000, all alive; gravity, wind and drag, and curl noise with --turbulence), then prints\n"
        "'raster particles-sim count=<N> turbulence=<0|1> ms_per_step_median=<t> steps=<K>'.\n"
        "blend-figures times each blend-* scene (a line each, as above) and prints the differences of\n"
        "blend-wboit and blend-unsorted from blend-sorted; --out DIR writes the figures and the\n"
        "differences' heat maps (<scene>-diff.png) into the folder DIR.\n"
        "soft-particles renders the smoke at full resolution, at 1/2 and 1/4 with and without the edge\n"
        "fix, for --count particles (default 1000 to 100000), and prints a table: the median frame time\n"
        "and the errors against full resolution (docs/SOFT_PARTICLES.md); --out DIR writes its figures.\n"
        "error sweeps the media integrators and accuracy knobs on --rays rays drawn from --seed against a\n"
        "float64 reference, prints the table and the time to reach 1e-2, 1e-3 and 0.5/255, and writes\n"
        "--out-dir/error.csv and error.png (gnuplot; docs/ACCURACY.md).\n"
        "fog-accuracy measures raster's fog and medium closed forms, the lecture's, Unreal's and the\n"
        "max(sigma, 1e-5) floor over an adversarial grid in float ulps of a long-double reference and\n"
        "prints the table (docs/ACCURACY.md); --out DIR writes fog-accuracy.csv, the plot's points and\n"
        "script, and fog-accuracy.png where gnuplot is installed; --exhaustive adds psi at every float\n"
        "(on --threads threads).");
    return {command, [args] { return runBench(*args); }};
}

}  // namespace raster::tools
