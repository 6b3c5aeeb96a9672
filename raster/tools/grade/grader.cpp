#include "grade/grader.hpp"

#include <fcntl.h>
#include <pwd.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <utility>

#include "grade/diagnose.hpp"
#include "grade/trace_json.hpp"
#include "raster/check.hpp"
#include "raster/pipeline.hpp"
#include "raster/trace.hpp"

namespace raster::grade {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string readText(const std::string& path, size_t max_bytes) {
    std::ifstream in(path, std::ios::binary);
    RASTER_REQUIRE(in, BadFile, "cannot read '" + path + "'");
    std::string text(max_bytes, '\0');
    in.read(text.data(), std::streamsize(max_bytes));
    text.resize(size_t(in.gcount()));
    return text;
}

// The last `count` lines of a child's output, for an explanation.
std::string tail(const std::string& text, size_t count) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    std::string out;
    for (size_t i = lines.size() > count ? lines.size() - count : 0; i < lines.size(); ++i)
        out += lines[i] + "\n";
    return out;
}

// What ended a sandboxed run that did not succeed, as the start of a reason.
std::string failureReason(const SandboxResult& r) {
    switch (r.outcome) {
        case SandboxOutcome::Signaled:
            return "crashed: " + r.description;
        case SandboxOutcome::WallTimeLimit:
        case SandboxOutcome::CpuTimeLimit:
            return "timed out: " + r.description;
        case SandboxOutcome::MemoryLimit:
            return "ran out of memory: " + r.description;
        case SandboxOutcome::OutputSizeLimit:
            return "wrote too much: " + r.description;
        case SandboxOutcome::ProcessLimit:
            return "too many processes: " + r.description;
        case SandboxOutcome::StartFailed:
            return "could not start: " + r.description;
        case SandboxOutcome::Exited:
            break;
    }
    return "failed: " + r.description;
}

// Where a compiler's or linker's output names its first error: the line "file:line:column: error:
// message" (GCC and clang) or the linker's "undefined reference to ..." line. npos when none does.
size_t firstToolErrorLine(const std::vector<std::string>& lines) {
    for (size_t i = 0; i < lines.size(); ++i)
        if (lines[i].find(": error: ") != std::string::npos || lines[i].find(": fatal error: ") != std::string::npos ||
            lines[i].find("undefined reference to") != std::string::npos)
            return i;
    return std::string::npos;
}

std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// The user whose tasks RLIMIT_NPROC counts in the child: the one it drops to when the grader is root.
uid_t childUid(const SandboxCommand& command) {
    if (geteuid() != 0 || !command.dropToUser) return getuid();
    const passwd* user = getpwnam(command.dropToUser->c_str());
    return user ? user->pw_uid : getuid();
}

// What a submission's build and runs may open (isolation.hpp), besides their scratch directory: the
// system's programs, headers and libraries for the compile and link; for the runner, the shared
// libraries and the dynamic loader's cache, and nothing it could execute but itself.
const std::vector<std::string> kBuildSystem = {
    "/usr", "/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32", "/etc/alternatives", "/etc/ld.so.cache"};
const std::vector<std::string> kRunSystem = {"/usr/lib",    "/usr/lib32", "/usr/lib64",
                                             "/usr/libx32", "/lib",       "/lib32",
                                             "/lib64",      "/libx32",    "/etc/ld.so.cache"};

// Where a grading run's commands may reach (Confinement::build and run add the lab's scratch).
struct Confinement {
    Isolation isolation = Isolation::Auto;
    std::vector<fs::path> includeRoots;  // the compiler's include search path, resolved
    std::vector<std::string> buildReadable;
    FileAccess build(const std::string& scratch) const { return {buildReadable, {scratch}}; }
    FileAccess run(const std::string& scratch) const { return {kRunSystem, {scratch}}; }
};

SandboxResult runLimited(std::vector<std::string> argv, const std::string& dir, SandboxLimits limits,
                         const FileAccess& files, Isolation isolation) {
    SandboxCommand command;
    command.argv = std::move(argv);
    command.workingDirectory = command.scratchDirectory = dir;
    if (limits.processes > 0) limits.processes += userTaskCount(childUid(command));
    command.limits = limits;
    command.files = files;
    command.isolation = isolation;
    return runSandboxed(command);
}

