// raster grade's engine (docs/GRADING.md): grades one submission, lab by lab and scene by scene,
// into a GradeRun that report.hpp writes.
//
// For each lab (grading.hpp says where its scenes are declared):
//  1. build: the submission's <lab>.cpp (never through a symbolic link) is copied alone into a scratch
//     directory (under TMPDIR, never the source tree) and compiled there to assembly with the flags the
//     library was built with (the toolchain file, grade_toolchain.json beside build/bin/raster, written
//     by CMake); a compile that read a file neither the lab's nor beneath the compiler's include path
//     (its -MD list), or whose assembly reads a file (.incbin, .include) or defines a macro, is refused;
//     then it is assembled and linked with the lab runner (lab_runner_main.cpp) and raster_lib: two
//     sandboxed commands (sandbox.hpp), buildLimits each, reading only the system's folders, the
//     include path and the libraries, writing only the scratch directory (isolation.hpp);
//  2. render: each scene by the submission's runner in the sandbox (renderLimits; reading only the
//     system's libraries), to a PNG in the scratch directory that the grader then reads; the expected
//     image of the same scene by the solution compiled into this program (<lab>@solution, makeScene),
//     in-process;
//  3. compare with the scene's declared comparison; the scene scores its points when it passes;
//  4. for a scene that fails, diagnose (diagnose.hpp) at the representative pixel of the largest failing
//     region: the runner renders again with the trace on that pixel, the solution in-process likewise.
// A build that fails, a crash, a hang, a runaway allocation or fork: the scenes affected score 0 as
// Error, the reason named, and grading goes on. Nothing the submission writes is trusted but its PNG's
// pixels (and the pixel history, which only feeds the diagnosis): the grader writes every report itself,
// after the submission's processes have ended, into a directory the submission is never told of.
#pragma once

#include <string>
#include <vector>

#include "grade/grading.hpp"
#include "grade/report.hpp"
#include "grade/sandbox.hpp"
#include "raster/image_io.hpp"
#include "raster/trace.hpp"

namespace raster::grade {

// How to build a lab's file like the library: grade_toolchain.json, {"compiler": path, "compile":
// [flags, -I, -D...], "link": [libraries and flags after the objects]}.
struct Toolchain {
    std::string compiler;
    std::vector<std::string> compileArgs, linkArgs;
};
// Throws Error(BadFile) naming the path and the field.
Toolchain readToolchain(const std::string& path);

struct GraderOptions {
    std::string gradingRoot;          // holds labs/<lab>/grading.json and solutions/<lab>/grading.json
    std::string toolchainPath;        // grade_toolchain.json
    std::string outDir;               // the reports and PNGs; created; empty: no files, only the GradeRun
    std::vector<std::string> labs;    // only these; empty: what the submission holds (see gradeSubmission)
    bool publicOnly = false;          // only the public scenes
    unsigned jobs = 1;                // scenes rendered at once
    unsigned runnerThreads = 1;       // the runner's Context threads (--threads of lab_runner)
    std::string runnerPath = "fast";  // the runner's pipeline: fast, plain or reference (measurements)
    bool keepScratch = false;         // leave the scratch directory (its path is in GradeRun::output)
    SandboxLimits buildLimits, renderLimits;  // processes: added to the user's tasks at each start
    // How the build and the runs are kept to their files (isolation.hpp; Auto: the best this machine has).
    Isolation isolation = Isolation::Auto;
};

// Limits for a course's machine: a build 300 s wall and CPU, 4 GiB; a render 30 s, 2 GiB; 64 more
// processes than the user runs; files up to 256 MiB.
GraderOptions defaultGraderOptions();

// `submission`: a folder laid out like labs/ (<lab>/<lab>.cpp for each lab) or one lab's folder
// (<lab>.cpp). Graded labs: options.labs if given (an unknown one is an Error(InvalidArgument)), else
// the labs whose file is directly in the folder, else every declared lab (a missing file scores 0).
// Throws Error for what stops the whole run (no such folder, a bad declaration or toolchain file);
// everything the submission does is a scene's verdict.
GradeRun gradeSubmission(const std::string& submission, const GraderOptions& options);

// The solution's image of a scene, rendered in-process by the <lab>@solution compiled into this
// program (Error(InvalidArgument) where it was built without it); the trace, when given, records it.
ImageRgba8 renderExpected(const std::string& lab, const SceneOptions& options, Trace* trace);

// A handout's reference image of a scene: <root>/labs/<lab>/reference/<scene>.png. A handout (built
// without solutions/, docs/HANDOUT.md) ships one per public scene, and <lab>@solution.png, the
// solution at its defaults (what the viewer's K shows); the grader compares with it where this
// program has no <lab>@solution, and cannot then diagnose.
std::string referenceImagePath(const std::string& root, const std::string& lab, const std::string& scene);

// Writes the reference images of every lab that declares its grading under `root` (public scenes
// only, at their options, and <lab>@solution at the defaults) beneath out_root, as
// referenceImagePath(out_root, ...) names them; returns their paths. Throws Error(InvalidState) for a
// lab whose solution this program lacks.
std::vector<std::string> writeReferenceImages(const std::string& root, const std::string& out_root);

// Writes results.json, junit.xml, report.html into options.outDir (created) and returns nothing: the
// PNGs are already there (gradeSubmission writes them).
void writeReports(const GradeRun& run, const std::string& out_dir);

}  // namespace raster::grade
