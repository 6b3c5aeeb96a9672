// JUnit XML of a grading run (report.hpp): a testsuite per lab, a testcase per scene, the images as
// [[ATTACHMENT|path]] lines.
#include <cstdio>
#include <filesystem>

#include "grade/report.hpp"

namespace raster::grade {
namespace {

std::string seconds(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", value < 0 ? 0.0 : value);
    return text;
}

std::string attribute(std::string_view name, std::string_view value) {
    std::string text(" ");  // appended, not "literal" + std::string: GCC 12's false -Wrestrict (bug 105329)
    return text.append(name).append("=\"").append(xmlEscape(value, true)).append("\"");
}

// The counts a <testsuites> or <testsuite> carries.
std::string counts(size_t tests, size_t failures, size_t errors, double time) {
    return attribute("tests", std::to_string(tests)) + attribute("failures", std::to_string(failures)) +
           attribute("errors", std::to_string(errors)) + attribute("skipped", "0") +
           attribute("time", seconds(time));
}

std::string attachmentPath(const std::string& path, const JUnitOptions& options) {
    namespace fs = std::filesystem;
    const fs::path absolute = fs::absolute(path).lexically_normal();
    if (options.attachmentBase.empty()) return absolute.string();
    return absolute.lexically_relative(fs::absolute(options.attachmentBase).lexically_normal()).string();
}

std::string testcase(const LabResult& lab, const SceneResult& scene, const JUnitOptions& options) {
    std::string xml = "    <testcase" + attribute("classname", lab.name) + attribute("name", scene.name) +
                      attribute("time", seconds(scene.seconds)) + ">\n";
    const std::string comparison = scene.comparison ? comparisonText(*scene.comparison) : "";
    if (scene.verdict == Verdict::Fail) {
        const std::string text =
            comparison + (comparison.empty() || scene.explanation.empty() ? "" : "\n\n") + scene.explanation;
        xml += "      <failure" + attribute("message", scene.diagnosis) +
               attribute("type", scene.comparison ? scene.comparison->metric : "fail") + ">" +
               xmlEscape(text) + "</failure>\n";
    } else if (scene.verdict == Verdict::Error) {
        xml += "      <error" + attribute("message", scene.headline()) + attribute("type", "error") + ">" +
               xmlEscape(scene.explanation) + "</error>\n";
    }
    std::string out = "score: " + formatScore(scene.score) + " / " + formatScore(scene.maxScore) + "\n";
    if (scene.verdict == Verdict::Pass && !comparison.empty()) out += comparison + "\n";
    for (const std::string* image : {&scene.submissionImage, &scene.expectedImage, &scene.heatMapImage})
        if (!image->empty()) out += "[[ATTACHMENT|" + attachmentPath(*image, options) + "]]\n";
    xml += "      <system-out>" + xmlEscape(out) + "</system-out>\n";
    return xml + "    </testcase>\n";
}

}  // namespace

std::string junitXml(const GradeRun& run, const JUnitOptions& options) {
    std::string xml =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites" +
        attribute("name", "raster grade: " + run.submission) +
        counts(run.sceneCount(), run.count(Verdict::Fail), run.count(Verdict::Error), run.seconds) + ">\n";
    for (const LabResult& lab : run.labs) {
        size_t failures = 0, errors = 0;
        double time = 0;
        for (const SceneResult& scene : lab.scenes) {
            failures += scene.verdict == Verdict::Fail;
            errors += scene.verdict == Verdict::Error;
            time += scene.seconds;
        }
        xml += "  <testsuite" + attribute("name", lab.name) +
               counts(lab.scenes.size(), failures, errors, time) + ">\n";
        xml += "    <properties>\n";
        xml += "      <property" + attribute("name", "title") + attribute("value", lab.title) + "/>\n";
        xml += "      <property" + attribute("name", "score") + attribute("value", formatScore(lab.score())) +
               "/>\n";
        xml += "      <property" + attribute("name", "max_score") +
               attribute("value", formatScore(lab.maxScore())) + "/>\n";
        xml += "    </properties>\n";
        for (const SceneResult& scene : lab.scenes) xml += testcase(lab, scene, options);
        xml += "  </testsuite>\n";
    }
    return xml + "</testsuites>\n";
}

void writeJUnitXml(const std::string& path, const GradeRun& run, const JUnitOptions& options) {
    writeTextFile(path, junitXml(run, options));
}

}  // namespace raster::grade
