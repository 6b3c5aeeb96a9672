// The reports of raster grade (docs/GRADING.md): what one grading run found — per lab, per scene, a
// score, a verdict and why — written for each reader:
//  - Gradescope's results.json (writeGradescopeResults), what a student sees on Gradescope;
//  - JUnit XML (writeJUnitXml), what CI servers (Jenkins, GitLab) show as tests, with the images as
//    attachments;
//  - a self-contained HTML page (writeHtmlReport), what a teacher or a student opens offline: a table
//    of every scene, and for each one that failed its image, the expected one and the heat map of
//    their difference side by side;
//  - a plain-text summary for a terminal or a CI log (terminalSummary);
//  - heat-map PNGs of a per-pixel error (heatMap), for the HTML page and the attachments.
//
//   raster::grade::GradeRun run{"alice", {{"lab2", "Depth and blending", {scene, ...}}}};
//   raster::grade::writeGradescopeResults("/autograder/results/results.json", run);
//   std::fputs(raster::grade::terminalSummary(run).c_str(), stdout);
//
// Text from a submission (its stderr, a crash's message) can hold anything: every writer turns it into
// valid UTF-8 without control characters first (sanitizeText), then escapes it for its format. Scores
// are points (any non-negative numbers: a lab's is the sum of its scenes'); times are seconds.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "raster/image_compare.hpp"
#include "raster/image_io.hpp"

namespace raster::grade {

// ---- The data model ----

enum class Verdict {
    Pass,   // the image is close enough to the expected one
    Fail,   // it rendered, and the comparison says it is wrong
    Error,  // no image to compare: the build or the render failed (crashed, timed out, ...)
};
// "pass", "fail", "error".
const char* verdictName(Verdict verdict);

// Who sees a scene's result on Gradescope, and when (its "visibility" values).
enum class Visibility { Visible, Hidden, AfterDueDate, AfterPublished };
// "visible", "hidden", "after_due_date", "after_published".
const char* visibilityName(Visibility visibility);
// The rule of raster grade: a public scene's result is visible at once, a hidden one's after the due date.
inline Visibility sceneVisibility(bool is_public) {
    return is_public ? Visibility::Visible : Visibility::AfterDueDate;
}

// The comparison that decided a verdict: its figure and the bound it was held to.
struct Comparison {
    std::string metric;    // what was measured: "FLIP mean", "largest channel difference"
    double value = 0;      // the figure, in `unit`
    double threshold = 0;  // the scene passes with value <= threshold
    std::string unit;      // "" for a plain number, "steps" (1/255 of full intensity), ...
};
// "FLIP mean 0.213 (at most 0.05)", "largest channel difference 12 steps (at most 3 steps)".
std::string comparisonText(const Comparison& comparison);

// What the right end of a heat map's colour ramp stands for (the left end is always 0, no error):
// for the legend under a heat map. A FLIP error map: {1, "FLIP error"}; a DifferenceMap shown with
// heatMap(map, 16): {16, "steps"}.
struct HeatMapScale {
    double fullScale = 1;
    std::string unit = "error";
};

struct SceneResult {
    std::string name;    // the scene: "depth_test"
    std::string number;  // "2.3": Gradescope orders and labels tests by it
    double score = 0, maxScore = 0;
    Visibility visibility = Visibility::Visible;
    Verdict verdict = Verdict::Fail;
    // Error only: what went wrong instead of a picture, "crashed: segmentation fault (SIGSEGV)",
    // "timed out: wall-time limit of 10 s exceeded".
    std::string reason;
    // One line: what is wrong in the picture ("the far cube covers the near one"), or for a pass,
    // empty or a remark.
    std::string diagnosis;
    // Any number of lines: how it was found, what to look at, where it comes from.
    std::string explanation;
    std::optional<Comparison> comparison;  // none where no comparison was made (an Error)
    double seconds = 0;                    // the render and the comparison (JUnit's time)
    // PNG files; empty where there is none (no image from a crashed render, no heat map for a pass).
    std::string submissionImage, expectedImage, heatMapImage;
    HeatMapScale heatMapScale;

    // The one line that stands for the scene in tables: the reason and the diagnosis of an Error
    // ("crashed: segmentation fault (SIGSEGV)"), else the diagnosis.
    std::string headline() const;
};

struct LabResult {
    std::string name;   // "lab2": JUnit's classname, the first column of the tables
    std::string title;  // "Depth and blending"; may be empty
    std::vector<SceneResult> scenes;

    double score() const;
    double maxScore() const;
};

struct GradeRun {
    std::string submission;  // whose: a student, a folder's name
    std::vector<LabResult> labs;
    std::string output;  // about the whole run (the build's log, notes): Gradescope's top-level output
    double seconds = 0;  // the whole run

