// The lab runner: the main() that raster grade links with a submission's lab file (and raster_lib) into
// a program of its own, run in the sandbox. It renders one registered scene (the lab's) with the options
// given and writes the image as a PNG; with --pixel it renders with the pipeline trace on that pixel
// and writes the trace as JSON too (grade/trace_json.hpp), for the grader's diagnosis.
//
//   lab_runner --scene billboards --out scene.png --width 320 --height 180 --count 500
//              [--camera EX,EY,EZ,TX,TY,TZ] [--seed N] [--cubes N] [--fog constant|height] [--time T]
//              [--fov DEGREES] [--sigma R,G,B] [--source R,G,B] [--falloff B] [--threads N]
//              [--path fast|plain|reference] [--pixel X,Y --history FILE]
//
// Exit status 0 when the image was written; 1 with a message on stderr for anything else (an option it
// does not know, an Error from the scene). The grader trusts none of what it writes: it reads the PNG
// and compares it itself, and the history only feeds a diagnosis.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <memory>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "grade/trace_json.hpp"
#include "raster/check.hpp"
#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"
#include "raster/trace.hpp"

namespace {

using raster::Error;
using raster::ErrorCode;

struct RunnerArgs {
    std::string scene, out, history, path = "fast";
    raster::SceneOptions options;
    unsigned threads = 0;
    bool pixel = false;
    int32_t px = 0, py = 0;
};

std::vector<float> numbers(const std::string& option, const std::string& text, size_t count) {
    std::vector<float> out;
    std::stringstream in(text);
    std::string part;
    while (std::getline(in, part, ',')) {
        char* end = nullptr;
        out.push_back(std::strtof(part.c_str(), &end));
        RASTER_REQUIRE(!part.empty() && *end == 0, InvalidArgument,
                       option + ": '" + part + "' is not a number");
    }
    RASTER_REQUIRE(
        out.size() == count, InvalidArgument,
        option + " takes " + std::to_string(count) + " numbers separated by commas, not '" + text + "'");
    return out;
}

uint32_t whole(const std::string& option, const std::string& text) {
    char* end = nullptr;
    const unsigned long v = std::strtoul(text.c_str(), &end, 10);
    RASTER_REQUIRE(!text.empty() && *end == 0 && text[0] != '-' && v <= UINT32_MAX, InvalidArgument,
                   option + ": '" + text + "' is not a whole number");
    return uint32_t(v);
}

RunnerArgs parseArgs(int argc, char** argv) {
    RunnerArgs a;
    for (int i = 1; i < argc; ++i) {
        const std::string option = argv[i];
        RASTER_REQUIRE(i + 1 < argc, InvalidArgument, option + " needs a value");
        const std::string value = argv[++i];
        if (option == "--scene")
            a.scene = value;
        else if (option == "--out")
            a.out = value;
        else if (option == "--history")
            a.history = value;
        else if (option == "--path")
            a.path = value;
        else if (option == "--width")
            a.options.width = whole(option, value);
        else if (option == "--height")
            a.options.height = whole(option, value);
        else if (option == "--count")
            a.options.count = whole(option, value);
        else if (option == "--seed")
            a.options.seed = whole(option, value);
        else if (option == "--cubes")
            a.options.cubes = whole(option, value);
        else if (option == "--time") {
            char* end = nullptr;
            const double t = std::strtod(value.c_str(), &end);
            RASTER_REQUIRE(!value.empty() && *end == 0 && t >= 0.0 && t <= raster::kMaxStartTime,
                           InvalidArgument, option + ": '" + value + "' is not a time in [0, 600] seconds");
            a.options.time = t;
        } else if (option == "--threads")
            a.threads = whole(option, value);
        else if (option == "--fog")
            a.options.heightFog = value == "height";
        else if (option == "--camera") {
            const std::vector<float> v = numbers(option, value, 6);
            a.options.camera = raster::SceneCamera{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
        } else if (option == "--fov") {
            const float fov = numbers(option, value, 1)[0];
            RASTER_REQUIRE(fov > 0.0f && fov <= 179.0f, InvalidArgument,
                           option + ": '" + value + "' is not a field of view in (0, 179] degrees");
            a.options.fovDegrees = fov;
        } else if (option == "--sigma" || option == "--source" || option == "--falloff") {
            const bool rgb = option != "--falloff";
            const std::vector<float> v = numbers(option, value, rgb ? 3 : 1);
            for (const float x : v) {
                const std::string problem = raster::fogValueProblem(x);
                RASTER_REQUIRE(problem.empty(), InvalidArgument, option + ": " + problem);
            }
            if (option == "--sigma") a.options.fogSigma = glm::vec3(v[0], v[1], v[2]);
            if (option == "--source") a.options.fogSource = glm::vec3(v[0], v[1], v[2]);
            if (option == "--falloff") a.options.fogFalloff = v[0];
        } else if (option == "--pixel") {
            const std::vector<float> v = numbers(option, value, 2);
            a.pixel = true, a.px = int32_t(v[0]), a.py = int32_t(v[1]);
        } else {
            throw Error(ErrorCode::InvalidArgument, "unknown option '" + option + "'");
        }
    }
    RASTER_REQUIRE(!a.scene.empty() && !a.out.empty(), InvalidArgument, "--scene and --out are required");
    RASTER_REQUIRE(a.path == "fast" || a.path == "plain" || a.path == "reference", InvalidArgument,
                   "--path takes fast, plain or reference, not '" + a.path + "'");
    RASTER_REQUIRE(!a.pixel || !a.history.empty(), InvalidArgument, "--pixel needs --history FILE");
    return a;
}

int run(const RunnerArgs& a) {
    std::unique_ptr<raster::Scene> scene = raster::makeScene(a.scene, a.options);
    raster::Context context({a.threads, a.path == "reference", a.path == "plain"});
    raster::RenderTarget color(a.options.width, a.options.height);
    raster::DepthTarget depth(a.options.width, a.options.height);
    raster::TraceOptions trace_options;
    trace_options.pixels = {a.px, a.py, a.px, a.py};
    trace_options.maxGeometryRecords = 1u << 18;
    raster::Trace trace(trace_options);
    if (a.pixel) context.setTrace(&trace);
    context.resetFrameStatistics();
    scene->render(context, color, depth);
    color.savePng(a.out);
    if (a.pixel) {
        std::ofstream file(a.history, std::ios::binary);
        file << raster::grade::traceToJson(trace);
        RASTER_REQUIRE(file.good(), BadFile, "cannot write '" + a.history + "'");
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(parseArgs(argc, argv));
    } catch (const std::bad_alloc& e) {
        std::fprintf(stderr, "lab runner: out of memory (%s)\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lab runner: %s\n", e.what());
    }
    return 1;
}
