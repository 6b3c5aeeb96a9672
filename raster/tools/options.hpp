// Command-line options shared by the subcommands, declared with CLI11 (libcli11-dev). Every option
// is declared once, with its range or its choices; a bad value, an unknown option or a missing value
// is a CLI::ParseError naming the option, which main() prints and exits with kUsageExit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "raster/check.hpp"
#include "raster/render_target.hpp"
#include "raster/scenes.hpp"

namespace raster::tools {

// The exit status of a command line that does not parse; an error while running exits 1.
constexpr int kUsageExit = 2;

// Digits only, leading zeros dropped: CLI11 alone would read "010" as octal 8 and take "+5", " 5"
// and "0x10". Returns "" or what is wrong (the form of a CLI::Validator's function).
inline std::string wholeNumber(std::string& text) {
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
        return "'" + text + "' is not a whole number";
    text.erase(0, std::min(text.find_first_not_of('0'), text.size() - 1));
    return "";
}

// Adds `name` taking a whole number in [lo, hi], its default shown in --help.
inline CLI::Option* addWholeNumber(CLI::App& command, const std::string& name, uint32_t& value, uint32_t lo,
                                   uint32_t hi, const std::string& help) {
    return command.add_option(name, value, help)
        ->transform(CLI::Validator(wholeNumber, ""))
        ->check(CLI::Range(lo, hi).description(""))
        ->type_name("N in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]")
        ->capture_default_str();
}

// Adds `name` taking a whole number in [lo, hi] into an optional (unset: the scene's own default).
inline CLI::Option* addOptionalWholeNumber(CLI::App& command, const std::string& name,
                                           std::optional<uint32_t>& value, uint32_t lo, uint32_t hi,
                                           const std::string& help) {
    return command.add_option_function<uint32_t>(name, [&value](const uint32_t& v) { value = v; }, help)
        ->transform(CLI::Validator(wholeNumber, ""))
        ->check(CLI::Range(lo, hi).description(""))
        ->type_name("N in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

// "[lo, hi]" or "(lo, hi]", the numbers as %g prints them.
inline std::string realRange(double lo, double hi, bool open_low) {
    char text[64];
    std::snprintf(text, sizeof text, "%s%g, %g]", open_low ? "(" : "[", lo, hi);
    return text;
}

// A decimal number in [lo, hi] (lo excluded when `open_low`), finite: CLI11 alone would take "nan"
// and "inf". Returns "" or what is wrong.
inline std::string realNumber(const std::string& text, double lo, double hi, bool open_low) {
    double value = 0.0;
    size_t used = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || text.find_first_of("nNiIxX") != std::string::npos)
        return "'" + text + "' is not a decimal number";
    if (!std::isfinite(value) || value > hi || value < lo || (open_low && value == lo))
        return "'" + text + "' is outside " + realRange(lo, hi, open_low);
    return "";
}

// Adds `name` taking a decimal number as realNumber checks it; set(value) gets it.
inline CLI::Option* addRealNumber(CLI::App& command, const std::string& name, double lo, double hi,
                                  bool open_low, std::function<void(double)> set, const std::string& help) {
    return command.add_option_function<double>(name, [set](const double& v) { set(v); }, help)
        ->check(CLI::Validator([=](std::string& text) { return realNumber(text, lo, hi, open_low); }, ""))
        ->type_name("T in " + realRange(lo, hi, open_low));
}

// Reads "A<separator>B", two whole numbers each in [lo, hi], into out. Returns "" or what is wrong,
// naming the half (first_name or second_name) that is.
inline std::string readPair(std::string text, char separator, const char* first_name, const char* second_name,
                            uint32_t lo, uint32_t hi, std::pair<uint32_t, uint32_t>& out) {
    const size_t at = text.find(separator);
    if (at == std::string::npos)
        return "takes " + std::string(first_name) + separator + second_name + ", not '" + text + "'";
    std::string halves[2] = {text.substr(0, at), text.substr(at + 1)};
    const char* names[2] = {first_name, second_name};
    uint32_t values[2] = {};
    for (int i = 0; i < 2; ++i) {
        std::string error = wholeNumber(halves[i]);
        if (error.empty()) error = CLI::Range(lo, hi)(halves[i]);
        if (!error.empty()) return std::string(names[i]) + " of '" + text + "': " + error;
        values[i] = uint32_t(std::stoul(halves[i]));
    }
    out = {values[0], values[1]};
    return "";
}

// Adds `name` taking "A<separator>B" (view --size WxH, trace --pixel X,Y); set(a, b) gets the pair.
inline CLI::Option* addPair(CLI::App& command, const std::string& name, char separator,
                            const char* first_name, const char* second_name, uint32_t lo, uint32_t hi,
                            std::function<void(uint32_t, uint32_t)> set, const std::string& help) {
    const auto read = [=](const std::string& text, std::pair<uint32_t, uint32_t>& out) {
        return readPair(text, separator, first_name, second_name, lo, hi, out);
    };
    return command
        .add_option_function<std::string>(
            name,
            [read, set](const std::string& text) {
                std::pair<uint32_t, uint32_t> pair;
                read(text, pair);
                set(pair.first, pair.second);
            },
            help)
        ->check([read](const std::string& text) {
            std::pair<uint32_t, uint32_t> pair;
            return read(text, pair);
        })
        ->type_name(std::string(first_name) + separator + second_name);
}

// A CLI::Validator from a function that throws Error for a bad value (parseScript, parseSolution):
// the Error's message, without its code, becomes the option's.
template <class Parse>
CLI::Validator throwingCheck(Parse parse) {
    return CLI::Validator(
        [parse](std::string& text) -> std::string {
            try {
                parse(text);
                return "";
            } catch (const Error& e) {
                const std::string message = e.what(), code = std::string(errorCodeName(e.code())) + ": ";
                return message.starts_with(code) ? message.substr(code.size()) : message;
            }
        },
        "");
}

// Adds a subcommand. A repeated option takes its last value, as getopt's programs do.
inline CLI::App* addCommand(CLI::App& app, const std::string& name, const std::string& description) {
    CLI::App* command = app.add_subcommand(name, description);
    command->option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    return command;
}

// The positional scene name: one of sceneNames() (the lecture's scenes, the labs, their solutions).
inline CLI::Option* addSceneName(CLI::App& command, std::string& name) {
    return command.add_option("scene", name, "fire, sprites, forest, particles, fog, or a lab (raster render --list)")
        ->check(CLI::IsMember(sceneNames()));
}

// --width, --height: the image's size in pixels; --fov: the field of view (bench, render, trace).
inline void addSizeOptions(CLI::App& command, SceneOptions& options) {
    addWholeNumber(command, "--width", options.width, 1, RenderTarget::kMaxSize, "image width in pixels");
    addWholeNumber(command, "--height", options.height, 1, RenderTarget::kMaxSize, "image height in pixels");
    addRealNumber(
        command, "--fov", 0.0, 179.0, true, [&options](double d) { options.fovDegrees = float(d); },
        "the vertical field of view in degrees (60); wide angles show the sprites' edge effects");
}

// A fog parameter's components: "R,G,B" (count 3) or "B" (count 1), decimal numbers each a finite
// float >= 0 (fogValueProblem), into out. Returns "" or what is wrong: "-1 is negative", "'x' is not a
// number", "takes R,G,B: three numbers separated by commas, not '1,2'".
inline std::string readFogValues(const std::string& text, size_t count, float* out) {
    std::vector<std::string> parts(1);
    for (const char c : text) {
        if (c == ',')
            parts.emplace_back();
        else
            parts.back().push_back(c);
    }
    if (parts.size() != count && !(count == 3 && parts.size() == 1))
        return count == 3 ? "takes R,G,B (or one number for all three), not '" + text + "'"
                          : "takes one number, not '" + text + "'";
    for (size_t i = 0; i < count; ++i) {
        const std::string& part = parts[parts.size() == 1 ? 0 : i];
        double value = 0.0;
        size_t used = 0;
        try {
            value = std::stod(part, &used);
        } catch (const std::out_of_range&) {
            return "'" + part + "' is too large for a float";
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != part.size() || part.find_first_of(" \t") != std::string::npos)
            return "'" + part + "' is not a number";
        if (const std::string problem = fogValueProblem(value); !problem.empty()) return problem;
        out[i] = float(value);
    }
    return "";
}

// --sigma R,G,B, --source R,G,B, --falloff B: the fog scenes' and the fog lab's medium (SceneOptions).
inline void addFogMediumOptions(CLI::App& command, SceneOptions& options) {
    const auto add = [&](const std::string& name, size_t count, std::function<void(const float*)> set,
                         const std::string& help) {
        command
            .add_option_function<std::string>(
                name,
                [count, set](const std::string& text) {
                    float v[3] = {};
                    readFogValues(text, count, v);
                    set(v);
                },
                help)
            ->check(CLI::Validator(
                [count](std::string& text) {
                    float v[3] = {};
                    return readFogValues(text, count, v);
                },
                ""))
            ->type_name(count == 3 ? "R,G,B" : "B");
    };
    add("--sigma", 3, [&options](const float* v) { options.fogSigma = glm::vec3(v[0], v[1], v[2]); },
        "fog scenes: the extinction sigma per metre, R,G,B or one number (each >= 0)");
    add("--source", 3, [&options](const float* v) { options.fogSource = glm::vec3(v[0], v[1], v[2]); },
        "fog scenes: the source term q per metre, R,G,B or one number; the fog's colour is q/sigma");
    add("--falloff", 1, [&options](const float* v) { options.fogFalloff = v[0]; },
        "height fog: its density falls as e^(-B*y), B >= 0 per metre");
}

// --light KIND:X,Y,Z: "point:X,Y,Z" (a point light at X,Y,Z, world metres) or "dir:X,Y,Z" (a directional
// light towards X,Y,Z, any length), into out. Returns "" or what is wrong: "takes point:X,Y,Z or
// dir:X,Y,Z, not 'x'", "'point:1,2' needs three numbers", "'x' is not a number", "nan is not a number",
// "inf is infinite", "'dir:0,0,0': the direction (0, 0, 0) has no length".
inline std::string readSceneLight(const std::string& text, SceneLight& out) {
    const size_t colon = text.find(':');
    const std::string kind = text.substr(0, colon);
    if (colon == std::string::npos || (kind != "point" && kind != "dir"))
        return "takes point:X,Y,Z or dir:X,Y,Z, not '" + text + "'";
    std::vector<std::string> parts(1);
    for (const char c : text.substr(colon + 1)) {
        if (c == ',')
            parts.emplace_back();
        else
            parts.back().push_back(c);
    }
    if (parts.size() != 3) return "'" + text + "' needs three numbers";
    SceneLight light;
    light.point = kind == "point";
    for (size_t i = 0; i < 3; ++i) {
        double value = 0.0;
        size_t used = 0;
        try {
            value = std::stod(parts[i], &used);
        } catch (const std::out_of_range&) {
            return "'" + parts[i] + "' is too large for a float";
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != parts[i].size() || parts[i].find_first_of(" \t") != std::string::npos)
            return "'" + parts[i] + "' is not a number";
        if (const std::string problem = finiteValueProblem(value); !problem.empty()) return problem;
        light.value[int(i)] = float(value);
    }
    if (const std::string problem = sceneLightProblem(light); !problem.empty()) return "'" + text + "': " + problem;
    out = light;
    return "";
}

// --light point:X,Y,Z or dir:X,Y,Z, --light-intensity R,G,B: the volume light of the media and cloud
// scenes (SceneOptions::light, lightIntensity).
inline void addLightOptions(CLI::App& command, SceneOptions& options) {
    command
        .add_option_function<std::string>(
            "--light",
            [&options](const std::string& text) {
                SceneLight light;
                readSceneLight(text, light);
                options.light = light;
            },
            "media, cloud: the volume light, a point light at X,Y,Z (metres) or a directional one towards X,Y,Z")
        ->check(CLI::Validator(
            [](std::string& text) {
                SceneLight light;
                return readSceneLight(text, light);
            },
            ""))
        ->type_name("point:X,Y,Z|dir:X,Y,Z");
    command
        .add_option_function<std::string>(
            "--light-intensity",
            [&options](const std::string& text) {
                float v[3] = {};
                readFogValues(text, 3, v);
                options.lightIntensity = glm::vec3(v[0], v[1], v[2]);
            },
            "media, cloud: a point light's intensity I (per steradian; irradiance I/r^2 at r metres) or a "
            "directional one's irradiance, R,G,B or one number (unset: the scene's medium lit as by its own)")
        ->check(CLI::Validator(
            [](std::string& text) {
                float v[3] = {};
                return readFogValues(text, 3, v);
            },
            ""))
        ->type_name("R,G,B");
}

// --count, --seed, --cubes, --fog, --sigma, --source, --falloff, --light: what the lecture's scenes and the
// labs hold (bench, render, trace, view).
inline void addContentOptions(CLI::App& command, SceneOptions& options) {
    addOptionalWholeNumber(command, "--count", options.count, 0, 50'000'000,
                           "particles: the number of billboards (10000); fire: the particle slots (4000)");
    addWholeNumber(command, "--seed", options.seed, 0, UINT32_MAX,
                   "the simulation's seed (fire, labs that simulate; particles and fog have none)");
    addWholeNumber(command, "--cubes", options.cubes, 0, 1024, "fog: cubes per side of the grid");
    addOptionalWholeNumber(command, "--voxels", options.voxels, 1, 1024,
                           "cloud: voxels per axis of the generated cloud (256)");
    command.add_option("--volume", options.volume,
                       "cloud: a volume file instead of the generated cloud (.nvdb, name_XxYxZ_uint8.raw or "
                       "name_XxYxZ_float32.raw)");
    command
        .add_option_function<std::string>(
            "--fog", [&options](const std::string& fog) { options.heightFog = fog == "height"; },
            "fog: the fog model")
        ->check(CLI::IsMember({"constant", "height"}))
        ->default_str(options.heightFog ? "height" : "constant");
    addFogMediumOptions(command, options);
    addLightOptions(command, options);
}

// --time T: an animated scene's start time (bench, render). Static scenes ignore it.
inline void addTimeOptions(CLI::App& command, SceneOptions& options) {
    addRealNumber(
        command, "--time", 0.0, kMaxStartTime, false, [&options](double t) { options.time = t; },
        "animated scenes: the start time in seconds, simulated before the first frame (fire: 3)");
}

// --threads T: the Context's worker threads; unset, one per hardware thread.
inline void addThreadsOption(CLI::App& command, uint32_t& threads) {
    addWholeNumber(command, "--threads", threads, 1, 1024, "worker threads")->default_str("all cores");
}

}  // namespace raster::tools