// `path` lies at or beneath `root` (both absolute and normal).
bool beneath(const fs::path& path, const fs::path& root) {
    return std::mismatch(root.begin(), root.end(), path.begin(), path.end()).first == root.end();
}

// `path` as the kernel resolves it: absolute (against `dir`), links followed as far as it exists
// (before "..": a/../b is b beside where the link a leads).
fs::path resolved(const std::string& path, const std::string& dir) {
    std::error_code error;
    const fs::path absolute = fs::path(dir) / path;
    const fs::path real = fs::weakly_canonical(absolute, error);
    return error ? absolute.lexically_normal() : real;
}

// The folders the compiler searches for headers with the toolchain's flags (`-v`'s list: raster's
// include folders, then the compiler's and the system's), resolved.
std::vector<fs::path> includeSearchPath(const Toolchain& toolchain) {
    SandboxCommand probe;
    probe.argv = {toolchain.compiler};
    probe.argv.insert(probe.argv.end(), toolchain.compileArgs.begin(), toolchain.compileArgs.end());
    probe.argv.insert(probe.argv.end(), {"-x", "c++", "-E", "-v", "/dev/null", "-o", "/dev/null"});
    probe.workingDirectory = "/";
    probe.dropToUser.reset();  // the grader's own compiler on an empty file
    probe.limits.wallSeconds = probe.limits.cpuSeconds = 60;
    const SandboxResult r = runSandboxed(probe);
    RASTER_REQUIRE(
        r.succeeded(), InvalidState,
        "the toolchain's compiler " + toolchain.compiler + " " + r.description + ":\n" + r.stderrText);
    std::vector<fs::path> roots;
    std::istringstream in(r.stderrText);
    bool listing = false;
    for (std::string line; std::getline(in, line);) {
        if (line.find("search starts here:") != std::string::npos)
            listing = true;
        else if (line.rfind("End of search list.", 0) == 0)
            listing = false;
        else if (listing && line.size() > 1 && line[0] == ' ')
            roots.push_back(resolved(line.substr(1, line.find(" (") - 1), "/"));
    }
    RASTER_REQUIRE(!roots.empty(), InvalidState,
                   "the toolchain's compiler " + toolchain.compiler + " lists no include folder (-v)");
    return roots;
}

Confinement confinementFor(const Toolchain& toolchain, Isolation isolation) {
    std::string why;
    RASTER_REQUIRE(isolation != Isolation::Landlock || landlockAbi(&why) > 0, InvalidState,
                   "Landlock isolation asked for, and this machine has none: " + why);
    RASTER_REQUIRE(
        isolation != Isolation::Bubblewrap || !findBubblewrap().empty(), InvalidState,
        "bubblewrap isolation asked for, and there is no bwrap in /usr/local/bin, /usr/bin or /bin");
    Confinement c{isolation, includeSearchPath(toolchain), kBuildSystem};
    for (const fs::path& root : c.includeRoots) c.buildReadable.push_back(root.string());
    // The link's inputs (raster's libraries, the runner's main): the absolute paths among its arguments.
    for (const std::string& arg : toolchain.linkArgs)
        if (fs::path(arg).is_absolute()) c.buildReadable.push_back(arg);
    return c;
}

// ---- One lab ----

struct LabBuild {
    std::string scratch;      // the lab's scratch directory: its source, its runner, its images
    std::string runner;       // the runner's path, empty when the build failed
    std::string reason, log;  // why it failed, the compiler's output
    std::string excerpt;      // the part of the output that says why: around the first error
    FileAccess runFiles;      // what the runner may open
    Isolation isolation = Isolation::Auto;
};

// A lab's file in a submission: its path, or why there is none to grade.
struct LabFile {
    std::string path, problem;
};

