#include "grade/grading.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "raster/check.hpp"

namespace raster::grade {
namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

struct FieldReader {
    std::string where;  // "labs/billboards/grading.json: scene 2"

    [[noreturn]] void fail(const std::string& what) const {
        throw Error(ErrorCode::BadFile, where + ": " + what);
    }
    void onlyKnown(const Json& j, std::initializer_list<const char*> known) const {
        if (!j.is_object()) fail("an object was expected, not " + j.dump());
        for (const auto& [key, value] : j.items())
            if (std::none_of(known.begin(), known.end(), [&](const char* k) { return key == k; }))
                fail("unknown field \"" + key + "\"");
    }
    uint32_t whole(const Json& j, const char* field, uint32_t lo, uint32_t hi) const {
        if (!j.is_number_unsigned() || j.get<uint64_t>() < lo || j.get<uint64_t>() > hi)
            fail(std::string("\"") + field + "\" must be a whole number in [" + std::to_string(lo) + ", " +
                 std::to_string(hi) + "], not " + j.dump());
        return uint32_t(j.get<uint64_t>());
    }
    glm::vec3 point(const Json& j, const char* field) const {
        if (!j.is_array() || j.size() != 3 ||
            !std::all_of(j.begin(), j.end(), [](const Json& v) { return v.is_number(); }))
            fail(std::string("\"") + field + "\" must be 3 numbers, not " + j.dump());
        return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
    }
    std::string text(const Json& j, const char* field) const {
        if (!j.is_string() || j.get<std::string>().empty())
            fail(std::string("\"") + field + "\" must be a non-empty string");
        return j.get<std::string>();
    }

    SceneOptions options(const Json& j) const {
        onlyKnown(j, {"width", "height", "count", "seed", "cubes", "fog", "camera", "time", "fov", "sigma",
                      "source", "falloff"});
        SceneOptions o;
        if (j.contains("width")) o.width = whole(j["width"], "width", 1, 8192);
        if (j.contains("height")) o.height = whole(j["height"], "height", 1, 8192);
        if (j.contains("count")) o.count = whole(j["count"], "count", 0, 50'000'000);
        if (j.contains("seed")) o.seed = whole(j["seed"], "seed", 0, UINT32_MAX);
        if (j.contains("time")) {
            if (!j["time"].is_number() || !(j["time"].get<double>() >= 0.0) ||
                !(j["time"].get<double>() <= kMaxStartTime))
                fail("\"time\" must be a number of seconds in [0, " + std::to_string(int(kMaxStartTime)) +
                     "], not " + j["time"].dump());
            o.time = j["time"].get<double>();
        }
        if (j.contains("cubes")) o.cubes = whole(j["cubes"], "cubes", 0, 1024);
        if (j.contains("fog")) {
            const std::string fog = text(j["fog"], "fog");
            if (fog != "constant" && fog != "height")
                fail("\"fog\" is \"constant\" or \"height\", not \"" + fog + "\"");
            o.heightFog = fog == "height";
        }
        if (j.contains("camera")) {
            const Json& c = j["camera"];
            onlyKnown(c, {"eye", "target"});
            if (!c.contains("eye") || !c.contains("target")) fail("\"camera\" needs \"eye\" and \"target\"");
            o.camera = SceneCamera{point(c["eye"], "eye"), point(c["target"], "target")};
        }
        if (j.contains("fov")) {  // the vertical field of view, degrees (SceneOptions::fovDegrees)
            if (!j["fov"].is_number() || !(j["fov"].get<double>() > 0.0) ||
                !(j["fov"].get<double>() <= 179.0))
                fail("\"fov\" must be a number of degrees in (0, 179], not " + j["fov"].dump());
            o.fovDegrees = j["fov"].get<float>();
        }
        if (j.contains("sigma")) o.fogSigma = fogValues(j["sigma"], "sigma");
        if (j.contains("source")) o.fogSource = fogValues(j["source"], "source");
        if (j.contains("falloff")) o.fogFalloff = fogValue(j["falloff"], "\"falloff\"");
        return o;
    }
    // A fog parameter's component, named `what` in messages: a number, finite and >= 0 as a float
    // (fogValueProblem).
    float fogValue(const Json& j, const std::string& what) const {
        if (!j.is_number()) fail(what + " must be a number, not " + j.dump());
        const std::string problem = fogValueProblem(j.get<double>());
        if (!problem.empty()) fail(what + ": " + problem);
        return j.get<float>();
    }
    // σ or q: 3 such numbers, R, G, B.
    glm::vec3 fogValues(const Json& j, const char* field) const {
        if (!j.is_array() || j.size() != 3)
            fail(std::string("\"") + field + "\" must be 3 numbers (R, G, B), not " + j.dump());
        glm::vec3 v;
        for (int c = 0; c < 3; ++c) v[c] = fogValue(j[c], std::string("\"") + field + "\" " + "RGB"[c]);
        return v;
    }

