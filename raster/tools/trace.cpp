// raster trace <scene>: renders one frame of a scene with the pipeline trace on and prints
//   --stats         the pipeline statistics of each draw and of the frame
//   --pixel X,Y     the pixel's history: every fragment that reached it, in order, with its depth
//                   test and blend (as a table, or with --json as one JSON object for tools)
//   --draw N        draw N's geometry: input-assembler vertices, vertex and geometry shader
//                   outputs, primitives after clipping and setup (the first --limit of each)
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "options.hpp"
#include "raster/scenes.hpp"
#include "raster/trace.hpp"

namespace raster::tools {

namespace {

// "X,Y" → two coordinates.
void parsePixel(std::string_view text, uint32_t& x, uint32_t& y) {
    const size_t comma = text.find(',');
    RASTER_REQUIRE(comma != std::string_view::npos, InvalidArgument,
                   "--pixel takes X,Y (two whole numbers), not '" + std::string(text) + "'");
    x = parseUint("--pixel X", text.substr(0, comma), 0, RenderTarget::kMaxSize - 1);
    y = parseUint("--pixel Y", text.substr(comma + 1), 0, RenderTarget::kMaxSize - 1);
}

}  // namespace

int trace(int argc, char** argv) {
    ArgReader args(argc, argv);
    const char* usage =
        "usage: raster trace particles|fog [--stats] [--pixel X,Y [--json]] [--draw N [--limit K]]\n"
        "                    [--width W] [--height H] [--count N] [--cubes M] [--fog constant|height]\n"
        "                    [--threads T] [--reference]\n";
    if (args.done()) {
        std::fputs(usage, stderr);
        return 2;
    }
    const std::string scene_name(args.take());
    SceneOptions options;
    uint32_t threads = 0, px = 0, py = 0, draw = 0, limit = 16;
    bool reference = false, stats = false, pixel = false, json = false, geometry = false;
    while (!args.done()) {
        const std::string_view a = args.take();
        if (a == "--stats") stats = true;
        else if (a == "--pixel") pixel = true, parsePixel(args.value(a), px, py);
        else if (a == "--json") json = true;
        else if (a == "--draw") geometry = true, draw = parseUint(a, args.value(a), 0, UINT32_MAX - 1);
        else if (a == "--limit") limit = parseUint(a, args.value(a), 0, 1u << 20);
        else if (a == "--width") options.width = parseUint(a, args.value(a), 1, RenderTarget::kMaxSize);
        else if (a == "--height") options.height = parseUint(a, args.value(a), 1, RenderTarget::kMaxSize);
        else if (a == "--count") options.count = parseUint(a, args.value(a), 0, 50'000'000);
        else if (a == "--cubes") options.cubes = parseUint(a, args.value(a), 0, 1024);
        else if (a == "--threads") threads = parseUint(a, args.value(a), 1, 1024);
        else if (a == "--reference") reference = true;
        else if (a == "--fog") {
            const std::string_view f = args.value(a);
            RASTER_REQUIRE(f == "constant" || f == "height", InvalidArgument,
                           "--fog takes constant or height, not '" + std::string(f) + "'");
            options.heightFog = f == "height";
        } else {
            throw Error(ErrorCode::InvalidArgument, "unknown option '" + std::string(a) + "'\n" + usage);
        }
    }
    RASTER_REQUIRE(stats || pixel || geometry, InvalidArgument,
                   "raster trace needs --stats, --pixel X,Y or --draw N\n" + std::string(usage));
    RASTER_REQUIRE(!json || pixel, InvalidArgument, "--json applies to --pixel");
    RASTER_REQUIRE(!pixel || (px < options.width && py < options.height), InvalidArgument,
                   "--pixel " + std::to_string(px) + "," + std::to_string(py) + " is outside the " +
                       std::to_string(options.width) + "x" + std::to_string(options.height) + " target");

    std::unique_ptr<Scene> scene = makeScene(scene_name, options);
    Context context({threads, reference});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    TraceOptions trace_options;
    if (pixel) trace_options.pixels = {int32_t(px), int32_t(py), int32_t(px), int32_t(py)};
    trace_options.geometry = geometry;
    trace_options.maxGeometryRecords = limit;
    Trace trace(trace_options);
    context.resetFrameStatistics();
    if (pixel || geometry) context.setTrace(&trace);
    scene->render(context, color, depth);

    if (geometry) {
        RASTER_REQUIRE(draw < trace.draws().size(), InvalidArgument,
                       "--draw " + std::to_string(draw) + ": the frame has " + std::to_string(trace.draws().size()) +
                           " draws (0.." + std::to_string(int64_t(trace.draws().size()) - 1) + ")");
        std::printf("%s\n", formatDraw(trace.draws()[draw], limit).c_str());
    }
    if (stats) {
        const auto& log = context.drawStatisticsLog();
        for (size_t i = 0; i < log.size(); ++i) std::printf("# draw %zu\n%s\n", i, log[i].toString().c_str());
        std::printf("# frame (%zu draws)\n%s", log.size(), context.frameStatistics().toString().c_str());
    }
    if (pixel) std::fputs((json ? pixelHistoryJson(trace, int32_t(px), int32_t(py))
                                : formatPixelHistory(trace, int32_t(px), int32_t(py)))
                              .c_str(),
                          stdout);
    return 0;
}

}  // namespace raster::tools