// <lab>/<lab>.cpp, else <lab>.cpp. A symbolic link on the way (the file, or <lab>/) is refused: it
// could lead anywhere the grader may read, the solutions among them.
LabFile findLabFile(const fs::path& submission, const std::string& lab) {
    for (const fs::path& relative : {fs::path(lab) / (lab + ".cpp"), fs::path(lab + ".cpp")}) {
        fs::path path = submission, shown;
        for (const fs::path& part : relative) {
            path /= part;
            shown /= part;
            std::error_code error;
            const fs::file_status status = fs::symlink_status(path, error);
            if (fs::is_symlink(status))
                return {"", shown.string() + " is a symbolic link (to " +
                                fs::read_symlink(path, error).string() +
                                "), which the grader does not follow: submit the file itself"};
            if (!fs::exists(status)) break;
            if (part == relative.filename() && fs::is_regular_file(status)) return {path.string(), ""};
        }
    }
    return {"", "no " + lab + ".cpp in the submission"};
}

// Copies a lab's file without following a link put in its place since findLabFile looked.
void copyLabFile(const std::string& from, const std::string& to) {
    const int fd = ::open(from.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    RASTER_REQUIRE(fd >= 0, BadFile, "cannot open '" + from + "' (a link is not followed)");
    std::string text;
    char buffer[65536];
    for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) text.append(buffer, size_t(n));
    ::close(fd);
    std::ofstream(to, std::ios::binary | std::ios::trunc) << text;
}

// The files a make rule (-MD's) names after its target, unescaped ("\ " a space, "$$" a dollar).
std::vector<std::string> ruleInputs(const std::string& rule) {
    std::vector<std::string> inputs;
    std::string current;
    const size_t colon = rule.find(": ");
    for (size_t i = colon == std::string::npos ? rule.size() : colon + 2; i < rule.size(); ++i) {
        const char c = rule[i];
        if (c == '\\' && i + 1 < rule.size() && (rule[i + 1] == ' ' || rule[i + 1] == '#')) {
            current += rule[++i];
        } else if (c == '\\' && i + 1 < rule.size() && rule[i + 1] == '\n') {
            ++i;
        } else if (c == '$' && i + 1 < rule.size() && rule[i + 1] == '$') {
            current += rule[++i];
        } else if (std::isspace((unsigned char)c)) {
            if (!current.empty()) inputs.push_back(std::move(current));
            current.clear();
        } else {
            current += c;
        }
    }
    if (!current.empty()) inputs.push_back(current);
    return inputs;
}

// The path a failed compile could not open, from its fatal error (GCC: "fatal error: PATH: Permission
// denied"; Clang: "fatal error: cannot open file 'PATH': ..."), or "".
std::string unopenedInclude(const std::string& log) {
    std::istringstream in(log);
    for (std::string line; std::getline(in, line);) {
        const size_t at = line.find("fatal error: ");
        if (at == std::string::npos) continue;
        std::string rest = line.substr(at + 13);
        for (const char* prefix : {"cannot open file '", "'"})
            if (rest.rfind(prefix, 0) == 0) rest = rest.substr(std::strlen(prefix));
        for (const char* ending :
             {": Permission denied", ": No such file or directory", "' file not found"}) {
            const size_t end = rest.rfind(ending);
            if (end != std::string::npos && end + std::strlen(ending) == rest.size()) {
                rest.resize(end);
                if (!rest.empty() && rest.back() == '\'') rest.pop_back();
                return rest;
            }
        }
    }
    return "";
}

