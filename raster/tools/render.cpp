// raster render [scene...] [--out-dir D] [--width W] [--height H] [--reference] [--view] [--list]:
// renders the lecture's scenes and the labs' (all of them by default) to D/<scene>.png; with --view
// it then opens the viewer on the first of them where a display exists (DISPLAY or WAYLAND_DISPLAY
// set). --list prints the scenes, one a line, and what each is.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "options.hpp"
#include "raster/scenes.hpp"
#include "view/viewer.hpp"

namespace raster::tools {
namespace {

struct RenderArgs {
    std::vector<std::string> names;
    std::string outDir = "out";
    SceneOptions options;
    bool reference = false, plain = false, viewAfter = false, list = false;
};

// --list: each scene's name and what it is.
void listScenes() {
    for (const std::string& name : sceneNames()) {
        const SceneEntry* entry = findRegisteredScene(name);
        const char* title = name == "particles" ? "the lecture's fire billboards (../shared/bench/SCENES.md)"
                            : name == "fog"     ? "cubes on a ground plane in fog (../shared/bench/SCENES.md)"
                            : entry             ? entry->title.c_str()
                                                : "";
        std::printf("%-24s %s\n", name.c_str(), title);
    }
}

// The viewer on the first scene rendered, where a display exists.
int viewAfter(const std::string& scene) {
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!display || !*display) && (!wayland || !*wayland)) {
        std::puts("no display (DISPLAY and WAYLAND_DISPLAY unset): not opening the viewer");
        return 0;
    }
    std::fflush(stdout);
    ViewerOptions options;
    options.scene = scene;
    return openViewer(std::move(options));
}

// Each scene's PNG is written before the next scene is made: an error in a later scene leaves the
// earlier files in place.
int runRender(const RenderArgs& args) {
    if (args.list) {
        listScenes();
        return 0;
    }
    const std::vector<std::string> names = args.names.empty() ? sceneNames() : args.names;
    const SceneOptions& options = args.options;
    std::error_code ec;
    std::filesystem::create_directories(args.outDir, ec);
    RASTER_REQUIRE(!ec, BadFile, "cannot create output directory '" + args.outDir + "': " + ec.message());
    Context context({0, args.reference, args.plain});
    for (const std::string& name : names) {
        std::unique_ptr<Scene> scene = makeScene(name, options);
        RenderTarget color(options.width, options.height);
        DepthTarget depth(options.width, options.height);
        scene->render(context, color, depth);
        const std::string path = args.outDir + "/" + name + ".png";
        color.savePng(path);
        std::printf("wrote %s (%ux%u)\n", path.c_str(), options.width, options.height);
        std::fflush(stdout);
    }
    return args.viewAfter ? viewAfter(names.front()) : 0;
}

}  // namespace

Command addRender(CLI::App& app) {
    CLI::App* command = addCommand(app, "render", "render the lecture's scenes and the labs' to PNG files");
    auto args = std::make_shared<RenderArgs>();
    command->add_option("--out-dir", args->outDir, "write <scene>.png here (created if missing)")
        ->capture_default_str();
    addSizeOptions(*command, args->options);
    command->add_flag("--reference", args->reference, "render through the reference pipeline");
    command->add_flag("--plain", args->plain, "every primitive through the plain path (fill/quads.hpp): for stepping in a debugger");
    command->add_flag("--view", args->viewAfter,
                      "then open raster view on the first scene, if a display exists");
    // After the options: `--height --width 64` takes "--width" as --height's value, and that error,
    // not "64" as a scene, is the one reported (checks run in the order of declaration).
    command->add_option("scene", args->names, "the scenes to render (default: all of them)")
        ->check(CLI::IsMember(sceneNames()));
    command->add_flag("--list", args->list, "print the scenes, one a line, and what each is (renders none)");
    return {command, [args] { return runRender(*args); }};
}

}  // namespace raster::tools
