// raster microbench [Google Benchmark flags]: runs build/bin/raster-microbench (microbench.cpp), the
// per-stage microbenchmarks, with the same arguments. They are a program of their own so that building
// `raster` (the README's first command) does not compile them; `cmake --build build` builds both.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"
#include "options.hpp"
#include "raster/check.hpp"

namespace raster::tools {

namespace {

// raster-microbench beside this program.
std::filesystem::path microbenchProgram() {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) throw Error(ErrorCode::BadFile, "raster microbench: cannot find this program's folder (/proc/self/exe: " +
                                                ec.message() + ")");
    return self.parent_path() / "raster-microbench";
}

// Replaces this process with raster-microbench: its output and exit status are the command's.
int runMicrobench(const std::vector<std::string>& args) {
    const std::filesystem::path program = microbenchProgram();
    if (!std::filesystem::exists(program))
        throw Error(ErrorCode::BadFile, program.string() +
                                            " is not built (the README's first command builds raster alone): "
                                            "cmake --build build --target raster_microbench");
    std::vector<std::string> storage = {program.string()};
    storage.insert(storage.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : storage) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    throw Error(ErrorCode::BadFile, "cannot run " + program.string() + ": " + std::strerror(errno));
}

}  // namespace

// Every argument after "microbench", from the first one that is not --help, goes to Google
// Benchmark as it is (CLI11's prefix command).
Command addMicrobench(CLI::App& app) {
    CLI::App* command = addCommand(app, "microbench", "per-stage microbenchmarks (Google Benchmark)");
    command->prefix_command();
    command->footer(
        "The arguments are Google Benchmark's flags, passed on to it as they are, e.g.\n"
        "  --benchmark_filter=REGEX     run only the benchmarks whose names match\n"
        "  --benchmark_list_tests       list the benchmarks, run none\n"
        "  --benchmark_min_time=SECONDS time per benchmark (default here 0.3)\n"
        "  --benchmark_repetitions=N    --benchmark_format=console|json|csv  --benchmark_out=FILE\n"
        "An argument it does not know exits with status 2. They run in build/bin/raster-microbench,\n"
        "which `cmake --build build --target raster_microbench` builds.");
    return {command, [command] { return runMicrobench(command->remaining()); }};
}

}  // namespace raster::tools
