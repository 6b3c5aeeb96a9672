// raster render [scene...] [--out-dir D] [--width W] [--height H] [--reference] [--view] [--list]:
// renders the lecture's scenes and the labs' (all of them by default) to D/<scene>.png; with --view
// it then opens the viewer on the first of them where a display exists (DISPLAY or WAYLAND_DISPLAY
// set). --list prints the scenes, one a line, and what each is.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"
#include "options.hpp"
#include "raster/scenes.hpp"

namespace raster::tools {

int render(int argc, char** argv) {
    ArgReader args(argc, argv);
    std::vector<std::string> names;
    std::string out_dir = "out";
    SceneOptions options;
    bool reference = false, view_after = false;
    while (!args.done()) {
        const std::string_view a = args.take();
        if (a == "--out-dir") out_dir = args.value(a);
        else if (a == "--width") options.width = parseUint(a, args.value(a), 1, RenderTarget::kMaxSize);
        else if (a == "--height") options.height = parseUint(a, args.value(a), 1, RenderTarget::kMaxSize);
        else if (a == "--reference") reference = true;
        else if (a == "--view") view_after = true;
        else if (a == "--list") {
            for (const std::string& name : sceneNames()) {
                const SceneEntry* entry = findRegisteredScene(name);
                const char* title = name == "particles" ? "the lecture's fire billboards (../shared/bench/SCENES.md)"
                                    : name == "fog"     ? "cubes on a ground plane in fog (../shared/bench/SCENES.md)"
                                    : entry             ? entry->title.c_str()
                                                        : "";
                std::printf("%-24s %s\n", name.c_str(), title);
            }
            return 0;
        }
        else if (a == "--help" || a == "-h") {
            std::puts("usage: raster render [scene ...] [--out-dir D] [--width W] [--height H] [--reference]\n"
                      "                     [--view]  (then opens raster view on the first scene if a display exists)\n"
                      "       raster render --list    (the scenes: the lecture's, the labs' and their solutions)");
            return 0;
        } else if (a.starts_with("--")) {
            throw Error(ErrorCode::InvalidArgument, "unknown option '" + std::string(a) + "'");
        } else {
            names.emplace_back(a);
        }
    }
    if (names.empty()) names = sceneNames();
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    RASTER_REQUIRE(!ec, BadFile, "cannot create output directory '" + out_dir + "': " + ec.message());
    Context context({0, reference});
    for (const std::string& name : names) {
        std::unique_ptr<Scene> scene = makeScene(name, options);
        RenderTarget color(options.width, options.height);
        DepthTarget depth(options.width, options.height);
        scene->render(context, color, depth);
        const std::string path = out_dir + "/" + name + ".png";
        color.savePng(path);
        std::printf("wrote %s (%ux%u)\n", path.c_str(), options.width, options.height);
    }
    if (view_after) {
        const char* display = std::getenv("DISPLAY");
        const char* wayland = std::getenv("WAYLAND_DISPLAY");
        if ((!display || !*display) && (!wayland || !*wayland)) {
            std::puts("no display (DISPLAY and WAYLAND_DISPLAY unset): not opening the viewer");
            return 0;
        }
        std::fflush(stdout);
        std::string scene = names.front();
        char* view_argv[] = {scene.data()};
        return view(1, view_argv);
    }
    return 0;
}

}  // namespace raster::tools
