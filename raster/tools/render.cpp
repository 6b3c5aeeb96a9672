// raster render [scene...] [--out-dir D] [--width W] [--height H] [--time T] [--frames N [--fps F]]
//               [--threads T] [--reference] [--view] [--list]:
// renders the lecture's scenes and the labs' (all of them by default) to D/<scene>.png, animated
// ones at their start time (--time T, or the scene's own). --frames N writes a sequence instead,
// D/<scene>_0000.png … D/<scene>_<N−1>.png, frame k at time T + k/F (F = --fps, 30 by default; the
// scene's fixed steps in that time, scenes.hpp): only for animated scenes (all of them when none is
// named); naming a static scene with --frames is refused, as its frames would all be the same.
// With --view it then opens the viewer on the first scene where a display exists (DISPLAY or
// WAYLAND_DISPLAY set). --list prints the scenes, one a line, and what each is. --threads T: the
// worker threads (any T gives the same bits; tests/scenes_test.cpp).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
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
    uint32_t frames = 0;  // 0: one picture, <scene>.png
    double fps = 30.0;
    uint32_t threads = 0;  // 0: one per hardware thread
    bool reference = false, plain = false, viewAfter = false, list = false;
};

// The lecture's blend and depth figures (src/scene_blending.cpp, docs/BLENDING.md).
const char* blendFigureTitle(const std::string& name) {
    static const std::map<std::string, const char*> titles = {
        {"blend-additive", "blend figure: additive, depth test on, depth write off (correct for fire)"},
        {"blend-depthwrite", "blend figure: additive with depth write on (particles cut out in squares)"},
        {"blend-nodepth", "blend figure: additive, no depth test (particles over the occluder)"},
        {"blend-unsorted", "blend figure: \"over\" in storage order (far ones cover near ones)"},
        {"blend-sorted", "blend figure: \"over\" sorted back to front (correct)"},
        {"blend-wboit", "weighted blended order-independent transparency (McGuire & Bavoil 2013)"}};
    const auto it = titles.find(name);
    return it == titles.end() ? nullptr : it->second;
}

// The lecture's fog figures (src/scene_fog.cpp, src/scene_media.cpp) and part 1's figures by ray
// marching (src/scene_media_figures.cpp), and the slides' diagrams (src/scene_slide_figures.cpp); --sigma,
// --source and --falloff change the medium of the fog and media figures.
const char* fogFigureTitle(const std::string& name) {
    static const std::map<std::string, const char*> titles = {
        {"fog-constant", "fog figure: constant fog, L0*e^(-sigma*s) + (q/sigma)*(1 - e^(-sigma*s)), the sky at s = inf"},
        {"fog-black", "fog figure: \"zero source term, black fog\" (q = 0): everything fades to black"},
        {"fog-coloured", "fog figure: coloured fog that hides the background (its colour q/sigma)"},
        {"fog-height", "fog figure: exponential height fog, denser below (--falloff B)"},
        {"media-closed-form", "a box of medium before the world: absorption, emission, both (--sigma, --source)"},
        {"media-absorption", "ray-marched metaballs that only absorb before a checkered room (--sigma)"},
        {"media-emission", "ray-marched metaballs that only emit, glowing before a dim room (--source)"},
        {"media-scattering", "single scattering, back-lit: isotropic | Rayleigh | Henyey-Greenstein g = 0.7"},
        {"media-euler", "Euler | exponential step at 8 steps | converged; red: L > 1, blue: L < 0"},
        {"cloud", "a 256^3 voxel cloud, sun-lit with shadow rays, over the fog's ground (--voxels, --volume)"},
        {"cloud-point", "the cloud at night lit from below by a point light (1/r^2, shadow rays to the light)"},
        {"phase-polar", "slide diagram: isotropic, Rayleigh, Henyey-Greenstein g = +-0.3 | +-0.7 as polar plots"},
        {"media-march-steps", "slide diagram: the media scene's centre ray in 24 steps: samples, mu*ds, T, L"}};
    const auto it = titles.find(name);
    return it == titles.end() ? nullptr : it->second;
}

