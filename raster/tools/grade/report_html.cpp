// The self-contained HTML report of a grading run (report.hpp): inline CSS, images as data: URIs, the
// heat map's legend as a CSS gradient of the same ramp, no script and nothing fetched.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "grade/report.hpp"
#include "grade/report_text.hpp"
#include "raster/check.hpp"

namespace raster::grade {
namespace {

constexpr const char* kStyle =
    R"(body{font:15px/1.45 system-ui,sans-serif;margin:1.5em;color:#1d1d1f;background:#fbfbfb}
h1{font-size:1.5em;margin:0 0 .3em}h2{font-size:1.25em;margin:1.6em 0 .5em}h3{font-size:1.1em;margin:1.4em 0 .3em}
table{border-collapse:collapse;margin:.6em 0}th,td{border:1px solid #c8c8cc;padding:.25em .6em;text-align:left;vertical-align:top}
th{background:#ececf0}td.score{text-align:right;white-space:nowrap}
.pass{color:#16692c;font-weight:600}.fail{color:#b0161b;font-weight:600}.error{color:#8a4b00;font-weight:600}
.note{color:#666;font-size:.9em}pre{white-space:pre-wrap;background:#f0f0f3;padding:.6em;border-radius:4px;margin:.4em 0}
.images{display:flex;flex-wrap:wrap;gap:1.2em;align-items:flex-start;margin:.6em 0}
figure{margin:0;max-width:calc(min(28vw,320px) + 2px)}figcaption{font-size:.9em;color:#444;margin-top:.2em}
figure img{display:block;width:min(28vw,320px);image-rendering:pixelated;border:1px solid #999;background:#fff}
.missing{width:min(28vw,320px);height:6em;border:1px dashed #999;display:flex;align-items:center;justify-content:center;color:#777}
.bar{width:min(28vw,320px);height:12px;border:1px solid #999;margin-top:.4em}
.ticks{width:min(28vw,320px);display:flex;justify-content:space-between;font-size:.8em;color:#444}
)";

std::string esc(std::string_view text) {
    return xmlEscape(text);
}

std::string dataUri(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    RASTER_REQUIRE(in, BadFile,
                   "cannot read the image " + path + " for the HTML report: " + std::strerror(errno));
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    RASTER_REQUIRE(!in.bad(), BadFile, "cannot read the image " + path + " for the HTML report");
    return "data:image/png;base64," + base64(bytes);
}

std::string figure(const std::string& path, const std::string& caption, const std::string& extra = "") {
    const std::string picture = path.empty()
                                    ? "<div class=\"missing\">no image</div>"
                                    : "<img src=\"" + dataUri(path) + "\" alt=\"" + esc(caption) + "\">";
    return "<figure>" + picture + "<figcaption>" + esc(caption) + "</figcaption>" + extra + "</figure>\n";
}

std::string cssColour(float error) {
    const auto rgb = heatColour(error);
    char text[32];
    std::snprintf(text, sizeof text, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
    return text;
}

// The heat map's colour bar (heatColour at 65 points, and black alone at 0) and its scale.
std::string legend(const HeatMapScale& scale) {
    std::string stops = "#000000 0%";
    for (int i = 0; i <= 64; ++i) {
        char stop[48];  // the first just above 0, where the ramp leaves black
        std::snprintf(stop, sizeof stop, ",%s %.2f%%", cssColour(i == 0 ? 1e-6f : float(i) / 64).c_str(),
                      i == 0 ? 0.5 : 100.0 * i / 64);
        stops += stop;
    }
    std::string ticks;
    for (int i = 0; i <= 4; ++i) {
        char text[32];
        std::snprintf(text, sizeof text, "%.3g", scale.fullScale * i / 4);
        ticks += "<span>" + std::string(text) + (i == 4 && scale.fullScale > 0 ? "+" : "") + "</span>";
    }
    return "<div class=\"bar\" style=\"background:linear-gradient(to right," + stops +
           ")\"></div><div class=\"ticks\">" + ticks + "</div><div class=\"note\">" + esc(scale.unit) +
           ": black = no difference, brighter = larger</div>";
}

std::string verdictCell(Verdict verdict) {
    return std::string("<td class=\"") + verdictName(verdict) + "\">" + verdictName(verdict) + "</td>";
}

std::string summaryTable(const GradeRun& run) {
    std::string html =
        "<table>\n<tr><th>Lab</th><th>Scene</th><th>Score</th><th>Verdict</th><th>Diagnosis</th></tr>\n";
    size_t index = 0;
    for (const LabResult& lab : run.labs)
        for (const SceneResult& scene : lab.scenes) {
            const std::string name = esc(scene.number + " " + scene.name);
            const std::string shown =
                scene.verdict == Verdict::Pass
                    ? name
                    : "<a href=\"#scene-" + std::to_string(index) + "\">" + name + "</a>";
            const std::string hidden =
                scene.visibility == Visibility::Visible
                    ? ""
                    : " <span class=\"note\">(" + esc(visibilityName(scene.visibility)) + ")</span>";
            html += "<tr><td>" + esc(lab.name) + "</td><td>" + shown + hidden + "</td><td class=\"score\">" +
                    formatScore(scene.score) + " / " + formatScore(scene.maxScore) + "</td>" +
                    verdictCell(scene.verdict) + "<td>" + esc(oneLine(scene.headline())) + "</td></tr>\n";
            ++index;
        }
    return html + "</table>\n";
}

std::string sceneSection(const LabResult& lab, const SceneResult& scene, size_t index) {
    std::string html = "<section id=\"scene-" + std::to_string(index) + "\">\n<h3>" + esc(lab.name) + " · " +
                       esc(scene.number + " " + scene.name) + ": <span class=\"" +
                       verdictName(scene.verdict) + "\">" + verdictName(scene.verdict) + "</span>, " +
                       formatScore(scene.score) + " / " + formatScore(scene.maxScore) + "</h3>\n";
    if (!scene.headline().empty()) html += "<p>" + esc(scene.headline()) + "</p>\n";
    if (scene.comparison) html += "<p class=\"note\">" + esc(comparisonText(*scene.comparison)) + "</p>\n";
    if (!scene.explanation.empty()) html += "<pre>" + esc(scene.explanation) + "</pre>\n";
    html += "<div class=\"images\">\n" + figure(scene.submissionImage, "submission") +
            figure(scene.expectedImage, "expected") +
            figure(scene.heatMapImage, "heat map of the difference", legend(scene.heatMapScale)) + "</div>\n";
    return html + "</section>\n";
}

}  // namespace

std::string htmlReport(const GradeRun& run) {
    const std::string title = "raster grade: " + run.submission;
    std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
                       esc(title) + "</title>\n<style>\n" + kStyle + "</style>\n</head>\n<body>\n<h1>" +
                       esc(title) + "</h1>\n";
    html += "<p>Score: <b>" + formatScore(run.score()) + " / " + formatScore(run.maxScore()) + "</b> — " +
            verdictCounts(run) + "</p>\n";
    if (!run.output.empty())
        html += "<details><summary>Output</summary><pre>" + esc(run.output) + "</pre></details>\n";
    if (run.sceneCount() == 0) return html + "<p>No scenes were graded.</p>\n</body>\n</html>\n";
    html += summaryTable(run);
    std::string sections;
    size_t index = 0;
    for (const LabResult& lab : run.labs)
        for (const SceneResult& scene : lab.scenes) {
            if (scene.verdict != Verdict::Pass) sections += sceneSection(lab, scene, index);
            ++index;
        }
    if (!sections.empty()) html += "<h2>Scenes that did not pass</h2>\n" + sections;
    return html + "</body>\n</html>\n";
}

void writeHtmlReport(const std::string& path, const GradeRun& run) {
    writeTextFile(path, htmlReport(run));
}

}  // namespace raster::grade