// The first line of the compiler's assembly that would have the assembler read a file (.incbin,
// .include) or build a directive it could not see (a macro: .macro, .irp, .irpc), or "". GCC writes
// none of them itself; a submission can, by inline asm or by a section's or symbol's name, and the
// compiler's list of what it read (-MD) does not show what the assembler reads.
std::string assemblerFileRead(const std::string& assembly_path) {
    std::ifstream in(assembly_path);
    for (std::string line; std::getline(in, line);) {
        std::string lower(line);
        std::transform(lower.begin(), lower.end(), lower.begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
        for (const char* directive : {".incbin", ".include", ".macro", ".irp"})
            if (lower.find(directive) != std::string::npos)
                return line.substr(line.find_first_not_of(" \t"), 160);
    }
    return "";
}

// Why a compile must be refused: a file it read (its -MD list) or could not open (its fatal error:
// the isolation's doing) that is neither the lab's copy nor beneath the include search path, and
// that exists; or an assembler directive that reads a file. "" when there is none.
std::string refusal(const LabBuild& build, const std::string& lab, const SandboxResult& step,
                    const Confinement& confinement) {
    if (const std::string line = assemblerFileRead(build.scratch + "/" + lab + ".s"); !line.empty())
        return "compile refused: your file has the assembler read a file or define a macro (" + line +
               "), which the lab does not need";
    std::vector<std::string> read;
    std::ifstream deps(build.scratch + "/" + lab + ".d");
    if (deps) read = ruleInputs(std::string(std::istreambuf_iterator<char>(deps), {}));
    // A file the compile could not open, where its compiler would have looked: beside the lab's file,
    // then in each include folder (a file hidden by bubblewrap is named as the #include wrote it).
    const std::string unopened = step.succeeded() ? "" : unopenedInclude(step.stderrText);
    if (!unopened.empty()) {
        read.push_back(unopened);
        if (fs::path(unopened).is_relative())
            for (const fs::path& root : confinement.includeRoots) read.push_back((root / unopened).string());
    }
    const fs::path own = resolved(lab + ".cpp", build.scratch);
    for (const std::string& file : read) {
        const fs::path path = resolved(file, build.scratch);
        std::error_code error;
        if (path == own || !fs::exists(path, error)) continue;
        if (std::none_of(confinement.includeRoots.begin(), confinement.includeRoots.end(),
                         [&](const fs::path& root) { return beneath(path, root); }))
            return "compile refused: your file includes " + path.string() + ", which is not part of the lab";
    }
    return "";
}

LabBuild buildLab(const LabFile& source, const std::string& lab, const std::string& scratch,
                  const Toolchain& toolchain, const GraderOptions& options, const Confinement& confinement) {
    LabBuild build{scratch, "", "", "", "", confinement.run(scratch), confinement.isolation};
    fs::create_directories(scratch);
    if (source.path.empty()) {
        build.reason = source.problem;
        return build;
    }
    copyLabFile(source.path, scratch + "/" + lab + ".cpp");
    std::vector<std::string> compile = {toolchain.compiler};
    compile.insert(compile.end(), toolchain.compileArgs.begin(), toolchain.compileArgs.end());
    // To assembly first (-S), which refusal() reads before the link step assembles it; -MD lists what
    // the compiler read.
    compile.insert(compile.end(), {"-MD", "-MF", lab + ".d", "-S", lab + ".cpp", "-o", lab + ".s"});
    std::vector<std::string> link = {toolchain.compiler, lab + ".s"};
    link.insert(link.end(), toolchain.linkArgs.begin(), toolchain.linkArgs.end());
    link.insert(link.end(), {"-o", "lab_runner"});
    const std::pair<const char*, const std::vector<std::string>*> steps[] = {{"compile", &compile}, {"link", &link}};
    for (const auto& [name, argv] : steps) {
        const SandboxResult r =
            runLimited(*argv, scratch, options.buildLimits, confinement.build(scratch), confinement.isolation);
        const std::string output = r.stdoutText + r.stderrText;
        build.log += output;
        if (!(build.reason = refusal(build, lab, r, confinement)).empty()) {
            build.excerpt = tail(output, 30);
            return build;
        }
        if (!r.succeeded()) {
            // The first error first, where a student looks (a compile error is the submission's code,
            // a link error a function it declares but does not define), then the lines around it.
            const std::vector<std::string> lines = splitLines(output);
            const size_t first = firstToolErrorLine(lines);
            if (r.outcome == SandboxOutcome::Exited && first != std::string::npos) {
                build.reason = std::string(name) + " failed: " + lines[first] + " (" + r.description + ")";
                build.excerpt.clear();
                for (size_t i = first >= 3 ? first - 3 : 0; i < lines.size() && i < first + 27; ++i)
                    build.excerpt += lines[i] + "\n";
            } else {
                build.reason = std::string(name) + " " + failureReason(r);
                build.excerpt = tail(output, 30);
            }
            return build;
        }
    }
    build.runner = scratch + "/lab_runner";
    return build;
}

std::vector<std::string> runnerArgs(const LabBuild& build, const std::string& lab, const GradedScene& scene,
                                    const std::string& png, const GraderOptions& options) {
    std::vector<std::string> argv = {build.runner, "--scene", lab, "--out", png};
    for (const std::string& arg : runnerOptionArgs(scene.options)) argv.push_back(arg);
    argv.insert(argv.end(),
                {"--threads", std::to_string(options.runnerThreads), "--path", options.runnerPath});
    return argv;
}

TraceOptions pixelTraceOptions(uint32_t x, uint32_t y) {
    TraceOptions t;
    t.pixels = {int32_t(x), int32_t(y), int32_t(x), int32_t(y)};
    t.maxGeometryRecords = 1u << 18;
    return t;
}

// The diagnosis of a failing scene at its largest failing region's pixel, into the result.
void diagnoseScene(SceneResult& result, const LabBuild& build, const std::string& lab,
                   const GradedScene& scene, const PixelRegion& region, const GraderOptions& options) {
    const std::string history = build.scratch + "/" + scene.name + ".history.json";
    std::vector<std::string> argv =
        runnerArgs(build, lab, scene, build.scratch + "/" + scene.name + ".traced.png", options);
    argv.insert(argv.end(),
                {"--pixel", std::to_string(region.x) + "," + std::to_string(region.y), "--history", history});
    result.explanation = "the largest wrong region: " + std::to_string(region.pixels) + " pixels in (" +
                         std::to_string(region.left) + ", " + std::to_string(region.top) + ")-(" +
                         std::to_string(region.right) + ", " + std::to_string(region.bottom) +
                         "); its worst pixel (" + std::to_string(region.x) + ", " + std::to_string(region.y) +
                         ")";
    const SandboxResult r =
        runLimited(argv, build.scratch, options.renderLimits, build.runFiles, build.isolation);
    if (!r.succeeded()) {
        result.diagnosis = "no diagnosis: the traced render " + failureReason(r);
        return;
    }
    try {
        const Trace yours =
            traceFromJson(readText(history, options.renderLimits.fileSizeBytes), "the submission's trace");
        Trace theirs(pixelTraceOptions(region.x, region.y));
        renderExpected(lab, scene.options, &theirs);
        const Diagnosis d = diagnosePixel(yours, theirs, int32_t(region.x), int32_t(region.y));
        result.diagnosis = std::string(stageName(d.stage)) + ": " + d.headline;
        if (d.nonFiniteOutput) {  // the parameters that led there (a lab's hidden ones included)
            result.diagnosis += "; the scene's parameters:";
            for (const std::string& arg : runnerOptionArgs(scene.options)) result.diagnosis += " " + arg;
        }
        for (const std::string& line : d.details) result.explanation += "\n" + line;
    } catch (const Error& e) {
        result.diagnosis = std::string("no diagnosis: ") + e.what();
    }
}

std::string metricOf(const ComparisonResult& c) {
    return c.method == CompareMethod::Flip ? "FLIP mean" : "pixels outside the allowance";
}

void writeImages(SceneResult& result, const ImageRgba8& yours, const ImageRgba8& expected,
                 const ComparisonResult* comparison, const std::string& out_dir, const std::string& stem) {
    if (out_dir.empty()) return;
    result.submissionImage = out_dir + "/" + stem + ".png";
    result.expectedImage = out_dir + "/" + stem + ".expected.png";
    writePngRgba8(result.submissionImage, yours.width, yours.height, yours.pixels);
    writePngRgba8(result.expectedImage, expected.width, expected.height, expected.pixels);
    if (!comparison || comparison->passed) return;
    // Exact, threshold, position: 1/255 is a step past the allowance; 16 steps fill the ramp.
    const bool flip = comparison->method == CompareMethod::Flip;
    const float scale = flip ? 1.0f : 255.0f / 16.0f;
    std::vector<float> error(comparison->error);
    for (float& e : error) e = std::min(1.0f, e * scale);
    const ImageRgba8 heat = heatMap(error, comparison->width, comparison->height, {.colourBar = true});
    result.heatMapImage = out_dir + "/" + stem + ".heat.png";
    result.heatMapScale = flip ? HeatMapScale{1, "FLIP error"} : HeatMapScale{16, "steps past the allowance"};
    writePngRgba8(result.heatMapImage, heat.width, heat.height, heat.pixels);
}

SceneResult gradeScene(const LabBuild& build, const std::string& lab, const GradedScene& scene,
                       const GraderOptions& options, const std::string& out_dir) {
    const Clock::time_point start = Clock::now();
    SceneResult result{scene.name,    scene.number, 0, scene.points, sceneVisibility(scene.isPublic),
                       Verdict::Error};
    result.explanation = scene.comparison.describe();
    // The solution compiled in (a lecturer's build), else the handout's image of it (public scenes).
    const bool solved = findRegisteredScene(lab + "@solution") != nullptr;
    const std::string reference = referenceImagePath(options.gradingRoot, lab, scene.name);
    if (!solved && !fs::is_regular_file(reference)) {
        result.reason = "no expected image: this raster was built without solutions/" + lab + "/, and " +
                        reference + " is not there";
        return result;
    }
    if (build.runner.empty()) {
        result.reason = build.reason;
        result.explanation = build.excerpt;
        return result;
    }
    const std::string png = build.scratch + "/" + scene.name + ".png";
    const SandboxResult r = runLimited(runnerArgs(build, lab, scene, png, options), build.scratch,
                                       options.renderLimits, build.runFiles, build.isolation);
    ImageRgba8 yours;
    try {
        if (!r.succeeded()) throw Error(ErrorCode::BadFile, failureReason(r));
        yours = readImageRgba8(png);
    } catch (const Error& e) {
        result.reason = r.succeeded() ? std::string("no image: ") + e.what() : failureReason(r);
        result.explanation = tail(r.stderrText, 20);
        result.seconds = secondsSince(start);
        return result;
    }
    const ImageRgba8 expected = solved ? renderExpected(lab, scene.options, nullptr) : readImageRgba8(reference);
    if (yours.width != expected.width || yours.height != expected.height) {
        result.verdict = Verdict::Fail;
        result.diagnosis = "the image is " + std::to_string(yours.width) + "x" +
                           std::to_string(yours.height) + ", the scene's " + std::to_string(expected.width) +
                           "x" + std::to_string(expected.height);
        result.seconds = secondsSince(start);
        return result;
    }
    const ComparisonResult c = compare(scene.comparison, expected, yours);
    result.comparison =
        grade::Comparison{metricOf(c), c.figure, c.limit, c.method == CompareMethod::Flip ? "" : "pixels"};
    result.verdict = c.passed ? Verdict::Pass : Verdict::Fail;
    result.score = c.passed ? scene.points : 0;
    writeImages(result, yours, expected, &c, out_dir, scene.name);
    if (!c.passed && solved) diagnoseScene(result, build, lab, scene, largestFailingRegion(c), options);
    if (!c.passed && !solved)
        result.diagnosis = "no diagnosis: this copy has the solution's image (labs/" + lab +
                           "/reference/), not its pipeline trace";
    result.seconds = secondsSince(start);
    return result;
}

// Runs work(i) for i in [0, count) on `jobs` threads.
template <class Work>
void parallelFor(size_t count, unsigned jobs, Work work) {
    std::atomic<size_t> next{0};
    std::vector<std::thread> threads;
    for (unsigned t = 0; t < std::max(1u, std::min<unsigned>(jobs, unsigned(count))); ++t)
        threads.emplace_back([&] {
            for (size_t i = next++; i < count; i = next++) work(i);
        });
    for (std::thread& t : threads) t.join();
}

LabResult gradeLab(const fs::path& submission, const LabGrading& lab, const Toolchain& toolchain,
                   const GraderOptions& options, const std::string& scratch_root,
                   const Confinement& confinement) {
    const LabBuild build = buildLab(findLabFile(submission, lab.lab), lab.lab, scratch_root + "/" + lab.lab,
                                    toolchain, options, confinement);
    const std::string out_dir = options.outDir.empty() ? "" : options.outDir + "/" + lab.lab;
    if (!out_dir.empty()) fs::create_directories(out_dir);
    LabResult result{lab.lab, lab.title, std::vector<SceneResult>(lab.scenes.size())};
    std::mutex errors_mutex;
    std::string first_error;
    parallelFor(lab.scenes.size(), options.jobs, [&](size_t i) {
        try {
            result.scenes[i] = gradeScene(build, lab.lab, lab.scenes[i], options, out_dir);
        } catch (const std::exception& e) {  // the grader's own failure (a disk full): stops the run
            const std::lock_guard lock(errors_mutex);
            if (first_error.empty()) first_error = "scene '" + lab.scenes[i].name + "': " + e.what();
        }
    });
    RASTER_REQUIRE(first_error.empty(), InvalidState, "lab '" + lab.lab + "': " + first_error);
    return result;
}

std::vector<LabGrading> labsToGrade(const fs::path& submission, const GraderOptions& options) {
    std::vector<LabGrading> declared = discoverLabs(options.gradingRoot, options.publicOnly);
    std::vector<LabGrading> chosen;
    for (const std::string& name : options.labs) {
        auto it = std::find_if(declared.begin(), declared.end(),
                               [&](const LabGrading& l) { return l.lab == name; });
        RASTER_REQUIRE(it != declared.end(), InvalidArgument,
                       "--lab " + name + ": no lab of that name declares its grading in '" +
                           options.gradingRoot + "/labs'");
        chosen.push_back(*it);
    }
    if (!chosen.empty()) return chosen;
    for (const LabGrading& lab : declared)
        if (fs::is_regular_file(submission / (lab.lab + ".cpp"))) chosen.push_back(lab);
    return chosen.empty() ? declared : chosen;
}

// The user a submission runs as: nobody under a root grader, else the grader's.
std::string childUserName() {
    if (geteuid() == 0) return "nobody";
    const passwd* user = getpwuid(geteuid());
    return user ? user->pw_name : "uid " + std::to_string(geteuid());
}

// The run's first lines: how a submission's commands are confined (isolation.hpp), and any folder a
// submission must not see that the confinement still lets it read.
std::string sandboxNote(const Confinement& c, const GraderOptions& options, const std::string& submission) {
    IsolationChoice choice = isolationFor(std::string("nobody"));
    if (c.isolation != Isolation::Auto) {
        choice.isolation = c.isolation;
        choice.description =
            c.isolation == Isolation::Landlock     ? "Landlock ABI " + std::to_string(landlockAbi())
            : c.isolation == Isolation::Bubblewrap ? "bubblewrap (" + findBubblewrap() + ")"
                                                   : "no file-system isolation (asked for none)";
    }
    if (choice.isolation == Isolation::None)
        return "sandbox: " + choice.description + ": the submission's build and runs may read what " +
               childUserName() + " may; at build time the compiler's list of what it read is checked\n";
    std::string note = "sandbox: " + choice.description +
                       ": the submission's build reads only the system's folders, the compiler's include "
                       "path and raster's libraries, its runs only the system's libraries; each writes "
                       "only its scratch folder\n";
    std::vector<std::string> kept = {options.gradingRoot + "/solutions",
                                     fs::absolute(submission).lexically_normal().parent_path().string()};
    if (!options.outDir.empty()) kept.push_back(options.outDir);
    for (const std::string& folder : kept)
        for (const std::string& root : c.buildReadable)
            if (beneath(resolved(folder, "/"), resolved(root, "/"))) {
                note += "sandbox: warning: " + folder + " lies beneath " + root +
                        ", which a submission's build may read\n";
                break;
            }
    return note;
}

}  // namespace

