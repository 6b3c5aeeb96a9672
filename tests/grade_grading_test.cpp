// raster grade's declarations (raster/tools/grade/grading.hpp): the `time` an animated lab's scene may
// set, checked when the file is read, and handed to the lab runner with every bit of the double; the
// fog lab's medium (`sigma`, `source`, `falloff`) likewise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "grade/grading.hpp"
#include "raster/check.hpp"

namespace raster::grade {
namespace {

// A grading.json holding one scene with these options, in a fresh temporary folder.
std::string gradingFile(const std::string& options) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() /
        ("grade_grading_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "grading.json").string();
    std::ofstream(path) << R"({"scenes": [{"name": "a", "number": "1.1", "points": 1, "options": )" << options
                        << R"(, "comparison": {"method": "exact"}}]})";
    return path;
}

// The value after `flag` in the runner's arguments, or "" when the flag is absent.
std::string argAfter(const std::vector<std::string>& args, const std::string& flag) {
    const auto it = std::find(args.begin(), args.end(), flag);
    return it != args.end() && it + 1 != args.end() ? *(it + 1) : "";
}

TEST(GradingFile, ReadsATimeAndHandsTheRunnerItsExactBits) {
    for (const double t : {2.25, 1.0 / 3.0, 600.0, 0.0}) {
        char text[64];
        std::snprintf(text, sizeof text, "%.17g", t);
        const LabGrading lab =
            readGradingFile(gradingFile(std::string(R"({"time": )") + text + "}"), "x", true);
        ASSERT_EQ(lab.scenes.size(), 1u);
        ASSERT_TRUE(lab.scenes[0].options.time.has_value());
        EXPECT_EQ(*lab.scenes[0].options.time, t);
        const std::string arg = argAfter(runnerOptionArgs(lab.scenes[0].options), "--time");
        ASSERT_FALSE(arg.empty());
        EXPECT_EQ(std::strtod(arg.c_str(), nullptr), t) << arg;
    }
}

TEST(GradingFile, LeavesTheTimeUnsetWhenNotGiven) {
    const LabGrading lab = readGradingFile(gradingFile(R"({"width": 64})"), "x", true);
    EXPECT_FALSE(lab.scenes[0].options.time.has_value()) << "the lab's own start time";
    EXPECT_EQ(argAfter(runnerOptionArgs(lab.scenes[0].options), "--time"), "");
}

TEST(GradingFile, RefusesATimeThatIsNoSecondsInRange) {
    for (const char* bad :
         {R"({"time": -1})", R"({"time": 600.5})", R"({"time": "3"})", R"({"time": null})"}) {
        try {
            readGradingFile(gradingFile(bad), "x", true);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::BadFile) << e.what();
            EXPECT_NE(std::string(e.what()).find("\"time\" must be a number of seconds in [0, 600]"),
                      std::string::npos)
                << e.what();
        }
    }
}

// The fog lab's medium: sigma and source as 3 numbers, falloff one, each handed to the runner with
// every bit of the float; negative, too large or not numbers refused naming the field.
TEST(GradingFile, ReadsAFogMediumAndHandsTheRunnerItsExactBits) {
    const LabGrading lab = readGradingFile(
        gradingFile(R"({"sigma": [1e-7, 0, 0.07], "source": [0.03, 0.004, 0.05], "falloff": 2.5})"), "x", true);
    const SceneOptions& o = lab.scenes[0].options;
    ASSERT_TRUE(o.fogSigma && o.fogSource && o.fogFalloff);
    EXPECT_EQ(*o.fogSigma, glm::vec3(1e-7f, 0.0f, 0.07f));
    const std::vector<std::string> args = runnerOptionArgs(o);
    float back[3] = {};
    ASSERT_EQ(std::sscanf(argAfter(args, "--sigma").c_str(), "%g,%g,%g", &back[0], &back[1], &back[2]), 3);
    EXPECT_EQ(glm::vec3(back[0], back[1], back[2]), *o.fogSigma) << argAfter(args, "--sigma");
    ASSERT_EQ(std::sscanf(argAfter(args, "--source").c_str(), "%g,%g,%g", &back[0], &back[1], &back[2]), 3);
    EXPECT_EQ(glm::vec3(back[0], back[1], back[2]), *o.fogSource);
    EXPECT_EQ(std::strtof(argAfter(args, "--falloff").c_str(), nullptr), 2.5f);
    EXPECT_EQ(argAfter(runnerOptionArgs({}), "--sigma"), "") << "unset: the scene's own medium";
}

TEST(GradingFile, RefusesABadFogMediumNamingTheField) {
    const std::pair<const char*, const char*> cases[] = {
        {R"({"sigma": [0.1, -1, 0.1]})", "\"sigma\" G: -1 is negative"},
        {R"({"source": [0.1, 0.1]})", "\"source\" must be 3 numbers (R, G, B)"},
        {R"({"source": [0.1, "x", 0.1]})", "\"source\" G must be a number"},
        {R"({"falloff": 1e39})", "\"falloff\": 1e+39 is too large for a float"},
        {R"({"falloff": -0.5})", "\"falloff\": -0.5 is negative"}};
    for (const auto& [bad, words] : cases) {
        try {
            readGradingFile(gradingFile(bad), "x", true);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::BadFile) << e.what();
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what() << " lacks " << words;
        }
    }
}

}  // namespace
}  // namespace raster::grade
