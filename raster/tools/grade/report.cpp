// The data model's sums, the text helpers, Gradescope's results.json and the terminal's summary
// (report.hpp). JUnit XML, the HTML page and the heat maps have files of their own.
#include "grade/report.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "grade/report_text.hpp"
#include "raster/check.hpp"

namespace raster::grade {

// ---- The data model ----

const char* verdictName(Verdict verdict) {
    switch (verdict) {
        case Verdict::Pass:
            return "pass";
        case Verdict::Fail:
            return "fail";
        case Verdict::Error:
            return "error";
    }
    return "error";
}

const char* visibilityName(Visibility visibility) {
    switch (visibility) {
        case Visibility::Visible:
            return "visible";
        case Visibility::Hidden:
            return "hidden";
        case Visibility::AfterDueDate:
            return "after_due_date";
        case Visibility::AfterPublished:
            return "after_published";
    }
    return "hidden";
}

std::string formatScore(double points) {
    char text[64];
    std::snprintf(text, sizeof text, "%.2f", points);
    std::string s = text;
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    return s == "-0" ? "0" : s;
}

std::string comparisonText(const Comparison& comparison) {
    auto figure = [&](double value) {
        char text[64];
        std::snprintf(text, sizeof text, "%.4g", value);
        return comparison.unit.empty() ? std::string(text) : std::string(text) + " " + comparison.unit;
    };
    return comparison.metric + " " + figure(comparison.value) + " (at most " + figure(comparison.threshold) +
           ")";
}

std::string SceneResult::headline() const {
    if (verdict != Verdict::Error || reason.empty()) return diagnosis;
    return diagnosis.empty() ? reason : reason + "; " + diagnosis;
}

namespace {

// The sum of value(item) over `items`.
template <class Items, class Value>
double sumOf(const Items& items, Value value) {
    double sum = 0;
    for (const auto& item : items) sum += double(value(item));
    return sum;
}

}  // namespace

double LabResult::score() const {
    return sumOf(scenes, [](const SceneResult& scene) { return scene.score; });
}
double LabResult::maxScore() const {
    return sumOf(scenes, [](const SceneResult& scene) { return scene.maxScore; });
}
double GradeRun::score() const {
    return sumOf(labs, [](const LabResult& lab) { return lab.score(); });
}
double GradeRun::maxScore() const {
    return sumOf(labs, [](const LabResult& lab) { return lab.maxScore(); });
}
size_t GradeRun::sceneCount() const {
    return size_t(sumOf(labs, [](const LabResult& lab) { return lab.scenes.size(); }));
}
size_t GradeRun::count(Verdict verdict) const {
    return size_t(sumOf(labs, [verdict](const LabResult& lab) {
        return std::count_if(lab.scenes.begin(), lab.scenes.end(),
                             [verdict](const SceneResult& scene) { return scene.verdict == verdict; });
    }));
}

// ---- Text ----

std::string sanitizeText(std::string_view text) {
    static constexpr char kReplacement[] = "\xEF\xBF\xBD";  // U+FFFD
    const auto* s = reinterpret_cast<const unsigned char*>(text.data());
    const size_t n = text.size();
    std::string out;
    out.reserve(n);
    for (size_t i = 0; i < n;) {
        const unsigned lead = s[i];
        if (lead == '\r') {
            out += '\n';
            i += i + 1 < n && s[i + 1] == '\n' ? 2 : 1;
            continue;
        }
        if (lead < 0x80) {
            const bool allowed = lead == '\t' || lead == '\n' || (lead >= 0x20 && lead != 0x7F);
            allowed ? out += char(lead) : out += kReplacement;
            ++i;
            continue;
        }
        // The length of the sequence, its lead's bits and the least code point it may encode (shorter
        // encodings of smaller ones are overlong, hence invalid).
        const size_t length = lead >= 0xC2 && lead <= 0xDF   ? 2
                              : lead >= 0xE0 && lead <= 0xEF ? 3
                              : lead >= 0xF0 && lead <= 0xF4 ? 4
                                                             : 0;
        uint32_t code = length == 2 ? lead & 0x1F : length == 3 ? lead & 0x0F : lead & 0x07;
        const uint32_t least = length == 2 ? 0x80 : length == 3 ? 0x800 : 0x10000;
        bool valid = length > 0 && i + length <= n;
        for (size_t k = 1; valid && k < length; ++k) {
            valid = (s[i + k] & 0xC0) == 0x80;
            code = (code << 6) | (s[i + k] & 0x3F);
        }
        valid = valid && code >= least && code <= 0x10FFFF && !(code >= 0xD800 && code <= 0xDFFF);
        if (!valid) {
            out += kReplacement;  // this byte; what follows is looked at again
            ++i;
            continue;
        }
        const bool control = (code >= 0x80 && code <= 0x9F) || code == 0xFFFE || code == 0xFFFF;
        control ? out += kReplacement : out.append(text.substr(i, length));
        i += length;
    }
    return out;
}

std::string xmlEscape(std::string_view text, bool attribute) {
    const std::string clean = sanitizeText(text);
    std::string out;
    out.reserve(clean.size() + clean.size() / 8);
    for (const char c : clean) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&#39;";
                break;
            case '\n':
                out += attribute ? "&#10;" : "\n";
                break;
            case '\t':
                out += attribute ? "&#9;" : "\t";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::string base64(std::span<const uint8_t> bytes) {
    static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const size_t left = bytes.size() - i;
        const uint32_t triple = uint32_t(bytes[i]) << 16 | (left > 1 ? uint32_t(bytes[i + 1]) << 8 : 0) |
                                (left > 2 ? uint32_t(bytes[i + 2]) : 0);
        out += kDigits[triple >> 18 & 63];
        out += kDigits[triple >> 12 & 63];
        out += left > 1 ? kDigits[triple >> 6 & 63] : '=';
        out += left > 2 ? kDigits[triple & 63] : '=';
    }
    return out;
}

void writeTextFile(const std::string& path, std::string_view content) {
    const std::string temporary = path + ".tmp." + std::to_string(getpid());
    auto fail = [&](const std::string& why) {
        std::remove(temporary.c_str());
        throw Error(ErrorCode::BadFile, "cannot write the report " + path + ": " + why);
    };
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) fail(std::strerror(errno));
        out.write(content.data(), std::streamsize(content.size()));
        out.close();
        if (!out) fail(std::strerror(errno));
    }
    if (std::rename(temporary.c_str(), path.c_str()) != 0) fail(std::strerror(errno));
}