Toolchain readToolchain(const std::string& path) {
    const Json j = Json::parse(readText(path, 1 << 20), nullptr, false);
    const auto fail = [&](const std::string& what) -> Toolchain {
        throw Error(ErrorCode::BadFile, "toolchain file '" + path + "': " + what);
    };
    if (j.is_discarded() || !j.is_object()) return fail("not a JSON object");
    Toolchain t;
    if (!j.contains("compiler") || !j["compiler"].is_string()) return fail("no \"compiler\" string");
    t.compiler = j["compiler"].get<std::string>();
    for (const char* key : {"compile", "link"}) {
        if (!j.contains(key) || !j[key].is_array()) return fail(std::string("no \"") + key + "\" array");
        for (const Json& arg : j[key]) {
            if (!arg.is_string()) return fail(std::string("\"") + key + "\" holds a non-string");
            const std::string s = arg.get<std::string>();
            // Generator expressions over empty lists leave "", "-I" or "-D" behind: nothing to pass.
            if (s.empty() || s == "-I" || s == "-D") continue;
            (std::string(key) == "compile" ? t.compileArgs : t.linkArgs).push_back(s);
        }
    }
    return t;
}

GraderOptions defaultGraderOptions() {
    GraderOptions o;
    o.buildLimits = {300, 300, 4 * kGiB, 64, 256 * kMiB, 1 * kMiB, 1 * kMiB};
    o.renderLimits = {30, 30, 2 * kGiB, 64, 256 * kMiB, 1 * kMiB, 1 * kMiB};
    return o;
}

