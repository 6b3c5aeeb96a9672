// Runs a fuzz target's LLVMFuzzerTestOneInput once on each file of the given corpus folders (or
// files), in name order, without libFuzzer: the fuzz targets' contracts as a plain test in any
// build, with any compiler (tests/fuzz/CMakeLists.txt, <target>_replay). A broken contract aborts,
// naming the input being run. Exit 0 when every input ran; 2 on a bad argument or an unreadable file.
//
//   <target>_replay [--max-seconds S] <corpus-folder-or-file> ...
//
// --max-seconds bounds the wall time: inputs left when it has passed are not run (and counted).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstring>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

namespace fs = std::filesystem;

// The input being run, for the abort handler (which may only write(2)).
char current_input_path[4096] = "";

void onAbort(int sig) {
    const char kPrefix[] = "replay: the input that failed: ";
    (void)!write(2, kPrefix, sizeof kPrefix - 1);
    (void)!write(2, current_input_path, std::strlen(current_input_path));
    (void)!write(2, "\n", 1);
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

std::vector<fs::path> inputsOf(const std::vector<std::string>& args) {
    std::vector<fs::path> files;
    for (const std::string& a : args) {
        std::error_code ec;
        if (fs::is_directory(a, ec)) {
            for (const auto& entry : fs::directory_iterator(a))
                if (entry.is_regular_file()) files.push_back(entry.path());
        } else if (fs::is_regular_file(a, ec)) {
            files.emplace_back(a);
        } else {
            std::fprintf(stderr, "replay: '%s' is neither a folder nor a file\n", a.c_str());
            std::exit(2);
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::vector<uint8_t> readAll(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::fprintf(stderr, "replay: cannot read '%s'\n", path.c_str());
        std::exit(2);
    }
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

int main(int argc, char** argv) {
    double max_seconds = 1e30;
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--max-seconds" && i + 1 < argc) {
            char* end = nullptr;
            max_seconds = std::strtod(argv[++i], &end);
            if (*end != '\0' || !(max_seconds > 0)) {
                std::fprintf(stderr, "replay: --max-seconds: '%s' is not a positive number\n", argv[i]);
                return 2;
            }
        } else {
            args.push_back(a);
        }
    }
    if (args.empty()) {
        std::fprintf(stderr, "usage: %s [--max-seconds S] <corpus-folder-or-file> ...\n", argv[0]);
        return 2;
    }
    const std::vector<fs::path> files = inputsOf(args);
    std::signal(SIGABRT, onAbort);
    std::signal(SIGSEGV, onAbort);
    const auto start = std::chrono::steady_clock::now();
    size_t ran = 0, bytes = 0;
    for (const fs::path& file : files) {
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > max_seconds) break;
        const std::vector<uint8_t> data = readAll(file);
        std::snprintf(current_input_path, sizeof current_input_path, "%s", file.c_str());
        LLVMFuzzerTestOneInput(data.data(), data.size());
        ++ran;
        bytes += data.size();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("replay: %zu of %zu inputs (%zu bytes) in %.2f s%s\n", ran, files.size(), bytes, seconds,
                ran < files.size() ? ", the rest left for want of time" : "");
    return 0;
}
