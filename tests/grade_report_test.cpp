// raster/tools/grade/report.hpp: a grading run of two labs and four scenes (a pass, a failure, a
// crash, a hidden pass) written as Gradescope's results.json (parsed back: every field, the sum, the
// visibility of each scene), as JUnit XML (parsed back by python3's xml.etree, with a diagnosis full of
// <&"' and a control byte), as HTML (three images as data: URIs, nothing external, text escaped) and
// as the terminal's summary; the heat map's ramp (its ends, its luminance never falling); a run
// without scenes; text from a submission made safe; a report that cannot be written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "grade/report.hpp"
#include "raster/check.hpp"
#include "raster/image_compare.hpp"
#include "raster/image_io.hpp"

namespace raster::grade {
namespace {

namespace fs = std::filesystem;

class TemporaryDirectory {
  public:
    TemporaryDirectory() {
        char name[] = "/tmp/grade_report_test_XXXXXX";
        path_ = mkdtemp(name) ? name : "";
    }
    ~TemporaryDirectory() { fs::remove_all(path_); }
    std::string operator/(const std::string& name) const { return path_ + "/" + name; }

  private:
    std::string path_;
};

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A 4x4 image of one colour.
ImageRgba8 flat(uint8_t r, uint8_t g, uint8_t b) {
    ImageRgba8 image{4, 4, {}};
    for (int i = 0; i < 16; ++i) image.pixels.insert(image.pixels.end(), {r, g, b, 255});
    return image;
}

// What a submission's stderr may hold, in a diagnosis: markup, quotes, a control byte, bad UTF-8.
const std::string kNastyDiagnosis = "depth test <inverted> & \"far\" wins over 'near'\x01 \xff";

// Two labs: lab1 with a pass (public) and a failure (hidden), lab2 with a crash (public) and a hidden
// pass. The failure has its three images in `dir`.
GradeRun sampleRun(const TemporaryDirectory& dir) {
    const ImageRgba8 submission = flat(200, 10, 10), expected = flat(10, 10, 200);
    writePngRgba8(dir / "depth.png", 4, 4, submission.pixels);
    writePngRgba8(dir / "depth_expected.png", 4, 4, expected.pixels);
    const ImageRgba8 heat = heatMap(differenceMap(submission, expected), 255, {true});
    writePngRgba8(dir / "depth_heat.png", heat.width, heat.height, heat.pixels);

    SceneResult pass{.name = "triangle",
                     .number = "1.1",
                     .score = 2,
                     .maxScore = 2,
                     .visibility = sceneVisibility(true),
                     .verdict = Verdict::Pass,
                     .comparison = Comparison{"FLIP mean", 0.001, 0.05, ""},
                     .seconds = 0.25};
    SceneResult fail{.name = "depth",
                     .number = "1.2",
                     .score = 0.5,
                     .maxScore = 3,
                     .visibility = sceneVisibility(false),
                     .verdict = Verdict::Fail,
                     .diagnosis = kNastyDiagnosis,
                     .explanation = "The depth test keeps the farther fragment.\nCheck <= against >=.",
                     .comparison = Comparison{"FLIP mean", 0.213, 0.05, ""},
                     .seconds = 0.5,
                     .submissionImage = dir / "depth.png",
                     .expectedImage = dir / "depth_expected.png",
                     .heatMapImage = dir / "depth_heat.png"};
    SceneResult crash{.name = "blend",
                      .number = "2.1",
                      .score = 0,
                      .maxScore = 4,
                      .visibility = sceneVisibility(true),
                      .verdict = Verdict::Error,
                      .reason = "crashed: segmentation fault (SIGSEGV)",
                      .explanation = "stderr:\n\x1b[31mSegmentation fault\x1b[0m ]]> <!-- --> &amp;",
                      .seconds = 1};
    SceneResult hidden{.name = "blend_hidden",
                       .number = "2.2",
                       .score = 1.25,
                       .maxScore = 1.25,
                       .visibility = sceneVisibility(false),
                       .verdict = Verdict::Pass,
                       .seconds = 0.125};
    return GradeRun{"alice <a&b>",
                    {{"lab1", "Rasterizer", {pass, fail}}, {"lab2", "Blending", {crash, hidden}}},
                    "built in 12 s\n",
                    14.6};
}

// python3's xml.etree reading `path`, as JSON: the root's attributes, and per testsuite its
// attributes and testcases (attributes, failure and error with message and text, system-out).
nlohmann::json parseJUnitWithPython(const std::string& path) {
    static constexpr const char* kScript = R"(import json, sys, xml.etree.ElementTree as E
root = E.parse(sys.argv[1]).getroot()
def node(n):
    return None if n is None else {"attrib": n.attrib, "text": n.text or ""}
print(json.dumps({"tag": root.tag, "attrib": root.attrib, "suites": [
    {"attrib": s.attrib, "cases": [{"attrib": c.attrib, "failure": node(c.find("failure")),
                                    "error": node(c.find("error")), "out": c.findtext("system-out")}
                                   for c in s.findall("testcase")]}
    for s in root.findall("testsuite")]}))
)";
    const std::string script = path + ".py";
    std::ofstream(script) << kScript;
    std::FILE* pipe = popen(("python3 '" + script + "' '" + path + "' 2>&1").c_str(), "r");
    std::string out;
    char buffer[4096];
    for (size_t n; pipe && (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
    const int status = pipe ? pclose(pipe) : -1;
    EXPECT_EQ(status, 0) << "python3 could not parse the XML:\n" << out;
    return status == 0 ? nlohmann::json::parse(out) : nlohmann::json();
}

TEST(GradeReport, GradescopeResultsHaveEveryFieldTheSumAndEachVisibility) {
    TemporaryDirectory dir;
    const GradeRun run = sampleRun(dir);
    writeGradescopeResults(dir / "results.json", run);
    const nlohmann::json results = nlohmann::json::parse(readFile(dir / "results.json"));
    EXPECT_DOUBLE_EQ(results.at("score").get<double>(), 2 + 0.5 + 0 + 1.25);
    EXPECT_EQ(results.at("execution_time"), 15);
    EXPECT_EQ(results.at("output"), "built in 12 s\n");
    EXPECT_EQ(results.at("stdout_visibility"), "hidden");
    EXPECT_FALSE(results.contains("visibility")) << "no top-level visibility unless asked for";
    EXPECT_EQ(results.at("test_output_format"), "text");
    EXPECT_DOUBLE_EQ(results.at("extra_data").at("max_score").get<double>(), 2 + 3 + 4 + 1.25);
    const nlohmann::json& tests = results.at("tests");
    ASSERT_EQ(tests.size(), 4u);
    double sum = 0;
    const char* names[] = {"lab1: triangle", "lab1: depth", "lab2: blend", "lab2: blend_hidden"};
    const char* numbers[] = {"1.1", "1.2", "2.1", "2.2"};
    const char* visibility[] = {"visible", "after_due_date", "visible", "after_due_date"};
    const char* status[] = {"passed", "failed", "failed", "passed"};
    for (size_t i = 0; i < tests.size(); ++i) {
        for (const char* field : {"name", "number", "score", "max_score", "status", "output", "visibility"})
            EXPECT_TRUE(tests[i].contains(field)) << "test " << i << " has no " << field;
        EXPECT_EQ(tests[i].at("name"), names[i]);
        EXPECT_EQ(tests[i].at("number"), numbers[i]);
        EXPECT_EQ(tests[i].at("visibility"), visibility[i]);
        EXPECT_EQ(tests[i].at("status"), status[i]);
        EXPECT_LE(tests[i].at("score").get<double>(), tests[i].at("max_score").get<double>());
        sum += tests[i].at("score").get<double>();
    }
    EXPECT_DOUBLE_EQ(sum, results.at("score").get<double>());
    const std::string depth = tests[1].at("output");
    EXPECT_EQ(depth.substr(0, depth.find('\n')), sanitizeText(kNastyDiagnosis))
        << "the diagnosis comes first";
    EXPECT_NE(depth.find("comparison: FLIP mean 0.213 (at most 0.05)"), std::string::npos) << depth;
    EXPECT_NE(depth.find("Check <= against >=."), std::string::npos) << "then the explanation";
    EXPECT_EQ(tests[2].at("output").get<std::string>().rfind("crashed: segmentation fault (SIGSEGV)", 0), 0u);

    GradescopeOptions later;
    later.visibility = Visibility::AfterPublished;
    later.stdoutVisibility = Visibility::Visible;
    const nlohmann::json hidden = nlohmann::json::parse(gradescopeResultsJson(run, later));
    EXPECT_EQ(hidden.at("visibility"), "after_published");
    EXPECT_EQ(hidden.at("stdout_visibility"), "visible");
}

TEST(GradeReport, JUnitXmlIsWellFormedAndEscapesEverything) {
    TemporaryDirectory dir;
    const GradeRun run = sampleRun(dir);
    writeJUnitXml(dir / "junit.xml", run);
    const std::string xml = readFile(dir / "junit.xml");
    EXPECT_EQ(sanitizeText(xml), xml) << "valid UTF-8 without control characters";
    EXPECT_NE(xml.find("&lt;inverted&gt; &amp; &quot;far&quot; wins over &#39;near&#39;"), std::string::npos);
    EXPECT_EQ(xml.find("]]>"), std::string::npos);

    const nlohmann::json parsed = parseJUnitWithPython(dir / "junit.xml");
    ASSERT_FALSE(parsed.is_null());
    EXPECT_EQ(parsed.at("tag"), "testsuites");
    EXPECT_EQ(parsed.at("attrib").at("tests"), "4");
    EXPECT_EQ(parsed.at("attrib").at("failures"), "1");
    EXPECT_EQ(parsed.at("attrib").at("errors"), "1");
    ASSERT_EQ(parsed.at("suites").size(), 2u);
    const nlohmann::json& lab1 = parsed.at("suites")[0];
    EXPECT_EQ(lab1.at("attrib").at("name"), "lab1");
    EXPECT_EQ(lab1.at("attrib").at("tests"), "2");
    EXPECT_EQ(lab1.at("attrib").at("time"), "0.750");
    const nlohmann::json& depth = lab1.at("cases")[1];
    EXPECT_EQ(depth.at("attrib").at("classname"), "lab1");
    EXPECT_EQ(depth.at("attrib").at("name"), "depth");
    EXPECT_EQ(depth.at("attrib").at("time"), "0.500");
    EXPECT_EQ(depth.at("failure").at("attrib").at("message"), sanitizeText(kNastyDiagnosis));
    EXPECT_NE(depth.at("failure").at("text").get<std::string>().find("Check <= against >=."),
              std::string::npos);
    const std::string out = depth.at("out");
    for (const char* image : {"depth.png", "depth_expected.png", "depth_heat.png"})
        EXPECT_NE(out.find("\n[[ATTACHMENT|" + (dir / image) + "]]\n"), std::string::npos) << out;
    EXPECT_TRUE(lab1.at("cases")[0].at("failure").is_null()) << "a pass has no failure";
    const nlohmann::json& blend = parsed.at("suites")[1].at("cases")[0];
    EXPECT_TRUE(blend.at("failure").is_null());
    EXPECT_EQ(blend.at("error").at("attrib").at("message"), "crashed: segmentation fault (SIGSEGV)");
    EXPECT_EQ(blend.at("error").at("text"), sanitizeText(run.labs[1].scenes[0].explanation));

    JUnitOptions relative;
    relative.attachmentBase = dir / "";
    EXPECT_NE(junitXml(run, relative).find("[[ATTACHMENT|depth_heat.png]]"), std::string::npos);
}

TEST(GradeReport, HtmlEmbedsTheThreeImagesAndEscapesText) {
    TemporaryDirectory dir;
    GradeRun run = sampleRun(dir);
    run.labs[0].scenes[1].explanation = "<script>alert('x')</script> & more";
    const std::string html = htmlReport(run);
    for (const char* image : {"depth.png", "depth_expected.png", "depth_heat.png"}) {
        const std::string bytes = readFile(dir / image);
        const std::string uri = "src=\"data:image/png;base64," +
                                base64({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}) + "\"";
        EXPECT_NE(html.find(uri), std::string::npos) << image << " is not embedded";
    }
    for (const char* external :
         {"http://", "https://", "src=\"/", "src='/", "<script", "<link", "@import", "url("})
        EXPECT_EQ(html.find(external), std::string::npos) << "the page holds " << external;
    EXPECT_NE(html.find("&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt; &amp; more"), std::string::npos);
    EXPECT_NE(html.find("alice &lt;a&amp;b&gt;"), std::string::npos);
    EXPECT_NE(html.find("linear-gradient(to right,#000000 0%"), std::string::npos)
        << "the legend's colour bar";
    EXPECT_NE(html.find("<span>0</span><span>0.25</span><span>0.5</span><span>0.75</span><span>1+</span>"),
              std::string::npos);
    EXPECT_NE(html.find("<section id=\"scene-1\">"), std::string::npos) << "the failure's section";
    EXPECT_NE(html.find("<section id=\"scene-2\">"), std::string::npos) << "the crash's section";
    EXPECT_EQ(html.find("<section id=\"scene-0\">"), std::string::npos) << "no section for a pass";
    EXPECT_NE(html.find("<div class=\"missing\">no image</div>"), std::string::npos)
        << "the crash has no image";
    EXPECT_EQ(sanitizeText(html), html);

    run.labs[0].scenes[1].heatMapImage = dir / "gone.png";
    try {
        htmlReport(run);
        ADD_FAILURE() << "a missing image was not refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::BadFile);
        EXPECT_NE(std::string(e.what()).find(dir / "gone.png"), std::string::npos) << e.what();
    }
}

// Relative luminance of an sRGB colour (linear light, Rec. 709 weights).
double luminance(std::array<uint8_t, 3> rgb) {
    auto linear = [](uint8_t c) {
        const double v = c / 255.0;
        return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    };
    return 0.2126 * linear(rgb[0]) + 0.7152 * linear(rgb[1]) + 0.0722 * linear(rgb[2]);
}

TEST(GradeReport, HeatMapRampRunsFromBlackToItsEndWithRisingLuminance) {
    const std::array<uint8_t, 3> black{0, 0, 0}, end{255, 240, 176};
    EXPECT_EQ(heatColour(0.0f), black);
    EXPECT_EQ(heatColour(1.0f), end);
    EXPECT_EQ(heatColour(-3.0f), black);
    EXPECT_EQ(heatColour(7.0f), end);
    EXPECT_EQ(heatColour(std::nanf("")), end) << "an unknown error is not shown as none";
    EXPECT_GT(luminance(heatColour(1.0f / 255)), 0.01) << "one step off stands out from black";
    double previous = luminance(heatColour(0.0f));
    for (int i = 1; i <= 4096; ++i) {
        const double current = luminance(heatColour(float(i) / 4096));
        ASSERT_GE(current, previous) << "the luminance falls at " << float(i) / 4096;
        previous = current;
    }
    EXPECT_GT(luminance(end), 0.8);

    const std::vector<float> errors{0.0f, 1.0f, 0.5f, 0.25f};
    const ImageRgba8 map = heatMap(errors, 2, 2);
    ASSERT_EQ(map.width * map.height, 4u);
    EXPECT_EQ((std::array<uint8_t, 4>{map.pixels[0], map.pixels[1], map.pixels[2], map.pixels[3]}),
              (std::array<uint8_t, 4>{0, 0, 0, 255}));
    EXPECT_EQ((std::array<uint8_t, 3>{map.pixels[4], map.pixels[5], map.pixels[6]}), end);

    DifferenceMap difference{3, 1, {0, 8, 200}, 200};
    const std::vector<float> scaled = differenceErrors(difference, 16);
    EXPECT_EQ(scaled, (std::vector<float>{0.0f, 0.5f, 1.0f}));
    const ImageRgba8 barred = heatMap(difference, 16, {true});
    EXPECT_EQ(barred.height, 1u + 2 + 4) << "the map, a 2-pixel gap, a 4-pixel bar";
    const size_t bar_row = size_t(4) * 3 * 3;  // row 3, the bar's first
    EXPECT_EQ((std::array<uint8_t, 3>{barred.pixels[bar_row], barred.pixels[bar_row + 1],
                                      barred.pixels[bar_row + 2]}),
              black);
    EXPECT_EQ((std::array<uint8_t, 3>{barred.pixels[bar_row + 8], barred.pixels[bar_row + 9],
                                      barred.pixels[bar_row + 10]}),
              end);
    const ImageRgba8 bar = colourBar(5, 2);
    EXPECT_EQ(bar.pixels.size(), 5u * 2 * 4);
    EXPECT_THROW(heatMap(errors, 3, 2), Error);
    EXPECT_THROW(differenceErrors(difference, 0), Error);
}

TEST(GradeReport, ZeroSceneRunWritesValidEmptyReports) {
    TemporaryDirectory dir;
    const GradeRun run{"bob", {}, "", 0};
    writeGradescopeResults(dir / "results.json", run);
    writeJUnitXml(dir / "junit.xml", run);
    writeHtmlReport(dir / "report.html", run);
    const nlohmann::json results = nlohmann::json::parse(readFile(dir / "results.json"));
    EXPECT_EQ(results.at("score"), 0.0);
    EXPECT_TRUE(results.at("tests").is_array());
    EXPECT_TRUE(results.at("tests").empty());
    const nlohmann::json junit = parseJUnitWithPython(dir / "junit.xml");
    ASSERT_FALSE(junit.is_null());
    EXPECT_EQ(junit.at("attrib").at("tests"), "0");
    EXPECT_TRUE(junit.at("suites").empty());
    const std::string html = readFile(dir / "report.html");
    EXPECT_NE(html.find("No scenes were graded."), std::string::npos);
    EXPECT_NE(html.find("</html>"), std::string::npos);
    EXPECT_EQ(terminalSummary(run),
              "raster grade: bob\n  no scenes were graded\ntotal: 0 / 0 points; 0 scenes: 0 "
              "passed, 0 failed, 0 errors\n");
}

TEST(GradeReport, TerminalSummaryAlignsItsColumnsAndTotals) {
    TemporaryDirectory dir;
    GradeRun run = sampleRun(dir);
    run.labs[0].scenes[1].diagnosis += "\nsecond line\x1b[2J";
    const std::string summary = terminalSummary(run);
    std::vector<std::string> lines;
    std::istringstream in(summary);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    ASSERT_EQ(lines.size(), 1u + 2 + 4 + 1) << summary;
    EXPECT_EQ(lines[0], "raster grade: alice <a&b>");
    EXPECT_EQ(lines[1], "lab1  Rasterizer: 2.5 / 5");
    EXPECT_EQ(lines[4], "lab2  Blending: 1.25 / 5.25");
    EXPECT_EQ(lines[7], "total: 3.75 / 10.25 points; 4 scenes: 2 passed, 1 failed, 1 error");
    const size_t column = lines[2].find("PASS");
    EXPECT_EQ(lines[3].find("FAIL"), column) << summary;
    EXPECT_EQ(lines[5].find("ERROR"), column);
    EXPECT_EQ(lines[6].find("PASS"), column);
    EXPECT_NE(lines[2].find("  1.1  triangle"), std::string::npos) << lines[2];
    EXPECT_NE(lines[3].find("0.5 / 3  FAIL   FLIP mean 0.213 (at most 0.05)  depth test"), std::string::npos)
        << lines[3];
    EXPECT_NE(lines[5].find("crashed: segmentation fault (SIGSEGV)"), std::string::npos);
    EXPECT_EQ(summary.find('\x1b'), std::string::npos) << "no escape sequence reaches the terminal";
}

TEST(GradeReport, SubmissionTextIsMadeValidUtf8WithoutControls) {
    const std::string r = "\xEF\xBF\xBD";
    EXPECT_EQ(sanitizeText("a\x01"
                           "b\x7f"
                           "c"),
              "a" + r + "b" + r + "c");
    EXPECT_EQ(sanitizeText("caf\xC3\xA9 \xE2\x89\xA4 \xF0\x9F\x8E\xA8"),
              "caf\xC3\xA9 \xE2\x89\xA4 \xF0\x9F\x8E\xA8");
    EXPECT_EQ(sanitizeText("x\xC3"), "x" + r) << "a sequence cut short";
    EXPECT_EQ(sanitizeText("\xC0\xAF"), r + r) << "overlong";
    EXPECT_EQ(sanitizeText("\xED\xA0\x80"), r + r + r) << "a surrogate";
    EXPECT_EQ(sanitizeText("\xC2\x85"), r) << "a C1 control";
    EXPECT_EQ(sanitizeText("\xEF\xBF\xBF"), r) << "U+FFFF";
    EXPECT_EQ(sanitizeText("a\r\nb\rc\td\n"), "a\nb\nc\td\n");
    EXPECT_EQ(xmlEscape("<a b=\"c\" d='e'>&\n\t</a>", true),
              "&lt;a b=&quot;c&quot; d=&#39;e&#39;&gt;&amp;&#10;&#9;&lt;/a&gt;");
    EXPECT_EQ(xmlEscape("line\n\tnext"), "line\n\tnext");
    auto encode = [](std::string_view s) {
        return base64({reinterpret_cast<const uint8_t*>(s.data()), s.size()});
    };
    EXPECT_EQ(encode(""), "");
    EXPECT_EQ(encode("f"), "Zg==");
    EXPECT_EQ(encode("fo"), "Zm8=");
    EXPECT_EQ(encode("foo"), "Zm9v");
    EXPECT_EQ(encode("foobar"), "Zm9vYmFy");
    EXPECT_EQ(formatScore(2), "2");
    EXPECT_EQ(formatScore(2.5), "2.5");
    EXPECT_EQ(formatScore(1.0 / 3), "0.33");
}

TEST(GradeReport, UnwritablePathIsNamed) {
    TemporaryDirectory dir;
    const std::string path = dir / "no-such-folder/results.json";
    try {
        writeGradescopeResults(path, sampleRun(dir));
        ADD_FAILURE() << "nothing was refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::BadFile);
        EXPECT_NE(
            std::string(e.what()).find("cannot write the report " + path + ": No such file or directory"),
            std::string::npos)
            << e.what();
    }
    for (const auto& entry : fs::directory_iterator(dir / ""))
        EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos)
            << "left behind: " << entry.path();
}

}  // namespace
}  // namespace raster::grade
