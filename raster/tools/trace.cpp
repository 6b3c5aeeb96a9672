// raster trace <scene> --stats: renders one frame of a scene and prints the pipeline statistics
// of each draw (D3D11_QUERY_DATA_PIPELINE_STATISTICS and what was skipped, and why) and of the frame.
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "options.hpp"
#include "raster/scenes.hpp"

namespace raster::tools {

int trace(int argc, char** argv) {
    ArgReader args(argc, argv);
    const char* usage =
        "usage: raster trace particles|fog --stats [--width W] [--height H] [--count N] [--cubes M]\n"
        "                    [--fog constant|height] [--threads T] [--reference]\n";
    if (args.done()) {
        std::fputs(usage, stderr);
        return 2;
    }
    const std::string scene_name(args.take());
    SceneOptions options;
    uint32_t threads = 0;
    bool reference = false, stats = false;
    while (!args.done()) {
        const std::string_view a = args.take();
        if (a == "--stats") stats = true;
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
    RASTER_REQUIRE(stats, InvalidArgument,
                   "raster trace needs --stats (pixel history and stepping are not implemented yet)\n" +
                       std::string(usage));
    std::unique_ptr<Scene> scene = makeScene(scene_name, options);
    Context context({threads, reference});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    context.resetFrameStatistics();
    scene->render(context, color, depth);
    const auto& log = context.drawStatisticsLog();
    for (size_t i = 0; i < log.size(); ++i) std::printf("# draw %zu\n%s\n", i, log[i].toString().c_str());
    std::printf("# frame (%zu draws)\n%s", log.size(), context.frameStatistics().toString().c_str());
    return 0;
}

}  // namespace raster::tools