ImageRgba8 renderExpected(const std::string& lab, const SceneOptions& options, Trace* trace) {
    std::unique_ptr<Scene> scene = makeScene(lab + "@solution", options);
    Context context;
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    context.resetFrameStatistics();
    if (trace) context.setTrace(trace);
    scene->render(context, color, depth);
    return {options.width, options.height, color.toRgba8()};
}

std::string referenceImagePath(const std::string& root, const std::string& lab, const std::string& scene) {
    return (fs::path(root) / "labs" / lab / "reference" / (scene + ".png")).string();
}

std::vector<std::string> writeReferenceImages(const std::string& root, const std::string& out_root) {
    std::vector<std::string> written;
    const auto write = [&](const std::string& path, const ImageRgba8& image) {
        fs::create_directories(fs::path(path).parent_path());
        writePngRgba8(path, image.width, image.height, image.pixels);
        written.push_back(path);
    };
    for (const LabGrading& lab : discoverLabs(root, true)) {
        RASTER_REQUIRE(findRegisteredScene(lab.lab + "@solution"), InvalidState,
                       "no " + lab.lab + "@solution in this raster: it was built without solutions/" +
                           lab.lab + "/");
        for (const GradedScene& scene : lab.scenes)
            write(referenceImagePath(out_root, lab.lab, scene.name), renderExpected(lab.lab, scene.options, nullptr));
        write(referenceImagePath(out_root, lab.lab, lab.lab + "@solution"),
              renderExpected(lab.lab, SceneOptions{}, nullptr));
    }
    return written;
}

