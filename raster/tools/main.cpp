// build/bin/raster: one program, one subcommand per file, the command line parsed by CLI11.
// Exit status: 0 done (or --help), kUsageExit (2) a command line that does not parse (a bad value,
// an unknown option or subcommand, a missing value), 1 an error while running.
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "commands.hpp"
#include "options.hpp"
#include "raster/check.hpp"
#include "raster/simd/base.hpp"

namespace {

// "raster" or "raster bench": the program and the subcommand on the command line, if any.
std::string commandName(const CLI::App& app) {
    const std::vector<CLI::App*> parsed = app.get_subcommands();
    return parsed.empty() ? "raster" : "raster " + parsed.front()->get_name();
}

int usageError(const CLI::App& app, const CLI::ParseError& e) {
    const std::string name = commandName(app);
    std::fprintf(stderr, "%s: %s\n(%s --help lists the %s)\n", name.c_str(), e.what(), name.c_str(),
                 app.get_subcommands().empty() ? "commands" : "options");
    return raster::tools::kUsageExit;
}

int runError(const CLI::App& app, const std::string& message) {
    std::fprintf(stderr, "%s: %s\n", commandName(app).c_str(), message.c_str());
    return 1;
}

// Parses the command line, then runs the subcommand on it; returns the exit status.
int run(CLI::App& app, const std::vector<raster::tools::Command>& commands, int argc, char** argv) {
    try {
        app.parse(argc, argv);
        for (const raster::tools::Command& command : commands)
            if (command.app->parsed()) return command.run();
        const bool asked = app.get_subcommand("help")->parsed();
        std::fputs(app.get_formatter()->make_help(&app, "raster", CLI::AppFormatMode::Normal).c_str(),
                   asked ? stdout : stderr);
        return asked ? 0 : raster::tools::kUsageExit;
    } catch (const CLI::Success& e) {
        return app.exit(e);  // --help: printed on stdout
    } catch (const CLI::ParseError& e) {
        return usageError(app, e);
    } catch (const raster::Error& e) {
        return runError(app, e.what());
    } catch (const std::bad_alloc& e) {
        return runError(app, std::string("out of memory (") + e.what() + ")");
    } catch (const std::exception& e) {
        return runError(app, e.what());
    }
}

// `raster --version`: the version, and which of the SIMD layer's paths (raster/simd/) this build
// compiled and this processor can run: what a test run on this machine exercised.
std::string versionText() {
    auto yes = [](bool b) { return b ? "yes" : "no"; };
#if defined(__SSSE3__)
    constexpr bool kSse = true;
#else
    constexpr bool kSse = false;
#endif
#if defined(__AVX2__) && defined(__FMA__)
    constexpr bool kAvx2 = true;
#else
    constexpr bool kAvx2 = false;
#endif
    __builtin_cpu_init();
    const bool cpu_avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                            __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
    std::string text = "raster " RASTER_VERSION "\n";
    text += std::string("SIMD paths compiled: simd/x86_128 (SSE2, SSSE3) ") + yes(kSse) + ", simd/avx2 (AVX2, FMA) " +
            yes(kAvx2) + ", simd/avx512 (AVX-512 F, BW, DQ, VL) " + yes(raster::simd::kAvx512) +
            "; simd/portable where one is not\n";
    text += std::string("this processor: AVX2 ") + yes(__builtin_cpu_supports("avx2")) + ", AVX-512 F/BW/DQ/VL " +
            yes(cpu_avx512);
    return text;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app("raster: a software rasterizer emulating the Direct3D 11 pipeline", "raster");
    app.require_subcommand(0, 1);
    app.set_version_flag("--version", versionText());
    const std::vector<raster::tools::Command> commands = {
        raster::tools::addBench(app), raster::tools::addGrade(app), raster::tools::addMicrobench(app), raster::tools::addReferences(app),
        raster::tools::addRender(app),
        raster::tools::addTrace(app), raster::tools::addView(app)};
    app.add_subcommand("help", "this text");
    app.footer(
        "raster <command> --help lists a command's options. Exit status: 0 done, 2 a command line\n"
        "that does not parse, 1 an error while running.");
    return run(app, commands, argc, argv);
}
