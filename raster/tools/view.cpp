// raster view <scene>: the SDL2 viewer (raster/tools/view/viewer.hpp), in a window or headless.
#include <memory>
#include <string>

#include "commands.hpp"
#include "options.hpp"
#include "view/viewer.hpp"

namespace raster::tools {
namespace {

// --help's text after the options: what the viewer does, and its keys.
std::string about() {
    std::string text =
        "Opens a window on the scene's framebuffer. --script runs space-separated keys first (also\n"
        "click:X,Y  drag:X0,Y0,X1,Y1  wheel:N  resize:WxH  wait); --headless runs it on SDL's offscreen\n"
        "driver and exits. Screenshots (S, F12) save the framebuffer to D/<scene>-NNNN.png;\n"
        "--screenshot-window also saves the window, text included. A click prints the pixel's colour and\n"
        "depth, then its history (every fragment, from a traced render); O, X, L, G and V show views of\n"
        "the pipeline trace (frames are traced only for them).\n"
        "--solution: what K shows and J compares the frame with - reference (this scene through the\n"
        "reference pipeline), another scene (e.g. a lab's solution) at the same size, camera and step,\n"
        "or a PNG of the frame's size; rendered only while K or J is on. A lab's default is its solution\n"
        "(<lab>@solution), when solutions/ was built, else the handout's image of it at the lab's\n"
        "defaults (labs/<lab>/reference/<lab>@solution.png).\n"
        "Animated scenes (fire) play in the window from the start; --paused or --headless start them\n"
        "paused (Space plays, . and , step a frame of 1/60 s, so a script's frames are exact).\n"
        "keys:";
    for (const std::string& line : keyHelp()) text += "\n  " + line;
    return text;
}

// A check that the value is not empty: `what` says what the option takes instead.
CLI::Validator notEmpty(std::string what) {
    return CLI::Validator(
        [what](std::string& text) { return text.empty() ? what + ", not ''" : std::string(); }, "");
}

}  // namespace

int openViewer(ViewerOptions options) {
    defaultCamera(options.scene);     // an unknown scene fails here, before a window opens
    parseSolution(options.solution);  // so does a bad --solution
    Viewer viewer(std::move(options));
    viewer.run();
    return 0;
}

Command addView(CLI::App& app) {
    CLI::App* command = addCommand(app, "view", "the SDL2 viewer: step through draws and primitives");
    auto options = std::make_shared<ViewerOptions>();
    SceneOptions& scene = options->sceneOptions;
    addSceneName(*command, options->scene)->required();
    addPair(
        *command, "--size", 'x', "W", "H", 1, RenderTarget::kMaxSize,
        [options](uint32_t w, uint32_t h) {
            options->sceneOptions.width = w, options->sceneOptions.height = h;
        },
        "the framebuffer's (and the window's first) size")
        ->default_str(std::to_string(scene.width) + "x" + std::to_string(scene.height));
    addContentOptions(*command, scene);
    addThreadsOption(*command, options->context.threads);
    command->add_flag("--reference", options->context.reference, "run the reference pipeline");
    command->add_flag("--plain", options->context.plain,
                      "every primitive through the plain path (fill/quads.hpp): for stepping in a debugger");
    addTimeOptions(*command, scene);
    command->add_flag("--paused", options->paused, "animated scenes: start paused (Space plays)");
    command->add_flag("--headless", options->headless, "SDL's offscreen driver: run --script, then exit");
    command
        ->add_option_function<std::string>(
            "--script", [options](const std::string& text) { options->script = parseScript(text); },
            "keys to play first, space-separated")
        ->check(throwingCheck(parseScript));
    command->add_option("--screenshot-dir", options->screenshotDir, "where S and F12 save screenshots")
        ->check(notEmpty("needs a directory"))
        ->capture_default_str();
    command->add_flag("--screenshot-window", options->screenshotWindow,
                      "also save the window, text included");
    command
        ->add_option("--solution", options->solution,
                     "what K shows and J compares with: reference|<scene>|<file.png>")
        ->check(notEmpty("takes reference, a scene or a .png file"))
        ->check(throwingCheck(parseSolution));
    command->footer(about);
    return {command, [options] { return openViewer(*options); }};
}

}  // namespace raster::tools