std::string oneLine(std::string_view text) {
    std::string line = sanitizeText(text);
    std::replace_if(
        line.begin(), line.end(), [](char c) { return c == '\n' || c == '\t'; }, ' ');
    return line;
}

std::string verdictCounts(const GradeRun& run) {
    auto counted = [](size_t n, const char* one, const char* many) {
        return std::to_string(n) + " " + (n == 1 ? one : many);
    };
    return counted(run.sceneCount(), "scene", "scenes") + ": " + std::to_string(run.count(Verdict::Pass)) +
           " passed, " + std::to_string(run.count(Verdict::Fail)) + " failed, " +
           counted(run.count(Verdict::Error), "error", "errors");
}

// ---- Gradescope ----

namespace {

// A test's "output": the headline, the comparison, then the explanation.
std::string gradescopeOutput(const SceneResult& scene) {
    std::string output = scene.headline().empty()
                             ? (scene.verdict == Verdict::Pass ? "passed" : verdictName(scene.verdict))
                             : scene.headline();
    if (scene.comparison) output += "\ncomparison: " + comparisonText(*scene.comparison);
    if (!scene.explanation.empty()) output += "\n\n" + scene.explanation;
    return sanitizeText(output);
}

nlohmann::ordered_json gradescopeTest(const LabResult& lab, const SceneResult& scene) {
    nlohmann::ordered_json extra = {
        {"lab", lab.name}, {"scene", scene.name}, {"verdict", verdictName(scene.verdict)}};
    if (scene.comparison)
        extra["comparison"] = {{"metric", scene.comparison->metric},
                               {"value", scene.comparison->value},
                               {"threshold", scene.comparison->threshold},
                               {"unit", scene.comparison->unit}};
    return {{"name", sanitizeText(lab.name + ": " + scene.name)},
            {"number", sanitizeText(scene.number)},
            {"score", scene.score},
            {"max_score", scene.maxScore},
            {"status", scene.verdict == Verdict::Pass ? "passed" : "failed"},
            {"visibility", visibilityName(scene.visibility)},
            {"output", gradescopeOutput(scene)},
            {"extra_data", extra}};
}

}  // namespace