GradeRun gradeSubmission(const std::string& submission, const GraderOptions& options) {
    const Clock::time_point start = Clock::now();
    RASTER_REQUIRE(fs::is_directory(submission), BadFile, "submission '" + submission + "' is not a folder");
    const Toolchain toolchain = readToolchain(options.toolchainPath);
    // Not dumpable: a submission running as the same user (a grader that is not root) can then not
    // open /proc/<grader>/cwd, fd, environ or mem (the kernel's ptrace access check), where the
    // grader's working directory, open files and memory would lead it to the solutions.
    prctl(PR_SET_DUMPABLE, 0, 0, 0, 0);
    const std::vector<LabGrading> labs = labsToGrade(submission, options);
    const Confinement confinement = confinementFor(toolchain, options.isolation);
    const char* tmp = std::getenv("TMPDIR");
    std::string scratch = std::string(tmp && *tmp ? tmp : "/tmp") + "/raster-grade-XXXXXX";
    RASTER_REQUIRE(mkdtemp(scratch.data()), BadFile, "cannot make a scratch directory '" + scratch + "'");
    // Searchable, not listable: the unprivileged user of a root grader reaches its lab's folder (handed
    // to it by the sandbox) and no other.
    chmod(scratch.c_str(), 0711);
    GradeRun run{fs::path(submission).lexically_normal().filename().string(),
                 {},
                 sandboxNote(confinement, options, submission),
                 0};
    if (run.submission.empty())
        run.submission = fs::path(submission).lexically_normal().parent_path().filename().string();
    try {
        for (const LabGrading& lab : labs)
            run.labs.push_back(gradeLab(submission, lab, toolchain, options, scratch, confinement));
    } catch (...) {
        if (!options.keepScratch) fs::remove_all(scratch);
        throw;
    }
    if (options.keepScratch)
        run.output += "scratch directory kept: " + scratch + "\n";
    else
        fs::remove_all(scratch);
    run.seconds = secondsSince(start);
    return run;
}

void writeReports(const GradeRun& run, const std::string& out_dir) {
    fs::create_directories(out_dir);
    writeGradescopeResults(out_dir + "/results.json", run);
    writeJUnitXml(out_dir + "/junit.xml", run);
    writeHtmlReport(out_dir + "/report.html", run);
}

}  // namespace raster::grade
