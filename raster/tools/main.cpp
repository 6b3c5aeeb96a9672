// build/bin/raster: one program, one subcommand per file.
#include <cstdio>
#include <cstring>
#include <string>

#include "commands.hpp"
#include "raster/check.hpp"

namespace {

void usage(FILE* out) {
    std::fprintf(out,
                 "usage: raster <command> [options]\n"
                 "commands:\n"
                 "  bench particles|fog [options]   time a benchmark scene of SCENES.md (raster bench --help)\n"
                 "  microbench [benchmark flags]    per-stage microbenchmarks (Google Benchmark: --benchmark_filter=...)\n"
                 "  render [scene...] [--out-dir D] render the lecture's scenes to PNG files\n"
                 "  trace <scene> --stats           pipeline statistics of each draw of one frame\n"
                 "  view <scene> [options]          the SDL2 viewer: step through draws and primitives (raster view --help)\n"
                 "  help                            this text\n");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    const std::string command = argv[1];
    try {
        if (command == "bench") return raster::tools::bench(argc - 2, argv + 2);
        if (command == "microbench") return raster::tools::microbench(argc - 2, argv + 2);
        if (command == "render") return raster::tools::render(argc - 2, argv + 2);
        if (command == "trace") return raster::tools::trace(argc - 2, argv + 2);
        if (command == "view") return raster::tools::view(argc - 2, argv + 2);
        if (command == "help" || command == "--help" || command == "-h") {
            usage(stdout);
            return 0;
        }
        std::fprintf(stderr, "raster: unknown command '%s'\n", command.c_str());
        usage(stderr);
        return 2;
    } catch (const raster::Error& e) {
        std::fprintf(stderr, "raster %s: %s\n", command.c_str(), e.what());
        return 1;
    }
}