std::string gradescopeResultsJson(const GradeRun& run, const GradescopeOptions& options) {
    nlohmann::ordered_json results;
    results["score"] = run.score();
    results["execution_time"] = std::llround(std::max(0.0, run.seconds));
    results["output"] = sanitizeText(run.output);
    results["output_format"] = "text";
    results["test_output_format"] = "text";
    results["test_name_format"] = "text";
    if (options.visibility) results["visibility"] = visibilityName(*options.visibility);
    results["stdout_visibility"] = visibilityName(options.stdoutVisibility);
    results["extra_data"] = {{"submission", sanitizeText(run.submission)},
                             {"max_score", run.maxScore()},
                             {"scenes", run.sceneCount()},
                             {"passed", run.count(Verdict::Pass)},
                             {"failed", run.count(Verdict::Fail)},
                             {"errors", run.count(Verdict::Error)}};
    results["tests"] = nlohmann::ordered_json::array();
    for (const LabResult& lab : run.labs)
        for (const SceneResult& scene : lab.scenes) results["tests"].push_back(gradescopeTest(lab, scene));
    // Strings were sanitized; `replace` is the guard for any that were not (nlohmann throws otherwise).
    return results.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

void writeGradescopeResults(const std::string& path, const GradeRun& run, const GradescopeOptions& options) {
    writeTextFile(path, gradescopeResultsJson(run, options));
}

// ---- The terminal ----

namespace {

// Code points, as a terminal counts columns for the scripts a scene's name uses.
size_t columns(std::string_view text) {
    return size_t(
        std::count_if(text.begin(), text.end(), [](char c) { return (uint8_t(c) & 0xC0) != 0x80; }));
}

std::string padded(std::string text, size_t width, bool right = false) {
    const size_t fill = width > columns(text) ? width - columns(text) : 0;
    return right ? std::string(fill, ' ') + text : text + std::string(fill, ' ');
}

struct Row {
    std::string number, name, score, verdict, comparison, headline;
};

Row rowOf(const SceneResult& scene) {
    static constexpr const char* kVerdicts[] = {"PASS", "FAIL", "ERROR"};
    return {oneLine(scene.number),
            oneLine(scene.name),
            formatScore(scene.score) + " / " + formatScore(scene.maxScore),
            kVerdicts[int(scene.verdict)],
            scene.comparison ? oneLine(comparisonText(*scene.comparison)) : "-",
            oneLine(scene.headline())};
}

}  // namespace

std::string terminalSummary(const GradeRun& run) {
    std::string out = "raster grade: " + oneLine(run.submission) + "\n";
    std::vector<std::vector<Row>> rows;
    std::array<size_t, 5> width{};
    for (const LabResult& lab : run.labs) {
        rows.emplace_back();
        for (const SceneResult& scene : lab.scenes) {
            const Row& row = rows.back().emplace_back(rowOf(scene));
            const std::string* cells[] = {&row.number, &row.name, &row.score, &row.verdict, &row.comparison};
            for (size_t c = 0; c < width.size(); ++c) width[c] = std::max(width[c], columns(*cells[c]));
        }
    }
    if (run.sceneCount() == 0) out += "  no scenes were graded\n";
    for (size_t l = 0; l < run.labs.size(); ++l) {
        const LabResult& lab = run.labs[l];
        out += oneLine(lab.name) + (lab.title.empty() ? "" : "  " + oneLine(lab.title)) + ": " +
               formatScore(lab.score()) + " / " + formatScore(lab.maxScore()) + "\n";
        for (const Row& row : rows[l]) {
            std::string line = "  " + padded(row.number, width[0]) + "  " + padded(row.name, width[1]) +
                               "  " + padded(row.score, width[2], true) + "  " +
                               padded(row.verdict, width[3]) + "  " + padded(row.comparison, width[4]) +
                               "  " + row.headline;
            while (!line.empty() && line.back() == ' ') line.pop_back();
            out += line + "\n";
        }
    }
    out += "total: " + formatScore(run.score()) + " / " + formatScore(run.maxScore()) + " points; " +
           verdictCounts(run) + "\n";
    return out;
}

}  // namespace raster::grade
