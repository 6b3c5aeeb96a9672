// raster grade's declarations (raster/tools/grade/grading.hpp): the `time` an animated lab's scene may
// set, checked when the file is read, and handed to the lab runner with every bit of the double.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
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

}  // namespace
}  // namespace raster::grade