    double score() const;
    double maxScore() const;
    size_t sceneCount() const;
    size_t count(Verdict verdict) const;
};

// "2", "2.5", "0.33": a score with at most two decimals and no trailing zeros.
std::string formatScore(double points);

// ---- Writers ----
// Each write* writes the file whole or not at all (a temporary file renamed over it), and throws
// Error(BadFile) naming the path when it cannot.

struct GradescopeOptions {
    // Top-level "visibility", of the whole result; nullopt leaves it out (Gradescope's default:
    // visible), and each test keeps its own.
    std::optional<Visibility> visibility;
    // "stdout_visibility": whether students see what run_autograder printed (the terminal summary,
    // which names hidden scenes too): hidden by default.
    Visibility stdoutVisibility = Visibility::Hidden;
};

// Gradescope's results.json (its autograder specification, "Output format"): "score" (the sum of the
// tests'), "execution_time" (whole seconds), "output" (run.output), "output_format",
// "test_output_format" and "test_name_format" all "text" (a submission's text is shown as it is, never
// as HTML or Markdown), "stdout_visibility", "visibility" if set, "extra_data" (the submission, the
// maximum score and the counts of verdicts: the specification has no top-level "max_score") and
// "tests", one per scene in order: "name" ("lab2: depth_test"), "number", "score", "max_score",
// "status" ("passed" for Pass, else "failed"), "visibility", "output" (the headline, the comparison,
// then the explanation) and "extra_data" (lab, scene, verdict, comparison).
std::string gradescopeResultsJson(const GradeRun& run, const GradescopeOptions& options = {});
void writeGradescopeResults(const std::string& path, const GradeRun& run,
                            const GradescopeOptions& options = {});

struct JUnitOptions {
    // The images' paths in the [[ATTACHMENT|path]] lines: empty writes them absolute (Jenkins' JUnit
    // attachments plugin wants that), else relative to this directory (GitLab wants them relative to
    // the project's directory).
    std::string attachmentBase;
};

// JUnit XML: <testsuites> with the run's totals, a <testsuite> per lab (name = the lab, with tests,
// failures, errors, skipped and time, and the lab's title and scores as properties), a <testcase> per
// scene (classname = the lab, name = the scene, time = its seconds) holding a <failure> for Fail
// (message = the diagnosis, type = the metric, text = the comparison and the explanation) or an
// <error> for Error (message = the headline, type = "error", text = the explanation), then a
// <system-out> with the score and one [[ATTACHMENT|path]] line per image (on a line of its own, as
// the attachments plugin reads them). XML 1.0, UTF-8.
std::string junitXml(const GradeRun& run, const JUnitOptions& options = {});
void writeJUnitXml(const std::string& path, const GradeRun& run, const JUnitOptions& options = {});

// One HTML page that opens offline: inline CSS, no script, the PNGs embedded as data: URIs (read from
// the scenes' image paths now), nothing fetched from anywhere. A summary (the score, the counts), a
// table of every scene (lab, scene, score, verdict, headline) and, for each scene that did not pass,
// its headline, comparison and explanation, and its image, the expected one and the heat map side
// by side, the heat map over a legend: the colour ramp with its scale labelled (heatMapScale). Throws
// Error(BadFile) naming a path that is given and cannot be read.
std::string htmlReport(const GradeRun& run);
void writeHtmlReport(const std::string& path, const GradeRun& run);

// Plain text for a terminal and a CI log (no colours, no control characters), a line per scene with
// columns aligned: number, scene, score / max, verdict (PASS, FAIL, ERROR), the comparison and the
// headline; a line per lab with its score; the total with the counts of verdicts. Ends with a newline.
std::string terminalSummary(const GradeRun& run);

// ---- Heat maps ----
//
// A per-pixel error in [0, 1] shown on a colour ramp whose luminance rises with the error: 0 is black
// (the pixels agree), any error above 0 is at least a visible dark violet (so a pixel off by one step
// stands out from the black around it), then through magenta, red-orange and orange to pale yellow
// at 1. Every channel of the ramp rises (or stays) from each control point to the next, so its
// luminance never falls: brighter always means more wrong, in colour and in grey.

// The ramp's colour (R, G, B) for `error`, clamped to [0, 1]; NaN counts as 1 (an error whose size is
// unknown must not read as none).
std::array<uint8_t, 3> heatColour(float error);

struct HeatMapOptions {
    // A strip along the bottom showing the ramp from 0 (left) to 1 (right), below a 2-pixel grey gap:
    // max(4, height / 12) pixels high. The image is that much taller than the error map.
    bool colourBar = false;
};

// `error` holds width · height values, row 0 on top. Throws Error(InvalidArgument) when the count is
// not width · height, or for a zero side.
ImageRgba8 heatMap(std::span<const float> error, uint32_t width, uint32_t height,
                   HeatMapOptions options = {});
// A DifferenceMap (largest channel difference per pixel, 0..255 steps) with `full_scale_steps` (1..255)
// at the ramp's end: a difference of that many steps or more is shown as 1. Use a small full scale
// (8, 16) to see small differences; HeatMapScale{full_scale_steps, "steps"} is its legend.
ImageRgba8 heatMap(const DifferenceMap& map, int full_scale_steps = 255, HeatMapOptions options = {});
// The DifferenceMap's values as errors in [0, 1], as heatMap(map, full_scale_steps) shows them.
std::vector<float> differenceErrors(const DifferenceMap& map, int full_scale_steps = 255);
// The ramp alone, 0 on the left, 1 on the right: the legend's colour bar.
ImageRgba8 colourBar(uint32_t width, uint32_t height);

// ---- Text ----

// `text` as valid UTF-8 that XML 1.0, HTML and a terminal accept as it is: every byte that is not part
// of a well-formed UTF-8 sequence, and every control character but tab and newline (C0, DEL, C1,
// U+FFFE, U+FFFF), becomes U+FFFD; "\r\n" and a lone "\r" become "\n".
std::string sanitizeText(std::string_view text);
// sanitizeText, with &, <, >, " and ' as character references; in attributes tab and newline too
// (&#9; &#10;), so that a parser gives them back rather than spaces. For XML text and attributes, and
// for HTML (the same escapes).
std::string xmlEscape(std::string_view text, bool attribute = false);
// RFC 4648 base64 with padding, for data: URIs.
std::string base64(std::span<const uint8_t> bytes);
// Writes `content` to `path` whole: a temporary file beside it, then renamed over it. Throws
// Error(BadFile) naming the path and the reason.
void writeTextFile(const std::string& path, std::string_view content);

}  // namespace raster::grade
