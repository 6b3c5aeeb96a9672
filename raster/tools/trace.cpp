// raster trace <scene>: renders one frame of a scene with the pipeline trace on and prints
//   --stats         the pipeline statistics of each draw and of the frame
//   --pixel X,Y     the pixel's history: every fragment that reached it, in order, with its depth
//                   test and blend (as a table, or with --json as one JSON object for tools); in a
//                   media scene (Scene::pixelMarch) the pixel's ray march instead, sample by sample
//   --draw N        draw N's geometry: input-assembler vertices, vertex and geometry shader
//                   outputs, primitives after clipping and setup (the first --limit of each)
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "options.hpp"
#include "raster/scenes.hpp"
#include "raster/shader_context.hpp"
#include "raster/trace.hpp"
#include "raster/trace_format.hpp"

namespace raster::tools {
namespace {

struct TraceArgs {
    std::string scene;
    SceneOptions options;
    uint32_t threads = 0, px = 0, py = 0, draw = 0, limit = 16;
    bool reference = false, plain = false, stats = false, json = false;
    bool pixel = false, geometry = false;  // --pixel, --draw given
};

// What was asked for, printed after the traced render.
void printTrace(const TraceArgs& args, const Context& context, const Trace& trace) {
    if (args.geometry) {
        if (args.draw >= trace.draws().size())
            throw CLI::ValidationError("--draw " + std::to_string(args.draw) + ": the frame has " +
                                       std::to_string(trace.draws().size()) + " draws (0.." +
                                       std::to_string(int64_t(trace.draws().size()) - 1) + ")");
        std::printf("%s\n", formatDraw(trace.draws()[args.draw], args.limit).c_str());
    }
    if (args.stats) {
        const auto& log = context.drawStatisticsLog();
        for (size_t i = 0; i < log.size(); ++i) std::printf("# draw %zu\n%s\n", i, log[i].toString().c_str());
        std::printf("# frame (%zu draws)\n%s", log.size(), context.frameStatistics().toString().c_str());
    }
    const int32_t x = int32_t(args.px), y = int32_t(args.py);
    if (args.pixel)
        std::fputs((args.json ? pixelHistoryJson(trace, x, y) : formatPixelHistory(trace, x, y)).c_str(),
                   stdout);
}

// A colour channel in [0, 1] as the render target's 8 bits store it.
int toByte(float v) {
    return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

// The march of a media scene's pixel: one line per evaluated sample (the skipped stretches, where the
// medium is empty and nothing is added, summarised), then L, T and the colour, and the rendered
// pixel's bytes beside the colour's. A march blended over what earlier draws left (PixelMarch::over)
// takes that pixel, dst, from the trace's history (the march's fragment's colour before it blended),
// and compares colour + T·dst: the same bytes, or within one unit (the blend's own rounding).
void printPixelMarch(const PixelMarch& m, uint32_t x, uint32_t y, const RenderTarget& color,
                     const Trace& trace) {
    std::printf(
        "pixel (%u, %u): ray march, %u steps of ds=%.6g m over s in [%.6g, %.6g]; %zu samples evaluated, "
        "%u density evaluations\n",
        x, y, m.steps, double(m.ds), double(m.t0), double(m.t1), m.samples.size(), m.densityEvaluations);
    std::printf("%6s %10s %12s %12s %12s %12s %12s %12s %12s\n", "i", "s", "mu", "mu*ds", "T", "T_shadow",
                "added.r", "added.g", "added.b");
    uint32_t next = 0;
    auto skipped = [&](uint32_t upto) {
        if (upto > next)
            std::printf("%6s samples %u..%u skipped: empty, nothing added\n", "...", next, upto - 1);
    };
    for (const media::MarchSample& s : m.samples) {
        skipped(s.index);
        std::printf("%6u %10.6f %12.9g %12.9g %12.9g %12.9g %12.9g %12.9g %12.9g\n", s.index, double(s.s),
                    double(s.extinction), double(s.opticalStep), double(s.transmittance),
                    double(s.shadowTransmittance), double(s.added.r), double(s.added.g), double(s.added.b));
        next = s.index + 1;
    }
    if (m.t1 > m.t0) skipped(m.steps);
    std::printf("L = (%.9g, %.9g, %.9g)  T = %.9g  L_bg = (%.9g, %.9g, %.9g)\n", double(m.radiance.r),
                double(m.radiance.g), double(m.radiance.b), double(m.transmittance), double(m.background.r),
                double(m.background.g), double(m.background.b));
    const std::vector<uint8_t> rgba = color.toRgba8();
    const uint8_t* p = rgba.data() + (size_t(y) * color.width() + x) * 4;
    glm::vec3 expected = m.colour;
    if (!m.over) {
        std::printf("colour = clamp(L + T*L_bg) = (%.9g, %.9g, %.9g)", double(m.colour.r), double(m.colour.g),
                    double(m.colour.b));
    } else {
        const std::vector<TraceFragment> history = trace.pixelHistory(int32_t(x), int32_t(y));
        if (history.empty()) {
            std::printf(
                "colour (premultiplied) = (%.9g, %.9g, %.9g), blended over the pixel behind: no fragment "
                "of the march's draw reached the pixel\n",
                double(m.colour.r), double(m.colour.g), double(m.colour.b));
            return;
        }
        const glm::vec3 dst(history.back().colorBefore);
        const float inv_alpha = 1.0f - (1.0f - m.transmittance);  // INV_SRC_ALPHA of alpha = 1 − T
        expected = m.colour + inv_alpha * dst;
        std::printf(
            "colour = rgb + T*dst = (%.9g, %.9g, %.9g), rgb = (%.9g, %.9g, %.9g) the shader's premultiplied "
            "output blended over dst = (%.9g, %.9g, %.9g), the pixel before draw %u",
            double(expected.r), double(expected.g), double(expected.b), double(m.colour.r),
            double(m.colour.g), double(m.colour.b), double(dst.r), double(dst.g), double(dst.b),
            history.back().draw);
    }
    const int r = toByte(expected.r), g = toByte(expected.g), b = toByte(expected.b);
    std::printf(" = rgb8 (%d, %d, %d)\n", r, g, b);
    const int off = std::max({std::abs(p[0] - r), std::abs(p[1] - g), std::abs(p[2] - b)});
    std::printf("rendered pixel: rgb8 (%d, %d, %d) %s\n", p[0], p[1], p[2],
                off == 0             ? "same"
                : m.over && off == 1 ? "within one unit (the blend's rounding)"
                                     : "DIFFERENT");
}

int runTrace(const TraceArgs& args) {
    const SceneOptions& options = args.options;
    const bool pixel = args.pixel, geometry = args.geometry;
    if (!args.stats && !pixel && !geometry)
        throw CLI::RequiredError("one of --stats, --pixel X,Y or --draw N");
    if (pixel && (args.px >= options.width || args.py >= options.height))
        throw CLI::ValidationError("--pixel", std::to_string(args.px) + "," + std::to_string(args.py) +
                                                  " is outside the " + std::to_string(options.width) + "x" +
                                                  std::to_string(options.height) + " target");

    std::unique_ptr<Scene> scene = makeScene(args.scene, options);
    Context context({args.threads, args.reference, args.plain});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    TraceOptions trace_options;
    if (pixel)
        trace_options.pixels = {int32_t(args.px), int32_t(args.py), int32_t(args.px), int32_t(args.py)};
    trace_options.geometry = geometry;
    trace_options.maxGeometryRecords = args.limit;
    Trace trace(trace_options);
    context.resetFrameStatistics();
    if (pixel || geometry) context.setTrace(&trace);
    scene->render(context, color, depth);
    if (pixel) {
        detail::tReferenceMode = args.reference;  // the march's exp as the render's pixel shader ran it
        const std::optional<PixelMarch> march = scene->pixelMarch(args.px, args.py, options.width, options.height);
        detail::tReferenceMode = false;
        if (march) {
            printPixelMarch(*march, args.px, args.py, color, trace);
            TraceArgs rest = args;
            rest.pixel = false;
            printTrace(rest, context, trace);
            return 0;
        }
    }
    printTrace(args, context, trace);
    return 0;
}

}  // namespace

Command addTrace(CLI::App& app) {
    CLI::App* command = addCommand(app, "trace", "render one frame with the pipeline trace on and print it");
    auto args = std::make_shared<TraceArgs>();
    addSceneName(*command, args->scene)->required();
    command->add_flag("--stats", args->stats, "the pipeline statistics of each draw and of the frame");
    CLI::Option* pixel = addPair(
        *command, "--pixel", ',', "X", "Y", 0, RenderTarget::kMaxSize - 1,
        [args](uint32_t x, uint32_t y) { args->px = x, args->py = y; },
        "the pixel's history: every fragment that reached it, in order");
    command->add_flag("--json", args->json, "--pixel's history as one JSON object")->needs(pixel);
    CLI::Option* draw = addWholeNumber(*command, "--draw", args->draw, 0, UINT32_MAX - 1,
                                       "draw N's geometry, stage by stage (draws count from 0)");
    addWholeNumber(*command, "--limit", args->limit, 0, 1u << 20, "--draw: the records listed of each stage");
    addSizeOptions(*command, args->options);
    addContentOptions(*command, args->options);
    addThreadsOption(*command, args->threads);
    command->add_flag("--reference", args->reference, "run the reference pipeline");
    command->add_flag("--plain", args->plain, "every primitive through the plain path (fill/quads.hpp): for stepping in a debugger");
    return {command, [args, pixel, draw] {
                args->pixel = pixel->count() > 0;
                args->geometry = draw->count() > 0;
                return runTrace(*args);
            }};
}

}  // namespace raster::tools