    GradedScene scene(const Json& j, bool is_public) const {
        onlyKnown(j, {"name", "number", "points", "options", "comparison"});
        for (const char* required : {"name", "number", "points", "comparison"})
            if (!j.contains(required)) fail(std::string("no \"") + required + "\"");
        GradedScene s;
        s.name = text(j["name"], "name");
        if (s.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-") != std::string::npos)
            fail("scene name \"" + s.name + "\" has characters other than [a-z0-9_-]");
        s.number = text(j["number"], "number");
        if (!j["points"].is_number() || j["points"].get<double>() <= 0)
            fail("\"points\" must be a number above 0");
        s.points = j["points"].get<double>();
        s.isPublic = is_public;
        if (j.contains("options")) s.options = options(j["options"]);
        try {
            s.comparison = raster::Comparison::parse(j["comparison"].dump());
        } catch (const Error& e) {
            fail(std::string("scene \"") + s.name + "\": " + e.what());
        }
        return s;
    }
};

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    RASTER_REQUIRE(in, BadFile, "cannot read '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace

LabGrading readGradingFile(const std::string& path, const std::string& lab, bool is_public) {
    const Json j = Json::parse(readText(path), nullptr, false);
    FieldReader read{path};
    if (j.is_discarded()) read.fail("not JSON");
    read.onlyKnown(j, {"title", "scenes"});
    if (!j.contains("scenes") || !j["scenes"].is_array() || j["scenes"].empty())
        read.fail("\"scenes\" must be a non-empty array");
    LabGrading grading{lab, j.contains("title") ? read.text(j["title"], "title") : "", {}};
    for (size_t i = 0; i < j["scenes"].size(); ++i) {
        const FieldReader scene_reader{path + ": scene " + std::to_string(i + 1)};
        grading.scenes.push_back(scene_reader.scene(j["scenes"][i], is_public));
    }
    return grading;
}

std::vector<LabGrading> discoverLabs(const std::string& root, bool public_only) {
    const fs::path labs_dir = fs::path(root) / "labs";
    RASTER_REQUIRE(fs::is_directory(labs_dir), BadFile, "no labs/ folder in the grading root '" + root + "'");
    std::vector<std::string> names;
    for (const fs::directory_entry& entry : fs::directory_iterator(labs_dir))
        if (entry.is_directory() && fs::is_regular_file(entry.path() / "grading.json"))
            names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    std::vector<LabGrading> labs;
    for (const std::string& name : names) {
        LabGrading lab = readGradingFile((labs_dir / name / "grading.json").string(), name, true);
        const fs::path hidden = fs::path(root) / "solutions" / name / "grading.json";
        if (!public_only && fs::is_regular_file(hidden)) {
            LabGrading more = readGradingFile(hidden.string(), name, false);
            if (lab.title.empty()) lab.title = more.title;
            for (GradedScene& s : more.scenes) lab.scenes.push_back(std::move(s));
        }
        std::set<std::string> scene_names, numbers;
        for (const GradedScene& s : lab.scenes) {
            RASTER_REQUIRE(scene_names.insert(s.name).second, InvalidArgument,
                           "lab '" + name + "': scene name '" + s.name + "' is declared twice");
            RASTER_REQUIRE(numbers.insert(s.number).second, InvalidArgument,
                           "lab '" + name + "': scene number '" + s.number + "' is declared twice");
        }
        labs.push_back(std::move(lab));
    }
    return labs;
}

std::vector<std::string> runnerOptionArgs(const SceneOptions& o) {
    std::vector<std::string> args = {"--width",  std::to_string(o.width),
                                     "--height", std::to_string(o.height),
                                     "--seed",   std::to_string(o.seed),
                                     "--cubes",  std::to_string(o.cubes),
                                     "--fog",    o.heightFog ? "height" : "constant"};
    if (o.count) args.insert(args.end(), {"--count", std::to_string(*o.count)});
    if (o.time) {
        char time[64];
        std::snprintf(time, sizeof time, "%.17g", *o.time);  // every bit of the double
        args.insert(args.end(), {"--time", time});
    }
    if (o.camera) {
        char camera[256];
        std::snprintf(camera, sizeof camera, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", o.camera->eye.x,
                      o.camera->eye.y, o.camera->eye.z, o.camera->target.x, o.camera->target.y,
                      o.camera->target.z);
        args.insert(args.end(), {"--camera", camera});
    }
    const auto floats = [](const float* v, int n) {  // every bit of each float, comma-separated
        std::string text;
        for (int i = 0; i < n; ++i) {
            char number[32];
            std::snprintf(number, sizeof number, "%s%.9g", i ? "," : "", double(v[i]));
            text += number;
        }
        return text;
    };
    if (o.fogSigma) args.insert(args.end(), {"--sigma", floats(&o.fogSigma->x, 3)});
    if (o.fogSource) args.insert(args.end(), {"--source", floats(&o.fogSource->x, 3)});
    if (o.fogFalloff) args.insert(args.end(), {"--falloff", floats(&*o.fogFalloff, 1)});
    if (o.fovDegrees) {
        char fov[32];
        std::snprintf(fov, sizeof fov, "%.9g", double(*o.fovDegrees));  // every bit of the float
        args.insert(args.end(), {"--fov", fov});
    }
    return args;
}

}  // namespace raster::grade
