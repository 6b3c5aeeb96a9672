// raster grade <submission> [--lab NAME ...] [--out DIR] [--public] [--jobs N]: builds a submission's
// labs, renders their graded scenes, compares each with the solution's image, diagnoses what fails and
// writes the reports (grade/grader.hpp, grade/report.hpp). Exit status 0 whenever grading finished,
// whatever the score; 1 when it could not (no such folder, a bad grading declaration).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "grade/grader.hpp"
#include "options.hpp"
#include "source_tree.hpp"

namespace raster::tools {
namespace {

struct GradeArgs {
    std::string submission, out = "grade-report", toolchain;
    grade::GraderOptions options = grade::defaultGraderOptions();
    uint32_t jobs = 1, renderSeconds = 30, buildSeconds = 300, threads = 1, renderMemory = 2048;
    std::string isolation = "auto";
};

// grade_toolchain.json beside this program (CMake writes it into build/bin).
std::string defaultToolchain() {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? "grade_toolchain.json" : (self.parent_path() / "grade_toolchain.json").string();
}

int runGrade(GradeArgs& args) {
    grade::GraderOptions& o = args.options;
    o.toolchainPath = args.toolchain.empty() ? defaultToolchain() : args.toolchain;
    o.outDir = args.out;
    o.jobs = args.jobs;
    o.runnerThreads = args.threads;
    o.renderLimits.wallSeconds = args.renderSeconds;
    o.renderLimits.cpuSeconds = args.renderSeconds;
    o.renderLimits.addressSpaceBytes = uint64_t(args.renderMemory) * grade::kMiB;
    o.buildLimits.wallSeconds = args.buildSeconds;
    o.buildLimits.cpuSeconds = args.buildSeconds;
    o.isolation = grade::parseIsolation(args.isolation);
    const grade::GradeRun run = grade::gradeSubmission(args.submission, o);
    std::fputs(run.output.c_str(), stdout);
    grade::writeReports(run, args.out);
    std::fputs(grade::terminalSummary(run).c_str(), stdout);
    std::printf("reports in %s: results.json, junit.xml, report.html\n", args.out.c_str());
    return 0;
}

}  // namespace

Command addGrade(CLI::App& app) {
    CLI::App* command =
        addCommand(app, "grade", "grade a submission's labs against the solutions (autograder)");
    auto args = std::make_shared<GradeArgs>();
    command->add_option("submission", args->submission, "a folder laid out like labs/, or one lab's folder")
        ->required()
        ->check(CLI::ExistingDirectory);
    command->add_option("--lab", args->options.labs, "grade only this lab (repeatable)")
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    command->add_option("--out", args->out, "write results.json, junit.xml, report.html and the PNGs here")
        ->capture_default_str();
    command->add_flag("--public", args->options.publicOnly,
                      "only the public scenes (labs/<lab>/grading.json)");
    addWholeNumber(*command, "--jobs", args->jobs, 1, 64, "scenes rendered at once");
    addWholeNumber(*command, "--threads", args->threads, 1, 64, "the lab runner's render threads");
    command
        ->add_option("--path", args->options.runnerPath,
                     "the lab runner's pipeline (for measuring thresholds)")
        ->check(CLI::IsMember({"fast", "plain", "reference"}))
        ->capture_default_str();
    addWholeNumber(*command, "--render-seconds", args->renderSeconds, 1, 3600,
                   "wall and CPU seconds of each render of the submission");
    addWholeNumber(*command, "--render-memory", args->renderMemory, 64, 1 << 20,
                   "address space of each render of the submission, in MiB");
    addWholeNumber(*command, "--build-seconds", args->buildSeconds, 1, 3600,
                   "wall and CPU seconds of each compile and link of the submission");
    args->options.gradingRoot = sourceTree();
    command
        ->add_option("--grading-root", args->options.gradingRoot,
                     "the folder whose labs/ and solutions/ hold the grading declarations")
        ->check(CLI::ExistingDirectory)
        ->capture_default_str();
    command->add_option("--toolchain", args->toolchain, "grade_toolchain.json (default: beside this program)")
        ->check(CLI::ExistingFile);
    command
        ->add_option("--isolation", args->isolation,
                     "how the submission's build and runs are kept to their files: auto (Landlock, else "
                     "bubblewrap, else none), landlock, bubblewrap, none")
        ->check(CLI::IsMember({"auto", "landlock", "bubblewrap", "none"}))
        ->capture_default_str();
    command->add_flag("--keep-scratch", args->options.keepScratch,
                      "keep the scratch directory (builds, images)");
    return {command, [args] { return runGrade(*args); }};
}

// raster references <out-root>: the expected images a handout ships (docs/HANDOUT.md), written by
// this program's compiled solutions.
Command addReferences(CLI::App& app) {
    CLI::App* command = addCommand(app, "references",
                                   "write the handout's reference images: each lab's solution at its public "
                                   "scenes (out/labs/<lab>/reference/<scene>.png) and at its defaults "
                                   "(<lab>@solution.png)");
    auto out = std::make_shared<std::string>();
    auto root = std::make_shared<std::string>(sourceTree());
    command->add_option("out", *out, "the folder that gets labs/<lab>/reference/")->required();
    command
        ->add_option("--grading-root", *root, "the folder whose labs/ hold the public grading declarations")
        ->check(CLI::ExistingDirectory)
        ->capture_default_str();
    return {command, [out, root] {
                const std::vector<std::string> written = grade::writeReferenceImages(*root, *out);
                std::printf("%zu reference images in %s/labs/<lab>/reference/\n", written.size(), out->c_str());
                return 0;
            }};
}

}  // namespace raster::tools