// --list: each scene's name and what it is.
void listScenes() {
    for (const std::string& name : sceneNames()) {
        const SceneEntry* entry = findRegisteredScene(name);
        const char* figure = blendFigureTitle(name);
        if (!figure) figure = fogFigureTitle(name);
        const char* title = name == "fire"        ? "the lecture's fire over the occluder, animated (a particle system)"
                            : name == "smoke"     ? "grey smoke blended over, sorted and soft against a box (animated)"
                            : name == "smoke-volume"
                                ? "the smoke's particles splatted into a voxel volume, ray marched with shadow rays (animated)"
                            : name == "sprites"
                                ? "sprites three ways, rows top to bottom: (a) classic transforms, (b) own transform, "
                                  "(c) geometry shader, then turned to the eye; animated (try --fov 120)"
                            : name == "forest"
                                ? "trees as axis billboards, shrubs as billboard clouds, alpha tested; the camera orbits"
                            : name == "particles" ? "the lecture's fire billboards (../shared/bench/SCENES.md)"
                            : name == "fog"     ? "cubes on a ground plane in fog (../shared/bench/SCENES.md)"
                            : figure            ? figure
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

// The scenes to render: the named ones, or all; with --frames the animated ones of all, and a named
// static one is a usage error.
std::vector<std::string> scenesToRender(const RenderArgs& args) {
    if (args.frames == 0) return args.names.empty() ? sceneNames() : args.names;
    std::vector<std::string> names;
    for (const std::string& name : args.names.empty() ? sceneNames() : args.names) {
        const bool animated = makeScene(name, {.width = 1, .height = 1, .count = 0})->animated();
        if (animated) names.push_back(name);
        else if (!args.names.empty())
            throw CLI::ValidationError("--frames", "scene '" + name +
                                                       "' is static: its frames would all be the same "
                                                       "(--frames takes animated scenes, such as fire)");
    }
    return names;
}

// Writes one scene's picture, or its --frames sequence: frame k after k advances of 1/fps.
void renderScene(Context& context, const std::string& name, const RenderArgs& args) {
    const SceneOptions& options = args.options;
    std::unique_ptr<Scene> scene = makeScene(name, options);
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    for (uint32_t k = 0; k < std::max(args.frames, 1u); ++k) {
        if (k > 0) scene->advance(1.0 / args.fps);
        scene->render(context, color, depth);
        char suffix[16] = "";
        if (args.frames > 0) std::snprintf(suffix, sizeof suffix, "_%04u", k);
        const std::string path = args.outDir + "/" + name + suffix + ".png";
        color.savePng(path);
        if (scene->animated())
            std::printf("wrote %s (%ux%u, t=%.4f s)\n", path.c_str(), options.width, options.height, scene->time());
        else
            std::printf("wrote %s (%ux%u)\n", path.c_str(), options.width, options.height);
        std::fflush(stdout);
    }
}

// Each PNG is written before the next frame or scene is made: an error in a later one leaves the
// earlier files in place.
int runRender(const RenderArgs& args) {
    if (args.list) {
        listScenes();
        return 0;
    }
    const std::vector<std::string> names = scenesToRender(args);
    std::error_code ec;
    std::filesystem::create_directories(args.outDir, ec);
    RASTER_REQUIRE(!ec, BadFile, "cannot create output directory '" + args.outDir + "': " + ec.message());
    Context context({args.threads, args.reference, args.plain});
    for (const std::string& name : names) renderScene(context, name, args);
    return args.viewAfter && !names.empty() ? viewAfter(names.front()) : 0;
}

}  // namespace

Command addRender(CLI::App& app) {
    CLI::App* command = addCommand(app, "render", "render the lecture's scenes and the labs' to PNG files");
    auto args = std::make_shared<RenderArgs>();
    command->add_option("--out-dir", args->outDir, "write <scene>.png here (created if missing)")
        ->capture_default_str();
    addSizeOptions(*command, args->options);
    addContentOptions(*command, args->options);
    addTimeOptions(*command, args->options);
    addWholeNumber(*command, "--frames", args->frames, 1, 100'000,
                   "write N frames <scene>_0000.png ... of the animated scenes")
        ->default_str("one picture, <scene>.png");
    addRealNumber(
        *command, "--fps", 0.0, 1000.0, true, [args](double fps) { args->fps = fps; },
        "--frames: frames per second of simulated time (frame k at --time + k/F)")
        ->default_str("30");
    addThreadsOption(*command, args->threads);
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
