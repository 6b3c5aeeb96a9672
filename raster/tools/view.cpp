// raster view <scene>: the SDL2 viewer (raster/tools/view/viewer.hpp), in a window or headless.
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "options.hpp"
#include "view/viewer.hpp"

namespace raster::tools {
namespace {

constexpr const char* kUsage =
    "usage: raster view <scene> [--size WxH] [--count N] [--cubes M] [--fog constant|height]\n"
    "              [--threads T] [--reference] [--headless] [--script \"N N ] S\"]\n"
    "              [--screenshot-dir D] [--screenshot-window]\n"
    "              [--solution reference|<scene>|<file.png>]\n"
    "  <scene>: particles, fog (the lecture's benchmark scenes) or a lab (labs/<name>/, see raster render\n"
    "  --list).\n"
    "  Opens a window on the scene's framebuffer (default 1280x720). --script runs space-separated\n"
    "  keys first (also click:X,Y  drag:X0,Y0,X1,Y1  wheel:N  resize:WxH  wait); --headless runs it\n"
    "  on SDL's offscreen driver and exits. Screenshots (S, F12) save the framebuffer to\n"
    "  D/<scene>-NNNN.png (D defaults to .); --screenshot-window also saves the window, text included.\n"
    "  A click prints the pixel's colour and depth, then its history (every fragment, from a traced\n"
    "  render); O, X, L, G and V show views of the pipeline trace (frames are traced only for them).\n"
    "  --solution: what K shows and J compares the frame with - reference (this scene through the\n"
    "  reference pipeline), another scene (e.g. a lab's solution) at the same size, camera and step,\n"
    "  or a PNG of the frame's size; rendered only while K or J is on. A lab's default is its solution\n"
    "  (<lab>@solution), when solutions/ was built.\n"
    "keys:\n";

// "WxH" → width, height, each 1..RenderTarget::kMaxSize.
void parseSize(std::string_view text, SceneOptions& options) {
    const size_t x = text.find('x');
    RASTER_REQUIRE(x != std::string_view::npos, InvalidArgument,
                   "--size takes WxH (e.g. 1280x720), not '" + std::string(text) + "'");
    options.width = parseUint("--size width", text.substr(0, x), 1, RenderTarget::kMaxSize);
    options.height = parseUint("--size height", text.substr(x + 1), 1, RenderTarget::kMaxSize);
}

void printUsage(FILE* out) {
    std::fputs(kUsage, out);
    for (const std::string& line : keyHelp()) std::fprintf(out, "  %s\n", line.c_str());
}

}  // namespace

int view(int argc, char** argv) {
    ArgReader args(argc, argv);
    if (args.done()) {
        printUsage(stderr);
        return 2;
    }
    ViewerOptions options;
    options.scene = args.take();
    if (options.scene == "--help" || options.scene == "-h") {
        printUsage(stdout);
        return 0;
    }
    while (!args.done()) {
        const std::string_view a = args.take();
        if (a == "--size")
            parseSize(args.value(a), options.sceneOptions);
        else if (a == "--count")
            options.sceneOptions.count = parseUint(a, args.value(a), 0, 50'000'000);
        else if (a == "--cubes")
            options.sceneOptions.cubes = parseUint(a, args.value(a), 0, 1024);
        else if (a == "--threads")
            options.context.threads = parseUint(a, args.value(a), 1, 1024);
        else if (a == "--reference")
            options.context.reference = true;
        else if (a == "--headless")
            options.headless = true;
        else if (a == "--script")
            options.script = parseScript(args.value(a));
        else if (a == "--screenshot-dir")
            options.screenshotDir = args.value(a);
        else if (a == "--screenshot-window")
            options.screenshotWindow = true;
        else if (a == "--solution") {
            options.solution = args.value(a);
            RASTER_REQUIRE(!options.solution.empty(), InvalidArgument,
                           "--solution takes reference, a scene or a .png file, not ''");
        } else if (a == "--fog") {
            const std::string_view f = args.value(a);
            RASTER_REQUIRE(f == "constant" || f == "height", InvalidArgument,
                           "--fog takes constant or height, not '" + std::string(f) + "'");
            options.sceneOptions.heightFog = f == "height";
        } else if (a == "--help" || a == "-h") {
            printUsage(stdout);
            return 0;
        } else {
            throw Error(ErrorCode::InvalidArgument,
                        "unknown option '" + std::string(a) + "' (raster view --help)");
        }
    }
    RASTER_REQUIRE(!options.screenshotDir.empty(), InvalidArgument,
                   "--screenshot-dir needs a directory, not ''");
    defaultCamera(options.scene);     // an unknown scene fails here, before a window opens
    parseSolution(options.solution);  // so does a bad --solution
    Viewer viewer(std::move(options));
    viewer.run();
    return 0;
}

}  // namespace raster::tools
